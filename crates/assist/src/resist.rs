//! Resistive modes for strong patients: a virtual spring, damper and inertia acting against
//! the motion (thesis §5.1.2 "active resist"), `τ = −K (θ − θ₀) − B_v θ̇ − M â`.
//!
//! Spring and damper are passive for any `K, B_v ≥ 0`. The inertia term needs an
//! acceleration estimate: here a first-order low-pass (time constant
//! [`ACCEL_FILTER_S`]) of the backward difference of the measured velocity. Rendering a large
//! virtual mass that way can go unstable on a real device, so the spec bounds `M` to a few
//! times the rim inertia (see `spec.rs`), and the output passes the same ceiling and slew
//! limits as every other mode.

/// Time constant of the acceleration estimate's low-pass, s.
pub const ACCEL_FILTER_S: f64 = 0.02;

/// Spring–damper–inertia resistance.
#[derive(Clone, Debug)]
pub struct Resist {
    spring_nm_per_rad: f64,
    damper_nm_s_per_rad: f64,
    inertia_kg_m2: f64,
    center_rad: f64,
    prev_vel: Option<f64>,
    acc_est: f64,
}

impl Resist {
    /// Resistance around `center_rad` with the given spring, damper and virtual inertia.
    pub fn new(
        spring_nm_per_rad: f64,
        damper_nm_s_per_rad: f64,
        inertia_kg_m2: f64,
        center_rad: f64,
    ) -> Self {
        Self {
            spring_nm_per_rad,
            damper_nm_s_per_rad,
            inertia_kg_m2,
            center_rad,
            prev_vel: None,
            acc_est: 0.0,
        }
    }

    /// Forget the acceleration estimate.
    pub fn reset(&mut self) {
        self.prev_vel = None;
        self.acc_est = 0.0;
    }

    /// The estimated acceleration, rad/s².
    pub fn acceleration_estimate(&self) -> f64 {
        self.acc_est
    }

    /// Resisting torque for the measured state, N·m (unclamped; the caller limits it).
    pub fn torque_nm(&mut self, angle_rad: f64, vel_rad_s: f64, dt_s: f64) -> f64 {
        if let Some(prev) = self.prev_vel {
            let raw = (vel_rad_s - prev) / dt_s;
            let k = dt_s / (ACCEL_FILTER_S + dt_s);
            self.acc_est += k * (raw - self.acc_est);
        }
        self.prev_vel = Some(vel_rad_s);
        -self.spring_nm_per_rad * (angle_rad - self.center_rad)
            - self.damper_nm_s_per_rad * vel_rad_s
            - self.inertia_kg_m2 * self.acc_est
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_element_acts_against_its_own_quantity() {
        let mut spring = Resist::new(2.0, 0.0, 0.0, 0.1);
        assert_eq!(spring.torque_nm(0.6, 0.0, 0.001), -1.0);
        let mut damper = Resist::new(0.0, 0.5, 0.0, 0.0);
        assert_eq!(damper.torque_nm(0.0, 2.0, 0.001), -1.0);
        let mut mass = Resist::new(0.0, 0.0, 0.05, 0.0);
        let mut tau = 0.0;
        for i in 0..1000 {
            // constant acceleration of 4 rad/s²
            tau = mass.torque_nm(0.0, 4.0 * i as f64 * 0.001, 0.001);
        }
        assert!((tau + 0.2).abs() < 1e-6, "{tau}");
    }
}
