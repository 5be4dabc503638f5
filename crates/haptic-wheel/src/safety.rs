//! The last stage of every torque path: magnitude ceiling, slew limit, non-finite rejection.

/// A torque after the safety chain.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LimitedTorque {
    /// The torque that may go to the motor, N·m.
    pub torque_nm: f64,
    /// The request was larger than the ceiling or changed faster than the slew limit.
    pub clipped: bool,
    /// The request was NaN or infinite and was replaced by a ramp towards zero.
    pub rejected_non_finite: bool,
}

/// Magnitude ceiling plus slew-rate limit (DESIGN.md safety invariant 1 and 2).
///
/// Non-finite requests are treated as a request for zero torque, so a NaN from any sensor or
/// model can never reach the motor.
#[derive(Clone, Debug)]
pub struct TorqueLimiter {
    ceiling_nm: f64,
    slew_nm_per_s: f64,
    last_nm: f64,
}

impl TorqueLimiter {
    /// A limiter with a ceiling `|τ| ≤ ceiling_nm` and slew `|dτ/dt| ≤ slew_nm_per_s`.
    /// Non-finite or negative limits are replaced by zero (the safe state: no torque).
    pub fn new(ceiling_nm: f64, slew_nm_per_s: f64) -> Self {
        let sane = |v: f64| if v.is_finite() && v > 0.0 { v } else { 0.0 };
        Self {
            ceiling_nm: sane(ceiling_nm),
            slew_nm_per_s: sane(slew_nm_per_s),
            last_nm: 0.0,
        }
    }

    /// The magnitude ceiling, N·m.
    pub fn ceiling_nm(&self) -> f64 {
        self.ceiling_nm
    }

    /// The last torque let through, N·m.
    pub fn last_nm(&self) -> f64 {
        self.last_nm
    }

    /// Limit `requested_nm` for a tick of `dt_s` seconds.
    pub fn apply(&mut self, requested_nm: f64, dt_s: f64) -> LimitedTorque {
        let rejected = !requested_nm.is_finite();
        let want = if rejected { 0.0 } else { requested_nm };
        let capped = want.clamp(-self.ceiling_nm, self.ceiling_nm);
        let dt = if dt_s.is_finite() && dt_s > 0.0 {
            dt_s
        } else {
            0.0
        };
        let max_step = self.slew_nm_per_s * dt;
        let out = capped.clamp(self.last_nm - max_step, self.last_nm + max_step);
        // Re-clamp: a ceiling lowered at run time must hold immediately.
        let out = out.clamp(-self.ceiling_nm, self.ceiling_nm);
        self.last_nm = out;
        LimitedTorque {
            torque_nm: out,
            clipped: out != want,
            rejected_non_finite: rejected,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #[test]
        fn output_never_exceeds_ceiling_or_slew(reqs in proptest::collection::vec(prop_oneof![
            any::<f64>(), -10.0f64..10.0, Just(f64::NAN), Just(f64::INFINITY)], 1..200)) {
            let mut lim = TorqueLimiter::new(1.87, 50.0);
            let mut last = 0.0;
            for r in reqs {
                let out = lim.apply(r, 0.001);
                prop_assert!(out.torque_nm.is_finite());
                prop_assert!(out.torque_nm.abs() <= 1.87);
                prop_assert!((out.torque_nm - last).abs() <= 50.0 * 0.001 + 1e-12);
                last = out.torque_nm;
            }
        }
    }

    #[test]
    fn nan_request_ramps_to_zero() {
        let mut lim = TorqueLimiter::new(1.87, 10.0);
        for _ in 0..500 {
            lim.apply(1.5, 0.001);
        }
        let out = lim.apply(f64::NAN, 0.001);
        assert!(out.rejected_non_finite);
        assert!((out.torque_nm - 1.49).abs() < 1e-9);
    }
}
