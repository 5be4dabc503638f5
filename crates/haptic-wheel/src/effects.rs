//! Host-side rendering of the DirectInput effect set the thesis toolbox exposed (Appendix B):
//! condition effects (spring, damper, friction, inertia), constant force, ramp, and periodic
//! sine / square / triangle / sawtooth-up / sawtooth-down, each with envelope, duration, start
//! delay and gain; a fixed-capacity [`EffectStack`] that sums them and clamps once.
//!
//! # Units
//!
//! SI inside. Forces are N·m at the steering axis, positive turning the wheel left
//! (counter-clockwise). Condition effects act on one kinematic quantity each:
//!
//! | kind     | metric `m`         | offset, deadband | coefficient      | force law outside the deadband |
//! |----------|--------------------|------------------|------------------|--------------------------------|
//! | spring   | angle θ, rad       | rad              | N·m/rad          | `−c·(m − offset ∓ deadband)`   |
//! | damper   | velocity θ̇, rad/s  | rad/s            | N·m·s/rad        | same                           |
//! | inertia  | acceleration θ̈     | rad/s²           | N·m·s²/rad       | same                           |
//! | friction | velocity θ̇, rad/s  | rad/s            | N·m              | `−c·sat((m − offset ∓ deadband)/v_s)` |
//!
//! with the positive coefficient and saturation used above `offset + deadband` and the
//! negative ones below `offset − deadband`; a positive coefficient resists (restores
//! towards the offset). Friction uses a linear zone of [`FRICTION_SMOOTHING_RAD_S`] instead
//! of a sign function so quantised velocity near zero does not chatter.
//!
//! The toolbox's ±10 000 effect units (and its microsecond times and hundredths-of-degree
//! phase) are converted only at the edge, by [`toolbox::to_effect`] with a
//! [`DeviceProfile`](crate::DeviceProfile) (thesis eq. 3.2–3.3).

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;

/// Number of effects an [`EffectStack`] holds (DirectInput devices commonly offer 10–16).
pub const EFFECT_SLOTS: usize = 16;

/// Width of the friction effect's linear zone around zero velocity, rad/s.
pub const FRICTION_SMOOTHING_RAD_S: f64 = 0.02;

/// What can be wrong with an effect or a stack operation.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum EffectError {
    /// A parameter is not finite or out of its allowed range.
    #[error("effect parameter {field} = {value}, allowed {allowed}")]
    OutOfRange {
        /// The parameter's name.
        field: &'static str,
        /// The rejected value.
        value: f64,
        /// The allowed range, in words.
        allowed: &'static str,
    },
    /// Every slot of the stack is in use.
    #[error("effect stack is full ({EFFECT_SLOTS} effects)")]
    StackFull,
    /// The id does not name a live effect (removed, or from another stack).
    #[error("no such effect {0:?}")]
    NoSuchEffect(EffectId),
}

/// The wheel's kinematic state the condition effects and models read.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WheelState {
    /// Steering angle, rad.
    pub angle_rad: f64,
    /// Angular velocity, rad/s.
    pub vel_rad_s: f64,
    /// Angular acceleration, rad/s².
    pub acc_rad_s2: f64,
}

/// Which kinematic quantity a condition effect reacts to (see the module table).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum ConditionKind {
    /// Reacts to angle.
    Spring,
    /// Reacts to velocity.
    Damper,
    /// Reacts to the sign of velocity, constant magnitude.
    Friction,
    /// Reacts to acceleration.
    Inertia,
}

/// A condition effect (DirectInput `DICONDITION`), in SI; units per kind in the module table.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Condition {
    /// Which quantity the condition reacts to.
    pub kind: ConditionKind,
    /// Centre of the condition (rad, rad/s or rad/s²).
    pub offset: f64,
    /// Coefficient above `offset + deadband`.
    pub positive_coefficient: f64,
    /// Coefficient below `offset − deadband`.
    pub negative_coefficient: f64,
    /// Largest force magnitude above the offset, N·m (≥ 0).
    #[schemars(range(min = 0.0))]
    pub positive_saturation_nm: f64,
    /// Largest force magnitude below the offset, N·m (≥ 0).
    #[schemars(range(min = 0.0))]
    pub negative_saturation_nm: f64,
    /// Half width of the zone around the offset with no force (≥ 0, the metric's unit).
    #[schemars(range(min = 0.0))]
    pub deadband: f64,
}

impl Condition {
    /// A symmetric condition: same coefficient both sides, saturation `sat_nm`, no offset or
    /// deadband.
    pub fn symmetric(kind: ConditionKind, coefficient: f64, sat_nm: f64) -> Self {
        Self {
            kind,
            offset: 0.0,
            positive_coefficient: coefficient,
            negative_coefficient: coefficient,
            positive_saturation_nm: sat_nm,
            negative_saturation_nm: sat_nm,
            deadband: 0.0,
        }
    }

    /// Force of the condition for the wheel state, N·m.
    pub fn torque_nm(&self, s: &WheelState) -> f64 {
        let m = match self.kind {
            ConditionKind::Spring => s.angle_rad,
            ConditionKind::Damper | ConditionKind::Friction => s.vel_rad_s,
            ConditionKind::Inertia => s.acc_rad_s2,
        };
        let d = m - self.offset;
        let (excess, coef, sat) = if d > self.deadband {
            (
                d - self.deadband,
                self.positive_coefficient,
                self.positive_saturation_nm,
            )
        } else if d < -self.deadband {
            (
                d + self.deadband,
                self.negative_coefficient,
                self.negative_saturation_nm,
            )
        } else {
            return 0.0;
        };
        let f = match self.kind {
            ConditionKind::Friction => -coef * (excess / FRICTION_SMOOTHING_RAD_S).clamp(-1.0, 1.0),
            _ => -coef * excess,
        };
        f.clamp(-sat, sat)
    }

    /// Energy stored in a spring condition at `state`, J: the integral of its restoring
    /// force from the deadband edge (saturation included). Zero for the other kinds, which
    /// store nothing (damper, friction) or whose storage is not tracked (inertia). Used by
    /// the passivity observer so a deflected spring's own energy is not mistaken for
    /// energy generation.
    pub fn potential_j(&self, state: &WheelState) -> f64 {
        if self.kind != ConditionKind::Spring {
            return 0.0;
        }
        let d = state.angle_rad - self.offset;
        if d > self.deadband {
            saturated_spring_potential_j(
                self.positive_coefficient,
                self.positive_saturation_nm,
                d - self.deadband,
            )
        } else if d < -self.deadband {
            saturated_spring_potential_j(
                self.negative_coefficient,
                self.negative_saturation_nm,
                -d - self.deadband,
            )
        } else {
            0.0
        }
    }

    fn validate(&self) -> Result<(), EffectError> {
        finite("offset", self.offset)?;
        finite("positive_coefficient", self.positive_coefficient)?;
        finite("negative_coefficient", self.negative_coefficient)?;
        non_negative("positive_saturation_nm", self.positive_saturation_nm)?;
        non_negative("negative_saturation_nm", self.negative_saturation_nm)?;
        non_negative("deadband", self.deadband)
    }
}

/// Potential energy of a spring of stiffness `k` (N·m/rad) whose force saturates at
/// `sat_nm`, deflected by `x` rad (any sign), J. A negative `k` (a repelling, active spring)
/// gives a negative potential of the same shape.
pub fn saturated_spring_potential_j(k: f64, sat_nm: f64, x: f64) -> f64 {
    let (c, x, s) = (k.abs(), x.abs(), sat_nm.max(0.0));
    if c == 0.0 {
        return 0.0;
    }
    let p = if c * x <= s {
        0.5 * c * x * x
    } else {
        s * s / (2.0 * c) + s * (x - s / c)
    };
    k.signum() * p
}

/// Periodic waveform shapes. With phase 0 and `p = (t/T) mod 1`, each shape's unit wave is:
/// sine `sin 2πp`; square `+1` for `p < ½` else `−1`; triangle rising through zero at `p = 0`
/// to `+1` at `p = ¼` and `−1` at `p = ¾` (same zero crossings as the sine); sawtooth-up
/// `2p − 1`; sawtooth-down `1 − 2p`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum Waveform {
    /// Sine.
    Sine,
    /// Square.
    Square,
    /// Triangle.
    Triangle,
    /// Sawtooth rising.
    SawtoothUp,
    /// Sawtooth falling.
    SawtoothDown,
}

impl Waveform {
    /// The unit wave at cycle fraction `p ∈ [0, 1)`.
    pub fn unit(self, p: f64) -> f64 {
        match self {
            Self::Sine => (TAU * p).sin(),
            Self::Square => {
                if p < 0.5 {
                    1.0
                } else {
                    -1.0
                }
            }
            Self::Triangle => {
                if p < 0.25 {
                    4.0 * p
                } else if p < 0.75 {
                    2.0 - 4.0 * p
                } else {
                    4.0 * p - 4.0
                }
            }
            Self::SawtoothUp => 2.0 * p - 1.0,
            Self::SawtoothDown => 1.0 - 2.0 * p,
        }
    }
}

/// A periodic force (DirectInput `DIPERIODIC`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Periodic {
    /// Shape.
    pub waveform: Waveform,
    /// Peak deviation from the offset, N·m (the envelope shapes this).
    pub magnitude_nm: f64,
    /// Mean force, N·m.
    pub offset_nm: f64,
    /// Phase at the effect's start, rad.
    pub phase_rad: f64,
    /// Period, s (> 0).
    #[schemars(extend("exclusiveMinimum" = 0.0))]
    pub period_s: f64,
}

/// What an effect renders.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum EffectKind {
    /// A condition effect; envelopes do not apply (as in DirectInput).
    Condition(Condition),
    /// Constant force, N·m.
    Constant {
        /// The force, N·m.
        level_nm: f64,
    },
    /// Force ramping linearly from `start_nm` to `end_nm` over the effect's (finite) duration.
    Ramp {
        /// Force at the start, N·m.
        start_nm: f64,
        /// Force at the end, N·m.
        end_nm: f64,
    },
    /// A periodic force.
    Periodic(Periodic),
}

/// The envelope (DirectInput `DIENVELOPE`): the magnitude rises linearly from
/// `attack_level_nm` to the effect's own magnitude over `attack_time_s`, holds, and moves
/// linearly to `fade_level_nm` over the last `fade_time_s` of a finite duration.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Envelope {
    /// Magnitude at the start, N·m (≥ 0).
    #[schemars(range(min = 0.0))]
    pub attack_level_nm: f64,
    /// Time to reach the sustain magnitude, s (≥ 0).
    #[schemars(range(min = 0.0))]
    pub attack_time_s: f64,
    /// Magnitude at the end, N·m (≥ 0).
    #[schemars(range(min = 0.0))]
    pub fade_level_nm: f64,
    /// Time over which the magnitude moves to the fade level, s (≥ 0).
    #[schemars(range(min = 0.0))]
    pub fade_time_s: f64,
}

impl Envelope {
    /// The magnitude at local time `t_s` for a sustain magnitude `sustain_nm ≥ 0`.
    fn magnitude(&self, sustain_nm: f64, t_s: f64, duration_s: Option<f64>) -> f64 {
        let mut m = sustain_nm;
        if self.attack_time_s > 0.0 && t_s < self.attack_time_s {
            let a = t_s / self.attack_time_s;
            m = self.attack_level_nm + (sustain_nm - self.attack_level_nm) * a;
        }
        if let Some(d) = duration_s {
            let fade_start = d - self.fade_time_s;
            if self.fade_time_s > 0.0 && t_s > fade_start {
                let a = ((t_s - fade_start) / self.fade_time_s).min(1.0);
                // Fade from whatever the attack phase has reached (they may overlap).
                m += (self.fade_level_nm - m) * a;
            }
        }
        m
    }
}

/// One effect: what it renders and when.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Effect {
    /// What the effect renders.
    pub kind: EffectKind,
    /// Envelope; ignored for conditions.
    pub envelope: Option<Envelope>,
    /// Time from `play` to the effect starting, s (≥ 0). Default 0.
    #[serde(default)]
    #[schemars(range(min = 0.0))]
    pub start_delay_s: f64,
    /// How long the effect plays after its delay, s; `None` plays until stopped.
    #[schemars(extend("exclusiveMinimum" = 0.0))]
    pub duration_s: Option<f64>,
    /// Per-effect gain in [0, 1]. Default 1.
    #[serde(default = "unit_gain")]
    #[schemars(range(min = 0.0, max = 1.0))]
    pub gain: f64,
}

fn unit_gain() -> f64 {
    1.0
}

impl Effect {
    /// An effect of `kind` with no envelope, no delay, infinite duration and unit gain.
    pub fn new(kind: EffectKind) -> Self {
        Self {
            kind,
            envelope: None,
            start_delay_s: 0.0,
            duration_s: None,
            gain: 1.0,
        }
    }

    /// Check every parameter; the error names the field and its allowed range.
    pub fn validate(&self) -> Result<(), EffectError> {
        non_negative("start_delay_s", self.start_delay_s)?;
        if let Some(d) = self.duration_s {
            positive("duration_s", d)?;
        }
        if !(self.gain.is_finite() && (0.0..=1.0).contains(&self.gain)) {
            return Err(EffectError::OutOfRange {
                field: "gain",
                value: self.gain,
                allowed: "[0, 1]",
            });
        }
        if let Some(e) = &self.envelope {
            non_negative("attack_level_nm", e.attack_level_nm)?;
            non_negative("attack_time_s", e.attack_time_s)?;
            non_negative("fade_level_nm", e.fade_level_nm)?;
            non_negative("fade_time_s", e.fade_time_s)?;
        }
        match &self.kind {
            EffectKind::Condition(c) => c.validate(),
            EffectKind::Constant { level_nm } => finite("level_nm", *level_nm),
            EffectKind::Ramp { start_nm, end_nm } => {
                finite("start_nm", *start_nm)?;
                finite("end_nm", *end_nm)?;
                if self.duration_s.is_none() {
                    return Err(EffectError::OutOfRange {
                        field: "duration_s",
                        value: f64::INFINITY,
                        allowed: "finite for a ramp",
                    });
                }
                Ok(())
            }
            EffectKind::Periodic(p) => {
                finite("magnitude_nm", p.magnitude_nm)?;
                finite("offset_nm", p.offset_nm)?;
                finite("phase_rad", p.phase_rad)?;
                positive("period_s", p.period_s)
            }
        }
    }

    /// Whether the effect has ended `elapsed_s` after `play` (never, for infinite duration).
    pub fn finished(&self, elapsed_s: f64) -> bool {
        self.duration_s
            .is_some_and(|d| elapsed_s - self.start_delay_s >= d)
    }

    /// The effect's force `elapsed_s` after `play`, N·m, gain applied, before the stack's
    /// global gain and clamp. Zero before the start delay and after the duration.
    pub fn torque_nm(&self, elapsed_s: f64, state: &WheelState) -> f64 {
        let t = elapsed_s - self.start_delay_s;
        if t < 0.0 || self.finished(elapsed_s) {
            return 0.0;
        }
        let env = |base: f64| match &self.envelope {
            Some(e) => base.signum() * e.magnitude(base.abs(), t, self.duration_s),
            None => base,
        };
        let f = match &self.kind {
            EffectKind::Condition(c) => c.torque_nm(state),
            EffectKind::Constant { level_nm } => env(*level_nm),
            EffectKind::Ramp { start_nm, end_nm } => {
                let d = self.duration_s.unwrap_or(f64::INFINITY);
                let a = if d.is_finite() { t / d } else { 0.0 };
                env(start_nm + (end_nm - start_nm) * a)
            }
            EffectKind::Periodic(p) => {
                let cycles = t / p.period_s + p.phase_rad / TAU;
                let frac = cycles - cycles.floor();
                p.offset_nm + env(p.magnitude_nm) * p.waveform.unit(frac)
            }
        };
        self.gain * f
    }
}

fn finite(field: &'static str, value: f64) -> Result<(), EffectError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(EffectError::OutOfRange {
            field,
            value,
            allowed: "a finite number",
        })
    }
}

fn non_negative(field: &'static str, value: f64) -> Result<(), EffectError> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(EffectError::OutOfRange {
            field,
            value,
            allowed: "finite and >= 0",
        })
    }
}

fn positive(field: &'static str, value: f64) -> Result<(), EffectError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(EffectError::OutOfRange {
            field,
            value,
            allowed: "finite and > 0",
        })
    }
}

/// Handle to an effect in an [`EffectStack`]; stale after the effect is removed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct EffectId {
    slot: u16,
    generation: u32,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Playback {
    Stopped,
    /// `play` was called; the start time is taken at the next render.
    Starting,
    Playing {
        start_ns: u64,
    },
}

#[derive(Clone, Copy, Debug)]
struct Slot {
    effect: Option<Effect>,
    playback: Playback,
    generation: u32,
}

/// The stack's output for one tick.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EffectOutput {
    /// Sum of all playing effects times the global gain, clamped to the stack's limit, N·m.
    pub torque_nm: f64,
    /// The sum exceeded the limit and was clamped.
    pub clipped: bool,
    /// How many effects contributed this tick.
    pub active: u8,
    /// The condition effects' share of the sum (before the clamp), N·m: the passive part of
    /// the environment the passivity controller watches. Constant, ramp and periodic forces
    /// are intentional sources and are bounded by the safety clamp instead.
    pub condition_nm: f64,
}

/// A fixed-capacity set of effects, rendered by summing every playing effect, applying the
/// global gain and clamping once to `limit_nm` (DirectInput composition). No allocation
/// after construction; `render` is O([`EFFECT_SLOTS`]).
#[derive(Clone, Debug)]
pub struct EffectStack {
    slots: [Slot; EFFECT_SLOTS],
    gain: f64,
    limit_nm: f64,
}

impl EffectStack {
    /// An empty stack clamping its sum to `±limit_nm` (the device maximum). A non-finite or
    /// negative limit is replaced by zero (no torque).
    pub fn new(limit_nm: f64) -> Self {
        Self {
            slots: [Slot {
                effect: None,
                playback: Playback::Stopped,
                generation: 0,
            }; EFFECT_SLOTS],
            gain: 1.0,
            limit_nm: if limit_nm.is_finite() && limit_nm > 0.0 {
                limit_nm
            } else {
                0.0
            },
        }
    }

    /// Global gain in [0, 1] (DirectInput `DIPROP_FFGAIN`).
    pub fn set_gain(&mut self, gain: f64) -> Result<(), EffectError> {
        if !(gain.is_finite() && (0.0..=1.0).contains(&gain)) {
            return Err(EffectError::OutOfRange {
                field: "gain",
                value: gain,
                allowed: "[0, 1]",
            });
        }
        self.gain = gain;
        Ok(())
    }

    /// The global gain.
    pub fn gain(&self) -> f64 {
        self.gain
    }

    /// Add a validated effect (stopped). Errors if invalid or the stack is full.
    pub fn add(&mut self, effect: Effect) -> Result<EffectId, EffectError> {
        effect.validate()?;
        let (i, slot) = self
            .slots
            .iter_mut()
            .enumerate()
            .find(|(_, s)| s.effect.is_none())
            .ok_or(EffectError::StackFull)?;
        slot.effect = Some(effect);
        slot.playback = Playback::Stopped;
        Ok(EffectId {
            slot: i as u16,
            generation: slot.generation,
        })
    }

    fn slot_mut(&mut self, id: EffectId) -> Result<&mut Slot, EffectError> {
        self.slots
            .get_mut(id.slot as usize)
            .filter(|s| s.generation == id.generation && s.effect.is_some())
            .ok_or(EffectError::NoSuchEffect(id))
    }

    /// Replace an effect's parameters, keeping its playback state (DirectInput `SetParameters`).
    pub fn set(&mut self, id: EffectId, effect: Effect) -> Result<(), EffectError> {
        effect.validate()?;
        self.slot_mut(id)?.effect = Some(effect);
        Ok(())
    }

    /// Start (or restart) an effect; its clock starts at the next render.
    pub fn play(&mut self, id: EffectId) -> Result<(), EffectError> {
        self.slot_mut(id)?.playback = Playback::Starting;
        Ok(())
    }

    /// Stop an effect (it stays in the stack).
    pub fn stop(&mut self, id: EffectId) -> Result<(), EffectError> {
        self.slot_mut(id)?.playback = Playback::Stopped;
        Ok(())
    }

    /// Remove an effect and free its slot; its id becomes stale.
    pub fn remove(&mut self, id: EffectId) -> Result<(), EffectError> {
        let slot = self.slot_mut(id)?;
        slot.effect = None;
        slot.playback = Playback::Stopped;
        slot.generation = slot.generation.wrapping_add(1);
        Ok(())
    }

    /// Stop and remove every effect.
    pub fn clear(&mut self) {
        for s in &mut self.slots {
            if s.effect.take().is_some() {
                s.generation = s.generation.wrapping_add(1);
            }
            s.playback = Playback::Stopped;
        }
    }

    /// Whether an effect is playing (started and not yet finished).
    pub fn is_playing(&self, id: EffectId) -> bool {
        self.slots
            .get(id.slot as usize)
            .is_some_and(|s| s.generation == id.generation && s.playback != Playback::Stopped)
    }

    /// Render every playing effect at time `now_ns` for wheel state `state`: sum, global
    /// gain, one clamp. Effects whose duration has passed stop.
    pub fn render(&mut self, now_ns: u64, state: &WheelState) -> EffectOutput {
        let mut sum = 0.0;
        let mut condition_nm = 0.0;
        let mut active = 0u8;
        for s in &mut self.slots {
            let Some(effect) = &s.effect else { continue };
            let start_ns = match s.playback {
                Playback::Stopped => continue,
                Playback::Starting => {
                    s.playback = Playback::Playing { start_ns: now_ns };
                    now_ns
                }
                Playback::Playing { start_ns } => start_ns,
            };
            let elapsed_s = now_ns.saturating_sub(start_ns) as f64 * 1e-9;
            if effect.finished(elapsed_s) {
                s.playback = Playback::Stopped;
                continue;
            }
            let f = effect.torque_nm(elapsed_s, state);
            if matches!(effect.kind, EffectKind::Condition(_)) {
                condition_nm += f;
            }
            sum += f;
            active += 1;
        }
        let want = self.gain * sum;
        let want = if want.is_finite() { want } else { 0.0 };
        let torque_nm = want.clamp(-self.limit_nm, self.limit_nm);
        let condition_nm = self.gain * condition_nm;
        EffectOutput {
            torque_nm,
            clipped: torque_nm != want,
            active,
            condition_nm: if condition_nm.is_finite() {
                condition_nm
            } else {
                0.0
            },
        }
    }

    /// Energy stored in the playing spring conditions at `state`, J (gains applied); see
    /// [`Condition::potential_j`]. Reflects the playback state of the last render.
    pub fn storage_j(&self, state: &WheelState) -> f64 {
        self.slots
            .iter()
            .filter(|s| matches!(s.playback, Playback::Playing { .. }))
            .filter_map(|s| s.effect.as_ref())
            .map(|e| match &e.kind {
                EffectKind::Condition(c) => e.gain * c.potential_j(state),
                _ => 0.0,
            })
            .sum::<f64>()
            * self.gain
    }
}

/// The thesis toolbox's effect interface (Appendix B), in its own units, and its conversion
/// to SI with a device profile.
///
/// Toolbox units: forces, coefficients, saturations, offsets and deadbands ±10 000; times in
/// µs; phase in hundredths of a degree (0–35 999); durations `None` for `'inf'`.
pub mod toolbox {
    use super::*;
    use crate::profile::{DeviceProfile, EFFECT_FULL_SCALE_UNITS};

    /// `effect(duration, [envelope], 'type', [type parameters], [1 0])` of Appendix B.
    #[derive(Clone, Copy, Debug, PartialEq)]
    pub struct ToolboxEffect {
        /// Duration, µs; `None` for `'inf'`.
        pub duration_us: Option<f64>,
        /// `[attacklevel attacktime fadelevel fadetime]` (levels 0–10 000, times µs).
        pub envelope: Option<[f64; 4]>,
        /// The type and its parameters.
        pub kind: ToolboxKind,
    }

    /// Effect type and `[type parameters]`.
    #[derive(Clone, Copy, Debug, PartialEq)]
    pub enum ToolboxKind {
        /// `'spring'|'damper'|'friction'|'inertia'`, `[offset positivecoef negativecoef
        /// positivesatu negativesatu deadband]`.
        Condition(ConditionKind, [f64; 6]),
        /// `'constant'`, `[magnitude]`.
        Constant(f64),
        /// `'ramp'`, `[start end]`.
        Ramp(f64, f64),
        /// `'sine'|'square'|…`, `[magnitude offset phase period]` (phase in 1/100°, period µs).
        Periodic(Waveform, [f64; 4]),
    }

    /// Convert a toolbox effect to SI with `profile`'s scales (thesis eq. 3.2–3.3):
    /// force units × `Kt`; condition offsets and deadbands as a fraction of full scale of the
    /// metric (half range for a spring, the profile's full-scale velocity or acceleration
    /// otherwise); coefficients so that coefficient 10 000 gives full force at full scale.
    pub fn to_effect(t: &ToolboxEffect, profile: &DeviceProfile) -> Result<Effect, EffectError> {
        let nm = |u: f64| profile.effect_units_to_nm(u);
        let kind = match t.kind {
            ToolboxKind::Condition(kind, [off, pc, nc, ps, ns, db]) => {
                let full_metric = match kind {
                    ConditionKind::Spring => profile.half_range_rad,
                    ConditionKind::Damper | ConditionKind::Friction => {
                        profile.full_scale_velocity_rad_s
                    }
                    ConditionKind::Inertia => profile.full_scale_acceleration_rad_s2,
                };
                let metric = |u: f64| u / EFFECT_FULL_SCALE_UNITS * full_metric;
                // Friction's coefficient is a force, the others a force per unit of metric.
                let coef = |u: f64| match kind {
                    ConditionKind::Friction => nm(u),
                    _ => nm(u) / full_metric,
                };
                EffectKind::Condition(Condition {
                    kind,
                    offset: metric(off),
                    positive_coefficient: coef(pc),
                    negative_coefficient: coef(nc),
                    positive_saturation_nm: nm(ps),
                    negative_saturation_nm: nm(ns),
                    deadband: metric(db),
                })
            }
            ToolboxKind::Constant(m) => EffectKind::Constant { level_nm: nm(m) },
            ToolboxKind::Ramp(s, e) => EffectKind::Ramp {
                start_nm: nm(s),
                end_nm: nm(e),
            },
            ToolboxKind::Periodic(waveform, [mag, off, phase, period]) => {
                EffectKind::Periodic(Periodic {
                    waveform,
                    magnitude_nm: nm(mag),
                    offset_nm: nm(off),
                    phase_rad: (phase / 100.0).to_radians(),
                    period_s: period * 1e-6,
                })
            }
        };
        let effect = Effect {
            kind,
            envelope: t.envelope.map(|[al, at, fl, ft]| Envelope {
                attack_level_nm: nm(al),
                attack_time_s: at * 1e-6,
                fade_level_nm: nm(fl),
                fade_time_s: ft * 1e-6,
            }),
            start_delay_s: 0.0,
            duration_s: t.duration_us.map(|d| d * 1e-6),
            gain: 1.0,
        };
        effect.validate()?;
        Ok(effect)
    }
}

#[cfg(test)]
mod tests;
