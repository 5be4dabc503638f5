//! The standard assessment (issue 42): one fixed protocol, the same for every patient and
//! every time, so that its measures compare session with session and patient with patient
//! (an exercise's measures depend on its road, speed, assistance and the difficulty the
//! adapter chose; the assessment's do not).
//!
//! Protocol v1 ([`PROTOCOL_VERSION`]), about four minutes, no assistance, the wheel's feel
//! fixed ([`WHEEL_SPRING_NM_PER_RAD`], [`WHEEL_DAMPER_NM_S_PER_RAD`],
//! [`WHEEL_INERTIA_KG_M2`]), run as the existing dial and strength exercises:
//!
//! 1. **Active range** ([`AssessmentPart::Range`]): the needle at the wheel's end on the left
//!    for [`RANGE_HOLD_S`], then on the right (a dial step, [`DialSignal::Step`]): turn as far
//!    as you can, and hold.
//! 2. **Tracking** at three fixed frequencies ([`TRACKING_FREQUENCIES_RAD_S`]): a sine of
//!    [`TRACKING_AMPLITUDE_DEG`] for [`TRACKING_S`] each (the thesis's dial task, §3.3.3).
//! 3. **Steps** ([`AssessmentPart::Steps`]): target steps of [`STEP_DEG`] from the centre
//!    and back at unpredictable times, each level held between [`STEP_MIN_HOLD_S`] and
//!    [`STEP_MAX_HOLD_S`] drawn from the session's seed ([`DialSignal::RandomSteps`]); each
//!    step is one discrete movement, measured by the metrics crate (reaction and movement
//!    time, SPARC, LDLJ, path-length ratio, initial direction error).
//! 4. **Strength** each side ([`AssessmentPart::Strength`]): the strength test with the fixed
//!    [`STRENGTH_STIFFNESS_NM_PER_RAD`], [`STRENGTH_RAMP_NM_PER_S`] and [`STRENGTH_SIDE_S`].
//!
//! A change to any constant here is a new protocol: raise [`PROTOCOL_VERSION`], so results of
//! two protocols are never compared as one.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::dial::{DialSignal, MAX_DIAL_AMPLITUDE_DEG};
use crate::error::VehicleError;
use crate::exercise::{DialSpec, ExerciseSpec, StrengthSpec};

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

/// One part of the protocol, in the order [`protocol`] runs them.
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

    /// The existing exercise this part runs as, with the protocol's fixed settings.
    pub fn exercise(&self) -> ExerciseSpec {
        let tracking = |k: usize| {
            ExerciseSpec::Dial(DialSpec {
                reference: DialSignal::Sine {
                    amplitude_deg: TRACKING_AMPLITUDE_DEG,
                    frequency_rad_s: TRACKING_FREQUENCIES_RAD_S[k],
                },
                duration_s: TRACKING_S,
                drift_deg: 0.0,
            })
        };
        match self.part {
            AssessmentPart::Range => ExerciseSpec::Dial(DialSpec {
                reference: DialSignal::Step {
                    amplitude_deg: RANGE_TARGET_DEG,
                    hold_s: RANGE_HOLD_S,
                },
                duration_s: 2.0 * RANGE_HOLD_S,
                drift_deg: 0.0,
            }),
            AssessmentPart::TrackingSlow => tracking(0),
            AssessmentPart::TrackingMedium => tracking(1),
            AssessmentPart::TrackingFast => tracking(2),
            AssessmentPart::Steps => ExerciseSpec::Dial(DialSpec {
                reference: DialSignal::RandomSteps {
                    amplitude_deg: STEP_DEG,
                    min_hold_s: STEP_MIN_HOLD_S,
                    max_hold_s: STEP_MAX_HOLD_S,
                    seed: self.seed,
                },
                duration_s: STEPS_S,
                drift_deg: 0.0,
            }),
            AssessmentPart::Strength => ExerciseSpec::Strength(StrengthSpec {
                stiffness_nm_per_rad: STRENGTH_STIFFNESS_NM_PER_RAD,
                ramp_nm_per_s: STRENGTH_RAMP_NM_PER_S,
                side_s: STRENGTH_SIDE_S,
            }),
        }
    }
}

/// The whole protocol [`PROTOCOL_VERSION`] with `seed`: every part, in order.
pub fn protocol(seed: u32) -> Vec<ExerciseSpec> {
    AssessmentPart::ALL
        .into_iter()
        .map(|part| {
            ExerciseSpec::Assessment(AssessmentSpec {
                protocol: PROTOCOL_VERSION,
                part,
                seed,
            })
        })
        .collect()
}

/// Whether a short exercise name is a part of the assessment (`assessment-range`, …).
pub fn is_assessment_name(short: &str) -> bool {
    short.starts_with("assessment-")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::TargetSteps;

    #[test]
    fn the_protocol_builds_every_part_from_existing_exercises_in_three_to_five_minutes() {
        let parts = protocol(42);
        assert_eq!(parts.len(), AssessmentPart::ALL.len());
        let mut total_s = 0.0;
        for (spec, part) in parts.iter().zip(AssessmentPart::ALL) {
            spec.validate().unwrap();
            let ex = spec.build().unwrap();
            assert_eq!(ex.name, format!("assessment-{}", part.name()));
            assert!(ex.road.is_none(), "no road: the same task for everyone");
            assert_eq!(ExerciseSpec::from_name(&ex.name).unwrap().name(), ex.name);
            match part {
                AssessmentPart::Strength => assert!(ex.strength().is_some()),
                AssessmentPart::Steps => {
                    assert_eq!(ex.target_steps(), &TargetSteps::Jumps);
                    assert!(ex.is_dial());
                }
                _ => assert!(ex.is_dial()),
            }
            total_s += ex.planned_duration_s();
        }
        // The cards between the parts count as session time.
        total_s += 6.0 * (parts.len() - 1) as f64;
        assert!((180.0..=300.0).contains(&total_s), "{total_s} s");
        // A prescribed duration does not change a fixed protocol.
        assert_eq!(parts[1].with_duration_s(600.0), parts[1]);
        let text = toml::to_string(&parts[4]).unwrap();
        assert!(text.contains("kind = \"assessment\"") && text.contains("seed = 42"), "{text}");
        let back: ExerciseSpec = toml::from_str(&text).unwrap();
        assert_eq!(back, parts[4]);
    }

    #[test]
    fn the_steps_follow_the_seed_and_an_unknown_protocol_is_refused_by_name() {
        let steps = |seed| {
            ExerciseSpec::Assessment(AssessmentSpec {
                protocol: PROTOCOL_VERSION,
                part: AssessmentPart::Steps,
                seed,
            })
            .build()
            .unwrap()
        };
        let (a, b) = (steps(1), steps(2));
        let differ = (0..600).any(|i| {
            let t = f64::from(i) * 0.1;
            a.desired_angle_rad(t) != b.desired_angle_rad(t)
        });
        assert!(differ);
        let size = (0..600)
            .map(|i| a.desired_angle_rad(f64::from(i) * 0.1).unwrap().to_degrees().abs())
            .fold(0.0, f64::max);
        assert!((size - STEP_DEG).abs() < 1e-9, "{size}");
        let old = ExerciseSpec::Assessment(AssessmentSpec {
            protocol: 0,
            ..Default::default()
        });
        let msg = old.validate().unwrap_err().to_string();
        assert!(msg.contains("protocol") && msg.contains("assessment-range"), "{msg}");
    }
}
