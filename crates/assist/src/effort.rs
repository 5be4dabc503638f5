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
//! ω̂' = (τ_act − B ω̂ − τ_c sat(ω̂ / v_c) − τ_stop(θ, ω̂) + τ̂_h) / J + 3·ω₀²·e     (E.1)
//! τ̂_h' = J·ω₀³·e                                                                  (E.2)
//! ```
//!
//! all three poles at `−ω₀`. It needs no differentiation (the angle error is integrated), and
//! `τ̂_h` follows the hand's torque through `L(s) = ω₀³/(s + ω₀)³`: a lag of about `3/ω₀`,
//! with the encoder's quantisation let through as `≈ J ω₀² Δθ`. `τ_stop` is the end stop
//! beyond the wheel's range, where the rim pushes back whatever the hand does.
//!
//! **A fixed lag, stated.** The angle shows a change of the hand's torque only once the rim
//! has moved an encoder step: a change `Δτ` moves the bare rim `Δθ` in `√(2 J Δθ / Δτ)` —
//! 30 ms for 0.1 N·m on the thesis's wheel. No causal estimate of a torque that changes
//! within that time can be both prompt and quiet, so this one is *late by a fixed time* and
//! says so: `L(s)` is close to the pure delay `e^{−s·3/ω₀}` over the hand's band (at 2 Hz and
//! `ω₀` = 60 rad/s its gain is 0.94 and its phase that of the delay within 0.01 rad). The
//! estimate is of the hand's torque [`HAND_ESTIMATE_LAG_S`] (50 ms) before the angle it is
//! computed from; a reader pairs it with the wheel's motion of that time (the work share
//! does).
//!
//! **Not at the end stop.** Against its stop the rim is held by a contact whose torque
//! changes within a tick of the impact; no model of it read through an encoder is good to
//! a fraction of a newton-metre there, and the patient's push against a stop moves nothing.
//! So the estimate is *absent* while the rim is within [`STOP_MARGIN_RAD`] of its end stop
//! and for twice the lag after (the estimate of those ticks would carry the contact's error).
//!
//! **The motor's torque, exactly delayed.** Of the hand's torque `τ_h = J θ̈ + friction −
//! τ_act`, only the wheel's own inertial and friction torques must be inferred from the
//! angle; the motor's is known. The observer's estimate is `L(s)` of all three, so the known
//! part's distortion is replaced by the exact delay (E.3):
//!
//! ```text
//! τ̂_h(t − T) = τ̂_h + L(s) τ_act − τ_act(t − T),   T = 3/ω₀                       (E.3)
//! ```
//!
//! leaving only the wheel's own (small) inertial torque filtered. Where the motor's torque
//! moves fast (an assist, a road's kick) the arm's inertia, moving with the rim, passes a
//! share of it to the hand at once; (E.3) follows that where (E.2) alone could not.
//!
//! Allocation-free and a handful of multiplications a tick: it runs on the haptic thread. It
//! only *observes*: nothing it computes is ever commanded.

use serde::{Deserialize, Serialize};

/// Commands remembered for the actuation delay and the estimate's lag (ticks).
const HISTORY: usize = 128;

/// How long before the angle it is computed from the hand's torque estimate is (`3/ω₀`,
/// [`BANDWIDTH_RAD_S`]), s: a reader pairs the estimate with the wheel's motion of that time.
pub const HAND_ESTIMATE_LAG_S: f64 = 0.05;

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
    /// Half range of motion before the end stop, rad (infinite: no stop modelled).
    pub half_range_rad: f64,
    /// Stiffness of the end stop beyond the range, N·m/rad.
    pub end_stop_nm_per_rad: f64,
    /// Damping of the end stop beyond the range, N·m·s/rad.
    pub end_stop_nm_s_per_rad: f64,
}

impl WheelDynamics {
    /// A consumer force-feedback wheel of the thesis's class when nothing was measured:
    /// the simulated wheel's defaults (0.02 kg·m², 0.02 N·m·s/rad, 0.03 N·m, 2 ms of USB); its
    /// end stop not modelled (not measured).
    pub const NOMINAL: Self = Self {
        inertia_kg_m2: 0.02,
        viscous_nm_s_per_rad: 0.02,
        coulomb_nm: 0.03,
        delay_ticks: 3,
        half_range_rad: f64::INFINITY,
        end_stop_nm_per_rad: 0.0,
        end_stop_nm_s_per_rad: 0.0,
    };
}

/// How near its end stop the rim must be for the estimate to be absent, rad (1°).
pub const STOP_MARGIN_RAD: f64 = 0.0175;

/// Bandwidth `ω₀` of (E.1), rad/s: `3/ω₀` is the estimate's stated lag
/// ([`HAND_ESTIMATE_LAG_S`]; higher would be less late and let more encoder quantisation
/// through, `≈ J ω₀² Δθ` of noise).
pub const BANDWIDTH_RAD_S: f64 = 3.0 / HAND_ESTIMATE_LAG_S;

/// Tuning of the [`HandTorqueObserver`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ObserverTuning {
    /// Velocity `v_c` below which the Coulomb term of (E.1) fades linearly to zero, rad/s
    /// (the wheel at rest holds any torque within ±τ_c: unobservable).
    pub coulomb_fade_rad_s: f64,
}

impl Default for ObserverTuning {
    fn default() -> Self {
        Self {
            coulomb_fade_rad_s: 0.05,
        }
    }
}

/// The observer of eq. (E.1)–(E.3). Call [`step`](Self::step) with each tick's measured
/// angle, then [`commit`](Self::commit) with the torque sent to the motor that tick.
#[derive(Clone, Debug)]
pub struct HandTorqueObserver {
    wheel: WheelDynamics,
    tuning: ObserverTuning,
    angle_rad: f64,
    vel_rad_s: f64,
    hand_nm: f64,
    /// The acting torque through the three poles of `L(s)`, N·m (E.3).
    lagged_act_nm: [f64; 3],
    estimate_nm: f64,
    /// Ticks since the rim was last at its end stop.
    since_stop_ticks: usize,
    started: bool,
    sent: [f64; HISTORY],
    next: usize,
}

impl HandTorqueObserver {
    /// An observer of `wheel`, at rest until the first angle.
    pub fn new(wheel: WheelDynamics, tuning: ObserverTuning) -> Self {
        let wheel = WheelDynamics {
            delay_ticks: wheel.delay_ticks.min(HISTORY / 2 - 2),
            ..wheel
        };
        Self {
            wheel,
            tuning,
            angle_rad: 0.0,
            vel_rad_s: 0.0,
            hand_nm: 0.0,
            lagged_act_nm: [0.0; 3],
            estimate_nm: 0.0,
            since_stop_ticks: usize::MAX,
            started: false,
            sent: [0.0; HISTORY],
            next: 0,
        }
    }

    /// Observe the angle `angle_rad` measured `dt_s` after the last and return the hand's
    /// torque estimate (E.3), N·m: the torque of the step that angle ended,
    /// [`HAND_ESTIMATE_LAG_S`] earlier; `None` at the end stop (see the module's docs). A
    /// non-finite angle or `dt_s` observes nothing and returns the last estimate.
    pub fn step(&mut self, angle_rad: f64, dt_s: f64) -> Option<f64> {
        if angle_rad.is_finite() && dt_s.is_finite() && dt_s > 0.0 {
            self.observe(angle_rad, dt_s);
        }
        let clear_ticks = 2.0 * HAND_ESTIMATE_LAG_S / dt_s.max(1e-6);
        (self.since_stop_ticks as f64 > clear_ticks).then_some(self.estimate_nm)
    }

    fn observe(&mut self, angle_rad: f64, dt_s: f64) {
        if angle_rad.abs() > self.wheel.half_range_rad - STOP_MARGIN_RAD {
            self.since_stop_ticks = 0;
        } else {
            self.since_stop_ticks = self.since_stop_ticks.saturating_add(1);
        }
        if !self.started {
            self.angle_rad = angle_rad;
            self.started = true;
            return;
        }
        let d = &self.wheel;
        let w = BANDWIDTH_RAD_S;
        let acting = self.acting_nm(0);
        let e = angle_rad - self.angle_rad;
        let fade = self.tuning.coulomb_fade_rad_s.max(1e-9);
        let friction = d.viscous_nm_s_per_rad * self.vel_rad_s
            + d.coulomb_nm * (self.vel_rad_s / fade).clamp(-1.0, 1.0);
        let stop = common::end_stop_nm(
            angle_rad,
            self.vel_rad_s,
            d.half_range_rad,
            d.end_stop_nm_per_rad,
            d.end_stop_nm_s_per_rad,
        );
        let net = acting + stop - friction + self.hand_nm;
        // (E.1)–(E.2), explicit Euler (ω₀·dt ≪ 1 at 1 kHz).
        self.angle_rad += dt_s * (self.vel_rad_s + 3.0 * w * e);
        self.vel_rad_s += dt_s * (net / d.inertia_kg_m2 + 3.0 * w * w * e);
        self.hand_nm += dt_s * (d.inertia_kg_m2 * w * w * w * e);
        let mut lagged = acting;
        for y in &mut self.lagged_act_nm {
            *y += dt_s * w * (lagged - *y);
            lagged = *y;
        }
        // (E.3): the motor's torque of `T` ago in place of its filtered value.
        let lag_ticks = (HAND_ESTIMATE_LAG_S / dt_s)
            .round()
            .clamp(0.0, (HISTORY / 2) as f64) as usize;
        self.estimate_nm = self.hand_nm + lagged - self.acting_nm(lag_ticks);
    }

    /// The torque acting on the wheel over the coming step, `earlier` ticks before: the one
    /// sent `delay_ticks` ticks before that (at least one: the observer steps before this
    /// tick's command is sent), N·m.
    fn acting_nm(&self, earlier: usize) -> f64 {
        let back = self.wheel.delay_ticks.max(1) + earlier;
        self.sent[(self.next + HISTORY - back % HISTORY) % HISTORY]
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
    /// ω)`. Returns the estimate and the true hand torque it is of (the tick before the angle,
    /// [`HAND_ESTIMATE_LAG_S`] earlier), from 0.5 s on.
    fn run(hand: impl Fn(f64, f64, f64) -> f64) -> (Vec<f64>, Vec<f64>) {
        let wheel = WheelDynamics {
            coulomb_nm: 0.0,
            delay_ticks: 0,
            ..WheelDynamics::NOMINAL
        };
        let mut obs = HandTorqueObserver::new(wheel, ObserverTuning::default());
        let lag = (HAND_ESTIMATE_LAG_S / 1e-3).round() as usize;
        let (mut th, mut w, mut acting) = (0.0_f64, 0.0_f64, 0.0);
        let (mut est, mut truth, mut hands) = (Vec::new(), Vec::new(), vec![0.0; lag + 1]);
        for k in 0..8000 {
            let t = k as f64 * 1e-3;
            let q = (th / 0.002253).round() * 0.002253;
            let e = obs.step(q, 1e-3).unwrap_or(f64::NAN);
            if k >= 500 {
                est.push(e);
                truth.push(hands[hands.len() - 1 - lag]);
            }
            // Sent now, acting from the next step (delay_ticks = 0, taken as 1).
            let motor = -0.5 * q - 0.05 * obs.vel_rad_s();
            obs.commit(motor);
            let h = hand(t, th, w);
            hands.push(h);
            w += (acting + h - wheel.viscous_nm_s_per_rad * w) / wheel.inertia_kg_m2 * 1e-3;
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
        let (est, truth) = run(|_, _, _| 0.4);
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
        let (est, truth) = run(arm);
        let ratio = rms_error_ratio(&est, &truth);
        assert!(ratio < 0.10, "rms error {ratio:.3} of the rms hand torque");
    }

    #[test]
    fn a_step_of_the_hand_shows_in_the_estimate_after_the_stated_lag() {
        // The hand steps from 0 to 0.3 N·m at 2 s against the spring. Compared with the hand
        // of the stated lag before, the estimate crosses half the step within 15 ms of it
        // and has settled 60 ms after.
        let (est, truth) = run(|t, _, _| if t >= 2.0 { 0.3 } else { 0.0 });
        let step = truth.iter().position(|h| *h > 0.0).unwrap();
        let half = est.iter().position(|e| *e > 0.15).unwrap();
        assert!(half.abs_diff(step) <= 15, "half way {half}, step {step}");
        let before = est[step - 60..step - 40]
            .iter()
            .map(|e| e.abs())
            .fold(0.0, f64::max);
        let after = est[step + 60..step + 200].iter().sum::<f64>() / 140.0;
        assert!(before < 0.05, "the estimate moved {before} N·m early");
        assert!(
            (after - 0.3).abs() < 0.03,
            "the estimate after the step is {after} N·m"
        );
    }

    #[test]
    fn the_estimate_is_absent_at_the_end_stop_and_for_twice_the_lag_after() {
        let wheel = WheelDynamics {
            half_range_rad: 1.0,
            end_stop_nm_per_rad: 50.0,
            ..WheelDynamics::NOMINAL
        };
        let mut obs = HandTorqueObserver::new(wheel, ObserverTuning::default());
        assert!(obs.step(0.5, 1e-3).is_some());
        assert_eq!(obs.step(0.99, 1e-3), None, "within 1° of the stop");
        let clear = (0..200)
            .position(|_| obs.step(0.9, 1e-3).is_some())
            .unwrap();
        assert_eq!(clear, 100, "absent for 2 × 50 ms after leaving the stop");
        assert!(
            obs.step(f64::NAN, 1e-3).is_some(),
            "a bad angle keeps the last estimate"
        );
    }
}
