//! A simulated human arm holding the wheel: the PID "human" of thesis Ch. 5 (Table 5.1 uses
//! K_P = 2), with reaction delay, motor noise and weakness.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use serde::{Deserialize, Serialize};

/// Parameters of the simulated human.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct HumanArmParams {
    /// Proportional gain on angle error, N·m/rad (thesis Table 5.1: K_P = 2).
    pub kp_nm_per_rad: f64,
    /// Integral gain, N·m/(rad·s).
    pub ki_nm_per_rad_s: f64,
    /// Derivative gain on the wheel velocity, N·m·s/rad.
    pub kd_nm_s_per_rad: f64,
    /// Sensorimotor delay between seeing the target and acting, s.
    pub delay_s: f64,
    /// Standard deviation of additive motor noise, N·m.
    pub noise_nm: f64,
    /// Strongest torque the arm can produce on the wheel, N·m (weakness lowers it).
    pub max_torque_nm: f64,
}

impl Default for HumanArmParams {
    fn default() -> Self {
        Self {
            kp_nm_per_rad: 2.0,
            ki_nm_per_rad_s: 0.5,
            kd_nm_s_per_rad: 0.2,
            delay_s: 0.05,
            noise_nm: 0.02,
            max_torque_nm: 4.0,
        }
    }
}

/// The simulated arm: call [`HumanArm::step`] once per tick.
#[derive(Clone, Debug)]
pub struct HumanArm {
    params: HumanArmParams,
    delay_line: Vec<f64>,
    head: usize,
    integral: f64,
    rng: ChaCha8Rng,
    noise: Normal<f64>,
}

impl HumanArm {
    /// An arm for a loop with period `dt_s`, seeded for reproducible noise.
    pub fn new(params: HumanArmParams, dt_s: f64, seed: u64) -> Self {
        let delay_ticks = if dt_s > 0.0 {
            (params.delay_s / dt_s).round().max(0.0) as usize
        } else {
            0
        };
        let noise = Normal::new(0.0, params.noise_nm.abs())
            .unwrap_or(Normal::new(0.0, 0.0).expect("zero sd is valid"));
        Self {
            params,
            delay_line: vec![0.0; delay_ticks + 1],
            head: 0,
            integral: 0.0,
            rng: ChaCha8Rng::seed_from_u64(seed),
            noise,
        }
    }

    /// Hand torque on the wheel, N·m, for the target angle the human wants now, the wheel
    /// angle and velocity it feels (rad, rad/s), over a tick of `dt_s`.
    ///
    /// The target passes through the reaction delay; the arm feels the wheel directly.
    pub fn step(&mut self, target_rad: f64, angle_rad: f64, vel_rad_s: f64, dt_s: f64) -> f64 {
        let n = self.delay_line.len();
        self.delay_line[self.head] = target_rad;
        self.head = (self.head + 1) % n;
        let delayed_target = self.delay_line[self.head];
        let err = delayed_target - angle_rad;
        let p = &self.params;
        let unsat = p.kp_nm_per_rad * err + p.ki_nm_per_rad_s * self.integral
            - p.kd_nm_s_per_rad * vel_rad_s;
        // Conditional integration: no windup while the arm is at its strength limit.
        if unsat.abs() < p.max_torque_nm || unsat.signum() != err.signum() {
            self.integral += err * dt_s;
        }
        let torque = unsat + self.noise.sample(&mut self.rng);
        torque.clamp(-p.max_torque_nm, p.max_torque_nm)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn delayed_target_reaches_the_controller_after_the_delay() {
        let params = HumanArmParams {
            ki_nm_per_rad_s: 0.0,
            kd_nm_s_per_rad: 0.0,
            noise_nm: 0.0,
            delay_s: 0.005,
            ..Default::default()
        };
        let mut arm = HumanArm::new(params, 0.001, 1);
        let mut outs = Vec::new();
        for _ in 0..8 {
            outs.push(arm.step(1.0, 0.0, 0.0, 0.001));
        }
        assert_eq!(&outs[..5], &[0.0; 5]);
        assert_eq!(outs[5], 2.0);
    }

    #[test]
    fn same_seed_gives_same_noise() {
        let mut a = HumanArm::new(HumanArmParams::default(), 0.001, 7);
        let mut b = HumanArm::new(HumanArmParams::default(), 0.001, 7);
        for i in 0..100 {
            let t = i as f64 * 0.01;
            assert_eq!(a.step(t, 0.0, 0.0, 0.001), b.step(t, 0.0, 0.0, 0.001));
        }
    }
}
