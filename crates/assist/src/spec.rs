//! The serde-deserialisable description of an exercise's assist, as a regimen carries it.
//!
//! ```toml
//! [model]                      # optional; defaults: consumer wheel + relaxed arm
//! wheel = { inertia_kg_m2 = 0.02, damping_nm_s_per_rad = 0.02, stiffness_nm_per_rad = 0.0 }
//! arm = { inertia_kg_m2 = 0.1, damping_nm_s_per_rad = 0.3, stiffness_nm_per_rad = 0.1 }
//!
//! [mode]
//! kind = "motion"              # none | resist | motion | force | hybrid | assist_as_needed
//! authority = 0.8
//! ```

use crate::error::{AssistError, check_range};
use crate::model::{POLE_RAD_S, PlantParams, gains_for_poles};
use common::Bound;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Every angle of a mode (`center_rad`, `lower_rad`, `upper_rad`), rad.
pub const ANGLE_RAD: Bound = Bound::new(-PI, PI);
/// Resist: `spring_nm_per_rad`, N·m/rad.
pub const RESIST_SPRING_NM_PER_RAD: Bound = Bound::new(0.0, 20.0);
/// Resist: `damper_nm_s_per_rad`, N·m·s/rad.
pub const RESIST_DAMPER_NM_S_PER_RAD: Bound = Bound::new(0.0, 2.0);
/// Resist: `inertia_kg_m2`, kg·m².
pub const RESIST_INERTIA_KG_M2: Bound = Bound::new(0.0, 0.1);
/// Motion: `authority` (a fraction of the ceiling, above 0).
pub const AUTHORITY: Bound = Bound::new(1e-3, 1.0);
/// Motion: `governor_budget`.
pub const GOVERNOR_BUDGET: Bound = Bound::new(0.1, 1.0);
/// `governor_bandwidth_rad_s` of motion and force, rad/s.
pub const GOVERNOR_BANDWIDTH_RAD_S: Bound = Bound::new(0.5, 100.0);
/// Force: `fraction`.
pub const FORCE_FRACTION: Bound = Bound::new(0.0, 1.0);
/// Force: `bias_nm`, N·m.
pub const FORCE_BIAS_NM: Bound = Bound::new(-5.0, 5.0);
/// The force-loop gain (`gain_per_s`, `force_gain_per_s`), 1/s.
pub const FORCE_GAIN_PER_S: Bound = Bound::new(0.5, 500.0);
/// Hybrid: `contact_nm`, N·m.
pub const CONTACT_NM: Bound = Bound::new(0.0, 5.0);
/// Hybrid: `blend_rad`, rad.
pub const BLEND_RAD: Bound = Bound::new(0.005, 0.5);
/// Assist as needed: `period_s`, s.
pub const AAN_PERIOD_S: Bound = Bound::new(0.5, 120.0);
/// Assist as needed: `bins`.
pub const AAN_BINS: Bound = Bound::new(4.0, 256.0);
/// Assist as needed: `forgetting`.
pub const AAN_FORGETTING: Bound = Bound::new(0.0, 0.99);
/// Assist as needed: `gain_nm_per_rad`, N·m/rad.
pub const AAN_GAIN_NM_PER_RAD: Bound = Bound::new(0.0, 50.0);
/// Assist as needed: `feedback_nm_per_rad`, N·m/rad.
pub const AAN_FEEDBACK_NM_PER_RAD: Bound = Bound::new(0.0, 5.0);

/// Which assist an exercise uses, and the assist's parameters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct AssistSpec {
    /// The plant the model-based controllers are designed for.
    #[serde(default)]
    pub model: ModelSpec,
    /// The assist mode and its parameters.
    pub mode: AssistMode,
}

/// Wheel and arm as seen at the steering axis (eq. 5.5 and 5.6; combined by eq. 5.7).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct ModelSpec {
    /// Rim + motor: J₁, B₁, C₁.
    pub wheel: PlantParams,
    /// The patient's arm reflected to the wheel: J₂, B₂, C₂.
    pub arm: PlantParams,
}

impl Default for ModelSpec {
    fn default() -> Self {
        Self {
            wheel: PlantParams::CONSUMER_WHEEL,
            arm: PlantParams::RELAXED_ARM,
        }
    }
}

impl ModelSpec {
    /// The combined plant of eq. 5.7.
    pub fn total(&self) -> PlantParams {
        self.wheel.coupled_with(&self.arm)
    }

    /// Check both plants' ranges.
    pub fn validate(&self) -> Result<(), AssistError> {
        self.wheel.validate([
            "model.wheel.inertia_kg_m2",
            "model.wheel.damping_nm_s_per_rad",
            "model.wheel.stiffness_nm_per_rad",
        ])?;
        self.arm.validate([
            "model.arm.inertia_kg_m2",
            "model.arm.damping_nm_s_per_rad",
            "model.arm.stiffness_nm_per_rad",
        ])
    }
}

/// The assist modes a regimen can pick per exercise.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum AssistMode {
    /// No assist: zero torque. (A struct variant so that stray parameters are rejected.)
    None {},
    /// Spring, damper and inertia against the motion.
    Resist(ResistParams),
    /// Linearising motion assist tracking the (governed) reference.
    Motion(MotionParams),
    /// Force assist: deliver a fraction of the arm's torque demand, position not controlled.
    Force(ForceParams),
    /// Motion in the free range, force regulation at the exercise's constraint.
    Hybrid(HybridParams),
    /// Error-based learned help with forgetting.
    AssistAsNeeded(AanParams),
}

/// Parameters of [`AssistMode::Resist`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct ResistParams {
    /// Virtual spring `K`, N·m/rad, in [0, 20].
    #[schemars(range(min = RESIST_SPRING_NM_PER_RAD.min, max = RESIST_SPRING_NM_PER_RAD.max))]
    pub spring_nm_per_rad: f64,
    /// Virtual damper `B_v`, N·m·s/rad, in [0, 2].
    #[schemars(range(min = RESIST_DAMPER_NM_S_PER_RAD.min, max = RESIST_DAMPER_NM_S_PER_RAD.max))]
    pub damper_nm_s_per_rad: f64,
    /// Virtual inertia `M`, kg·m², in [0, 0.1] (at most ~5× a consumer rim).
    #[schemars(range(min = RESIST_INERTIA_KG_M2.min, max = RESIST_INERTIA_KG_M2.max))]
    pub inertia_kg_m2: f64,
    /// Spring rest angle, rad, in [−π, π].
    #[schemars(range(min = ANGLE_RAD.min, max = ANGLE_RAD.max))]
    pub center_rad: f64,
}

impl Default for ResistParams {
    fn default() -> Self {
        Self {
            spring_nm_per_rad: 0.5,
            damper_nm_s_per_rad: 0.1,
            inertia_kg_m2: 0.0,
            center_rad: 0.0,
        }
    }
}

/// Parameters of [`AssistMode::Motion`] (also the motion part of [`AssistMode::Hybrid`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct MotionParams {
    /// Closed-loop poles of the linearised error dynamics, rad/s, each in [−500, −0.1]
    /// (Table 5.1: −10, −20, −30 give K = 6000, 1100, 60).
    #[schemars(inner(range(min = POLE_RAD_S.min, max = POLE_RAD_S.max)))]
    pub poles_rad_s: [f64; 3],
    /// Fraction of the torque ceiling the assist may use, in (0, 1].
    #[schemars(range(min = AUTHORITY.min, max = AUTHORITY.max))]
    pub authority: f64,
    /// Fraction of the (authority-scaled) limits the reference governor plans with, in
    /// [0.1, 1]; the rest is left to feedback.
    #[schemars(range(min = GOVERNOR_BUDGET.min, max = GOVERNOR_BUDGET.max))]
    pub governor_budget: f64,
    /// Bandwidth of the reference governor, rad/s, in [0.5, 100].
    #[schemars(range(min = GOVERNOR_BANDWIDTH_RAD_S.min, max = GOVERNOR_BANDWIDTH_RAD_S.max))]
    pub governor_bandwidth_rad_s: f64,
}

impl Default for MotionParams {
    fn default() -> Self {
        Self {
            poles_rad_s: [-10.0, -20.0, -30.0],
            authority: 1.0,
            governor_budget: 0.8,
            governor_bandwidth_rad_s: 10.0,
        }
    }
}

impl MotionParams {
    fn validate(&self) -> Result<(), AssistError> {
        gains_for_poles(self.poles_rad_s)?;
        check_range(
            "motion.authority",
            self.authority,
            AUTHORITY.min,
            AUTHORITY.max,
            "(0, 1]",
        )?;
        check_range(
            "motion.governor_budget",
            self.governor_budget,
            GOVERNOR_BUDGET.min,
            GOVERNOR_BUDGET.max,
            "[0.1, 1]",
        )?;
        check_range(
            "motion.governor_bandwidth_rad_s",
            self.governor_bandwidth_rad_s,
            GOVERNOR_BANDWIDTH_RAD_S.min,
            GOVERNOR_BANDWIDTH_RAD_S.max,
            "[0.5, 100] rad/s",
        )
    }
}

/// Parameters of [`AssistMode::Force`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct ForceParams {
    /// Fraction of the arm's own torque demand `J₂ r̈ + B₂ ṙ + C₂ r` along the (governed)
    /// reference that the wheel delivers to the hand, in [0, 1].
    #[schemars(range(min = FORCE_FRACTION.min, max = FORCE_FRACTION.max))]
    pub fraction: f64,
    /// Constant extra hand torque, N·m, in [−5, 5] (isotonic loading or help).
    #[schemars(range(min = FORCE_BIAS_NM.min, max = FORCE_BIAS_NM.max))]
    pub bias_nm: f64,
    /// Force-loop gain `K_f` of eq. 5.40, 1/s, in [0.5, 500].
    #[schemars(range(min = FORCE_GAIN_PER_S.min, max = FORCE_GAIN_PER_S.max))]
    pub gain_per_s: f64,
    /// Bandwidth of the reference governor, rad/s, in [0.5, 100].
    #[schemars(range(min = GOVERNOR_BANDWIDTH_RAD_S.min, max = GOVERNOR_BANDWIDTH_RAD_S.max))]
    pub governor_bandwidth_rad_s: f64,
}

impl Default for ForceParams {
    fn default() -> Self {
        Self {
            fraction: 0.5,
            bias_nm: 0.0,
            gain_per_s: 50.0,
            governor_bandwidth_rad_s: 10.0,
        }
    }
}

impl ForceParams {
    fn validate(&self) -> Result<(), AssistError> {
        check_range(
            "force.fraction",
            self.fraction,
            FORCE_FRACTION.min,
            FORCE_FRACTION.max,
            "[0, 1]",
        )?;
        check_range(
            "force.bias_nm",
            self.bias_nm,
            FORCE_BIAS_NM.min,
            FORCE_BIAS_NM.max,
            "[-5, 5] N·m",
        )?;
        check_range(
            "force.gain_per_s",
            self.gain_per_s,
            FORCE_GAIN_PER_S.min,
            FORCE_GAIN_PER_S.max,
            "[0.5, 500] 1/s",
        )?;
        check_range(
            "force.governor_bandwidth_rad_s",
            self.governor_bandwidth_rad_s,
            GOVERNOR_BANDWIDTH_RAD_S.min,
            GOVERNOR_BANDWIDTH_RAD_S.max,
            "[0.5, 100] rad/s",
        )
    }
}

/// Parameters of [`AssistMode::Hybrid`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct HybridParams {
    /// Lower end of the free range, rad, in [−π, π].
    #[schemars(range(min = ANGLE_RAD.min, max = ANGLE_RAD.max))]
    pub lower_rad: f64,
    /// Upper end of the free range, rad, in [−π, π], above `lower_rad`.
    #[schemars(range(min = ANGLE_RAD.min, max = ANGLE_RAD.max))]
    pub upper_rad: f64,
    /// Hand torque regulated at the constraint, pushing back into the free range, N·m, in
    /// [0, 5].
    #[schemars(range(min = CONTACT_NM.min, max = CONTACT_NM.max))]
    pub contact_nm: f64,
    /// Width of the band beyond the constraint over which motion hands over to force, rad,
    /// in [0.005, 0.5].
    #[schemars(range(min = BLEND_RAD.min, max = BLEND_RAD.max))]
    pub blend_rad: f64,
    /// Force-loop gain `K_f` of eq. 5.40, 1/s, in [0.5, 500].
    #[schemars(range(min = FORCE_GAIN_PER_S.min, max = FORCE_GAIN_PER_S.max))]
    pub force_gain_per_s: f64,
    /// The motion part.
    pub motion: MotionParams,
}

impl Default for HybridParams {
    fn default() -> Self {
        Self {
            lower_rad: -0.5,
            upper_rad: 0.5,
            contact_nm: 0.5,
            blend_rad: 0.05,
            force_gain_per_s: 50.0,
            motion: MotionParams::default(),
        }
    }
}

impl HybridParams {
    fn validate(&self) -> Result<(), AssistError> {
        check_range(
            "hybrid.lower_rad",
            self.lower_rad,
            ANGLE_RAD.min,
            ANGLE_RAD.max,
            "[-π, π] rad",
        )?;
        check_range(
            "hybrid.upper_rad",
            self.upper_rad,
            ANGLE_RAD.min,
            ANGLE_RAD.max,
            "[-π, π] rad",
        )?;
        if self.upper_rad <= self.lower_rad {
            return Err(AssistError::Inconsistent(
                "hybrid.upper_rad must be above hybrid.lower_rad",
            ));
        }
        check_range(
            "hybrid.contact_nm",
            self.contact_nm,
            CONTACT_NM.min,
            CONTACT_NM.max,
            "[0, 5] N·m",
        )?;
        check_range(
            "hybrid.blend_rad",
            self.blend_rad,
            BLEND_RAD.min,
            BLEND_RAD.max,
            "[0.005, 0.5] rad",
        )?;
        check_range(
            "hybrid.force_gain_per_s",
            self.force_gain_per_s,
            FORCE_GAIN_PER_S.min,
            FORCE_GAIN_PER_S.max,
            "[0.5, 500] 1/s",
        )?;
        self.motion.validate()
    }
}

/// Parameters of [`AssistMode::AssistAsNeeded`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct AanParams {
    /// Length of one repetition, s, in [0.5, 120].
    #[schemars(range(min = AAN_PERIOD_S.min, max = AAN_PERIOD_S.max))]
    pub period_s: f64,
    /// Phase bins per repetition, in [4, 256].
    #[schemars(range(min = AAN_BINS.min, max = AAN_BINS.max))]
    pub bins: usize,
    /// Forgetting factor `f`, in [0, 0.99] (must be below the patient's retention).
    #[schemars(range(min = AAN_FORGETTING.min, max = AAN_FORGETTING.max))]
    pub forgetting: f64,
    /// Learning gain `g`, N·m/rad, in [0, 50].
    #[schemars(range(min = AAN_GAIN_NM_PER_RAD.min, max = AAN_GAIN_NM_PER_RAD.max))]
    pub gain_nm_per_rad: f64,
    /// Phase lead `L` of the update, bins, in [0, bins/2].
    #[schemars(range(min = 0))]
    pub lead_bins: usize,
    /// Compliant feedback `K_fb`, N·m/rad, in [0, 5].
    #[schemars(range(min = AAN_FEEDBACK_NM_PER_RAD.min, max = AAN_FEEDBACK_NM_PER_RAD.max))]
    pub feedback_nm_per_rad: f64,
}

impl Default for AanParams {
    fn default() -> Self {
        Self {
            period_s: 4.0,
            bins: 40,
            forgetting: 0.8,
            gain_nm_per_rad: 1.0,
            lead_bins: 2,
            feedback_nm_per_rad: 1.0,
        }
    }
}

impl AanParams {
    fn validate(&self) -> Result<(), AssistError> {
        check_range(
            "assist_as_needed.period_s",
            self.period_s,
            AAN_PERIOD_S.min,
            AAN_PERIOD_S.max,
            "[0.5, 120] s",
        )?;
        check_range(
            "assist_as_needed.bins",
            self.bins as f64,
            AAN_BINS.min,
            AAN_BINS.max,
            "[4, 256]",
        )?;
        check_range(
            "assist_as_needed.forgetting",
            self.forgetting,
            AAN_FORGETTING.min,
            AAN_FORGETTING.max,
            "[0, 0.99]",
        )?;
        check_range(
            "assist_as_needed.gain_nm_per_rad",
            self.gain_nm_per_rad,
            AAN_GAIN_NM_PER_RAD.min,
            AAN_GAIN_NM_PER_RAD.max,
            "[0, 50] N·m/rad",
        )?;
        check_range(
            "assist_as_needed.lead_bins",
            self.lead_bins as f64,
            0.0,
            (self.bins / 2) as f64,
            "[0, bins/2]",
        )?;
        check_range(
            "assist_as_needed.feedback_nm_per_rad",
            self.feedback_nm_per_rad,
            AAN_FEEDBACK_NM_PER_RAD.min,
            AAN_FEEDBACK_NM_PER_RAD.max,
            "[0, 5] N·m/rad",
        )
    }
}

impl ResistParams {
    fn validate(&self) -> Result<(), AssistError> {
        check_range(
            "resist.spring_nm_per_rad",
            self.spring_nm_per_rad,
            RESIST_SPRING_NM_PER_RAD.min,
            RESIST_SPRING_NM_PER_RAD.max,
            "[0, 20] N·m/rad",
        )?;
        check_range(
            "resist.damper_nm_s_per_rad",
            self.damper_nm_s_per_rad,
            RESIST_DAMPER_NM_S_PER_RAD.min,
            RESIST_DAMPER_NM_S_PER_RAD.max,
            "[0, 2] N·m·s/rad",
        )?;
        check_range(
            "resist.inertia_kg_m2",
            self.inertia_kg_m2,
            RESIST_INERTIA_KG_M2.min,
            RESIST_INERTIA_KG_M2.max,
            "[0, 0.1] kg·m²",
        )?;
        check_range(
            "resist.center_rad",
            self.center_rad,
            ANGLE_RAD.min,
            ANGLE_RAD.max,
            "[-π, π] rad",
        )
    }
}

impl AssistSpec {
    /// Check every field; the error names the field and its allowed range.
    pub fn validate(&self) -> Result<(), AssistError> {
        self.model.validate()?;
        match &self.mode {
            AssistMode::None {} => Ok(()),
            AssistMode::Resist(p) => p.validate(),
            AssistMode::Motion(p) => p.validate(),
            AssistMode::Force(p) => p.validate(),
            AssistMode::Hybrid(p) => p.validate(),
            AssistMode::AssistAsNeeded(p) => p.validate(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn motion_spec_parses_from_toml_with_defaults() {
        let spec: AssistSpec = toml::from_str(
            r#"
            [mode]
            kind = "motion"
            authority = 0.8
            "#,
        )
        .unwrap();
        spec.validate().unwrap();
        match spec.mode {
            AssistMode::Motion(p) => {
                assert_eq!(p.authority, 0.8);
                assert_eq!(p.poles_rad_s, [-10.0, -20.0, -30.0]);
            }
            other => panic!("{other:?}"),
        }
        assert_eq!(spec.model, ModelSpec::default());
    }

    #[test]
    fn every_mode_round_trips_through_toml() {
        for mode in [
            AssistMode::None {},
            AssistMode::Resist(ResistParams::default()),
            AssistMode::Motion(MotionParams::default()),
            AssistMode::Force(ForceParams::default()),
            AssistMode::Hybrid(HybridParams::default()),
            AssistMode::AssistAsNeeded(AanParams::default()),
        ] {
            let spec = AssistSpec {
                model: ModelSpec::default(),
                mode,
            };
            spec.validate().unwrap();
            let text = toml::to_string(&spec).unwrap();
            let back: AssistSpec = toml::from_str(&text).unwrap();
            assert_eq!(back, spec, "{text}");
        }
    }

    #[test]
    fn unknown_fields_are_rejected() {
        let r: Result<AssistSpec, _> = toml::from_str(
            r#"
            [mode]
            kind = "motion"
            authorty = 0.8
            "#,
        );
        assert!(r.unwrap_err().to_string().contains("authorty"));
        let r: Result<AssistSpec, _> = toml::from_str(
            r#"
            colour = 1
            [mode]
            kind = "none"
            "#,
        );
        assert!(r.is_err());
        let r: Result<AssistSpec, _> = toml::from_str(
            r#"
            [mode]
            kind = "none"
            spring_nm_per_rad = 3.0
            "#,
        );
        assert!(
            r.is_err(),
            "parameters given to `none` must not be ignored silently"
        );
        let r: Result<AssistSpec, _> = toml::from_str(
            r#"
            [mode]
            kind = "turbo"
            "#,
        );
        assert!(r.unwrap_err().to_string().contains("turbo"));
    }

    #[test]
    fn out_of_range_values_name_field_and_range() {
        let spec = AssistSpec {
            model: ModelSpec::default(),
            mode: AssistMode::AssistAsNeeded(AanParams {
                forgetting: 1.0,
                ..Default::default()
            }),
        };
        let e = spec.validate().unwrap_err().to_string();
        assert!(
            e.contains("assist_as_needed.forgetting") && e.contains("[0, 0.99]"),
            "{e}"
        );
        let spec = AssistSpec {
            model: ModelSpec {
                arm: PlantParams {
                    inertia_kg_m2: f64::NAN,
                    ..PlantParams::RELAXED_ARM
                },
                ..Default::default()
            },
            mode: AssistMode::None {},
        };
        let e = spec.validate().unwrap_err().to_string();
        assert!(e.contains("model.arm.inertia_kg_m2"), "{e}");
    }
}
