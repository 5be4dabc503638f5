//! Thesis Appendix E's haptic parameter studies: the dial's sine tracked for a while at each
//! of a few levels of the haptic model's spring `K`, damper `B` or inertia `I` (or of the
//! sine's frequency), the tracking error plotted against the level.
//!
//! A [`crate::exercise::HapticSweepSpec`] is prescribed as one regimen exercise
//! (`kind = "haptic-sweep"`) and run as one dial exercise per level
//! ([`crate::exercise::HapticSweepSpec::split`]), each with its own haptic model, so every
//! level passes through the same haptic chain and torque ceiling as any exercise.
//! [`error_slope`] is the trend the thesis looked for (none with K, B, I; rising with
//! frequency).

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// What a haptic sweep varies from level to level.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum SweepParameter {
    /// The haptic model's spring K, levels in N·m/rad.
    Spring,
    /// The haptic model's damper B, levels in N·m·s/rad.
    Damper,
    /// The haptic model's virtual inertia I, levels in kg·m².
    Inertia,
    /// The sine's frequency, levels in rad/s (the haptic model as prescribed throughout).
    Frequency,
}

impl SweepParameter {
    /// Every parameter, in the order of Appendix E's figures.
    pub const ALL: [SweepParameter; 4] = [
        SweepParameter::Spring,
        SweepParameter::Damper,
        SweepParameter::Inertia,
        SweepParameter::Frequency,
    ];

    /// Its short name (`spring`, `damper`, `inertia`, `frequency`).
    pub fn name(self) -> &'static str {
        match self {
            SweepParameter::Spring => "spring",
            SweepParameter::Damper => "damper",
            SweepParameter::Inertia => "inertia",
            SweepParameter::Frequency => "frequency",
        }
    }

    /// The levels' unit as written in names (`nm_per_rad`, `nm_s_per_rad`, `kg_m2`, `rad_s`).
    pub fn unit_key(self) -> &'static str {
        match self {
            SweepParameter::Spring => "nm_per_rad",
            SweepParameter::Damper => "nm_s_per_rad",
            SweepParameter::Inertia => "kg_m2",
            SweepParameter::Frequency => "rad_s",
        }
    }

    /// The levels' unit as a reader writes it (`N·m/rad`, …).
    pub fn unit(self) -> &'static str {
        match self {
            SweepParameter::Spring => "N·m/rad",
            SweepParameter::Damper => "N·m·s/rad",
            SweepParameter::Inertia => "kg·m²",
            SweepParameter::Frequency => "rad/s",
        }
    }

    /// The name of an exercise's measure holding its level (`sweep_spring_nm_per_rad`).
    pub fn level_measure(self) -> String {
        format!("sweep_{}_{}", self.name(), self.unit_key())
    }

    /// The parameter whose level an exercise measure named `name` holds, if any.
    pub fn of_level_measure(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|p| p.level_measure() == name)
    }
}

/// One level of a sweep: the exercise that runs it knows what it varies and to what.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SweepLevel {
    /// What the sweep varies.
    pub parameter: SweepParameter,
    /// Its value during this exercise, in the parameter's unit.
    pub level: f64,
}

/// Least-squares slope of `error` against `level` over `points` (level, error), error units
/// per level unit; `None` with fewer than two distinct levels or a non-finite point.
pub fn error_slope(points: &[(f64, f64)]) -> Option<f64> {
    if points.iter().any(|(x, y)| !x.is_finite() || !y.is_finite()) {
        return None;
    }
    let n = points.len() as f64;
    let mean_x = points.iter().map(|p| p.0).sum::<f64>() / n;
    let mean_y = points.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = points.iter().map(|p| (p.0 - mean_x).powi(2)).sum();
    let sxy: f64 = points.iter().map(|p| (p.0 - mean_x) * (p.1 - mean_y)).sum();
    (points.len() >= 2 && sxx > 0.0).then(|| sxy / sxx)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_error_slope_is_the_least_squares_line_and_none_without_two_levels() {
        let line: Vec<(f64, f64)> = (0..5)
            .map(|i| (f64::from(i), 3.0 + 2.0 * f64::from(i)))
            .collect();
        assert!((error_slope(&line).unwrap() - 2.0).abs() < 1e-12);
        let flat = [(0.0, 3.0), (0.5, 3.2), (1.0, 3.0)];
        assert!(error_slope(&flat).unwrap().abs() < 1e-12);
        assert_eq!(error_slope(&[(1.0, 3.0)]), None);
        assert_eq!(error_slope(&[(1.0, 3.0), (1.0, 4.0)]), None);
        assert_eq!(error_slope(&[(0.0, 3.0), (1.0, f64::NAN)]), None);
    }

    #[test]
    fn each_parameter_names_its_level_measure_with_its_unit_and_reads_it_back() {
        assert_eq!(
            SweepParameter::Spring.level_measure(),
            "sweep_spring_nm_per_rad"
        );
        for p in SweepParameter::ALL {
            assert_eq!(
                SweepParameter::of_level_measure(&p.level_measure()),
                Some(p)
            );
        }
        assert_eq!(SweepParameter::of_level_measure("dial_rms_error_deg"), None);
    }
}
