//! The standard assessment (issue 42): one fixed protocol, the same for every patient and
//! every time, so that its measures compare session with session and patient with patient
//! (an exercise's measures depend on its road, speed, assistance and the difficulty the
//! adapter chose; the assessment's do not).
//!
//! Protocol v1 ([`PROTOCOL_VERSION`]), about four minutes, no assistance, the wheel's feel
//! fixed ([`WHEEL_SPRING_NM_PER_RAD`], [`WHEEL_DAMPER_NM_S_PER_RAD`],
//! [`WHEEL_INERTIA_KG_M2`]), run as the existing dial and strength exercises
//! (`AssessmentSpec::exercise`; the whole protocol `ExerciseSpec::assessment_protocol`):
//!
//! 1. **Active range** ([`AssessmentPart::Range`]): the needle at the wheel's end on the left
//!    for [`RANGE_HOLD_S`], then on the right (a dial step, [`crate::dial::DialSignal::Step`]): turn as far
//!    as you can, and hold.
//! 2. **Tracking** at three fixed frequencies ([`TRACKING_FREQUENCIES_RAD_S`]): a sine of
//!    [`TRACKING_AMPLITUDE_DEG`] for [`TRACKING_S`] each (the thesis's dial task, §3.3.3).
//! 3. **Steps** ([`AssessmentPart::Steps`]): target steps of [`STEP_DEG`] from the centre
//!    and back at unpredictable times, each level held between [`STEP_MIN_HOLD_S`] and
//!    [`STEP_MAX_HOLD_S`] drawn from the session's seed ([`crate::dial::DialSignal::RandomSteps`]); each
//!    step is one discrete movement, measured by the metrics crate (reaction and movement
//!    time, SPARC, LDLJ, path-length ratio, initial direction error).
//! 4. **Strength** each side ([`AssessmentPart::Strength`]): the strength test with the fixed
//!    [`STRENGTH_STIFFNESS_NM_PER_RAD`], [`STRENGTH_RAMP_NM_PER_S`] and [`STRENGTH_SIDE_S`].
//!
//! A change to any constant here is a new protocol: raise [`PROTOCOL_VERSION`], so results of
//! two protocols are never compared as one.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::dial::MAX_DIAL_AMPLITUDE_DEG;
use crate::error::VehicleError;

/// The protocol's version: every result names it; a change to any constant below is a new one.
pub const PROTOCOL_VERSION: u32 = 1;

/// Active range: how long the needle stays at each end, s.
pub const RANGE_HOLD_S: f64 = 8.0;
/// Active range: where the needle stands, deg each way (the wheel's end: nobody is asked to
/// stop short of their own range).
pub const RANGE_TARGET_DEG: f64 = MAX_DIAL_AMPLITUDE_DEG;

/// Tracking: the sine's amplitude, deg.
pub const TRACKING_AMPLITUDE_DEG: f64 = 40.0;
/// Tracking: the three sines' frequencies, slow, medium and fast, rad/s (thesis Appendix E
/// tracked at 1 rad/s; its frequency sweep reached 2.5 rad/s).
pub const TRACKING_FREQUENCIES_RAD_S: [f64; 3] = [0.5, 1.0, 2.0];
/// Tracking: how long each frequency lasts, s.
pub const TRACKING_S: f64 = 30.0;

/// Steps: the size of every step, deg (from the centre to a side, or back).
pub const STEP_DEG: f64 = 20.0;
/// Steps: shortest time at a level, s.
pub const STEP_MIN_HOLD_S: f64 = 1.5;
/// Steps: longest time at a level, s.
pub const STEP_MAX_HOLD_S: f64 = 4.0;
/// Steps: how long the part lasts, s.
pub const STEPS_S: f64 = 60.0;

/// Strength: the spring holding the wheel, N·m/rad.
pub const STRENGTH_STIFFNESS_NM_PER_RAD: f64 = 40.0;
/// Strength: how fast the spring's limit rises, N·m/s.
pub const STRENGTH_RAMP_NM_PER_S: f64 = 0.5;
/// Strength: the time limit of each side, s.
pub const STRENGTH_SIDE_S: f64 = 12.0;

/// The wheel's feel during the assessment: no centring spring, N·m/rad.
pub const WHEEL_SPRING_NM_PER_RAD: f64 = 0.0;
/// The wheel's feel during the assessment: a light damper, N·m·s/rad.
pub const WHEEL_DAMPER_NM_S_PER_RAD: f64 = 0.02;
/// The wheel's feel during the assessment: no added inertia, kg·m².
pub const WHEEL_INERTIA_KG_M2: f64 = 0.0;

/// One part of the protocol, in the order it runs them ([`AssessmentPart::ALL`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum AssessmentPart {
    /// Active range each way.
    Range,
    /// Tracking the slow sine.
    TrackingSlow,
    /// Tracking the medium sine.
    TrackingMedium,
    /// Tracking the fast sine.
    TrackingFast,
    /// Steps at unpredictable times.
    Steps,
    /// Strength each side.
    Strength,
}

impl AssessmentPart {
    /// Every part, in the order the protocol runs them.
    pub const ALL: [AssessmentPart; 6] = [
        Self::Range,
        Self::TrackingSlow,
        Self::TrackingMedium,
        Self::TrackingFast,
        Self::Steps,
        Self::Strength,
    ];

    /// The part's short name (`range`, `tracking-slow`, …; the exercise is called
    /// `assessment-<name>`).
    pub fn name(self) -> &'static str {
        match self {
            Self::Range => "range",
            Self::TrackingSlow => "tracking-slow",
            Self::TrackingMedium => "tracking-medium",
            Self::TrackingFast => "tracking-fast",
            Self::Steps => "steps",
            Self::Strength => "strength",
        }
    }

    /// The part called `name` ([`Self::name`]).
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|p| p.name() == name)
    }
}

/// One part of the standard assessment as a regimen entry writes it (`kind = "assessment"`):
/// every setting comes from this module's constants, only the part and the seed vary.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct AssessmentSpec {
    /// The protocol version; only [`PROTOCOL_VERSION`] is run.
    pub protocol: u32,
    /// Which part.
    pub part: AssessmentPart,
    /// Draws the steps' times and sides (recorded with the results, so a session's steps can
    /// be laid out again).
    pub seed: u32,
}

impl Default for AssessmentSpec {
    fn default() -> Self {
        Self {
            protocol: PROTOCOL_VERSION,
            part: AssessmentPart::Range,
            seed: 0,
        }
    }
}

impl AssessmentSpec {
    /// The exercise's short name, `assessment-<part>`.
    pub fn name(&self) -> String {
        format!("assessment-{}", self.part.name())
    }

    /// The protocol must be one this build runs.
    pub fn validate(&self) -> Result<(), VehicleError> {
        if self.protocol == PROTOCOL_VERSION {
            return Ok(());
        }
        Err(VehicleError::OutOfRange {
            context: format!("exercise {:?}", self.name()),
            field: "protocol",
            value: f64::from(self.protocol),
            allowed: format!("{PROTOCOL_VERSION} (the only assessment protocol of this version)"),
        })
    }
}

/// Whether a short exercise name is a part of the assessment (`assessment-range`, …).
pub fn is_assessment_name(short: &str) -> bool {
    short.starts_with("assessment-")
}
