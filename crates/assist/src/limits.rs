//! The haptic layer's actuator limits as the controllers see them.

use serde::{Deserialize, Serialize};

/// Torque ceiling and slew limit of the haptic layer (DESIGN.md safety invariant 1).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Limits {
    /// Largest torque magnitude the assist may command, N·m (thesis wheel: 1.87).
    pub ceiling_nm: f64,
    /// Largest rate of change of the commanded torque, N·m/s.
    pub slew_nm_per_s: f64,
}

impl Limits {
    /// Limits that can be trusted: a non-finite or negative value becomes 0, so that a bad
    /// limit can only make the output smaller, never larger.
    pub fn sanitised(self) -> Self {
        let clean = |x: f64| if x.is_finite() && x > 0.0 { x } else { 0.0 };
        Self {
            ceiling_nm: clean(self.ceiling_nm),
            slew_nm_per_s: clean(self.slew_nm_per_s),
        }
    }

    /// `true` when both limits are finite and non-negative.
    pub fn is_sane(&self) -> bool {
        self.ceiling_nm.is_finite()
            && self.ceiling_nm >= 0.0
            && self.slew_nm_per_s.is_finite()
            && self.slew_nm_per_s >= 0.0
    }

    /// Move from `previous_nm` towards `request_nm` within the slew limit over `dt_s`, then
    /// clamp to the ceiling. Returns the torque and whether either limit was active.
    pub fn apply(&self, previous_nm: f64, request_nm: f64, dt_s: f64) -> (f64, bool) {
        let max_step = self.slew_nm_per_s * dt_s;
        let slewed = request_nm.clamp(previous_nm - max_step, previous_nm + max_step);
        let out = slewed.clamp(-self.ceiling_nm, self.ceiling_nm);
        (out, out != request_nm)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_limits_sanitise_to_zero() {
        let l = Limits {
            ceiling_nm: f64::NAN,
            slew_nm_per_s: -3.0,
        }
        .sanitised();
        assert_eq!((l.ceiling_nm, l.slew_nm_per_s), (0.0, 0.0));
    }

    #[test]
    fn apply_respects_slew_then_ceiling() {
        let l = Limits {
            ceiling_nm: 1.0,
            slew_nm_per_s: 100.0,
        };
        assert_eq!(l.apply(0.0, 5.0, 0.001), (0.1, true));
        assert_eq!(l.apply(0.95, 5.0, 0.001), (1.0, true));
        assert_eq!(l.apply(0.5, 0.55, 0.001), (0.55, false));
    }
}
