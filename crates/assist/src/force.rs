//! Force assist by input–output linearisation (thesis §5.4.2, eq. 5.34–5.40).
//!
//! With the torque as output (eq. 5.34) the relative degree is one (eq. 5.36) and the law is
//! `u = θ̇³_d + K_f (θ³_d − θ³)` (eq. 5.40), i.e. first-order tracking of the desired torque
//! with time constant `1/K_f`. Note: eq. 5.39 of the thesis picks `k = −1`, which puts the
//! root of `K(s) = s + k` at `s = +1` (unstable); eq. 5.40 with `K_f > 0` is the stable form
//! used here. The zero dynamics (eq. 5.37) are the passive plant, so the position is not
//! controlled and drifts (Fig. 5-6).
//!
//! On a real wheel there is no torque sensor, so the torque delivered to the hand has to be
//! estimated. Eq. 5.8, `τ_in = (1 − J₁/J) τ_act + (J₁B/J − B₁) θ̇ + (J₁C/J − C₁) θ`, gets the
//! acceleration from the combined model and so assumes the arm is *passive*: with an active
//! patient (the whole point) it is biased by `J₁/J·τ_h` (≈ 17 % of the hand torque for a
//! consumer rim and a relaxed arm). The controller therefore uses the rim's own balance,
//! eq. 5.5, `τ_in = τ_act − J₁θ̈ − B₁θ̇ − C₁θ`, quasi-statically: the `J₁θ̈` term is dropped
//! (no acceleration sensor; a differentiated, filtered velocity fed back with unit gain makes
//! an empty rim — hand off the wheel — marginally stable), which costs `J₁θ̈` ≈ 0.03 N·m at
//! the dial task's accelerations. [`ForceAssist::interaction_torque_passive_arm_nm`] keeps
//! eq. 5.8 for reference.

use crate::limits::Limits;
use crate::model::PlantParams;

/// Eq. 5.40: the torque rate that makes `measured_nm` track `desired_nm`, N·m/s.
pub fn force_law_rate(
    desired_nm: f64,
    desired_rate_nm_s: f64,
    measured_nm: f64,
    gain_per_s: f64,
) -> f64 {
    desired_rate_nm_s + gain_per_s * (desired_nm - measured_nm)
}

/// Force assist on a wheel of parameters `wheel` (J₁, B₁, C₁) coupled to an arm, combined
/// plant `total` (J, B, C of eq. 5.7). State: the actuator torque.
#[derive(Clone, Debug)]
pub struct ForceAssist {
    wheel: PlantParams,
    total: PlantParams,
    gain_per_s: f64,
    torque_state_nm: f64,
}

impl ForceAssist {
    /// A force controller with loop gain `gain_per_s` (`K_f` of eq. 5.40, 1/s).
    pub fn new(wheel: PlantParams, total: PlantParams, gain_per_s: f64) -> Self {
        Self {
            wheel,
            total,
            gain_per_s,
            torque_state_nm: 0.0,
        }
    }

    /// The actuator torque state, N·m.
    pub fn torque_state_nm(&self) -> f64 {
        self.torque_state_nm
    }

    /// Force the torque state to what the actuator really applied, N·m.
    pub fn track_applied(&mut self, applied_nm: f64) {
        self.torque_state_nm = applied_nm;
    }

    /// Torque delivered to the hand, quasi-static eq. 5.5 (`τ_act − B₁θ̇ − C₁θ`), N·m.
    pub fn interaction_torque_nm(&self, actuator_nm: f64, angle_rad: f64, vel_rad_s: f64) -> f64 {
        actuator_nm
            - self.wheel.damping_nm_s_per_rad * vel_rad_s
            - self.wheel.stiffness_nm_per_rad * angle_rad
    }

    /// Torque delivered to a *passive* arm by eq. 5.8 for actuator torque `actuator_nm`, N·m.
    pub fn interaction_torque_passive_arm_nm(
        &self,
        actuator_nm: f64,
        angle_rad: f64,
        vel_rad_s: f64,
    ) -> f64 {
        let r = self.wheel.inertia_kg_m2 / self.total.inertia_kg_m2;
        (1.0 - r) * actuator_nm
            + (r * self.total.damping_nm_s_per_rad - self.wheel.damping_nm_s_per_rad) * vel_rad_s
            + (r * self.total.stiffness_nm_per_rad - self.wheel.stiffness_nm_per_rad) * angle_rad
    }

    /// Actuator torque rate that drives the hand torque towards `desired_nm` (eq. 5.40 on
    /// the quasi-static eq. 5.5 estimate), N·m/s.
    pub fn rate_nm_per_s(
        &self,
        angle_rad: f64,
        vel_rad_s: f64,
        desired_nm: f64,
        desired_rate_nm_s: f64,
    ) -> f64 {
        let measured = self.interaction_torque_nm(self.torque_state_nm, angle_rad, vel_rad_s);
        force_law_rate(desired_nm, desired_rate_nm_s, measured, self.gain_per_s)
    }

    /// One saturation-aware tick (slew clamps the rate, the ceiling clamps the state): the
    /// actuator torque to apply, N·m.
    pub fn step(
        &mut self,
        angle_rad: f64,
        vel_rad_s: f64,
        desired_nm: f64,
        desired_rate_nm_s: f64,
        limits: Limits,
        dt_s: f64,
    ) -> f64 {
        let u = self
            .rate_nm_per_s(angle_rad, vel_rad_s, desired_nm, desired_rate_nm_s)
            .clamp(-limits.slew_nm_per_s, limits.slew_nm_per_s);
        self.torque_state_nm =
            (self.torque_state_nm + u * dt_s).clamp(-limits.ceiling_nm, limits.ceiling_nm);
        self.torque_state_nm
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ideal_wheel_estimate_is_the_actuator_torque() {
        let ideal = PlantParams {
            inertia_kg_m2: 0.0,
            damping_nm_s_per_rad: 0.0,
            stiffness_nm_per_rad: 0.0,
        };
        let f = ForceAssist::new(ideal, PlantParams::THESIS, 5.0);
        assert_eq!(f.interaction_torque_nm(1.3, 0.4, -2.0), 1.3);
    }

    #[test]
    fn passive_arm_receives_the_estimated_torque() {
        // Rigid wheel + arm under actuator torque: the hand torque is J₂θ̈ + B₂θ̇ + C₂θ.
        let wheel = PlantParams::CONSUMER_WHEEL;
        let arm = PlantParams::RELAXED_ARM;
        let total = wheel.coupled_with(&arm);
        let f = ForceAssist::new(wheel, total, 5.0);
        let (x, v, tau) = (0.3, -0.8, 0.9);
        let acc = total.acceleration(x, v, tau);
        let on_arm = arm.inverse_dynamics(x, v, acc);
        approx::assert_relative_eq!(
            f.interaction_torque_passive_arm_nm(tau, x, v),
            on_arm,
            max_relative = 1e-12
        );
    }
}
