//! A small fixed-step RK4 simulator of the wheel + arm plant `J θ̈ + B θ̇ + C θ + τ_c(θ̇) = τ`
//! (eq. 5.7 plus optional Coulomb friction), used by this crate's tests and benchmarks to
//! close the loop around the controllers, and the closed-loop dial-task harness
//! ([`run_dial_task`]: wheel + arm plant, simulated patient, assist) behind the figures in
//! BENCHMARKS.md. Pure: time comes in as `dt_s`.

use crate::error::AssistError;
use crate::human::{HumanArm, HumanArmParams};
use crate::limits::Limits;
use crate::model::PlantParams;
use crate::runtime::{Assist, Measurement};
use crate::spec::AssistSpec;

/// Plant state and parameters; the applied torque is held constant over each step (ZOH,
/// as a 1 kHz haptic loop does).
#[derive(Clone, Debug)]
pub struct Rk4Plant {
    params: PlantParams,
    coulomb_nm: f64,
    angle_rad: f64,
    vel_rad_s: f64,
}

/// Velocity scale of the smoothed Coulomb friction `τ_c = F·tanh(θ̇ / v₀)`, rad/s.
const COULOMB_SMOOTHING_RAD_S: f64 = 0.01;

impl Rk4Plant {
    /// A plant at rest at angle zero. `coulomb_nm` ≥ 0 adds dry friction.
    pub fn new(params: PlantParams, coulomb_nm: f64) -> Self {
        Self {
            params,
            coulomb_nm: coulomb_nm.max(0.0),
            angle_rad: 0.0,
            vel_rad_s: 0.0,
        }
    }

    /// Put the plant at `angle_rad`, `vel_rad_s`.
    pub fn set_state(&mut self, angle_rad: f64, vel_rad_s: f64) {
        self.angle_rad = angle_rad;
        self.vel_rad_s = vel_rad_s;
    }

    /// Angle, rad.
    pub fn angle_rad(&self) -> f64 {
        self.angle_rad
    }

    /// Angular velocity, rad/s.
    pub fn vel_rad_s(&self) -> f64 {
        self.vel_rad_s
    }

    /// Acceleration at the current state under `torque_nm`, rad/s².
    pub fn acceleration(&self, torque_nm: f64) -> f64 {
        self.deriv(self.angle_rad, self.vel_rad_s, torque_nm).1
    }

    fn deriv(&self, angle: f64, vel: f64, torque: f64) -> (f64, f64) {
        let friction = self.coulomb_nm * (vel / COULOMB_SMOOTHING_RAD_S).tanh();
        (vel, self.params.acceleration(angle, vel, torque - friction))
    }

    /// Advance by `dt_s` under the total torque `torque_nm` (motor + hand), classic RK4.
    pub fn step(&mut self, torque_nm: f64, dt_s: f64) {
        let (x, v) = (self.angle_rad, self.vel_rad_s);
        let k1 = self.deriv(x, v, torque_nm);
        let k2 = self.deriv(x + 0.5 * dt_s * k1.0, v + 0.5 * dt_s * k1.1, torque_nm);
        let k3 = self.deriv(x + 0.5 * dt_s * k2.0, v + 0.5 * dt_s * k2.1, torque_nm);
        let k4 = self.deriv(x + dt_s * k3.0, v + dt_s * k3.1, torque_nm);
        self.angle_rad = x + dt_s / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
        self.vel_rad_s = v + dt_s / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
    }
}

/// The dial task of the issue: follow `amplitude·sin(2π f t)` on the wheel.
#[derive(Clone, Debug, PartialEq)]
pub struct DialTask {
    /// Reference amplitude, rad (±40° in the issue).
    pub amplitude_rad: f64,
    /// Reference frequency, Hz (0.2–0.3 in the issue).
    pub frequency_hz: f64,
    /// Length of the run, s.
    pub duration_s: f64,
    /// Loop period, s.
    pub dt_s: f64,
    /// Haptic-layer limits handed to the assist.
    pub limits: Limits,
    /// Rim + motor.
    pub wheel: PlantParams,
    /// Patient's arm reflected to the wheel.
    pub arm: PlantParams,
    /// Coulomb friction of the rim, N·m.
    pub coulomb_nm: f64,
    /// Encoder resolution, rad (the measured angle is quantised to it; the measured velocity
    /// is a low-passed difference of the quantised angle, as a wheel driver reports it).
    pub encoder_step_rad: f64,
}

impl Default for DialTask {
    fn default() -> Self {
        Self {
            amplitude_rad: 40f64.to_radians(),
            frequency_hz: 0.25,
            duration_s: 60.0,
            dt_s: 0.001,
            limits: Limits {
                ceiling_nm: 1.87,
                slew_nm_per_s: 50.0,
            },
            wheel: PlantParams::CONSUMER_WHEEL,
            arm: PlantParams::RELAXED_ARM,
            coulomb_nm: 0.03,
            encoder_step_rad: 0.002253,
        }
    }
}

/// What a closed-loop dial run measured.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DialResult {
    /// RMS of `requested reference − true angle` over the run, rad.
    pub rms_error_rad: f64,
    /// RMS error per repetition (one reference period each), rad.
    pub rms_error_per_repetition_rad: Vec<f64>,
    /// Mean assistance level per repetition, 0–1.
    pub assistance_per_repetition: Vec<f64>,
    /// Largest |assist torque|, N·m.
    pub max_abs_torque_nm: f64,
    /// RMS assist torque, N·m.
    pub rms_torque_nm: f64,
    /// RMS hand torque, N·m.
    pub rms_hand_torque_nm: f64,
    /// Fraction of ticks on which a limit cut the torque.
    pub saturated_fraction: f64,
    /// Fraction of ticks on which the request was infeasible.
    pub infeasible_fraction: f64,
}

/// Time constant of the harness's velocity low-pass, s.
const VELOCITY_FILTER_S: f64 = 0.005;

/// Run `task` with the assist of `spec` and a simulated patient `human` (seeded by `seed`)
/// who watches the same reference. Deterministic.
pub fn run_dial_task(
    task: &DialTask,
    spec: &AssistSpec,
    human: &HumanArmParams,
    seed: u64,
) -> Result<DialResult, AssistError> {
    let mut assist = Assist::new(spec)?;
    let mut arm = HumanArm::new(human.clone(), task.dt_s, seed);
    let mut plant = Rk4Plant::new(task.wheel.coupled_with(&task.arm), task.coulomb_nm);
    let quantise = |x: f64| {
        if task.encoder_step_rad > 0.0 {
            (x / task.encoder_step_rad).round() * task.encoder_step_rad
        } else {
            x
        }
    };
    let steps = (task.duration_s / task.dt_s).round() as usize;
    let per_rep = ((1.0 / task.frequency_hz) / task.dt_s).round().max(1.0) as usize;
    let mut out = DialResult::default();
    let (mut sq_err, mut sq_tau, mut sq_hand) = (0.0, 0.0, 0.0);
    let (mut rep_sq, mut rep_level, mut rep_n) = (0.0, 0.0, 0usize);
    let mut prev_q = quantise(0.0);
    let mut vel_est = 0.0;
    let k = task.dt_s / (VELOCITY_FILTER_S + task.dt_s);
    for i in 0..steps {
        let t = i as f64 * task.dt_s;
        let reference = task.amplitude_rad * (std::f64::consts::TAU * task.frequency_hz * t).sin();
        let q = quantise(plant.angle_rad());
        vel_est += k * ((q - prev_q) / task.dt_s - vel_est);
        prev_q = q;
        let o = assist.step(
            Measurement {
                angle_rad: q,
                vel_rad_s: vel_est,
            },
            reference,
            task.limits,
            task.dt_s,
        );
        let hand = arm.step(reference, plant.angle_rad(), plant.vel_rad_s(), task.dt_s);
        plant.step(o.torque_nm + hand, task.dt_s);
        let e = reference - plant.angle_rad();
        sq_err += e * e;
        sq_tau += o.torque_nm * o.torque_nm;
        sq_hand += hand * hand;
        out.max_abs_torque_nm = out.max_abs_torque_nm.max(o.torque_nm.abs());
        rep_sq += e * e;
        rep_level += o.assistance_level;
        rep_n += 1;
        if rep_n == per_rep {
            out.rms_error_per_repetition_rad
                .push((rep_sq / rep_n as f64).sqrt());
            out.assistance_per_repetition.push(rep_level / rep_n as f64);
            (rep_sq, rep_level, rep_n) = (0.0, 0.0, 0);
        }
    }
    let n = steps.max(1) as f64;
    out.rms_error_rad = (sq_err / n).sqrt();
    out.rms_torque_nm = (sq_tau / n).sqrt();
    out.rms_hand_torque_nm = (sq_hand / n).sqrt();
    let status = assist.status();
    out.saturated_fraction = status.saturated_fraction;
    out.infeasible_fraction = status.infeasible_fraction;
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn step_response_matches_closed_form_first_order_plant() {
        // J θ̈ + B θ̇ = τ from rest: θ̇(t) = τ/B (1 − e^{−Bt/J}).
        let p = PlantParams {
            inertia_kg_m2: 0.12,
            damping_nm_s_per_rad: 0.3,
            stiffness_nm_per_rad: 0.0,
        };
        let mut plant = Rk4Plant::new(p, 0.0);
        for _ in 0..500 {
            plant.step(0.6, 0.001);
        }
        let expect = 0.6 / 0.3 * (1.0 - (-0.3 * 0.5 / 0.12f64).exp());
        assert_relative_eq!(plant.vel_rad_s(), expect, max_relative = 1e-9);
    }

    #[test]
    fn undamped_spring_conserves_energy() {
        let p = PlantParams {
            inertia_kg_m2: 1.0,
            damping_nm_s_per_rad: 0.0,
            stiffness_nm_per_rad: 4.0,
        };
        let mut plant = Rk4Plant::new(p, 0.0);
        plant.set_state(1.0, 0.0);
        for _ in 0..10_000 {
            plant.step(0.0, 0.001);
        }
        let e = 0.5 * plant.vel_rad_s().powi(2) + 0.5 * 4.0 * plant.angle_rad().powi(2);
        assert_relative_eq!(e, 2.0, max_relative = 1e-9);
    }
}
