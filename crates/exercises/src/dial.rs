//! The rotary dial tracking task (thesis §3.3.3, Appendix E): the patient turns the wheel so
//! its needle follows a desired angle that moves over time.
//!
//! Appendix E used a sine of ±120° (the wheel's range is ±129°) at 1 rad/s, and a frequency
//! sweep from 0 to 2.5 rad/s over 200 s; both are here ([`DialSignal::Sine`],
//! [`DialSignal::Chirp`]), with multi-sine, step and ramp references.

use std::cell::Cell;

use common::Bound;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::error::{VehicleError, check_range};

/// Largest reference amplitude, deg: the thesis wheel turns ±129°.
pub const MAX_DIAL_AMPLITUDE_DEG: f64 = 129.0;
/// `amplitude_deg` of every signal (a multi-sine's amplitudes together too), deg.
pub const AMPLITUDE_DEG: Bound = Bound::new(0.0, MAX_DIAL_AMPLITUDE_DEG);
/// Every frequency (`frequency_rad_s`, a chirp's `start_rad_s` and `end_rad_s`), rad/s.
pub const FREQUENCY_RAD_S: Bound = Bound::new(0.0, 10.0);
/// A multi-sine component's `phase_rad`, rad.
pub const PHASE_RAD: Bound = Bound::new(-100.0, 100.0);
/// How many components a multi-sine has.
pub const COMPONENTS: Bound = Bound::new(1.0, 16.0);
/// A step's `hold_s`, s.
pub const HOLD_S: Bound = Bound::new(0.5, 600.0);
/// A ramp's `rate_deg_s`, deg/s.
pub const RATE_DEG_S: Bound = Bound::new(1.0, 720.0);
/// A random step's `min_hold_s` and `max_hold_s`, s.
pub const RANDOM_HOLD_S: Bound = Bound::new(0.5, 60.0);
/// A chirp's `sweep_s`, s.
pub const SWEEP_S: Bound = Bound::new(1.0, 3600.0);
/// How far a dial exercise's target centre may drift over it (`drift_deg`), deg: the wheel's
/// range each way.
pub const DRIFT_DEG: Bound = Bound::new(-MAX_DIAL_AMPLITUDE_DEG, MAX_DIAL_AMPLITUDE_DEG);

/// A dial exercise's target: its signal around a centre that drifts linearly from 0 at the
/// start to `drift_rad` at `over_s` (then stays), the sum held within the wheel's range
/// (±[`MAX_DIAL_AMPLITUDE_DEG`]). Positive angles are to the patient's left.
#[derive(Clone, Debug, PartialEq)]
pub struct DialTarget {
    /// The signal around the centre.
    pub signal: DialSignal,
    /// Where the centre is at the end, rad (0: no drift).
    pub drift_rad: f64,
    /// How long the drift takes, s (the exercise's length).
    pub over_s: f64,
    /// Where [`DialSignal::RandomSteps`] was last found, so that each tick walks on from
    /// there instead of from the exercise's start (the 1 kHz loop's work stays constant however
    /// long the exercise runs).
    cursor: Cell<StepCursor>,
}

impl DialTarget {
    /// `signal` around a centre that drifts to `drift_rad` over `over_s`.
    pub fn new(signal: DialSignal, drift_rad: f64, over_s: f64) -> Self {
        Self {
            signal,
            drift_rad,
            over_s,
            cursor: Cell::default(),
        }
    }

    /// `signal` around a centre that stays at 0.
    pub fn steady(signal: DialSignal) -> Self {
        Self::new(signal, 0.0, 1.0)
    }

    /// The centre at `t_s` since the start, rad.
    pub fn centre_rad(&self, t_s: f64) -> f64 {
        if self.drift_rad == 0.0 || self.over_s <= 0.0 {
            return 0.0;
        }
        self.drift_rad * (t_s / self.over_s).clamp(0.0, 1.0)
    }

    /// Desired wheel angle at `t_s` since the start: the signal around the drifting centre,
    /// within the wheel's range, rad.
    pub fn desired_angle_rad(&self, t_s: f64) -> f64 {
        let max_rad = MAX_DIAL_AMPLITUDE_DEG.to_radians();
        (self.signal.desired_angle_rad_from(t_s, &self.cursor) + self.centre_rad(t_s))
            .clamp(-max_rad, max_rad)
    }
}

/// One sine component of a multi-sine reference.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SineComponent {
    /// Amplitude, deg of wheel angle.
    #[schemars(range(min = AMPLITUDE_DEG.min, max = AMPLITUDE_DEG.max))]
    pub amplitude_deg: f64,
    /// Angular frequency, rad/s.
    #[schemars(range(min = FREQUENCY_RAD_S.min, max = FREQUENCY_RAD_S.max))]
    pub frequency_rad_s: f64,
    /// Phase, rad.
    #[serde(default)]
    #[schemars(range(min = PHASE_RAD.min, max = PHASE_RAD.max))]
    pub phase_rad: f64,
}

/// Desired wheel angle over time. TOML: a table with `signal = "sine" | "multi-sine" | "step"
/// | "ramp" | "chirp"` and the variant's fields.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(tag = "signal", rename_all = "kebab-case", deny_unknown_fields)]
pub enum DialSignal {
    /// `A sin(ω t)`: Appendix E's reference (A = 120°, ω = 1 rad/s).
    Sine {
        /// Amplitude, deg.
        #[schemars(range(min = AMPLITUDE_DEG.min, max = AMPLITUDE_DEG.max))]
        amplitude_deg: f64,
        /// Angular frequency, rad/s.
        #[schemars(range(min = FREQUENCY_RAD_S.min, max = FREQUENCY_RAD_S.max))]
        frequency_rad_s: f64,
    },
    /// A sum of sines (harder to anticipate than one sine).
    MultiSine {
        /// The components; their amplitudes together must stay within ±129°.
        #[schemars(length(min = COMPONENTS.min as u32, max = COMPONENTS.max as u32))]
        components: Vec<SineComponent>,
    },
    /// Steps between +A and −A, holding each level for `hold_s` (starts at +A).
    Step {
        /// Step height from centre, deg.
        #[schemars(range(min = AMPLITUDE_DEG.min, max = AMPLITUDE_DEG.max))]
        amplitude_deg: f64,
        /// Time at each level, s.
        #[schemars(range(min = HOLD_S.min, max = HOLD_S.max))]
        hold_s: f64,
    },
    /// Steps of one size at unpredictable times: the target rests at the centre, jumps to
    /// +A or −A, back to the centre, and so on, each level held a time drawn evenly from
    /// [`min_hold_s`, `max_hold_s`] and each side drawn from `seed` (the same seed, the same
    /// steps). Every step is `amplitude_deg` high, so each is one discrete movement of the
    /// same size (the standard assessment's steps, `exercises::assessment`).
    RandomSteps {
        /// Step height from centre, deg.
        #[schemars(range(min = AMPLITUDE_DEG.min, max = AMPLITUDE_DEG.max))]
        amplitude_deg: f64,
        /// Shortest time at a level, s.
        #[schemars(range(min = RANDOM_HOLD_S.min, max = RANDOM_HOLD_S.max))]
        min_hold_s: f64,
        /// Longest time at a level, s (at least `min_hold_s`).
        #[schemars(range(min = RANDOM_HOLD_S.min, max = RANDOM_HOLD_S.max))]
        max_hold_s: f64,
        /// Draws the hold times and sides.
        seed: u32,
    },
    /// Constant-speed sweeps between −A and +A (a triangle wave, starting at 0 going up).
    Ramp {
        /// Turning point, deg.
        #[schemars(range(min = AMPLITUDE_DEG.min, max = AMPLITUDE_DEG.max))]
        amplitude_deg: f64,
        /// Wheel speed, deg/s.
        #[schemars(range(min = RATE_DEG_S.min, max = RATE_DEG_S.max))]
        rate_deg_s: f64,
    },
    /// Linear frequency sweep `A sin(ω0 t + (ω1 − ω0) t²/(2T))`, Appendix E's frequency test.
    Chirp {
        /// Amplitude, deg.
        #[schemars(range(min = AMPLITUDE_DEG.min, max = AMPLITUDE_DEG.max))]
        amplitude_deg: f64,
        /// Start frequency ω0, rad/s.
        #[schemars(range(min = FREQUENCY_RAD_S.min, max = FREQUENCY_RAD_S.max))]
        start_rad_s: f64,
        /// Frequency ω1 reached at `sweep_s`, rad/s.
        #[schemars(range(min = FREQUENCY_RAD_S.min, max = FREQUENCY_RAD_S.max))]
        end_rad_s: f64,
        /// Sweep duration T, s (the frequency stays at ω1 afterwards).
        #[schemars(range(min = SWEEP_S.min, max = SWEEP_S.max))]
        sweep_s: f64,
    },
}

impl Default for DialSignal {
    fn default() -> Self {
        DialSignal::Sine {
            amplitude_deg: 120.0,
            frequency_rad_s: 1.0,
        }
    }
}

impl DialSignal {
    /// Short name: `sine`, `multi-sine`, `step`, `ramp`, `chirp`.
    pub fn name(&self) -> &'static str {
        match self {
            DialSignal::Sine { .. } => "sine",
            DialSignal::MultiSine { .. } => "multi-sine",
            DialSignal::Step { .. } => "step",
            DialSignal::RandomSteps { .. } => "random-steps",
            DialSignal::Ramp { .. } => "ramp",
            DialSignal::Chirp { .. } => "chirp",
        }
    }

    /// Default reference of each kind, by [`DialSignal::name`].
    pub fn default_named(name: &str) -> Option<Self> {
        Some(match name {
            "sine" => Self::default(),
            "multi-sine" => DialSignal::MultiSine {
                components: vec![
                    SineComponent {
                        amplitude_deg: 60.0,
                        frequency_rad_s: 0.5,
                        phase_rad: 0.0,
                    },
                    SineComponent {
                        amplitude_deg: 30.0,
                        frequency_rad_s: 1.3,
                        phase_rad: 1.0,
                    },
                    SineComponent {
                        amplitude_deg: 15.0,
                        frequency_rad_s: 2.1,
                        phase_rad: 2.0,
                    },
                ],
            },
            "step" => DialSignal::Step {
                amplitude_deg: 60.0,
                hold_s: 4.0,
            },
            "ramp" => DialSignal::Ramp {
                amplitude_deg: 90.0,
                rate_deg_s: 45.0,
            },
            "chirp" => DialSignal::Chirp {
                amplitude_deg: 120.0,
                start_rad_s: 0.0,
                end_rad_s: 2.5,
                sweep_s: 200.0,
            },
            _ => return None,
        })
    }

    /// Check the parameters; `context` names the exercise in the message.
    pub fn validate(&self, context: &str) -> Result<(), VehicleError> {
        let r = |field: &'static str, v: f64, b: Bound, unit: &str| {
            check_range(context, field, v, b.min, b.max, unit)
        };
        let amp = |v: f64| r("amplitude_deg", v, AMPLITUDE_DEG, "deg");
        let freq = |field: &'static str, v: f64| r(field, v, FREQUENCY_RAD_S, "rad/s");
        match self {
            DialSignal::Sine {
                amplitude_deg,
                frequency_rad_s,
            } => {
                amp(*amplitude_deg)?;
                freq("frequency_rad_s", *frequency_rad_s)
            }
            DialSignal::MultiSine { components } => {
                if components.is_empty() {
                    return Err(VehicleError::OutOfRange {
                        context: context.into(),
                        field: "components",
                        value: 0.0,
                        allowed: "1 to 16 sine components".into(),
                    });
                }
                let n = components.len() as f64;
                r("components", n, COMPONENTS, "sine components")?;
                for c in components {
                    amp(c.amplitude_deg)?;
                    freq("frequency_rad_s", c.frequency_rad_s)?;
                    r("phase_rad", c.phase_rad, PHASE_RAD, "rad")?;
                }
                let total: f64 = components.iter().map(|c| c.amplitude_deg).sum();
                r(
                    "components (sum of amplitude_deg)",
                    total,
                    AMPLITUDE_DEG,
                    "deg",
                )
            }
            DialSignal::Step {
                amplitude_deg,
                hold_s,
            } => {
                amp(*amplitude_deg)?;
                r("hold_s", *hold_s, HOLD_S, "s")
            }
            DialSignal::RandomSteps {
                amplitude_deg,
                min_hold_s,
                max_hold_s,
                ..
            } => {
                amp(*amplitude_deg)?;
                r("min_hold_s", *min_hold_s, RANDOM_HOLD_S, "s")?;
                check_range(
                    context,
                    "max_hold_s",
                    *max_hold_s,
                    *min_hold_s,
                    RANDOM_HOLD_S.max,
                    "s (at least min_hold_s)",
                )
            }
            DialSignal::Ramp {
                amplitude_deg,
                rate_deg_s,
            } => {
                amp(*amplitude_deg)?;
                r("rate_deg_s", *rate_deg_s, RATE_DEG_S, "deg/s")
            }
            DialSignal::Chirp {
                amplitude_deg,
                start_rad_s,
                end_rad_s,
                sweep_s,
            } => {
                amp(*amplitude_deg)?;
                freq("start_rad_s", *start_rad_s)?;
                freq("end_rad_s", *end_rad_s)?;
                r("sweep_s", *sweep_s, SWEEP_S, "s")
            }
        }
    }

    /// Desired wheel angle at time `t_s` since the start, rad.
    pub fn desired_angle_rad(&self, t_s: f64) -> f64 {
        self.desired_angle_rad_from(t_s, &Cell::default())
    }

    /// [`DialSignal::desired_angle_rad`], random steps walked on from `cursor` (and `cursor`
    /// moved to `t_s`'s level): the same angle, without walking every level since the start.
    fn desired_angle_rad_from(&self, t_s: f64, cursor: &Cell<StepCursor>) -> f64 {
        let t = t_s.max(0.0);
        let deg = match self {
            DialSignal::Sine {
                amplitude_deg,
                frequency_rad_s,
            } => amplitude_deg * (frequency_rad_s * t).sin(),
            DialSignal::MultiSine { components } => components
                .iter()
                .map(|c| c.amplitude_deg * (c.frequency_rad_s * t + c.phase_rad).sin())
                .sum(),
            DialSignal::Step {
                amplitude_deg,
                hold_s,
            } => {
                if ((t / hold_s).floor() as u64).is_multiple_of(2) {
                    *amplitude_deg
                } else {
                    -amplitude_deg
                }
            }
            DialSignal::RandomSteps {
                amplitude_deg,
                min_hold_s,
                max_hold_s,
                seed,
            } => {
                let (level, at) =
                    random_step_level(*seed, *min_hold_s, *max_hold_s, t, cursor.get());
                cursor.set(at);
                level * amplitude_deg
            }
            DialSignal::Ramp {
                amplitude_deg,
                rate_deg_s,
            } => {
                if *amplitude_deg == 0.0 {
                    0.0
                } else {
                    // Triangle wave of period 4A/rate, starting at 0 going up.
                    let period = 4.0 * amplitude_deg / rate_deg_s;
                    let ph = (t / period + 0.25).rem_euclid(1.0);
                    amplitude_deg * (1.0 - 4.0 * (ph - 0.5).abs())
                }
            }
            DialSignal::Chirp {
                amplitude_deg,
                start_rad_s,
                end_rad_s,
                sweep_s,
            } => {
                let ts = t.min(*sweep_s);
                let phase = start_rad_s * ts
                    + (end_rad_s - start_rad_s) * ts * ts / (2.0 * sweep_s)
                    + end_rad_s * (t - ts);
                amplitude_deg * phase.sin()
            }
        };
        deg.to_radians()
    }
}

/// SplitMix64 (Steele, Lea & Flood 2014): the `k`-th draw of `seed`, in [0, 1), with no state
/// to carry, so the haptic thread can ask for any step's draw without allocating.
fn draw(seed: u32, k: u64) -> f64 {
    let mut z = u64::from(seed)
        .wrapping_mul(0x9E37_79B9_7F4A_7C15)
        .wrapping_add(k.wrapping_add(1).wrapping_mul(0xBF58_476D_1CE4_E5B9));
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 53) as f64
}

/// A level of [`DialSignal::RandomSteps`] and the time it starts, s.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct StepCursor {
    k: u64,
    start_s: f64,
}

/// Where [`DialSignal::RandomSteps`] rests at `t_s`: 0 at the centre, +1 or −1 at a side, and
/// the level it is in. Level `k` (0 at the centre, odd levels at a side) is held
/// `min + (max − min)·draw(2k)` s; an odd level's side is left when `draw(2k + 1) < 0.5`. The
/// walk starts at `from` when `t_s` is not before it (a level's start is the same sum of holds
/// whichever level the walk starts at), else at the first level.
fn random_step_level(
    seed: u32,
    min_hold_s: f64,
    max_hold_s: f64,
    t_s: f64,
    from: StepCursor,
) -> (f64, StepCursor) {
    let span_s = (max_hold_s - min_hold_s).max(0.0);
    let StepCursor { mut k, mut start_s } = if t_s >= from.start_s {
        from
    } else {
        StepCursor::default()
    };
    loop {
        let hold_s = (min_hold_s + span_s * draw(seed, 2 * k)).max(RANDOM_HOLD_S.min);
        if t_s < start_s + hold_s {
            break;
        }
        start_s += hold_s;
        k += 1;
    }
    let level = match (k % 2, draw(seed, 2 * k + 1) < 0.5) {
        (0, _) => 0.0,
        (_, true) => 1.0,
        (_, false) => -1.0,
    };
    (level, StepCursor { k, start_s })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A dial target walks its random steps on from where the last tick found them: the same
    /// angles as walking from the start every tick, forward in 1 ms ticks over 10 minutes and
    /// after a jump back in time.
    #[test]
    fn random_steps_walked_on_from_the_last_tick_are_the_steps_walked_from_the_start() {
        let signal = DialSignal::RandomSteps {
            amplitude_deg: 20.0,
            min_hold_s: 0.5,
            max_hold_s: 1.0,
            seed: 3,
        };
        let target = DialTarget::steady(signal.clone());
        let times = (0..600_000)
            .map(|i| f64::from(i) * 1e-3)
            .chain([3.2, 590.0, 0.0]);
        for t in times {
            assert_eq!(
                target.desired_angle_rad(t),
                signal.desired_angle_rad(t),
                "t = {t} s"
            );
        }
    }

    /// The random steps of one seed are the same every time, of the one size, at holds
    /// within their bounds, to both sides; another seed steps at other times.
    #[test]
    fn random_steps_are_one_size_within_their_holds_to_both_sides_and_repeat_with_their_seed() {
        let steps = |seed| DialSignal::RandomSteps {
            amplitude_deg: 20.0,
            min_hold_s: 1.5,
            max_hold_s: 4.0,
            seed,
        };
        let s = steps(7);
        s.validate("assessment").unwrap();
        let dt = 0.001;
        let deg: Vec<f64> = (0..120_000)
            .map(|i| s.desired_angle_rad(i as f64 * dt).to_degrees())
            .collect();
        assert_eq!(deg[0], 0.0, "starts at the centre");
        let mut changes = Vec::new();
        for i in 1..deg.len() {
            if deg[i] != deg[i - 1] {
                assert!(((deg[i] - deg[i - 1]).abs() - 20.0).abs() < 1e-9, "{i}");
                changes.push(i as f64 * dt);
            }
        }
        let holds: Vec<f64> = changes.windows(2).map(|w| w[1] - w[0]).collect();
        assert!(holds.len() > 25, "{}", holds.len());
        assert!(
            holds.iter().all(|h| (1.5 - 2e-3..=4.0 + 2e-3).contains(h)),
            "{holds:?}"
        );
        let spread = holds.iter().cloned().fold(0.0, f64::max)
            - holds.iter().cloned().fold(f64::INFINITY, f64::min);
        assert!(spread > 1.5, "the holds vary: {holds:?}");
        assert!(deg.iter().any(|d| *d > 19.0) && deg.iter().any(|d| *d < -19.0));
        let again: Vec<f64> = (0..120_000)
            .map(|i| steps(7).desired_angle_rad(i as f64 * dt).to_degrees())
            .collect();
        assert_eq!(deg, again);
        let other = steps(8);
        assert!((0..60_000).any(|i| other.desired_angle_rad(i as f64 * dt).to_degrees() != deg[i]));
        let bad = DialSignal::RandomSteps {
            amplitude_deg: 20.0,
            min_hold_s: 3.0,
            max_hold_s: 2.0,
            seed: 1,
        };
        let msg = bad.validate("assessment").unwrap_err().to_string();
        assert!(msg.contains("max_hold_s"), "{msg}");
    }

    #[test]
    fn a_drifting_target_starts_at_the_signal_reaches_half_way_at_the_middle_and_the_drift_at_the_end()
     {
        let target = DialTarget::new(
            DialSignal::Sine {
                amplitude_deg: 30.0,
                frequency_rad_s: 1.0,
            },
            40f64.to_radians(),
            60.0,
        );
        let deg = |t: f64| target.desired_angle_rad(t).to_degrees();
        let signal = |t: f64| target.signal.desired_angle_rad(t).to_degrees();
        assert!(
            (deg(0.0) - signal(0.0)).abs() < 1e-9,
            "no drift at the start"
        );
        assert!((deg(30.0) - (signal(30.0) + 20.0)).abs() < 1e-9, "half way");
        assert!(
            (deg(60.0) - (signal(60.0) + 40.0)).abs() < 1e-9,
            "all of it"
        );
        assert!(
            (deg(90.0) - (signal(90.0) + 40.0)).abs() < 1e-9,
            "held after"
        );
        assert_eq!(target.centre_rad(-1.0), 0.0, "nothing before the start");
    }

    #[test]
    fn a_drifting_target_never_leaves_the_wheels_range() {
        let target = DialTarget::new(
            DialSignal::Sine {
                amplitude_deg: 120.0,
                frequency_rad_s: 1.0,
            },
            (-60f64).to_radians(),
            10.0,
        );
        let max = MAX_DIAL_AMPLITUDE_DEG.to_radians();
        let mut clamped = 0;
        for k in 0..=2000 {
            let a = target.desired_angle_rad(k as f64 * 0.01);
            assert!(a.abs() <= max + 1e-12, "{a}");
            clamped += usize::from((a + max).abs() < 1e-12);
        }
        assert!(
            clamped > 0,
            "the drift pushed the sine's trough past the range: clamped"
        );
        assert_eq!(
            DialTarget::steady(DialSignal::default()).desired_angle_rad(1.0),
            DialSignal::default().desired_angle_rad(1.0)
        );
    }

    #[test]
    fn appendix_e_sine_reaches_120_degrees_at_quarter_period() {
        let s = DialSignal::default();
        let t = std::f64::consts::FRAC_PI_2;
        assert!((s.desired_angle_rad(t) - 120f64.to_radians()).abs() < 1e-12);
        s.validate("dial").unwrap();
    }

    #[test]
    fn step_alternates_and_ramp_is_a_triangle() {
        let st = DialSignal::default_named("step").unwrap();
        assert!(st.desired_angle_rad(1.0) > 0.0 && st.desired_angle_rad(5.0) < 0.0);
        let r = DialSignal::Ramp {
            amplitude_deg: 90.0,
            rate_deg_s: 45.0,
        };
        let d = |t: f64| r.desired_angle_rad(t).to_degrees();
        assert!(d(0.0).abs() < 1e-9);
        assert!((d(1.0) - 45.0).abs() < 1e-9 && (d(2.0) - 90.0).abs() < 1e-9);
        assert!((d(3.0) - 45.0).abs() < 1e-9 && (d(6.0) + 90.0).abs() < 1e-9);
    }

    #[test]
    fn chirp_frequency_rises_linearly() {
        let c = DialSignal::default_named("chirp").unwrap();
        // Instantaneous frequency at t is ω0 + (ω1 − ω0) t / T: check by finite difference of phase.
        if let DialSignal::Chirp {
            sweep_s, end_rad_s, ..
        } = c
        {
            let t = sweep_s / 2.0;
            let phase = |t: f64| end_rad_s * t * t / (2.0 * sweep_s);
            let w = (phase(t + 1e-3) - phase(t - 1e-3)) / 2e-3;
            assert!((w - end_rad_s / 2.0).abs() < 1e-9);
        }
        c.validate("dial").unwrap();
    }

    #[test]
    fn validate_rejects_amplitude_beyond_wheel_range() {
        let s = DialSignal::Sine {
            amplitude_deg: 200.0,
            frequency_rad_s: 1.0,
        };
        let msg = s
            .validate("exercise \"dial-sine\"")
            .unwrap_err()
            .to_string();
        assert!(msg.contains("dial-sine") && msg.contains("amplitude_deg") && msg.contains("129"));
        let m = DialSignal::default_named("multi-sine").unwrap();
        m.validate("x").unwrap();
    }

    #[test]
    fn toml_rejects_unknown_keys_and_signals() {
        let ok = "signal = \"sine\"\namplitude_deg = 10.0\nfrequency_rad_s = 1.0\n";
        assert!(toml::from_str::<DialSignal>(ok).is_ok());
        assert!(toml::from_str::<DialSignal>(&format!("{ok}bogus = 1\n")).is_err());
        assert!(toml::from_str::<DialSignal>("signal = \"square\"\n").is_err());
    }
}
