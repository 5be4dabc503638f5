//! Reference governor: turns the raw desired angle into a trajectory the actuator can
//! deliver, and says honestly when the raw request was not deliverable.
//!
//! The shaped reference is the output of a *virtual copy of the nominal plant*
//! (eq. 5.7, `J r̈ + B ṙ + C r = τ_g`) driven by a torque `τ_g` that is itself kept inside a
//! fraction `η` of the ceiling and of the slew limit. Whatever the raw request, the shaped
//! trajectory is therefore one the nominal plant can follow with at most `η·ceiling`, leaving
//! `(1 − η)·ceiling` to the tracking feedback for model error and the patient's torque.
//! This is the "model-based reference shaping" family of reference governors (Garone,
//! Di Cairano & Kolmanovsky 2017, "Reference and command governors for systems with
//! constraints: a survey", Automatica 75) in its simplest, always-feasible form.
//!
//! `τ_g` tracks a computed-torque target `τ* = J a* + B ṙ + C r` with
//! `a* = d̈ + 2ζω(ḋ − ṙ) + ω²(d − r)`: with the raw request feasible and the governor
//! started on it, `a* = d̈` and the shaped reference equals the raw one.

use crate::limits::Limits;
use crate::model::PlantParams;
use crate::motion::DesiredMotion;
use serde::{Deserialize, Serialize};

/// Why a requested exercise could not be delivered as asked.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum Infeasibility {
    /// The raw reference needs more torque than the ceiling (`|J d̈ + B ḋ + C d| > ceiling`).
    TorqueCeiling,
    /// The raw reference needs the torque to change faster than the slew limit.
    SlewLimit,
    /// A sensor, reference, limit or `dt` was NaN/∞ (or `dt ≤ 0`): the assist went to the safe
    /// state.
    NonFiniteInput,
}

/// Time constant of the low-pass on the raw request's torque demand, s (keeps the
/// finite-difference estimate of `d̈` from flagging single-tick steps as "infeasible").
const DEMAND_FILTER_S: f64 = 0.02;

/// The governor's state.
#[derive(Clone, Debug)]
pub struct ReferenceGovernor {
    model: PlantParams,
    budget_fraction: f64,
    bandwidth_rad_s: f64,
    // shaped trajectory
    r: f64,
    r_dot: f64,
    r_ddot: f64,
    tau_g: f64,
    // raw request finite differences
    d_prev: f64,
    d_dot_prev: f64,
    demand_nm: f64,
    demand_prev_nm: f64,
    /// Raw samples seen since the last reset (saturates at 2).
    samples: u8,
}

/// One tick of the governor's output.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapedReference {
    /// The trajectory to track (angle, velocity, acceleration, jerk).
    pub motion: DesiredMotion,
    /// Nominal-model torque the shaped trajectory needs, N·m (`τ_g`).
    pub feedforward_nm: f64,
    /// Why the raw request was not deliverable this tick, if it was not.
    pub infeasible: Option<Infeasibility>,
}

impl ReferenceGovernor {
    /// A governor for `model`, using `budget_fraction` ∈ (0, 1] of the limits, with
    /// tracking bandwidth `bandwidth_rad_s` (critically damped).
    pub fn new(model: PlantParams, budget_fraction: f64, bandwidth_rad_s: f64) -> Self {
        Self {
            model,
            budget_fraction,
            bandwidth_rad_s,
            r: 0.0,
            r_dot: 0.0,
            r_ddot: 0.0,
            tau_g: 0.0,
            d_prev: 0.0,
            d_dot_prev: 0.0,
            demand_nm: 0.0,
            demand_prev_nm: 0.0,
            samples: 0,
        }
    }

    /// Restart from the measured state (`angle_rad`, `vel_rad_s`) with zero torque; the next
    /// raw sample re-seeds the finite differences.
    pub fn reset_to(&mut self, angle_rad: f64, vel_rad_s: f64) {
        self.r = angle_rad;
        self.r_dot = vel_rad_s;
        self.r_ddot = 0.0;
        self.tau_g = 0.0;
        self.samples = 0;
    }

    /// Shape one raw sample `raw_rad` under `limits` over `dt_s` (> 0, finite).
    pub fn step(&mut self, raw_rad: f64, limits: Limits, dt_s: f64) -> ShapedReference {
        let m = self.model;
        let (j, b, c) = (
            m.inertia_kg_m2,
            m.damping_nm_s_per_rad,
            m.stiffness_nm_per_rad,
        );
        let ceiling = self.budget_fraction * limits.ceiling_nm;
        let slew = self.budget_fraction * limits.slew_nm_per_s;
        if self.samples == 0 {
            self.d_prev = raw_rad;
            self.d_dot_prev = 0.0;
        }
        // Raw request derivatives (backward differences), bounded by what the full ceiling
        // could ever produce so that a step in the request does not inject 1e6 rad/s².
        let v_cap = if b > 0.0 {
            limits.ceiling_nm / b
        } else {
            f64::INFINITY
        }
        .min(100.0);
        let a_cap = limits.ceiling_nm / j;
        let d_dot = ((raw_rad - self.d_prev) / dt_s).clamp(-v_cap, v_cap);
        // The first difference of velocity needs two velocity samples.
        let d_ddot = if self.samples >= 2 {
            ((d_dot - self.d_dot_prev) / dt_s).clamp(-a_cap * 4.0, a_cap * 4.0)
        } else {
            0.0
        };
        self.d_prev = raw_rad;
        self.d_dot_prev = d_dot;
        if self.samples < 2 {
            self.demand_nm = m.inverse_dynamics(raw_rad, d_dot, d_ddot);
            self.demand_prev_nm = self.demand_nm;
            self.samples += 1;
        }

        // Honest infeasibility check on the raw request (low-passed demand).
        let raw_demand = m.inverse_dynamics(raw_rad, d_dot, d_ddot);
        let k = dt_s / (DEMAND_FILTER_S + dt_s);
        self.demand_nm += k * (raw_demand - self.demand_nm);
        let demand_rate = (self.demand_nm - self.demand_prev_nm) / dt_s;
        self.demand_prev_nm = self.demand_nm;
        let infeasible = if self.demand_nm.abs() > limits.ceiling_nm {
            Some(Infeasibility::TorqueCeiling)
        } else if demand_rate.abs() > limits.slew_nm_per_s {
            Some(Infeasibility::SlewLimit)
        } else {
            None
        };

        // Virtual plant driven by a limited computed torque.
        let w = self.bandwidth_rad_s;
        let a_star = d_ddot + 2.0 * w * (d_dot - self.r_dot) + w * w * (raw_rad - self.r);
        let tau_star = m
            .inverse_dynamics(self.r, self.r_dot, a_star)
            .clamp(-ceiling, ceiling);
        let tau_prev = self.tau_g;
        self.tau_g = (tau_prev + (tau_star - tau_prev).clamp(-slew * dt_s, slew * dt_s))
            .clamp(-ceiling, ceiling);
        let tau_rate = (self.tau_g - tau_prev) / dt_s;
        // Semi-implicit Euler on the virtual plant; the reported acceleration is the one at the
        // new state, so `J r̈ + B ṙ + C r = τ_g` holds exactly for what is handed out.
        self.r_dot += m.acceleration(self.r, self.r_dot, self.tau_g) * dt_s;
        self.r += self.r_dot * dt_s;
        self.r_ddot = m.acceleration(self.r, self.r_dot, self.tau_g);
        // Jerk of the virtual plant: d/dt of eq. 5.10's second row.
        let jerk = (tau_rate - b * self.r_ddot - c * self.r_dot) / j;
        ShapedReference {
            motion: DesiredMotion {
                angle_rad: self.r,
                vel_rad_s: self.r_dot,
                acc_rad_s2: self.r_ddot,
                jerk_rad_s3: jerk,
            },
            feedforward_nm: self.tau_g,
            infeasible,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const WHEEL_ARM: PlantParams = PlantParams {
        inertia_kg_m2: 0.12,
        damping_nm_s_per_rad: 0.32,
        stiffness_nm_per_rad: 0.1,
    };
    const LIMITS: Limits = Limits {
        ceiling_nm: 1.87,
        slew_nm_per_s: 50.0,
    };

    #[test]
    fn feasible_sine_passes_almost_unchanged() {
        let mut g = ReferenceGovernor::new(WHEEL_ARM, 0.8, 10.0);
        let w = 2.0 * std::f64::consts::PI * 0.25;
        let mut worst: f64 = 0.0;
        for i in 0..20_000 {
            let t = i as f64 * 0.001;
            let d = 0.7 * (w * t).sin();
            let s = g.step(d, LIMITS, 0.001);
            assert_eq!(s.infeasible, None, "t = {t}");
            if t > 2.0 {
                worst = worst.max((s.motion.angle_rad - d).abs());
            }
        }
        assert!(worst < 0.01, "worst deviation {worst} rad");
    }

    #[test]
    fn thesis_plant_30_degree_move_in_2_s_is_flagged_and_shaped_within_budget() {
        // FIELD-NOTES: the thesis plant needs ≈17.6 N·m for this move; the wheel gives 1.87.
        let mut g = ReferenceGovernor::new(PlantParams::THESIS, 0.8, 10.0);
        let target = 30f64.to_radians();
        let mut flagged = false;
        for i in 0..4000 {
            let t = i as f64 * 0.001;
            // minimum-jerk move over 2 s
            let s = (t / 2.0).min(1.0);
            let d = target * (10.0 * s.powi(3) - 15.0 * s.powi(4) + 6.0 * s.powi(5));
            let out = g.step(d, LIMITS, 0.001);
            flagged |= out.infeasible == Some(Infeasibility::TorqueCeiling);
            assert!(out.feedforward_nm.abs() <= 0.8 * 1.87 + 1e-12);
            let need = PlantParams::THESIS.inverse_dynamics(
                out.motion.angle_rad,
                out.motion.vel_rad_s,
                out.motion.acc_rad_s2,
            );
            assert!(
                need.abs() <= 0.8 * 1.87 + 1e-9,
                "shaped trajectory needs {need}"
            );
        }
        assert!(flagged);
    }

    #[test]
    fn fast_small_oscillation_is_flagged_as_a_slew_problem() {
        // 0.008 rad at 6.4 Hz needs ≈1.5 N·m (under the ceiling) changing at ≈60 N·m/s.
        let slow_slew = Limits {
            ceiling_nm: 1.87,
            slew_nm_per_s: 30.0,
        };
        let mut g = ReferenceGovernor::new(WHEEL_ARM, 0.8, 10.0);
        let (mut slew, mut ceiling) = (0, 0);
        for i in 0..5000 {
            let d = 0.008 * (40.0 * i as f64 * 0.001).sin();
            match g.step(d, slow_slew, 0.001).infeasible {
                Some(Infeasibility::SlewLimit) => slew += 1,
                Some(Infeasibility::TorqueCeiling) => ceiling += 1,
                _ => {}
            }
        }
        assert!(
            slew > 1000 && ceiling == 0,
            "slew {slew}, ceiling {ceiling}"
        );
    }

    #[test]
    fn step_request_is_shaped_within_slew_budget() {
        let mut g = ReferenceGovernor::new(WHEEL_ARM, 0.8, 10.0);
        let mut prev = 0.0;
        for i in 0..3000 {
            let d = if i < 10 { 0.0 } else { 1.0 };
            let out = g.step(d, LIMITS, 0.001);
            assert!((out.feedforward_nm - prev).abs() <= 0.8 * 50.0 * 0.001 + 1e-12);
            prev = out.feedforward_nm;
        }
        let last = g.step(1.0, LIMITS, 0.001);
        assert!((last.motion.angle_rad - 1.0).abs() < 1e-3, "{last:?}");
    }
}
