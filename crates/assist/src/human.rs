//! A simulated human arm holding the wheel: the PID "human" of thesis Ch. 5 (Table 5.1 uses
//! K_P = 2), with reaction delay, motor noise and impairment — weakness, tremor (a
//! band-limited oscillation around 4–6 Hz), reduced range of motion — and improvement over
//! repetitions: recovery of strength and trial-to-trial learning of an anticipatory torque
//! (the improvement that assist-as-needed must make room for).

use crate::error::{AssistError, check_range};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal, StandardNormal};
use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;

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
    /// Sensorimotor delay between seeing the target and acting, s: the lag of the feedback
    /// loop while the target moves smoothly (a predictable target is followed with it alone).
    pub delay_s: f64,
    /// Visual reaction time to an unpredictable jump of the target, s: from the jump to the
    /// first change of the arm's torque (the delay included). Simple visual reaction time of
    /// healthy adults is about 0.21–0.23 s (Woods et al. 2015, Front Hum Neurosci 9:131,
    /// 1469 adults); after stroke it is longer and varies more, e.g. 0.40–0.47 s against
    /// 0.33 s in controls (Pauley et al. 2015, simple and choice reaction time of stroke
    /// survivors). 0: a jump is seen after `delay_s` like any other change (the thesis's PID
    /// human).
    pub reaction_s: f64,
    /// RMS of the motor noise in the torque the muscles produce, N·m (a neural noise
    /// low-passed by the muscles' activation, see `activation_s`; white when that is 0).
    pub noise_nm: f64,
    /// Time constant of the muscles' activation, s: the torque the muscles produce follows
    /// the neural command through a first-order lag (Winters & Stark 1985 give 10–40 ms for
    /// the arm's muscles; Zajac 1989 eq. 2). 0: the torque follows at once.
    pub activation_s: f64,
    /// Inertia of the arm reflected to the wheel's axis, kg·m² (a forearm and hand on a
    /// rim of 0.14 m: about 0.05–0.2 kg·m², the range `assist`'s `RELAXED_ARM` is taken from).
    /// The hand's torque on the rim is the muscles' torque less what accelerates the arm.
    pub inertia_kg_m2: f64,
    /// Strongest torque the healthy arm can produce on the wheel, N·m.
    pub max_torque_nm: f64,
    /// Fraction of strength lost to the impairment, in [0, 1): scales the PID gains and the
    /// strength limit by `1 − weakness`.
    pub weakness: f64,
    /// RMS torque of the tremor, N·m (0 = none).
    pub tremor_nm: f64,
    /// Centre frequency of the tremor, Hz (pathological tremor: about 4–6 Hz).
    pub tremor_hz: f64,
    /// Half-width of the band the tremor frequency wanders in, Hz.
    pub tremor_band_hz: f64,
    /// Half range of active motion, rad: the arm aims no further than ±this.
    pub range_of_motion_rad: f64,
    /// Fraction of the remaining weakness recovered per repetition, in [0, 1) (0 = none).
    pub recovery_per_repetition: f64,
    /// Length of one repetition of the exercise, s (for counting repetitions and for the
    /// phase of the learned anticipation).
    pub repetition_period_s: f64,
    /// Trial-to-trial learning gain `g_H` of the arm's anticipatory torque, N·m/rad (0 = the
    /// arm does not learn). Model: Emken et al. 2007, `x_{k+1} = f_H x_k + g_H e_k` per phase.
    pub learning_gain_nm_per_rad: f64,
    /// Retention `f_H` of the learned anticipation per repetition, in [0, 1].
    pub retention: f64,
    /// How far ahead the arm anticipates when it learns, s (error at phase `φ + lead` updates
    /// the torque at `φ`).
    pub learning_lead_s: f64,
}

impl Default for HumanArmParams {
    fn default() -> Self {
        Self {
            kp_nm_per_rad: 2.0,
            ki_nm_per_rad_s: 0.5,
            kd_nm_s_per_rad: 0.2,
            delay_s: 0.05,
            reaction_s: 0.0,
            noise_nm: 0.02,
            activation_s: 0.02,
            inertia_kg_m2: 0.06,
            max_torque_nm: 4.0,
            weakness: 0.0,
            tremor_nm: 0.0,
            tremor_hz: 5.0,
            tremor_band_hz: 1.0,
            range_of_motion_rad: std::f64::consts::PI,
            recovery_per_repetition: 0.0,
            repetition_period_s: 4.0,
            learning_gain_nm_per_rad: 0.0,
            retention: 0.98,
            learning_lead_s: 0.2,
        }
    }
}

impl HumanArmParams {
    /// Check the ranges of every field; the error names it as `human_arm.<field>`.
    pub fn validate(&self) -> Result<(), AssistError> {
        check_range(
            "human_arm.kp_nm_per_rad",
            self.kp_nm_per_rad,
            0.0,
            100.0,
            "[0, 100] N·m/rad",
        )?;
        check_range(
            "human_arm.ki_nm_per_rad_s",
            self.ki_nm_per_rad_s,
            0.0,
            100.0,
            "[0, 100] N·m/(rad·s)",
        )?;
        check_range(
            "human_arm.kd_nm_s_per_rad",
            self.kd_nm_s_per_rad,
            0.0,
            10.0,
            "[0, 10] N·m·s/rad",
        )?;
        check_range("human_arm.delay_s", self.delay_s, 0.0, 1.0, "[0, 1] s")?;
        check_range(
            "human_arm.reaction_s",
            self.reaction_s,
            0.0,
            2.0,
            "[0, 2] s",
        )?;
        check_range("human_arm.noise_nm", self.noise_nm, 0.0, 5.0, "[0, 5] N·m")?;
        check_range(
            "human_arm.activation_s",
            self.activation_s,
            0.0,
            0.2,
            "[0, 0.2] s",
        )?;
        check_range(
            "human_arm.inertia_kg_m2",
            self.inertia_kg_m2,
            0.0,
            1.0,
            "[0, 1] kg·m²",
        )?;
        check_range(
            "human_arm.max_torque_nm",
            self.max_torque_nm,
            0.0,
            50.0,
            "[0, 50] N·m",
        )?;
        check_range("human_arm.weakness", self.weakness, 0.0, 0.99, "[0, 0.99]")?;
        check_range(
            "human_arm.tremor_nm",
            self.tremor_nm,
            0.0,
            2.0,
            "[0, 2] N·m",
        )?;
        check_range(
            "human_arm.tremor_hz",
            self.tremor_hz,
            1.0,
            15.0,
            "[1, 15] Hz",
        )?;
        check_range(
            "human_arm.tremor_band_hz",
            self.tremor_band_hz,
            0.0,
            5.0,
            "[0, 5] Hz",
        )?;
        check_range(
            "human_arm.range_of_motion_rad",
            self.range_of_motion_rad,
            0.05,
            std::f64::consts::PI,
            "[0.05, π] rad",
        )?;
        check_range(
            "human_arm.recovery_per_repetition",
            self.recovery_per_repetition,
            0.0,
            0.99,
            "[0, 0.99]",
        )?;
        check_range(
            "human_arm.repetition_period_s",
            self.repetition_period_s,
            0.1,
            600.0,
            "[0.1, 600] s",
        )?;
        check_range(
            "human_arm.learning_gain_nm_per_rad",
            self.learning_gain_nm_per_rad,
            0.0,
            20.0,
            "[0, 20] N·m/rad",
        )?;
        check_range("human_arm.retention", self.retention, 0.0, 1.0, "[0, 1]")?;
        check_range(
            "human_arm.learning_lead_s",
            self.learning_lead_s,
            0.0,
            2.0,
            "[0, 2] s",
        )
    }

    /// A weak, slow, tremulous post-stroke arm: 85 % weakness, 150 ms delay, 0.03 N·m RMS
    /// tremor at 5 Hz, ±50° active range (a "weak patient" for the dial task).
    pub fn weak_patient() -> Self {
        Self {
            weakness: 0.85,
            delay_s: 0.15,
            tremor_nm: 0.03,
            range_of_motion_rad: 50f64.to_radians(),
            ..Self::default()
        }
    }
}

/// The share of the way a first-order activation of time constant `activation_s` moves
/// towards its command in a tick of `dt_s` (1: at once).
fn activation_step(activation_s: f64, dt_s: f64) -> f64 {
    if activation_s > 0.0 && dt_s > 0.0 {
        1.0 - (-dt_s / activation_s).exp()
    } else {
        1.0
    }
}

/// The factor on a white noise sample so that, low-passed by an activation of time constant
/// `activation_s` at the tick `dt_s`, its RMS is the sample's standard deviation: a first-order
/// lag `y' = a (u − y)` passes a white variance σ² as `σ² a / (2 − a)`.
fn activated_noise_gain(activation_s: f64, dt_s: f64) -> f64 {
    let a = activation_step(activation_s, dt_s);
    ((2.0 - a) / a).sqrt()
}

/// Phase bins of the arm's learned anticipation per repetition.
const LEARNING_BINS: usize = 40;

/// A change of the target larger than this in one tick is a jump the arm must react to, rad
/// (a 40° sine at 2 rad/s moves 0.08° a millisecond; a step of the assessment moves 20° at
/// once).
pub const JUMP_RAD: f64 = 0.035;

/// Time constant of the tremor's frequency and amplitude wander, s.
const TREMOR_WANDER_S: f64 = 0.5;

/// The simulated arm: call [`HumanArm::step`] once per tick.
#[derive(Clone, Debug)]
pub struct HumanArm {
    params: HumanArmParams,
    delay_line: Vec<f64>,
    head: usize,
    /// The target as the arm has seen it (held at its old value while reacting to a jump).
    seen_rad: f64,
    /// The target of the last tick, rad (to tell a jump).
    last_target_rad: f64,
    /// Ticks left before a jump is seen (0: the target is seen as it comes).
    reacting_ticks: usize,
    /// Ticks a jump is held back: `reaction_s − delay_s`, the delay line doing the rest.
    reaction_ticks: usize,
    integral: f64,
    rng: ChaCha8Rng,
    noise: Normal<f64>,
    weakness: f64,
    /// The muscles' torque now (after activation), N·m.
    activated_nm: f64,
    /// Scale of the white neural noise so that the activated noise has RMS `noise_nm`.
    noise_gain: f64,
    tremor_phase: f64,
    tremor_dev: f64,
    tremor_amp: f64,
    t_in_rep_s: f64,
    repetitions: u64,
    learned_nm: Vec<f64>,
    bin: usize,
    bin_err_sum: f64,
    bin_err_n: u32,
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
        let weakness = if params.weakness.is_finite() {
            params.weakness.clamp(0.0, 1.0)
        } else {
            0.0
        };
        let noise_gain = activated_noise_gain(params.activation_s, dt_s);
        let reaction_ticks = if dt_s > 0.0 {
            ((params.reaction_s - params.delay_s).max(0.0) / dt_s).round() as usize
        } else {
            0
        };
        Self {
            params,
            delay_line: vec![0.0; delay_ticks + 1],
            head: 0,
            seen_rad: 0.0,
            last_target_rad: 0.0,
            reacting_ticks: 0,
            reaction_ticks,
            integral: 0.0,
            rng: ChaCha8Rng::seed_from_u64(seed),
            noise,
            weakness,
            activated_nm: 0.0,
            noise_gain,
            tremor_phase: 0.0,
            tremor_dev: 0.0,
            tremor_amp: 0.0,
            t_in_rep_s: 0.0,
            repetitions: 0,
            learned_nm: vec![0.0; LEARNING_BINS],
            bin: 0,
            bin_err_sum: 0.0,
            bin_err_n: 0,
        }
    }

    /// The parameters the arm was built with.
    pub fn params(&self) -> &HumanArmParams {
        &self.params
    }

    /// Mean magnitude of the arm's learned anticipatory torque, N·m.
    pub fn mean_learned_nm(&self) -> f64 {
        self.learned_nm.iter().map(|u| u.abs()).sum::<f64>() / LEARNING_BINS as f64
    }

    /// Learn and return the anticipatory torque at the current phase (before strength
    /// scaling), N·m.
    fn anticipation_nm(&mut self, err: f64) -> f64 {
        let p = &self.params;
        if p.learning_gain_nm_per_rad <= 0.0 || p.repetition_period_s <= 0.0 {
            return 0.0;
        }
        let bin_s = p.repetition_period_s / LEARNING_BINS as f64;
        let bin = ((self.t_in_rep_s / bin_s) as usize).min(LEARNING_BINS - 1);
        if bin != self.bin {
            if self.bin_err_n > 0 {
                let lead = (p.learning_lead_s / bin_s).round() as usize % LEARNING_BINS;
                let target = (self.bin + LEARNING_BINS - lead) % LEARNING_BINS;
                let e = self.bin_err_sum / f64::from(self.bin_err_n);
                let cap = p.max_torque_nm;
                self.learned_nm[target] = (p.retention.clamp(0.0, 1.0) * self.learned_nm[target]
                    + p.learning_gain_nm_per_rad * e)
                    .clamp(-cap, cap);
            }
            self.bin = bin;
            self.bin_err_sum = 0.0;
            self.bin_err_n = 0;
        }
        self.bin_err_sum += err;
        self.bin_err_n += 1;
        self.learned_nm[bin]
    }

    /// Current fraction of full strength, `1 − weakness` (rises with recovery).
    pub fn strength_fraction(&self) -> f64 {
        1.0 - self.weakness
    }

    /// Completed repetitions.
    pub fn repetitions(&self) -> u64 {
        self.repetitions
    }

    /// Band-limited tremor torque: a sinusoid whose frequency and amplitude wander as
    /// Ornstein–Uhlenbeck processes (time constant [`TREMOR_WANDER_S`]), frequency clamped to
    /// `tremor_hz ± tremor_band_hz`; RMS ≈ `tremor_nm`.
    fn tremor_nm(&mut self, dt_s: f64) -> f64 {
        let p = &self.params;
        if p.tremor_nm <= 0.0 || !p.tremor_nm.is_finite() {
            return 0.0;
        }
        let a = (-dt_s / TREMOR_WANDER_S).exp();
        let s = (1.0 - a * a).sqrt();
        let n1: f64 = StandardNormal.sample(&mut self.rng);
        let n2: f64 = StandardNormal.sample(&mut self.rng);
        self.tremor_dev = a * self.tremor_dev + s * 0.5 * p.tremor_band_hz * n1;
        self.tremor_amp = a * self.tremor_amp + s * 0.2 * n2;
        let f = (p.tremor_hz + self.tremor_dev)
            .clamp(
                p.tremor_hz - p.tremor_band_hz,
                p.tremor_hz + p.tremor_band_hz,
            )
            .max(0.0);
        self.tremor_phase = (self.tremor_phase + TAU * f * dt_s) % TAU;
        p.tremor_nm
            * std::f64::consts::SQRT_2
            * (1.0 + self.tremor_amp).max(0.0)
            * self.tremor_phase.sin()
    }

    /// The target as the arm sees it this tick: a jump larger than [`JUMP_RAD`] is held back
    /// for the reaction time beyond the delay (`reaction_s − delay_s`, the delay line adds
    /// the rest); a jump while reacting restarts nothing (the arm reacts to the first and
    /// then sees the target as it is). Smooth changes pass at once.
    fn see(&mut self, target_rad: f64) -> f64 {
        let jumped = (target_rad - self.last_target_rad).abs() > JUMP_RAD;
        self.last_target_rad = target_rad;
        if jumped && self.reacting_ticks == 0 && self.reaction_ticks > 0 {
            self.reacting_ticks = self.reaction_ticks;
        }
        if self.reacting_ticks > 0 {
            self.reacting_ticks -= 1;
        } else {
            self.seen_rad = target_rad;
        }
        self.seen_rad
    }

    /// Hand torque on the wheel, N·m, for the target angle the human wants now, the wheel
    /// angle and velocity it feels (rad, rad/s), over a tick of `dt_s`.
    ///
    /// The target passes through the reaction delay and the range-of-motion limit; the arm
    /// feels the wheel directly. Gains and strength are scaled by `1 − weakness`.
    pub fn step(&mut self, target_rad: f64, angle_rad: f64, vel_rad_s: f64, dt_s: f64) -> f64 {
        let seen_rad = self.see(target_rad);
        let n = self.delay_line.len();
        self.delay_line[self.head] = seen_rad;
        self.head = (self.head + 1) % n;
        let rom = self.params.range_of_motion_rad.abs();
        let delayed_target = self.delay_line[self.head].clamp(-rom, rom);
        let err = delayed_target - angle_rad;
        let strength = 1.0 - self.weakness;
        // Trial-to-trial learning works on the remembered error profile of the repetition,
        // so it uses the undelayed error at each phase.
        let anticipation = self.anticipation_nm(target_rad.clamp(-rom, rom) - angle_rad);
        let p = &self.params;
        let max_torque = p.max_torque_nm * strength;
        // The muscles' active torque, and the arm's intrinsic (passive, at once) damping.
        let active =
            strength * (p.kp_nm_per_rad * err + p.ki_nm_per_rad_s * self.integral + anticipation);
        let passive = strength * p.kd_nm_s_per_rad * vel_rad_s;
        let unsat = active - passive;
        // Conditional integration: no windup while the arm is at its strength limit.
        if unsat.abs() < max_torque || unsat.signum() != err.signum() {
            self.integral += err * dt_s;
        }
        // The muscles follow the command and the neural noise through their activation.
        let command = (active + self.noise_gain * self.noise.sample(&mut self.rng))
            .clamp(-max_torque, max_torque);
        let a = activation_step(self.params.activation_s, dt_s);
        self.activated_nm += a * (command - self.activated_nm);
        let torque = self.activated_nm - passive + self.tremor_nm(dt_s);
        // Recovery over repetitions.
        self.t_in_rep_s += dt_s;
        let p = &self.params;
        if p.repetition_period_s > 0.0 && self.t_in_rep_s >= p.repetition_period_s {
            self.t_in_rep_s -= p.repetition_period_s;
            self.repetitions += 1;
            self.weakness *= 1.0 - p.recovery_per_repetition.clamp(0.0, 1.0);
        }
        torque.clamp(-max_torque, max_torque)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The first tick (from 0) the arm's torque leaves 0 after the target jumps at `t = 0.1 s`
    /// (or ramps smoothly from there at 0.5 rad/s), s after that time.
    fn first_push_after(params: HumanArmParams, jump: bool) -> f64 {
        let dt = 0.001;
        let mut arm = HumanArm::new(params, dt, 1);
        for k in 0..2000 {
            let t = f64::from(k) * dt;
            let target = match (jump, t >= 0.1) {
                (_, false) => 0.0,
                (true, true) => 0.35,
                (false, true) => 0.5 * (t - 0.1),
            };
            if arm.step(target, 0.0, 0.0, dt).abs() > 1e-12 {
                return t - 0.1;
            }
        }
        f64::INFINITY
    }

    #[test]
    fn a_jump_of_the_target_is_seen_after_the_reaction_time_a_smooth_change_after_the_delay() {
        let params = HumanArmParams {
            noise_nm: 0.0,
            activation_s: 0.0,
            delay_s: 0.05,
            reaction_s: 0.25,
            ..HumanArmParams::default()
        };
        let jump = first_push_after(params.clone(), true);
        let smooth = first_push_after(params.clone(), false);
        assert!((jump - 0.25).abs() < 0.0025, "jump seen after {jump} s");
        assert!((smooth - 0.05).abs() < 0.0025, "ramp seen after {smooth} s");
        // Without a reaction time a jump is seen after the delay alone.
        let plain = HumanArmParams {
            reaction_s: 0.0,
            ..params
        };
        let jump = first_push_after(plain, true);
        assert!((jump - 0.05).abs() < 0.0025, "jump seen after {jump} s");
    }

    #[test]
    fn delayed_target_reaches_the_controller_after_the_delay() {
        let params = HumanArmParams {
            ki_nm_per_rad_s: 0.0,
            kd_nm_s_per_rad: 0.0,
            noise_nm: 0.0,
            activation_s: 0.0,
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

    fn quiet(extra: HumanArmParams) -> HumanArm {
        HumanArm::new(
            HumanArmParams {
                noise_nm: 0.0,
                activation_s: 0.0,
                ki_nm_per_rad_s: 0.0,
                kd_nm_s_per_rad: 0.0,
                delay_s: 0.0,
                ..extra
            },
            0.001,
            3,
        )
    }

    #[test]
    fn defaults_and_weak_patient_validate_and_bad_values_are_named() {
        HumanArmParams::default().validate().unwrap();
        HumanArmParams::weak_patient().validate().unwrap();
        let e = HumanArmParams {
            tremor_hz: f64::NAN,
            ..Default::default()
        }
        .validate()
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("human_arm.tremor_hz") && e.contains("[1, 15] Hz"),
            "{e}"
        );
    }

    #[test]
    fn weakness_scales_gain_and_strength_limit() {
        let mut arm = quiet(HumanArmParams {
            weakness: 0.75,
            ..Default::default()
        });
        assert_eq!(arm.step(0.1, 0.0, 0.0, 0.001), 0.25 * 2.0 * 0.1);
        assert_eq!(arm.step(100.0, 0.0, 0.0, 0.001), 0.25 * 4.0);
    }

    #[test]
    fn range_of_motion_limits_the_aim() {
        let mut arm = quiet(HumanArmParams {
            range_of_motion_rad: 0.5,
            ..Default::default()
        });
        // Aiming at 1.0 rad from 0.5 rad: no active torque beyond the range.
        assert_eq!(arm.step(1.0, 0.5, 0.0, 0.001), 0.0);
    }

    #[test]
    fn tremor_has_its_power_in_the_4_to_6_hz_band_and_the_requested_rms() {
        let mut arm = quiet(HumanArmParams {
            kp_nm_per_rad: 0.0,
            tremor_nm: 0.05,
            ..Default::default()
        });
        let n = 20_000;
        let x: Vec<f64> = (0..n).map(|_| arm.step(0.0, 0.0, 0.0, 0.001)).collect();
        let rms = (x.iter().map(|v| v * v).sum::<f64>() / n as f64).sqrt();
        assert!((rms - 0.05).abs() < 0.015, "rms {rms}");
        // Goertzel-like DFT power: in band vs out of band.
        let power = |f: f64| {
            let (mut re, mut im) = (0.0, 0.0);
            for (k, v) in x.iter().enumerate() {
                let ph = TAU * f * k as f64 * 0.001;
                re += v * ph.cos();
                im += v * ph.sin();
            }
            re * re + im * im
        };
        let in_band: f64 = (40..=60).map(|f| power(f as f64 * 0.1)).sum();
        let out_band: f64 = (10..=30)
            .chain(80..=120)
            .map(|f| power(f as f64 * 0.1))
            .sum();
        assert!(in_band > 10.0 * out_band, "in {in_band} out {out_band}");
    }

    #[test]
    fn strength_recovers_over_repetitions() {
        let mut arm = quiet(HumanArmParams {
            weakness: 0.8,
            recovery_per_repetition: 0.1,
            repetition_period_s: 1.0,
            ..Default::default()
        });
        for _ in 0..10_005 {
            arm.step(0.0, 0.0, 0.0, 0.001);
        }
        assert_eq!(arm.repetitions(), 10);
        let expect = 1.0 - 0.8 * 0.9f64.powi(10);
        assert!((arm.strength_fraction() - expect).abs() < 1e-12);
    }

    #[test]
    fn the_muscles_torque_follows_a_step_of_the_command_through_its_activation() {
        let mut arm = HumanArm::new(
            HumanArmParams {
                noise_nm: 0.0,
                ki_nm_per_rad_s: 0.0,
                kd_nm_s_per_rad: 0.0,
                delay_s: 0.0,
                activation_s: 0.02,
                ..Default::default()
            },
            0.001,
            3,
        );
        // K_P = 2 on a 0.1 rad error: 0.2 N·m, reached as 1 − e^{−t/20 ms}.
        let out: Vec<f64> = (0..100).map(|_| arm.step(0.1, 0.0, 0.0, 0.001)).collect();
        let at_20ms = out[19] / 0.2;
        assert!(
            (at_20ms - (1.0 - (-1.0_f64).exp())).abs() < 0.01,
            "{at_20ms}"
        );
        assert!((out[99] / 0.2 - 1.0).abs() < 0.01);
    }

    #[test]
    fn the_activated_motor_noise_keeps_its_stated_rms() {
        let mut arm = HumanArm::new(
            HumanArmParams {
                kp_nm_per_rad: 0.0,
                ki_nm_per_rad_s: 0.0,
                kd_nm_s_per_rad: 0.0,
                noise_nm: 0.05,
                activation_s: 0.02,
                ..Default::default()
            },
            0.001,
            11,
        );
        let out: Vec<f64> = (0..200_000)
            .map(|_| arm.step(0.0, 0.0, 0.0, 0.001))
            .collect();
        let rms = (out.iter().map(|x| x * x).sum::<f64>() / out.len() as f64).sqrt();
        assert!((rms - 0.05).abs() < 0.005, "RMS {rms}");
        // Low-passed: neighbouring ticks nearly equal (white noise would not be).
        let diff =
            (out.windows(2).map(|w| (w[1] - w[0]).powi(2)).sum::<f64>() / out.len() as f64).sqrt();
        assert!(diff < 0.5 * rms, "tick-to-tick {diff}");
    }
}
