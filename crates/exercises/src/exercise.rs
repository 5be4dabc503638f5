//! The exercise library: parametric roads and the rotary dial task, serialisable to TOML
//! (thesis §1.4.1: roads of increasing curvature, sharp turns, sine and triangle roads;
//! §3.3.3: the dial tracking task).
//!
//! An [`ExerciseSpec`] is what a therapist prescribes (a TOML table with `kind = "..."`); its
//! [`ExerciseSpec::validate`] names the exercise, field and allowed range of anything wrong,
//! and [`ExerciseSpec::build`] turns it into an [`Exercise`] the station drives: a road (or
//! none for the dial), a target-speed profile, an end condition, cones and a dial reference.
//!
//! Every road starts at the origin heading along +x, begins with a straight lead-in and ends
//! with a straight lead-out, so a car placed by [`Exercise::start_state`] starts aligned.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use self::bounds::*;
use crate::assessment::{self as A, AssessmentPart, AssessmentSpec};
use crate::dial::{AMPLITUDE_DEG, DialSignal, FREQUENCY_RAD_S};
use crate::error::{VehicleError, check_range};
use crate::model::VehicleState;
use crate::path::{PathBuilder, PathRoad};
use crate::road::Road;
use crate::sweep::{SweepLevel, SweepParameter};
use crate::world::TrackLayout;

/// A haptic sweep's fields: the count of levels, each level within its parameter's bound
/// here (the dial's frequency) or non-negative (the haptic model's own bounds are checked
/// where the model is made, `regimen`), the time at each level and the sine.
fn validate_sweep(c: &str, d: &HapticSweepSpec) -> Result<(), VehicleError> {
    let r = |field: &'static str, v: f64, b: common::Bound, unit: &str| {
        check_range(c, field, v, b.min, b.max, unit)
    };
    r("levels (count)", d.levels.len() as f64, SWEEP_LEVELS, "")?;
    for l in &d.levels {
        match d.parameter {
            SweepParameter::Frequency => {
                r("levels", *l, FREQUENCY_RAD_S, d.parameter.unit())?;
            }
            _ if !(l.is_finite() && *l >= 0.0) => {
                return Err(VehicleError::OutOfRange {
                    context: c.to_string(),
                    field: "levels",
                    value: *l,
                    allowed: format!(
                        "0 {} or more, up to the haptic model's bound",
                        d.parameter.unit()
                    ),
                });
            }
            _ => {}
        }
    }
    r("level_s", d.level_s, LEVEL_S, "s")?;
    r("amplitude_deg", d.amplitude_deg, AMPLITUDE_DEG, "deg")?;
    r(
        "frequency_rad_s",
        d.frequency_rad_s,
        FREQUENCY_RAD_S,
        "rad/s",
    )
}

/// The standard assessment's parts as the existing exercises they run as (the protocol's
/// settings are `crate::assessment`'s constants).
impl AssessmentSpec {
    /// The existing exercise this part runs as, with the protocol's fixed settings.
    pub fn exercise(&self) -> ExerciseSpec {
        let tracking = |k: usize| {
            ExerciseSpec::Dial(DialSpec {
                reference: DialSignal::Sine {
                    amplitude_deg: A::TRACKING_AMPLITUDE_DEG,
                    frequency_rad_s: A::TRACKING_FREQUENCIES_RAD_S[k],
                },
                duration_s: A::TRACKING_S,
                drift_deg: 0.0,
            })
        };
        match self.part {
            AssessmentPart::Range => ExerciseSpec::Dial(DialSpec {
                reference: DialSignal::Step {
                    amplitude_deg: A::RANGE_TARGET_DEG,
                    hold_s: A::RANGE_HOLD_S,
                },
                duration_s: 2.0 * A::RANGE_HOLD_S,
                drift_deg: 0.0,
            }),
            AssessmentPart::TrackingSlow => tracking(0),
            AssessmentPart::TrackingMedium => tracking(1),
            AssessmentPart::TrackingFast => tracking(2),
            AssessmentPart::Steps => ExerciseSpec::Dial(DialSpec {
                reference: DialSignal::RandomSteps {
                    amplitude_deg: A::STEP_DEG,
                    min_hold_s: A::STEP_MIN_HOLD_S,
                    max_hold_s: A::STEP_MAX_HOLD_S,
                    seed: self.seed,
                },
                duration_s: A::STEPS_S,
                drift_deg: 0.0,
            }),
            AssessmentPart::Strength => ExerciseSpec::Strength(StrengthSpec {
                stiffness_nm_per_rad: A::STRENGTH_STIFFNESS_NM_PER_RAD,
                ramp_nm_per_s: A::STRENGTH_RAMP_NM_PER_S,
                side_s: A::STRENGTH_SIDE_S,
            }),
        }
    }
}

impl ExerciseSpec {
    /// The whole standard assessment (protocol `PROTOCOL_VERSION`) with `seed`: every part,
    /// in order.
    pub fn assessment_protocol(seed: u32) -> Vec<ExerciseSpec> {
        AssessmentPart::ALL
            .into_iter()
            .map(|part| {
                ExerciseSpec::Assessment(AssessmentSpec {
                    protocol: A::PROTOCOL_VERSION,
                    part,
                    seed,
                })
            })
            .collect()
    }
}

/// Straight before the exercise proper, m.
pub const LEAD_IN_M: f64 = 30.0;
/// Straight after it, m.
pub const LEAD_OUT_M: f64 = 30.0;
/// Largest lateral acceleration the target-speed profile allows, m/s².
pub const MAX_LATERAL_ACCEL_M_S2: f64 = 3.0;
/// Deceleration the target-speed profile plans with before a bend, m/s².
pub const PLANNED_DECEL_M_S2: f64 = 1.5;

/// The allowed range of every exercise field: [`ExerciseSpec::validate`] checks these and the
/// JSON Schema (`schemars`) states them, from the same constants.
pub mod bounds {
    use common::Bound;

    /// `lane_width_m`, m.
    pub const LANE_WIDTH_M: Bound = Bound::new(2.0, 8.0);
    /// `speed_m_s`, m/s.
    pub const SPEED_M_S: Bound = Bound::new(1.0, 30.0);
    /// `duration_s` (a road's time limit, a dial's length), s.
    pub const DURATION_S: Bound = Bound::new(1.0, 3600.0);
    /// A straight road's `length_m`, m.
    pub const STRAIGHT_LENGTH_M: Bound = Bound::new(10.0, 20_000.0);
    /// A sine road's `amplitude_m`, m.
    pub const SINE_AMPLITUDE_M: Bound = Bound::new(0.0, 50.0);
    /// A triangle road's `amplitude_m`, m.
    pub const TRIANGLE_AMPLITUDE_M: Bound = Bound::new(0.5, 50.0);
    /// `wavelength_m` of sine and triangle roads, m.
    pub const WAVELENGTH_M: Bound = Bound::new(20.0, 2000.0);
    /// Smallest triangle `corner_radius_m`, m (the largest depends on amplitude and
    /// wavelength: the corners must fit on the legs).
    pub const MIN_CORNER_RADIUS_M: f64 = 3.0;
    /// `periods` of sine and triangle roads.
    pub const PERIODS: Bound = Bound::new(1.0, 200.0);
    /// A clothoid's `length_m`, m.
    pub const CLOTHOID_LENGTH_M: Bound = Bound::new(10.0, 5000.0);
    /// A clothoid's `end_curvature_1_m`, 1/m.
    pub const END_CURVATURE_1_M: Bound = Bound::new(-0.2, 0.2);
    /// A clothoid's `unwind_m`, m.
    pub const UNWIND_M: Bound = Bound::new(5.0, 1000.0);
    /// `angle_deg` of sharp turns and S-bends, deg.
    pub const TURN_ANGLE_DEG: Bound = Bound::new(5.0, 180.0);
    /// `radius_m` of sharp turns and S-bends, m.
    pub const TURN_RADIUS_M: Bound = Bound::new(5.0, 500.0);
    /// Sharp turns' `straight_m`, m.
    pub const STRAIGHT_BETWEEN_M: Bound = Bound::new(5.0, 1000.0);
    /// `count` of sharp turns and lane changes.
    pub const COUNT: Bound = Bound::new(1.0, 100.0);
    /// A lane change's `offset_m`, m.
    pub const OFFSET_M: Bound = Bound::new(0.5, 20.0);
    /// A lane change's `transition_m`, m.
    pub const TRANSITION_M: Bound = Bound::new(5.0, 500.0);
    /// A lane change's `hold_m`, m.
    pub const HOLD_M: Bound = Bound::new(0.0, 1000.0);
    /// A slalom's `cone_spacing_m`, m.
    pub const CONE_SPACING_M: Bound = Bound::new(5.0, 200.0);
    /// A slalom's `cone_count`.
    pub const CONE_COUNT: Bound = Bound::new(1.0, 200.0);
    /// A slalom's `weave_m`, m.
    pub const WEAVE_M: Bound = Bound::new(0.5, 10.0);
    /// The strength test's `stiffness_nm_per_rad`, N·m/rad (stiff: the wheel barely moves).
    pub const STIFFNESS_NM_PER_RAD: Bound = Bound::new(5.0, 200.0);
    /// The strength test's `ramp_nm_per_s`, N·m/s (slow: the patient meets it gradually).
    pub const RAMP_NM_PER_S: Bound = Bound::new(0.05, 5.0);
    /// The strength test's `side_s`, s.
    pub const SIDE_S: Bound = Bound::new(3.0, 60.0);
    /// How many `levels` a haptic sweep runs (Appendix E: five to six).
    pub const SWEEP_LEVELS: Bound = Bound::new(1.0, 12.0);
    /// A haptic sweep's `level_s`, s (Appendix E: 60 s).
    pub const LEVEL_S: Bound = Bound::new(1.0, 600.0);
}

macro_rules! spec_struct {
    ($(#[$m:meta])* $name:ident { $($(#[$fm:meta])* $field:ident : $ty:ty = $def:expr),* $(,)? }) => {
        $(#[$m])*
        #[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
        #[serde(deny_unknown_fields, default)]
        pub struct $name {
            $($(#[$fm])* pub $field: $ty,)*
        }
        impl Default for $name {
            fn default() -> Self {
                Self { $($field: $def,)* }
            }
        }
    };
}

spec_struct!(
    /// A straight road.
    StraightSpec {
        /// Length of the exercise part, m.
        #[schemars(range(min = STRAIGHT_LENGTH_M.min, max = STRAIGHT_LENGTH_M.max))]
        length_m: f64 = 300.0,
        /// Lane width, m.
        #[schemars(range(min = LANE_WIDTH_M.min, max = LANE_WIDTH_M.max))]
        lane_width_m: f64 = 3.5,
        /// Target speed, m/s.
        #[schemars(range(min = SPEED_M_S.min, max = SPEED_M_S.max))]
        speed_m_s: f64 = 12.0,
        /// Prescribed duration, s: the exercise lasts exactly this long, the road continuing its
        /// shape as long as needed; without it the road is driven once.
        #[schemars(range(min = DURATION_S.min, max = DURATION_S.max))]
        duration_s: Option<f64> = None,
    }
);

spec_struct!(
    /// The thesis's sine road: `y = A (1 − cos(2π x/λ))` after the lead-in.
    SineSpec {
        // The default 6.5 m (the thesis's road has 4 m) turns the wheel ±27° at the default
        // steering ratio, so that the arm moves enough to be calibrated during the session:
        // the grip 47 mm RMS on a 0.14 m rim, where 4 m gives ±17° and 30 mm, under the
        // 40 mm the calibration asks for (BENCHMARKS.md, "Arm calibration during the
        // session"). A steering ratio raised instead (the road kept) would take the sharp
        // turns past the one-handed reach of the simulated patient.
        /// Amplitude `A`, m (peak-to-peak 2A).
        #[schemars(range(min = SINE_AMPLITUDE_M.min, max = SINE_AMPLITUDE_M.max))]
        amplitude_m: f64 = 6.5,
        /// Wavelength `λ`, m.
        #[schemars(range(min = WAVELENGTH_M.min, max = WAVELENGTH_M.max))]
        wavelength_m: f64 = 120.0,
        /// Number of whole waves.
        #[schemars(range(min = PERIODS.min, max = PERIODS.max))]
        periods: u32 = 4,
        /// Lane width, m.
        #[schemars(range(min = LANE_WIDTH_M.min, max = LANE_WIDTH_M.max))]
        lane_width_m: f64 = 3.5,
        /// Target speed, m/s.
        #[schemars(range(min = SPEED_M_S.min, max = SPEED_M_S.max))]
        speed_m_s: f64 = 12.0,
        /// Prescribed duration, s (the road continues its shape to last it).
        #[schemars(range(min = DURATION_S.min, max = DURATION_S.max))]
        duration_s: Option<f64> = None,
    }
);

spec_struct!(
    /// A triangle-wave road: straight legs at ±atan(4A/λ) joined by arcs of `corner_radius_m`.
    TriangleSpec {
        /// Amplitude of the underlying triangle wave, m.
        #[schemars(range(min = TRIANGLE_AMPLITUDE_M.min, max = TRIANGLE_AMPLITUDE_M.max))]
        amplitude_m: f64 = 4.0,
        /// Wavelength, m.
        #[schemars(range(min = WAVELENGTH_M.min, max = WAVELENGTH_M.max))]
        wavelength_m: f64 = 120.0,
        /// Radius of the rounded corners, m.
        #[schemars(range(min = MIN_CORNER_RADIUS_M))]
        corner_radius_m: f64 = 25.0,
        /// Number of whole waves.
        #[schemars(range(min = PERIODS.min, max = PERIODS.max))]
        periods: u32 = 4,
        /// Lane width, m.
        #[schemars(range(min = LANE_WIDTH_M.min, max = LANE_WIDTH_M.max))]
        lane_width_m: f64 = 3.5,
        /// Target speed, m/s.
        #[schemars(range(min = SPEED_M_S.min, max = SPEED_M_S.max))]
        speed_m_s: f64 = 12.0,
        /// Prescribed duration, s (the road continues its shape to last it).
        #[schemars(range(min = DURATION_S.min, max = DURATION_S.max))]
        duration_s: Option<f64> = None,
    }
);

spec_struct!(
    /// A road of increasing curvature: a clothoid from straight to `end_curvature_1_m`, then a
    /// short clothoid back to straight.
    ClothoidSpec {
        /// Length of the tightening clothoid, m.
        #[schemars(range(min = CLOTHOID_LENGTH_M.min, max = CLOTHOID_LENGTH_M.max))]
        length_m: f64 = 150.0,
        /// Curvature reached at its end, 1/m (positive: turning left).
        #[schemars(range(min = END_CURVATURE_1_M.min, max = END_CURVATURE_1_M.max))]
        end_curvature_1_m: f64 = 0.025,
        /// Length of the unwinding clothoid, m.
        #[schemars(range(min = UNWIND_M.min, max = UNWIND_M.max))]
        unwind_m: f64 = 40.0,
        /// Lane width, m.
        #[schemars(range(min = LANE_WIDTH_M.min, max = LANE_WIDTH_M.max))]
        lane_width_m: f64 = 3.5,
        /// Target speed, m/s.
        #[schemars(range(min = SPEED_M_S.min, max = SPEED_M_S.max))]
        speed_m_s: f64 = 12.0,
        /// Prescribed duration, s (the road continues its shape to last it).
        #[schemars(range(min = DURATION_S.min, max = DURATION_S.max))]
        duration_s: Option<f64> = None,
    }
);

spec_struct!(
    /// Sharp turns: `count` turns of `angle_deg` on arcs of `radius_m`, alternating left and
    /// right, separated by straights.
    SharpTurnsSpec {
        /// Turn angle, deg.
        #[schemars(range(min = TURN_ANGLE_DEG.min, max = TURN_ANGLE_DEG.max))]
        angle_deg: f64 = 90.0,
        /// Turn radius, m.
        #[schemars(range(min = TURN_RADIUS_M.min, max = TURN_RADIUS_M.max))]
        radius_m: f64 = 15.0,
        /// Straight between turns, m.
        #[schemars(range(min = STRAIGHT_BETWEEN_M.min, max = STRAIGHT_BETWEEN_M.max))]
        straight_m: f64 = 50.0,
        /// Number of turns.
        #[schemars(range(min = COUNT.min, max = COUNT.max))]
        count: u32 = 4,
        /// Lane width, m.
        #[schemars(range(min = LANE_WIDTH_M.min, max = LANE_WIDTH_M.max))]
        lane_width_m: f64 = 3.5,
        /// Target speed on the straights, m/s (slower in the turns, see [`Exercise::target_speed_m_s`]).
        #[schemars(range(min = SPEED_M_S.min, max = SPEED_M_S.max))]
        speed_m_s: f64 = 10.0,
        /// Prescribed duration, s (the road continues its shape to last it).
        #[schemars(range(min = DURATION_S.min, max = DURATION_S.max))]
        duration_s: Option<f64> = None,
    }
);

spec_struct!(
    /// An S-bend: a left arc then a right arc of the same radius and angle.
    SBendSpec {
        /// Radius of each arc, m.
        #[schemars(range(min = TURN_RADIUS_M.min, max = TURN_RADIUS_M.max))]
        radius_m: f64 = 30.0,
        /// Angle of each arc, deg.
        #[schemars(range(min = TURN_ANGLE_DEG.min, max = TURN_ANGLE_DEG.max))]
        angle_deg: f64 = 60.0,
        /// Lane width, m.
        #[schemars(range(min = LANE_WIDTH_M.min, max = LANE_WIDTH_M.max))]
        lane_width_m: f64 = 3.5,
        /// Target speed, m/s.
        #[schemars(range(min = SPEED_M_S.min, max = SPEED_M_S.max))]
        speed_m_s: f64 = 9.0,
        /// Prescribed duration, s (the road continues its shape to last it).
        #[schemars(range(min = DURATION_S.min, max = DURATION_S.max))]
        duration_s: Option<f64> = None,
    }
);

spec_struct!(
    /// Lane changes: `count` lateral shifts of `offset_m` (alternating left and right), each
    /// made of two opposite arcs over `transition_m`, with `hold_m` of straight after each.
    LaneChangeSpec {
        /// Lateral shift, m.
        #[schemars(range(min = OFFSET_M.min, max = OFFSET_M.max))]
        offset_m: f64 = 3.5,
        /// Longitudinal length of one change, m.
        #[schemars(range(min = TRANSITION_M.min, max = TRANSITION_M.max))]
        transition_m: f64 = 30.0,
        /// Straight after each change, m.
        #[schemars(range(min = HOLD_M.min, max = HOLD_M.max))]
        hold_m: f64 = 50.0,
        /// Number of changes.
        #[schemars(range(min = COUNT.min, max = COUNT.max))]
        count: u32 = 4,
        /// Lane width, m.
        #[schemars(range(min = LANE_WIDTH_M.min, max = LANE_WIDTH_M.max))]
        lane_width_m: f64 = 3.5,
        /// Target speed, m/s.
        #[schemars(range(min = SPEED_M_S.min, max = SPEED_M_S.max))]
        speed_m_s: f64 = 12.0,
        /// Prescribed duration, s (the road continues its shape to last it).
        #[schemars(range(min = DURATION_S.min, max = DURATION_S.max))]
        duration_s: Option<f64> = None,
    }
);

spec_struct!(
    /// Slalom: cones in a line every `cone_spacing_m`; the centre line weaves around them,
    /// passing each at `weave_m` on alternate sides.
    SlalomSpec {
        /// Distance between cones, m.
        #[schemars(range(min = CONE_SPACING_M.min, max = CONE_SPACING_M.max))]
        cone_spacing_m: f64 = 18.0,
        /// Number of cones.
        #[schemars(range(min = CONE_COUNT.min, max = CONE_COUNT.max))]
        cone_count: u32 = 8,
        /// Lateral distance of the centre line from each cone, m.
        #[schemars(range(min = WEAVE_M.min, max = WEAVE_M.max))]
        weave_m: f64 = 1.5,
        /// Lane width, m.
        #[schemars(range(min = LANE_WIDTH_M.min, max = LANE_WIDTH_M.max))]
        lane_width_m: f64 = 3.0,
        /// Target speed, m/s.
        #[schemars(range(min = SPEED_M_S.min, max = SPEED_M_S.max))]
        speed_m_s: f64 = 7.0,
        /// Prescribed duration, s (the road continues its shape to last it).
        #[schemars(range(min = DURATION_S.min, max = DURATION_S.max))]
        duration_s: Option<f64> = None,
    }
);

spec_struct!(
    /// The rotary dial tracking task: follow the needle with the wheel.
    DialSpec {
        /// The desired angle over time.
        reference: DialSignal = DialSignal::default(),
        /// Length of the exercise, s.
        #[schemars(range(min = DURATION_S.min, max = DURATION_S.max))]
        duration_s: f64 = 60.0,
        /// The target drifts this far to one side over the exercise, in degrees of wheel turn.
        /// It starts at the centre and moves evenly. It drifts into the neglected side when
        /// the patient has one (negative: out of it); otherwise positive is to the left.
        #[serde(skip_serializing_if = "no_drift")]
        #[schemars(range(min = crate::dial::DRIFT_DEG.min, max = crate::dial::DRIFT_DEG.max))]
        drift_deg: f64 = 0.0,
    }
);

/// A dial without drift leaves `drift_deg` out of what it writes, so stations older than the
/// field still read it.
fn no_drift(drift_deg: &f64) -> bool {
    *drift_deg == 0.0
}

spec_struct!(
    /// The strength test (see [`crate::strength`]): a stiff spring ramped slowly up to the
    /// torque ceiling holds the wheel while the patient pushes left, then right.
    StrengthSpec {
        /// Stiffness of the spring holding the wheel at the centre, N·m/rad.
        #[schemars(range(min = STIFFNESS_NM_PER_RAD.min, max = STIFFNESS_NM_PER_RAD.max))]
        stiffness_nm_per_rad: f64 = 40.0,
        /// How fast the spring's torque limit rises to the ceiling, N·m/s.
        #[schemars(range(min = RAMP_NM_PER_S.min, max = RAMP_NM_PER_S.max))]
        ramp_nm_per_s: f64 = 0.5,
        /// Time limit of each side, s.
        #[schemars(range(min = SIDE_S.min, max = SIDE_S.max))]
        side_s: f64 = 12.0,
    }
);

spec_struct!(
    /// Thesis Appendix E's haptic parameter study (see [`crate::sweep`]): the dial's sine
    /// tracked for `level_s` at each of `levels` of the swept parameter, run as one dial
    /// exercise per level ([`HapticSweepSpec::split`]).
    HapticSweepSpec {
        /// What changes from level to level: the haptic model's spring (levels in N·m/rad),
        /// damper (N·m·s/rad) or inertia (kg·m²), the rest of the model as prescribed (none:
        /// zero); or the sine's frequency (rad/s).
        parameter: SweepParameter = SweepParameter::Spring,
        /// The levels in the swept parameter's unit, in the order they are run (1 to 12, each
        /// at least 0 and within the haptic model's or the dial's bound for that parameter).
        #[schemars(length(min = SWEEP_LEVELS.min as u32, max = SWEEP_LEVELS.max as u32), inner(range(min = 0.0)))]
        levels: Vec<f64> = vec![0.0, 0.2, 0.4, 0.6, 0.8, 1.0],
        /// Time at each level, s.
        #[schemars(range(min = LEVEL_S.min, max = LEVEL_S.max))]
        level_s: f64 = 60.0,
        /// The sine's amplitude, deg (Appendix E: 120).
        #[schemars(range(min = AMPLITUDE_DEG.min, max = AMPLITUDE_DEG.max))]
        amplitude_deg: f64 = 120.0,
        /// The sine's frequency, rad/s (Appendix E: 1); a frequency sweep uses its levels.
        #[schemars(range(min = FREQUENCY_RAD_S.min, max = FREQUENCY_RAD_S.max))]
        frequency_rad_s: f64 = 1.0,
    }
);

impl HapticSweepSpec {
    /// The sweep as the station runs it: one sweep of one level per level, in order.
    pub fn split(&self) -> Vec<HapticSweepSpec> {
        self.levels
            .iter()
            .map(|l| HapticSweepSpec {
                levels: vec![*l],
                ..self.clone()
            })
            .collect()
    }

    /// The dial's reference at `level`: the prescribed sine, at `level` rad/s in a
    /// frequency sweep.
    fn reference(&self, level: f64) -> DialSignal {
        DialSignal::Sine {
            amplitude_deg: self.amplitude_deg,
            frequency_rad_s: match self.parameter {
                SweepParameter::Frequency => level,
                _ => self.frequency_rad_s,
            },
        }
    }
}

impl StrengthSpec {
    /// The longest the test lasts, s: both sides and the rest between them.
    pub fn duration_s(&self) -> f64 {
        2.0 * self.side_s + crate::strength::REST_S
    }
}

/// A prescribed exercise. TOML: a table with `kind = "straight" | "sine" | "triangle" |
/// "clothoid" | "sharp-turns" | "s-bend" | "lane-change" | "slalom" | "dial" | "strength" |
/// "haptic-sweep" | "assessment"` and that kind's
/// fields (all optional, defaults above: [`StraightSpec`], [`SineSpec`], …). Each variant's
/// doc is what the regimen's JSON Schema says of it, read by a therapist in the console's
/// prescribe form: the words before its colon name the exercise.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum ExerciseSpec {
    /// Straight road: keep the car in the middle of a straight lane.
    Straight(StraightSpec),
    /// Sine road: a road winding left and right in smooth waves (the thesis's road).
    Sine(SineSpec),
    /// Triangle road: straight stretches at an angle joined by rounded corners.
    Triangle(TriangleSpec),
    /// Clothoid road: a bend that tightens steadily, then straightens.
    Clothoid(ClothoidSpec),
    /// Sharp turns: turns alternating left and right, separated by straights.
    SharpTurns(SharpTurnsSpec),
    /// S-bend: a left bend then a right bend of the same radius.
    SBend(SBendSpec),
    /// Lane change: move into the other lane when the road does, then hold it.
    LaneChange(LaneChangeSpec),
    /// Slalom: steer between cones set in a line.
    Slalom(SlalomSpec),
    /// Dial: turn the wheel so the needle follows the moving target.
    Dial(DialSpec),
    /// Strength: push the wheel left, then right, as hard as you comfortably can against a
    /// spring that stiffens slowly; gives the peak and sustained torque each way.
    Strength(StrengthSpec),
    /// Haptic sweep: follow the swinging needle while the wheel's spring, damping or
    /// heaviness (or the needle's speed) changes in steps; gives the tracking error at each
    /// step, as the thesis's parameter studies did.
    HapticSweep(HapticSweepSpec),
    /// Assessment: one part of the standard assessment, the same for every patient, with no
    /// assistance (see [`crate::assessment`]). Not prescribed as an exercise (the regimen's
    /// schema leaves it out): the therapist schedules it with `[assessment]`, the station
    /// puts it first in a session when it is due, and its recordings keep it.
    #[schemars(skip)]
    Assessment(AssessmentSpec),
}

/// The built-in exercise names, each with its default parameters ([`ExerciseSpec::from_name`]).
pub const EXERCISE_NAMES: [&str; 15] = [
    "straight-road",
    "sine-road",
    "triangle-road",
    "clothoid-road",
    "sharp-turns",
    "s-bend",
    "lane-change",
    "slalom",
    "dial-sine",
    "dial-multi-sine",
    "dial-step",
    "dial-ramp",
    "dial-chirp",
    "strength",
    "haptic-sweep",
];

impl ExerciseSpec {
    /// The default exercise called `name` (one of [`EXERCISE_NAMES`]; a `kind` such as
    /// `"sine"` also works).
    pub fn from_name(name: &str) -> Result<Self, VehicleError> {
        let spec = match name {
            "straight-road" | "straight" => Self::Straight(Default::default()),
            "sine-road" | "sine" => Self::Sine(Default::default()),
            "triangle-road" | "triangle" => Self::Triangle(Default::default()),
            "clothoid-road" | "clothoid" | "increasing-curvature" => {
                Self::Clothoid(Default::default())
            }
            "sharp-turns" => Self::SharpTurns(Default::default()),
            "s-bend" => Self::SBend(Default::default()),
            "lane-change" => Self::LaneChange(Default::default()),
            "slalom" => Self::Slalom(Default::default()),
            "dial" => Self::Dial(Default::default()),
            "strength" => Self::Strength(Default::default()),
            "haptic-sweep" => Self::HapticSweep(Default::default()),
            other if other.starts_with("assessment-") => {
                match AssessmentPart::from_name(&other["assessment-".len()..]) {
                    Some(part) => Self::Assessment(AssessmentSpec {
                        part,
                        ..Default::default()
                    }),
                    None => {
                        return Err(VehicleError::UnknownExercise {
                            name: name.to_string(),
                            known: EXERCISE_NAMES.join(", "),
                        });
                    }
                }
            }
            other => match other
                .strip_prefix("dial-")
                .and_then(DialSignal::default_named)
            {
                Some(reference) => Self::Dial(DialSpec {
                    reference,
                    ..Default::default()
                }),
                None => {
                    return Err(VehicleError::UnknownExercise {
                        name: name.to_string(),
                        known: EXERCISE_NAMES.join(", "),
                    });
                }
            },
        };
        Ok(spec)
    }

    /// The same exercise prescribed for `duration_s`.
    pub fn with_duration_s(&self, duration_s: f64) -> Self {
        let mut spec = self.clone();
        match &mut spec {
            Self::Straight(s) => s.duration_s = Some(duration_s),
            Self::Sine(s) => s.duration_s = Some(duration_s),
            Self::Triangle(s) => s.duration_s = Some(duration_s),
            Self::Clothoid(s) => s.duration_s = Some(duration_s),
            Self::SharpTurns(s) => s.duration_s = Some(duration_s),
            Self::SBend(s) => s.duration_s = Some(duration_s),
            Self::LaneChange(s) => s.duration_s = Some(duration_s),
            Self::Slalom(s) => s.duration_s = Some(duration_s),
            Self::Dial(d) => d.duration_s = duration_s,
            // Both sides share the time, less the rest between them.
            Self::Strength(d) => {
                d.side_s =
                    ((duration_s - crate::strength::REST_S) / 2.0).clamp(SIDE_S.min, SIDE_S.max);
            }
            // The levels share the time.
            Self::HapticSweep(d) => {
                d.level_s =
                    (duration_s / d.levels.len().max(1) as f64).clamp(LEVEL_S.min, LEVEL_S.max);
            }
            // A fixed protocol: the same length for everyone.
            Self::Assessment(_) => {}
        }
        spec
    }

    /// The stable short name (`"sine-road"`, `"dial-step"`, …).
    pub fn name(&self) -> String {
        match self {
            Self::Straight(_) => "straight-road".into(),
            Self::Sine(_) => "sine-road".into(),
            Self::Triangle(_) => "triangle-road".into(),
            Self::Clothoid(_) => "clothoid-road".into(),
            Self::SharpTurns(_) => "sharp-turns".into(),
            Self::SBend(_) => "s-bend".into(),
            Self::LaneChange(_) => "lane-change".into(),
            Self::Slalom(_) => "slalom".into(),
            Self::Dial(d) => format!("dial-{}", d.reference.name()),
            Self::Strength(_) => "strength".into(),
            Self::HapticSweep(_) => "haptic-sweep".into(),
            Self::Assessment(a) => a.name(),
        }
    }

    /// Check every field; the message names the exercise, field and allowed range.
    pub fn validate(&self) -> Result<(), VehicleError> {
        let c = format!("exercise {:?}", self.name());
        let c = c.as_str();
        let r = |field: &'static str, v: f64, b: common::Bound, unit: &str| {
            check_range(c, field, v, b.min, b.max, unit)
        };
        // What every road has: lane width, target speed and an optional time limit.
        let road = |lane_width_m: f64, speed_m_s: f64, duration_s: Option<f64>| {
            r("lane_width_m", lane_width_m, LANE_WIDTH_M, "m")?;
            r("speed_m_s", speed_m_s, SPEED_M_S, "m/s")?;
            duration_s.map_or(Ok(()), |d| r("duration_s", d, DURATION_S, "s"))
        };
        let n = f64::from;
        match self {
            Self::Straight(s) => {
                r("length_m", s.length_m, STRAIGHT_LENGTH_M, "m")?;
                road(s.lane_width_m, s.speed_m_s, s.duration_s)
            }
            Self::Sine(s) => {
                r("amplitude_m", s.amplitude_m, SINE_AMPLITUDE_M, "m")?;
                r("wavelength_m", s.wavelength_m, WAVELENGTH_M, "m")?;
                r("periods", n(s.periods), PERIODS, "")?;
                road(s.lane_width_m, s.speed_m_s, s.duration_s)
            }
            Self::Triangle(s) => {
                r("amplitude_m", s.amplitude_m, TRIANGLE_AMPLITUDE_M, "m")?;
                r("wavelength_m", s.wavelength_m, WAVELENGTH_M, "m")?;
                let (leg, phi) = triangle_leg(s.amplitude_m, s.wavelength_m);
                // The corner tangents must fit on the half legs at both ends.
                let max_r = leg / (2.0 * (phi.tan() + (phi / 2.0).tan()));
                check_range(
                    c,
                    "corner_radius_m",
                    s.corner_radius_m,
                    MIN_CORNER_RADIUS_M,
                    max_r.max(MIN_CORNER_RADIUS_M),
                    "m (the corners must fit on the legs of this amplitude and wavelength)",
                )?;
                r("periods", n(s.periods), PERIODS, "")?;
                road(s.lane_width_m, s.speed_m_s, s.duration_s)
            }
            Self::Clothoid(s) => {
                r("length_m", s.length_m, CLOTHOID_LENGTH_M, "m")?;
                r(
                    "end_curvature_1_m",
                    s.end_curvature_1_m,
                    END_CURVATURE_1_M,
                    "1/m",
                )?;
                r("unwind_m", s.unwind_m, UNWIND_M, "m")?;
                road(s.lane_width_m, s.speed_m_s, s.duration_s)
            }
            Self::SharpTurns(s) => {
                r("angle_deg", s.angle_deg, TURN_ANGLE_DEG, "deg")?;
                r("radius_m", s.radius_m, TURN_RADIUS_M, "m")?;
                r("straight_m", s.straight_m, STRAIGHT_BETWEEN_M, "m")?;
                r("count", n(s.count), COUNT, "")?;
                road(s.lane_width_m, s.speed_m_s, s.duration_s)
            }
            Self::SBend(s) => {
                r("radius_m", s.radius_m, TURN_RADIUS_M, "m")?;
                r("angle_deg", s.angle_deg, TURN_ANGLE_DEG, "deg")?;
                road(s.lane_width_m, s.speed_m_s, s.duration_s)
            }
            Self::LaneChange(s) => {
                r("offset_m", s.offset_m, OFFSET_M, "m")?;
                r("transition_m", s.transition_m, TRANSITION_M, "m")?;
                r("hold_m", s.hold_m, HOLD_M, "m")?;
                r("count", n(s.count), COUNT, "")?;
                road(s.lane_width_m, s.speed_m_s, s.duration_s)
            }
            Self::Slalom(s) => {
                r("cone_spacing_m", s.cone_spacing_m, CONE_SPACING_M, "m")?;
                r("cone_count", n(s.cone_count), CONE_COUNT, "")?;
                r("weave_m", s.weave_m, WEAVE_M, "m")?;
                road(s.lane_width_m, s.speed_m_s, s.duration_s)
            }
            Self::Dial(d) => {
                d.reference.validate(c)?;
                r("duration_s", d.duration_s, DURATION_S, "s")?;
                r("drift_deg", d.drift_deg, crate::dial::DRIFT_DEG, "deg")
            }
            Self::Strength(d) => {
                r(
                    "stiffness_nm_per_rad",
                    d.stiffness_nm_per_rad,
                    STIFFNESS_NM_PER_RAD,
                    "N·m/rad",
                )?;
                r("ramp_nm_per_s", d.ramp_nm_per_s, RAMP_NM_PER_S, "N·m/s")?;
                r("side_s", d.side_s, SIDE_S, "s")
            }
            Self::HapticSweep(d) => validate_sweep(c, d),
            Self::Assessment(a) => a.validate(),
        }
    }

    /// Validate and build the exercise.
    pub fn build(&self) -> Result<Exercise, VehicleError> {
        self.validate()?;
        let name = self.name();
        let (speed, duration, mut cones) = match self {
            Self::Straight(s) => (s.speed_m_s, s.duration_s, Vec::new()),
            Self::Sine(s) => (s.speed_m_s, s.duration_s, Vec::new()),
            Self::Triangle(s) => (s.speed_m_s, s.duration_s, Vec::new()),
            Self::Clothoid(s) => (s.speed_m_s, s.duration_s, Vec::new()),
            Self::SharpTurns(s) => (s.speed_m_s, s.duration_s, Vec::new()),
            Self::SBend(s) => (s.speed_m_s, s.duration_s, Vec::new()),
            Self::LaneChange(s) => (s.speed_m_s, s.duration_s, Vec::new()),
            Self::Slalom(s) => (s.speed_m_s, s.duration_s, Vec::new()),
            // The existing exercise with the protocol's settings, under the part's name.
            Self::Assessment(a) => {
                let mut ex = a.exercise().build()?;
                ex.name = name;
                return Ok(ex);
            }
            Self::Dial(d) => {
                return Ok(Exercise {
                    name,
                    road: None,
                    length_m: 0.0,
                    lane_width_m: 0.0,
                    duration_s: Some(d.duration_s),
                    cones: Vec::new(),
                    speed_profile_m_s: Vec::new(),
                    dial: Some(crate::dial::DialTarget::new(
                        d.reference.clone(),
                        d.drift_deg.to_radians(),
                        d.duration_s,
                    )),
                    strength: None,
                    sweep: None,
                    steps: if matches!(
                        d.reference,
                        DialSignal::Step { .. } | DialSignal::RandomSteps { .. }
                    ) {
                        TargetSteps::Jumps
                    } else {
                        TargetSteps::None
                    },
                });
            }
            Self::Strength(d) => {
                return Ok(Exercise {
                    name,
                    road: None,
                    length_m: 0.0,
                    lane_width_m: 0.0,
                    duration_s: Some(d.duration_s()),
                    cones: Vec::new(),
                    speed_profile_m_s: Vec::new(),
                    dial: None,
                    strength: Some(d.clone()),
                    sweep: None,
                    steps: TargetSteps::None,
                });
            }
            // Built whole (as a regimen plans it), one dial of every level's time at its
            // first level; the station runs it split, one level per exercise.
            Self::HapticSweep(d) => {
                let level = d.levels.first().copied().unwrap_or_default();
                return Ok(Exercise {
                    name,
                    road: None,
                    length_m: 0.0,
                    lane_width_m: 0.0,
                    duration_s: Some(d.level_s * d.levels.len() as f64),
                    cones: Vec::new(),
                    speed_profile_m_s: Vec::new(),
                    dial: Some(crate::dial::DialTarget::steady(d.reference(level))),
                    strength: None,
                    sweep: Some(SweepLevel {
                        parameter: d.parameter,
                        level,
                    }),
                    steps: TargetSteps::None,
                });
            }
        };
        let reps = match duration {
            Some(d) => self.repetitions_for(d, speed)?,
            None => 1,
        };
        let road = self.road(reps)?;
        if let Self::Slalom(s) = self {
            // The cones stand on the centre line's axis y = w at its crests and troughs
            // ξ = k·spacing (see `centre_line`).
            cones = (1..=slalom_cones(s.cone_count, reps))
                .map(|k| [LEAD_IN_M + f64::from(k) * s.cone_spacing_m, s.weave_m])
                .collect();
        }
        let length_m = road.length_m();
        let lane_width_m = road.lane_width_m();
        let speed_profile_m_s = speed_profile(&road, speed);
        Ok(Exercise {
            name,
            road: Some(Box::new(road)),
            length_m,
            lane_width_m,
            duration_s: duration,
            cones,
            speed_profile_m_s,
            dial: None,
            strength: None,
            sweep: None,
            steps: self.lane_shifts(reps),
        })
    }

    /// The lane shifts of a lane change whose shape repeats `reps` times, as
    /// [`Self::centre_line`] lays them out (none for any other road).
    fn lane_shifts(&self, reps: u32) -> TargetSteps {
        let Self::LaneChange(s) = self else {
            return TargetSteps::None;
        };
        let (phi, r) = lane_change_arcs(s);
        let every_m = 2.0 * r * phi + s.hold_m;
        TargetSteps::LaneShifts(
            (0..s.count * reps.max(1))
                .map(|i| LaneShift {
                    s_m: LEAD_IN_M + f64::from(i) * every_m,
                    direction: if i % 2 == 0 { 1.0 } else { -1.0 },
                })
                .collect(),
        )
    }

    /// The road with its shape `reps` times over, then the lead-out straight.
    fn road(&self, reps: u32) -> Result<PathRoad, VehicleError> {
        self.centre_line(reps)
            .ok_or_else(|| VehicleError::InvalidInput("no road".into()))?
            .straight(LEAD_OUT_M)
            .build()
    }

    /// How many times the shape must repeat for a car following the target-speed profile to
    /// still be on the road after `duration_s` (a prescribed duration is honoured exactly, the
    /// road continued seamlessly rather than run out): the time to drive one shape at the
    /// profile, with a quarter more road and 5 s spare for a car slower than its target.
    fn repetitions_for(&self, duration_s: f64, speed_m_s: f64) -> Result<u32, VehicleError> {
        let one = self.road(1)?;
        let profile = speed_profile(&one, speed_m_s);
        let drive_s: f64 = profile.iter().map(|v| 1.0 / v.max(0.1)).sum();
        // The lead-in and lead-out are driven once, whatever the repetitions.
        let shape_s = (drive_s - (LEAD_IN_M + LEAD_OUT_M) / speed_m_s).max(0.1);
        let needed_s = 1.25 * duration_s + 5.0;
        if drive_s >= needed_s {
            return Ok(1);
        }
        Ok(((needed_s / shape_s).ceil() as u32).max(1))
    }

    /// A road exercise's centre line from its start to the end of its shape repeated `reps`
    /// times (the lead-out straight follows); `None` for the dial task. Every repetition
    /// continues the last one where it ended: roads that end turned (clothoid) mirror every
    /// other repetition so they wind back, counted shapes (waves, turns, lane changes, cones)
    /// continue their alternation.
    fn centre_line(&self, reps: u32) -> Option<PathBuilder> {
        let lead = |w: f64| PathBuilder::new(0.0, 0.0, 0.0, w).straight(LEAD_IN_M);
        let reps = reps.max(1);
        Some(match self {
            Self::Straight(s) => lead(s.lane_width_m).straight(s.length_m * f64::from(reps)),
            Self::Sine(s) => {
                lead(s.lane_width_m).sine(s.amplitude_m, s.wavelength_m, 2 * s.periods * reps)
            }
            Self::Triangle(s) => {
                let (leg, phi) = triangle_leg(s.amplitude_m, s.wavelength_m);
                let r = s.corner_radius_m;
                let t_full = r * phi.tan(); // tangent length of a 2φ corner
                let t_half = r * (phi / 2.0).tan(); // of a φ corner
                let mut b = lead(s.lane_width_m)
                    .arc(r, phi)
                    .straight(leg / 2.0 - t_half - t_full);
                for i in 0..2 * s.periods * reps {
                    let sign = if i % 2 == 0 { -1.0 } else { 1.0 };
                    let last = i + 1 == 2 * s.periods * reps;
                    b = b.arc(r, sign * 2.0 * phi).straight(if last {
                        leg / 2.0 - t_full - t_half
                    } else {
                        leg - 2.0 * t_full
                    });
                }
                b.arc(r, -phi)
            }
            Self::Clothoid(s) => {
                let mut b = lead(s.lane_width_m);
                for i in 0..reps {
                    let k = if i % 2 == 0 { 1.0 } else { -1.0 } * s.end_curvature_1_m;
                    b = b.clothoid(s.length_m, 0.0, k).clothoid(s.unwind_m, k, 0.0);
                }
                b
            }
            Self::SharpTurns(s) => {
                let mut b = lead(s.lane_width_m);
                for i in 0..s.count * reps {
                    let sign = if i % 2 == 0 { 1.0 } else { -1.0 };
                    b = b
                        .arc(s.radius_m, sign * s.angle_deg.to_radians())
                        .straight(s.straight_m);
                }
                b
            }
            Self::SBend(s) => {
                let a = s.angle_deg.to_radians();
                let mut b = lead(s.lane_width_m);
                for _ in 0..reps {
                    b = b.arc(s.radius_m, a).arc(s.radius_m, -a);
                }
                b
            }
            Self::LaneChange(s) => {
                let (phi, r) = lane_change_arcs(s);
                let mut b = lead(s.lane_width_m);
                for i in 0..s.count * reps {
                    let sign = if i % 2 == 0 { 1.0 } else { -1.0 };
                    b = b.arc(r, sign * phi).arc(r, -sign * phi).straight(s.hold_m);
                }
                b
            }
            // Centre line y = w (1 − cos(π ξ / spacing)) after the lead-in.
            Self::Slalom(s) => lead(s.lane_width_m).sine(
                s.weave_m,
                2.0 * s.cone_spacing_m,
                slalom_cones(s.cone_count, reps) + 1,
            ),
            Self::Dial(_) | Self::Strength(_) | Self::HapticSweep(_) | Self::Assessment(_) => {
                return None;
            }
        })
    }
}

/// The angle and radius of each of a lane change's two opposite arcs: two arcs shift by d
/// over length L with φ = 2 atan(d/L), R = L/(2 sin φ).
fn lane_change_arcs(s: &LaneChangeSpec) -> (f64, f64) {
    let phi = 2.0 * (s.offset_m / s.transition_m).atan();
    (phi, s.transition_m / (2.0 * phi.sin()))
}

/// A slalom's cones when its shape repeats `reps` times: the weave continues, a cone at
/// every crest and trough.
fn slalom_cones(cone_count: u32, reps: u32) -> u32 {
    (cone_count + 1) * reps.max(1) - 1
}

/// Leg length and leg angle of a triangle wave of amplitude `a` and wavelength `l`.
fn triangle_leg(a: f64, l: f64) -> (f64, f64) {
    ((l / 2.0).hypot(2.0 * a), (4.0 * a / l).atan())
}

/// Target speed every metre: at most `speed`, at most √(a_lat/|κ|), and reachable by braking
/// at [`PLANNED_DECEL_M_S2`] from the metre before.
fn speed_profile(road: &PathRoad, speed: f64) -> Vec<f64> {
    let n = road.length_m().ceil() as usize + 1;
    let mut v: Vec<f64> = (0..n)
        .map(|i| {
            let k = road.point(i as f64).curvature_1_m.abs();
            if k > 1e-9 {
                speed.min((MAX_LATERAL_ACCEL_M_S2 / k).sqrt())
            } else {
                speed
            }
        })
        .collect();
    for i in (0..n.saturating_sub(1)).rev() {
        v[i] = v[i].min((v[i + 1] * v[i + 1] + 2.0 * PLANNED_DECEL_M_S2).sqrt());
    }
    v
}

/// A built exercise, ready to drive. See [`ExerciseSpec::build`].
pub struct Exercise {
    /// The short name, e.g. `"sine-road"`.
    pub name: String,
    /// The road, `None` for the dial task.
    pub road: Option<Box<dyn Road + Send>>,
    /// Length of the road, m (the end of the exercise); 0 for the dial task.
    pub length_m: f64,
    /// Lane width, m (0 for the dial task).
    pub lane_width_m: f64,
    /// Time limit, s, if any (always set for the dial task).
    pub duration_s: Option<f64>,
    /// Cone positions, m.
    pub cones: Vec<[f64; 2]>,
    speed_profile_m_s: Vec<f64>,
    dial: Option<crate::dial::DialTarget>,
    strength: Option<StrengthSpec>,
    sweep: Option<SweepLevel>,
    steps: TargetSteps,
}

/// Which changes of an exercise's target are step changes a reaction is measured to (robot
/// assessments' reaction time and initial direction error, `metrics::robot`).
#[derive(Clone, Debug, Default, PartialEq)]
pub enum TargetSteps {
    /// None: the target moves continuously (roads, smooth dials) or its jumps are no cue to
    /// react to (the strength test's side changes).
    #[default]
    None,
    /// Every jump of the target angle (the stepping dial).
    Jumps,
    /// The lane shifts of a lane change: where the lane the patient must drive in starts to
    /// move, in the order the car meets them.
    LaneShifts(Vec<LaneShift>),
}

/// Where the lane of a lane change starts to move over.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LaneShift {
    /// Distance along the road where the centre line starts to shift, m.
    pub s_m: f64,
    /// The way the wheel must turn first to follow it: +1 left (the lane moves left, a
    /// positive wheel angle), −1 right.
    pub direction: f64,
}

impl std::fmt::Debug for Exercise {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Exercise")
            .field("name", &self.name)
            .field("length_m", &self.length_m)
            .field("duration_s", &self.duration_s)
            .field("cones", &self.cones.len())
            .field("dial", &self.dial)
            .field("strength", &self.strength)
            .field("sweep", &self.sweep)
            .field("steps", &self.steps)
            .finish()
    }
}

impl Exercise {
    /// `true` for the rotary dial task (no road, no car).
    pub fn is_dial(&self) -> bool {
        self.dial.is_some()
    }

    /// The strength test's settings; `None` for every other exercise.
    pub fn strength(&self) -> Option<&StrengthSpec> {
        self.strength.as_ref()
    }

    /// The haptic sweep's level this exercise runs (its first for a sweep built whole);
    /// `None` for every other exercise.
    pub fn sweep(&self) -> Option<SweepLevel> {
        self.sweep
    }

    /// Which of the target's changes are steps to react to.
    pub fn target_steps(&self) -> &TargetSteps {
        &self.steps
    }

    /// Desired wheel angle at `t_s` for the dial task, rad; `None` for road exercises.
    pub fn desired_angle_rad(&self, t_s: f64) -> Option<f64> {
        self.dial.as_ref().map(|d| d.desired_angle_rad(t_s))
    }

    /// Target forward speed at arc length `s_m`, m/s (slower before and in tight bends);
    /// 0 for the dial task.
    pub fn target_speed_m_s(&self, s_m: f64) -> f64 {
        match self.speed_profile_m_s.len() {
            0 => 0.0,
            n => {
                let i = if s_m.is_finite() && s_m > 0.0 {
                    (s_m as usize).min(n - 1)
                } else {
                    0
                };
                self.speed_profile_m_s[i]
            }
        }
    }

    /// Where the car starts: on the centre line at the road's start, aligned with it, at the
    /// target speed.
    pub fn start_state(&self) -> VehicleState {
        match &self.road {
            Some(road) => {
                let ([x, y], h, _) = road.centre(0.0);
                VehicleState {
                    x_m: x,
                    y_m: y,
                    yaw_rad: h,
                    ux_m_s: self.target_speed_m_s(0.0),
                    ..Default::default()
                }
            }
            None => VehicleState::default(),
        }
    }

    /// How long the exercise is planned to last, s: its time limit, or for a road without one
    /// the time to drive the road at its target speed profile (one-metre steps).
    pub fn planned_duration_s(&self) -> f64 {
        if let Some(d) = self.duration_s {
            return d;
        }
        self.speed_profile_m_s
            .iter()
            .take(self.length_m.ceil().max(0.0) as usize)
            .map(|v| if *v > 0.0 { 1.0 / v } else { 0.0 })
            .sum()
    }

    /// Whether the exercise is over at time `t_s` with the car at arc length `s_m`.
    pub fn is_finished(&self, t_s: f64, s_m: f64) -> bool {
        let timed_out = self.duration_s.is_some_and(|d| t_s >= d);
        let arrived = self.road.is_some() && s_m >= self.length_m;
        timed_out || arrived
    }

    /// The rapier track: edges at the lane's sides (sampled every metre), no barriers, the cones.
    pub fn track_layout(&self) -> TrackLayout {
        match &self.road {
            Some(road) => TrackLayout {
                cones: self.cones.clone(),
                ..TrackLayout::along_road(
                    road.as_ref(),
                    self.length_m,
                    self.lane_width_m / 2.0,
                    1.0,
                    None,
                )
            },
            None => TrackLayout::default(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_named_exercise_builds_and_round_trips_through_toml() {
        for name in EXERCISE_NAMES {
            let spec = ExerciseSpec::from_name(name).unwrap();
            assert_eq!(spec.name(), name);
            let ex = spec.build().unwrap();
            assert_eq!(ex.name, name);
            let text = toml::to_string(&spec).unwrap();
            let back: ExerciseSpec = toml::from_str(&text).unwrap();
            assert_eq!(back, spec, "{text}");
            if let Some(road) = &ex.road {
                // Starts at the origin along +x, ends after its lead-out straight.
                let ([x, y], h, _) = road.centre(0.0);
                assert!(x.abs() < 1e-12 && y.abs() < 1e-12 && h.abs() < 1e-12);
                assert!(ex.length_m > LEAD_IN_M + LEAD_OUT_M);
                assert_eq!(
                    road.centre(ex.length_m - 1.0).2,
                    0.0,
                    "{name} ends straight"
                );
            } else if let Some(s) = ex.strength() {
                assert_eq!(ex.planned_duration_s(), s.duration_s(), "{name}");
            } else {
                assert!(ex.is_dial() && ex.desired_angle_rad(1.0).is_some());
            }
        }
    }

    /// The shipped sample regimens: each `[[exercise]]` table is an `ExerciseSpec`; a station
    /// entry can flatten it beside its own keys (here a `haptic` table).
    #[test]
    fn sample_regimens_parse_validate_and_compose_with_station_keys() {
        #[derive(Deserialize)]
        #[serde(deny_unknown_fields)]
        struct Regimen {
            exercise: Vec<ExerciseSpec>,
        }
        #[derive(Deserialize)]
        struct StationEntry {
            #[serde(flatten)]
            exercise: ExerciseSpec,
            haptic: Option<toml::Table>,
        }
        for text in [
            include_str!("../../../regimens/easy.toml"),
            include_str!("../../../regimens/medium.toml"),
            include_str!("../../../regimens/hard.toml"),
        ] {
            let r: Regimen = toml::from_str(text).unwrap();
            assert!(r.exercise.len() >= 3);
            for e in &r.exercise {
                e.build().unwrap();
            }
        }
        let e: StationEntry = toml::from_str(
            "kind = \"sine\"\namplitude_m = 3.0\nduration_s = 20.0\n[haptic]\nk = 0.5\n",
        )
        .unwrap();
        assert!(e.haptic.is_some());
        // A misspelt exercise key is still rejected through the flatten.
        assert!(
            toml::from_str::<StationEntry>("kind = \"sine\"\namplitud_m = 3.0\n[haptic]\n")
                .is_err()
        );
        match e.exercise {
            ExerciseSpec::Sine(s) => assert_eq!((s.amplitude_m, s.duration_s), (3.0, Some(20.0))),
            other => panic!("{other:?}"),
        }
    }

    /// Every road kind prescribed for longer than its shape lasts is continued: the target
    /// speed profile takes longer than the prescription to drive, the road ends straight or
    /// on its own heading, and a slalom keeps a cone at every crest.
    #[test]
    fn a_prescribed_duration_longer_than_the_shape_continues_the_road() {
        // The strength test's sides have their own time limits (its own test below).
        for name in EXERCISE_NAMES.iter().filter(|n| **n != "strength") {
            let spec = ExerciseSpec::from_name(name).unwrap();
            let once = spec.build().unwrap();
            let ex = spec.with_duration_s(600.0).build().unwrap();
            assert_eq!(ex.planned_duration_s(), 600.0, "{name}");
            let Some(road) = &ex.road else { continue };
            assert!(ex.length_m > once.length_m, "{name}");
            let drive_s: f64 = (0..ex.length_m as usize)
                .map(|s| 1.0 / ex.target_speed_m_s(s as f64))
                .sum();
            assert!(drive_s > 600.0 * 1.2, "{name}: {drive_s} s of road");
            // Seamless: heading and position continuous along the whole road.
            let mut last = road.centre(0.0);
            let mut s = 0.5;
            while s < ex.length_m {
                let c = road.centre(s);
                let step = (c.0[0] - last.0[0]).hypot(c.0[1] - last.0[1]);
                assert!((step - 0.5).abs() < 1e-3, "{name} jumps at {s}: {step}");
                last = c;
                s += 0.5;
            }
            for c in &ex.cones {
                let p = road.project(c[0], c[1], f64::NAN);
                assert!((p.lateral_m.abs() - 1.5).abs() < 1e-3, "{name} {p:?}");
            }
        }
    }

    #[test]
    fn unknown_name_lists_the_library() {
        let e = ExerciseSpec::from_name("loop-the-loop")
            .unwrap_err()
            .to_string();
        assert!(e.contains("loop-the-loop") && e.contains("sine-road") && e.contains("dial-chirp"));
    }

    #[test]
    fn toml_kind_and_defaults_and_bad_fields() {
        let s: ExerciseSpec = toml::from_str("kind = \"sine\"\namplitude_m = 6.0\n").unwrap();
        match &s {
            ExerciseSpec::Sine(sine) => {
                assert_eq!(sine.amplitude_m, 6.0);
                assert_eq!(sine.wavelength_m, 120.0);
            }
            other => panic!("{other:?}"),
        }
        assert!(toml::from_str::<ExerciseSpec>("kind = \"sine\"\namplitude = 6.0\n").is_err());
        let bad: ExerciseSpec = toml::from_str("kind = \"sine\"\nwavelength_m = 5.0\n").unwrap();
        let msg = bad.validate().unwrap_err().to_string();
        assert!(
            msg.contains("sine-road") && msg.contains("wavelength_m") && msg.contains("20 to 2000"),
            "{msg}"
        );
        let dial: ExerciseSpec = toml::from_str(
            "kind = \"dial\"\nduration_s = 30.0\n[reference]\nsignal = \"step\"\namplitude_deg = 45.0\nhold_s = 3.0\n",
        )
        .unwrap();
        assert_eq!(dial.name(), "dial-step");
        dial.validate().unwrap();
    }

    #[test]
    fn triangle_corner_radius_too_large_for_its_legs_is_rejected() {
        let spec = ExerciseSpec::Triangle(TriangleSpec {
            corner_radius_m: 1000.0,
            ..Default::default()
        });
        let msg = spec.validate().unwrap_err().to_string();
        assert!(msg.contains("corner_radius_m"), "{msg}");
    }

    #[test]
    fn triangle_legs_have_the_wave_slope() {
        let ex = ExerciseSpec::from_name("triangle-road")
            .unwrap()
            .build()
            .unwrap();
        let road = ex.road.as_ref().unwrap();
        let phi = (16.0f64 / 120.0).atan();
        // Halfway along the first full leg the road is straight at −φ.
        let mut seen = false;
        let mut s = LEAD_IN_M;
        while s < ex.length_m {
            let (_, h, k) = road.centre(s);
            if k == 0.0 && s > LEAD_IN_M + 5.0 && s < ex.length_m - LEAD_OUT_M {
                assert!((h.abs() - phi).abs() < 1e-9, "s={s} heading {h}");
                seen = true;
            }
            s += 0.5;
        }
        assert!(seen);
    }

    #[test]
    fn lane_change_shifts_by_offset_and_slalom_passes_cones_at_weave_distance() {
        let ex = ExerciseSpec::from_name("lane-change")
            .unwrap()
            .build()
            .unwrap();
        let road = ex.road.as_ref().unwrap();
        let ([_, y], h, _) = road.centre(LEAD_IN_M + 31.0);
        assert!((y - 3.5).abs() < 1e-6 && h.abs() < 1e-9, "y={y}");
        let sl = ExerciseSpec::from_name("slalom").unwrap().build().unwrap();
        let road = sl.road.as_ref().unwrap();
        for c in &sl.cones {
            let p = road.project(c[0], c[1], c[0]);
            assert!((p.lateral_m.abs() - 1.5).abs() < 1e-6, "{p:?}");
        }
        assert_eq!(sl.track_layout().cones.len(), 8);
    }

    #[test]
    fn speed_profile_slows_for_sharp_turns_and_brakes_ahead() {
        let ex = ExerciseSpec::from_name("sharp-turns")
            .unwrap()
            .build()
            .unwrap();
        let in_turn = ex.target_speed_m_s(LEAD_IN_M + 5.0);
        assert!((in_turn - (3.0f64 * 15.0).sqrt()).abs() < 1e-9);
        assert_eq!(ex.target_speed_m_s(0.0), 10.0);
        let before = ex.target_speed_m_s(LEAD_IN_M - 3.0);
        assert!(before > in_turn && before < 10.0);
        assert!(!ex.is_finished(10.0, 5.0) && ex.is_finished(10.0, ex.length_m));
    }

    #[test]
    fn a_haptic_sweep_splits_into_one_dial_per_level_and_refuses_levels_out_of_bounds() {
        let toml_text = "kind = \"haptic-sweep\"\nparameter = \"frequency\"\nlevels = [0.5, 1.5, 2.5]\nlevel_s = 4.0\n";
        let spec: ExerciseSpec = toml::from_str(toml_text).unwrap();
        let ExerciseSpec::HapticSweep(sweep) = &spec else {
            panic!("{spec:?}")
        };
        assert_eq!(spec.build().unwrap().planned_duration_s(), 12.0);
        let parts = sweep.split();
        assert_eq!(parts.len(), 3);
        for (part, want) in parts.iter().zip([0.5, 1.5, 2.5]) {
            let ex = ExerciseSpec::HapticSweep(part.clone()).build().unwrap();
            assert_eq!(ex.planned_duration_s(), 4.0);
            assert_eq!(ex.sweep().unwrap().level, want);
            assert_eq!(ex.sweep().unwrap().parameter, SweepParameter::Frequency);
            // The needle swings at the level's frequency: a quarter period to its peak.
            let peak = ex
                .desired_angle_rad(std::f64::consts::FRAC_PI_2 / want)
                .unwrap();
            assert!((peak.to_degrees() - 120.0).abs() < 1e-9, "{peak}");
        }
        // The levels share a prescribed duration.
        let shared = spec.with_duration_s(30.0);
        assert_eq!(shared.build().unwrap().planned_duration_s(), 30.0);
        for bad in [
            "levels = [0.5, 11.0]",
            "levels = []",
            "levels = [-0.1]",
            "level_s = 0.5",
            "amplitude_deg = 130.0",
        ] {
            let text = format!("kind = \"haptic-sweep\"\nparameter = \"frequency\"\n{bad}\n");
            let spec: ExerciseSpec = toml::from_str(&text).unwrap();
            let msg = spec.validate().unwrap_err().to_string();
            let field = bad.split(' ').next().unwrap();
            assert!(
                msg.contains(field) && msg.contains("haptic-sweep"),
                "{bad}: {msg}"
            );
        }
        // A spring's level has the haptic model's bound (checked by the regimen), not the dial's.
        let stiff: ExerciseSpec =
            toml::from_str("kind = \"haptic-sweep\"\nlevels = [0.0, 50.0]\n").unwrap();
        stiff.validate().unwrap();
    }

    #[test]
    fn a_strength_test_shares_its_duration_between_its_sides_within_their_bounds() {
        let spec = ExerciseSpec::from_name("strength").unwrap();
        let ex = spec.with_duration_s(33.0).build().unwrap();
        assert_eq!(ex.planned_duration_s(), 33.0);
        assert_eq!(ex.strength().unwrap().side_s, 15.0);
        // A side is at most a minute: a longer prescription is capped.
        let long = spec.with_duration_s(600.0).build().unwrap();
        assert_eq!(long.strength().unwrap().side_s, SIDE_S.max);
        let soft = ExerciseSpec::Strength(StrengthSpec {
            stiffness_nm_per_rad: 1.0,
            ..Default::default()
        });
        let err = soft.validate().unwrap_err().to_string();
        assert!(
            err.contains("stiffness_nm_per_rad") && err.contains("N·m/rad"),
            "{err}"
        );
    }

    /// A lane change's shifts are where its centre line starts to bend towards the other
    /// lane, one per change (repetitions included), alternating left and right; the stepping
    /// dial's jumps are steps, and the strength test's side changes and smooth targets none.
    #[test]
    fn lane_shifts_start_where_the_lane_bends_and_only_stepping_targets_have_steps() {
        let spec = ExerciseSpec::from_name("lane-change").unwrap();
        let ExerciseSpec::LaneChange(lc) = &spec else {
            unreachable!()
        };
        let count = lc.count;
        for (spec, reps) in [(spec.clone(), 1), (spec.with_duration_s(120.0), 0)] {
            let ex = spec.build().unwrap();
            let TargetSteps::LaneShifts(shifts) = ex.target_steps() else {
                panic!("{:?}", ex.target_steps())
            };
            if reps == 1 {
                assert_eq!(shifts.len(), count as usize);
            } else {
                assert!(shifts.len() > count as usize, "{}", shifts.len());
            }
            let road = ex.road.as_ref().unwrap();
            for (k, sh) in shifts.iter().enumerate() {
                let (_, _, before) = road.centre(sh.s_m - 0.5);
                let (_, _, after) = road.centre(sh.s_m + 0.5);
                assert!(before.abs() < 1e-9, "shift {k}: straight before, {before}");
                assert_eq!(after.signum(), sh.direction, "shift {k}");
                assert_eq!(sh.direction, if k % 2 == 0 { 1.0 } else { -1.0 });
                assert!(sh.s_m < ex.length_m);
            }
        }
        let steps = |name: &str| {
            ExerciseSpec::from_name(name)
                .unwrap()
                .build()
                .unwrap()
                .steps
        };
        assert_eq!(steps("dial-step"), TargetSteps::Jumps);
        for name in ["strength", "dial-sine", "dial-ramp", "sine-road", "slalom"] {
            assert_eq!(steps(name), TargetSteps::None, "{name}");
        }
    }

    #[test]
    fn the_protocol_builds_every_part_from_existing_exercises_in_three_to_five_minutes() {
        let parts = ExerciseSpec::assessment_protocol(42);
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
        assert!(
            text.contains("kind = \"assessment\"") && text.contains("seed = 42"),
            "{text}"
        );
        let back: ExerciseSpec = toml::from_str(&text).unwrap();
        assert_eq!(back, parts[4]);
    }

    #[test]
    fn the_steps_follow_the_seed_and_an_unknown_protocol_is_refused_by_name() {
        let steps = |seed| {
            ExerciseSpec::Assessment(AssessmentSpec {
                protocol: A::PROTOCOL_VERSION,
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
            .map(|i| {
                a.desired_angle_rad(f64::from(i) * 0.1)
                    .unwrap()
                    .to_degrees()
                    .abs()
            })
            .fold(0.0, f64::max);
        assert!((size - A::STEP_DEG).abs() < 1e-9, "{size}");
        let old = ExerciseSpec::Assessment(AssessmentSpec {
            protocol: 0,
            ..Default::default()
        });
        let msg = old.validate().unwrap_err().to_string();
        assert!(
            msg.contains("protocol") && msg.contains("assessment-range"),
            "{msg}"
        );
    }
}
