//! The patient's own (hand) torque on the wheel, estimated from the measured angle and the
//! torque commanded to the motor: what a real wheel cannot measure.
//!
//! The wheel alone (no arm model: the arm is what is estimated) obeys the one-link form of
//! thesis eq. 5.5 with the hand's torque as the input it receives,
//!
//! ```text
//! J θ̈ + B θ̇ + τ_c sgn(θ̇) = τ_act + τ_h
//! ```
//!
//! and eq. 5.8 is that law solved for the acceleration. Read the other way it gives the hand's
//! torque, `τ_h = J θ̈ + B θ̇ + τ_c sgn(θ̇) − τ_act` — which needs `θ̈`. The angle is quantised
//! (0.0023 rad steps on the thesis wheel), so differentiating it twice is noise.
//!
//! **Observer.** A linear *extended-state observer* (Gao, "Scaling and bandwidth-
//! parameterization based controller tuning", ACC 2003: the disturbance observer of ADRC) of
//! that law, the hand's torque its extended state (modelled constant between ticks), with the
//! torque acting on the wheel as its known input — the command sent `delay_ticks` ticks
//! earlier, as the passivity observer pairs them:
//!
//! ```text
//! e = θ − θ̂
//! θ̂' = ω̂ + 3·ω₀·e
//! ω̂' = (τ_act − B ω̂ − τ_c sat(ω̂ / v_c) + τ̂_h) / J + 3·ω₀²·e          (E.1)
//! τ̂_h' = J·ω₀³·e                                                        (E.2)
//! ```
//!
//! all three poles at `−ω₀` (`bandwidth_rad_s`). It needs no differentiation (the angle error
//! is integrated), and `τ̂_h` follows the hand's torque through `ω₀³/(s + ω₀)³`: a lag of
//! about `3/ω₀` (50 ms at the default 60 rad/s), with the encoder's quantisation let through
//! as `≈ J ω₀² Δθ`. The form with the motor's torque fed through unfiltered (the observer
//! estimating only `J θ̈`) had no lag where the hand balances the motor but an error of the
//! whole inertial torque wherever the motor chatters (motion assist): it was the worse of the
//! two on the station's simulated patient (BENCHMARKS.md, "Hand torque estimate").
//!
//! Allocation-free and a handful of multiplications a tick: it runs on the haptic thread. It
//! only *observes*: nothing it computes is ever commanded.

use serde::{Deserialize, Serialize};

/// Commands remembered for the actuation delay (ticks).
const HISTORY: usize = 64;

/// The wheel's own dynamics as the estimator models them (eq. 5.5, one link, no arm).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct WheelDynamics {
    /// Rim + motor inertia at the steering axis `J`, kg·m².
    pub inertia_kg_m2: f64,
    /// Viscous friction `B`, N·m·s/rad.
    pub viscous_nm_s_per_rad: f64,
    /// Coulomb friction `τ_c`, N·m.
    pub coulomb_nm: f64,
    /// Ticks from sending a torque to the loop step it first acts in (USB and firmware
    /// latency; 1..=62, 0 taken as 1: the observer steps before the tick's command is sent).
    pub delay_ticks: usize,
}

impl WheelDynamics {
    /// A consumer force-feedback wheel of the thesis's class when nothing was measured:
    /// the simulated wheel's defaults (0.02 kg·m², 0.02 N·m·s/rad, 0.03 N·m, 2 ms of USB).
    pub const NOMINAL: Self = Self {
        inertia_kg_m2: 0.02,
        viscous_nm_s_per_rad: 0.02,
        coulomb_nm: 0.03,
        delay_ticks: 3,
    };
}

/// Tuning of the [`HandTorqueObserver`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ObserverTuning {
    /// Bandwidth `ω₀` of (E.1), rad/s: higher follows faster, and lets more encoder
    /// quantisation through (`≈ J ω₀² Δθ` of noise).
    pub bandwidth_rad_s: f64,
    /// Velocity `v_c` below which the Coulomb term of (E.1) fades linearly to zero, rad/s
    /// (the wheel at rest holds any torque within ±τ_c: unobservable).
    pub coulomb_fade_rad_s: f64,
}

impl Default for ObserverTuning {
    fn default() -> Self {
        Self {
            bandwidth_rad_s: 60.0,
            coulomb_fade_rad_s: 0.05,
        }
    }
}

/// The observer of eq. (E.1)–(E.2). Call [`step`](Self::step) with each tick's measured
/// angle, then [`commit`](Self::commit) with the torque sent to the motor that tick.
#[derive(Clone, Debug)]
pub struct HandTorqueObserver {
    wheel: WheelDynamics,
    tuning: ObserverTuning,
    angle_rad: f64,
    vel_rad_s: f64,
    hand_nm: f64,
    started: bool,
    sent: [f64; HISTORY],
    next: usize,
}

impl HandTorqueObserver {
    /// An observer of `wheel`, at rest until the first angle.
    pub fn new(wheel: WheelDynamics, tuning: ObserverTuning) -> Self {
        let wheel = WheelDynamics {
            delay_ticks: wheel.delay_ticks.min(HISTORY - 2),
            ..wheel
        };
        Self {
            wheel,
            tuning,
            angle_rad: 0.0,
            vel_rad_s: 0.0,
            hand_nm: 0.0,
            started: false,
            sent: [0.0; HISTORY],
            next: 0,
        }
    }

    /// The wheel it models.
    pub fn wheel(&self) -> &WheelDynamics {
        &self.wheel
    }

    /// Observe the angle `angle_rad` measured `dt_s` after the last and return the hand's
    /// torque estimate `τ̂_h` (E.2), N·m: the torque of the step that angle ended. A non-finite
    /// angle or `dt_s` observes nothing and returns the last estimate.
    pub fn step(&mut self, angle_rad: f64, dt_s: f64) -> f64 {
        if angle_rad.is_finite() && dt_s.is_finite() && dt_s > 0.0 {
            if self.started {
                let d = &self.wheel;
                let w = self.tuning.bandwidth_rad_s;
                let e = angle_rad - self.angle_rad;
                let fade = self.tuning.coulomb_fade_rad_s.max(1e-9);
                let friction = d.viscous_nm_s_per_rad * self.vel_rad_s
                    + d.coulomb_nm * (self.vel_rad_s / fade).clamp(-1.0, 1.0);
                let net = self.acting_nm() - friction + self.hand_nm;
                // (E.1), explicit Euler (ω₀·dt ≪ 1 at 1 kHz).
                self.angle_rad += dt_s * (self.vel_rad_s + 3.0 * w * e);
                self.vel_rad_s += dt_s * (net / d.inertia_kg_m2 + 3.0 * w * w * e);
                self.hand_nm += dt_s * (d.inertia_kg_m2 * w * w * w * e);
            } else {
                self.angle_rad = angle_rad;
                self.started = true;
            }
        }
        self.hand_nm
    }

    /// The torque acting on the wheel over the coming step: the one sent `delay_ticks` ticks
    /// ago (at least one: the observer steps before this tick's command is sent), N·m.
    fn acting_nm(&self) -> f64 {
        let back = self.wheel.delay_ticks.max(1);
        self.sent[(self.next + HISTORY - back) % HISTORY]
    }

    /// Record the torque sent to the motor this tick, N·m (non-finite: none, the wheel
    /// stops its motor on it).
    pub fn commit(&mut self, sent_nm: f64) {
        self.sent[self.next] = if sent_nm.is_finite() { sent_nm } else { 0.0 };
        self.next = (self.next + 1) % HISTORY;
    }

    /// The observer's velocity, rad/s.
    pub fn vel_rad_s(&self) -> f64 {
        self.vel_rad_s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The nominal wheel (J = 0.02 kg·m², no Coulomb friction, no delay), Euler-integrated
    /// as the station's simulated wheel is and its angle quantised to the thesis encoder,
    /// rendering a centring spring (0.5 N·m/rad, 0.05 N·m·s/rad) and held by a hand `hand(t, θ,
    /// ω)`. Returns the estimate and the true hand torque of the tick before (the one the
    /// angle shows), from 0.5 s on.
    fn run(hand: impl Fn(f64, f64, f64) -> f64, bandwidth_rad_s: f64) -> (Vec<f64>, Vec<f64>) {
        let wheel = WheelDynamics {
            coulomb_nm: 0.0,
            delay_ticks: 0,
            ..WheelDynamics::NOMINAL
        };
        let tuning = ObserverTuning {
            bandwidth_rad_s,
            ..ObserverTuning::default()
        };
        let mut obs = HandTorqueObserver::new(wheel, tuning);
        let (mut th, mut w, mut last_hand, mut acting) = (0.0_f64, 0.0_f64, 0.0, 0.0);
        let (mut est, mut truth) = (Vec::new(), Vec::new());
        for k in 0..8000 {
            let t = k as f64 * 1e-3;
            let q = (th / 0.002253).round() * 0.002253;
            let e = obs.step(q, 1e-3);
            if k >= 500 {
                est.push(e);
                truth.push(last_hand);
            }
            // Sent now, acting from the next step (delay_ticks = 0, taken as 1).
            let motor = -0.5 * q - 0.05 * obs.vel_rad_s();
            obs.commit(motor);
            last_hand = hand(t, th, w);
            w += (acting + last_hand - wheel.viscous_nm_s_per_rad * w) / wheel.inertia_kg_m2 * 1e-3;
            th += w * 1e-3;
            acting = motor;
        }
        (est, truth)
    }

    fn rms_error_ratio(est: &[f64], truth: &[f64]) -> f64 {
        let se: f64 = est.iter().zip(truth).map(|(e, h)| (e - h).powi(2)).sum();
        let sh: f64 = truth.iter().map(|h| h * h).sum();
        (se / sh).sqrt()
    }

    #[test]
    fn a_steady_hold_reads_as_the_hands_torque_on_average_within_two_percent() {
        // The hand holds 0.4 N·m against the spring (0.8 rad): no lag to speak of, only the
        // encoder's quantisation dithering around it.
        let (est, truth) = run(|_, _, _| 0.4, 60.0);
        let late = &est[est.len() - 1000..];
        let mean = late.iter().sum::<f64>() / late.len() as f64;
        assert!((mean - 0.4).abs() < 0.008, "mean {mean}");
        assert!(late.iter().all(|e| (e - 0.4).abs() < 0.05), "{late:?}");
        assert!(truth.iter().all(|h| *h == 0.4));
    }

    #[test]
    fn a_patient_following_a_slow_sine_is_estimated_within_ten_percent_rms() {
        // A PD arm (thesis Table 5.1, K_P = 2) following 0.7 rad at 0.25 Hz.
        let arm = |t: f64, th: f64, w: f64| {
            2.0 * (0.7 * (std::f64::consts::TAU * 0.25 * t).sin() - th) - 0.2 * w
        };
        let (est, truth) = run(arm, 60.0);
        let ratio = rms_error_ratio(&est, &truth);
        assert!(ratio < 0.10, "rms error {ratio:.3} of the rms hand torque");
    }
}
