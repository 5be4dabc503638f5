//! [`HapticChain`]: everything between a wheel reading and a motor torque, called once per
//! tick by the station's haptic loop. Effects + model + external torque (vehicle road feel,
//! assist) → passivity controller → safety supervisor → torque, with per-tick telemetry.
//! No allocation, no locks, no I/O, no clock: time comes in as `now_ns`.

use crate::effects::{EFFECT_SLOTS, Effect, EffectStack, WheelState};
use crate::filter::{KalmanEstimator, KalmanParams, StateEstimator};
use crate::model::{PassivityController, PassivityParams, SpringDamper};
use crate::safety::{Fault, SafetyConfig, Supervisor, WatchdogState};
use crate::wheel::{ConfigError, WheelError, WheelReading};
use serde::{Deserialize, Serialize};

/// Configuration of a [`HapticChain`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HapticChainConfig {
    /// Safety limits (ceiling, slew, soft start, fade, watchdog).
    pub safety: SafetyConfig,
    /// The spring–mass–damper model of eq. 3.5, or none.
    pub model: Option<SpringDamper>,
    /// Passivity controller tuning, or none to disable it.
    pub passivity: Option<PassivityParams>,
    /// Velocity/acceleration estimator tuning.
    pub estimator: KalmanParams,
}

impl HapticChainConfig {
    /// Defaults for a wheel whose encoder step is `encoder_step_rad`: default safety, no
    /// model, passivity on, Kalman estimator tuned for the haptic loop
    /// ([`KalmanParams::for_haptic_loop`]).
    pub fn for_encoder_step(encoder_step_rad: f64) -> Self {
        Self {
            safety: SafetyConfig::default(),
            model: None,
            passivity: Some(PassivityParams::default()),
            estimator: KalmanParams::for_haptic_loop(encoder_step_rad),
        }
    }

    /// Check every part; the error names the field and its allowed range.
    pub fn validate(&self, device_max_nm: f64) -> Result<(), ConfigError> {
        self.safety.validate(device_max_nm)?;
        if let Some(m) = &self.model {
            m.validate()?;
        }
        if let Some(p) = &self.passivity {
            p.validate()?;
        }
        self.estimator.validate()
    }
}

/// What the loop feeds the chain each tick.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TickInput {
    /// Now, ns, on the same clock as the wheel readings' `t_ns`.
    pub now_ns: u64,
    /// This tick's wheel reading; `None` if the read failed.
    pub reading: Option<WheelReading>,
    /// Torque from outside the chain (vehicle road feel, assist controller), N·m.
    pub external_nm: f64,
}

/// Per-tick record for the recorder (MCAP) and the live display.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct TickTelemetry {
    /// Now, ns.
    pub now_ns: u64,
    /// Time since the previous tick, s (0 on the first tick).
    pub dt_s: f64,
    /// Estimated angle, rad.
    pub angle_rad: f64,
    /// Estimated velocity, rad/s.
    pub vel_rad_s: f64,
    /// Estimated acceleration, rad/s².
    pub acc_rad_s2: f64,
    /// Sum of the effect stack after its own clamp, N·m.
    pub effects_nm: f64,
    /// The model's torque, N·m.
    pub model_nm: f64,
    /// The external torque as given, N·m.
    pub external_nm: f64,
    /// Damping added by the passivity controller, N·m·s/rad.
    pub passivity_damping_nm_s_per_rad: f64,
    /// Passivity observer energy, J (negative: the environment generated energy).
    pub passivity_energy_j: f64,
    /// The torque requested before safety, N·m.
    pub requested_nm: f64,
    /// The torque to send, N·m.
    pub torque_nm: f64,
    /// The effect stack or the safety limiter clipped this tick.
    pub clipped: bool,
    /// A non-finite value was rejected this tick.
    pub rejected_non_finite: bool,
    /// Soft-start / fade scale, 0..=1.
    pub safety_scale: f64,
    /// The watchdog's state.
    pub watchdog: WatchdogState,
}

impl TickTelemetry {
    /// The watchdog's fault this tick, if any.
    pub fn fault(&self) -> Option<Fault> {
        match self.watchdog {
            WatchdogState::Fault(f) => Some(f),
            _ => None,
        }
    }
}

/// The haptic pipeline the 1 kHz loop calls once per tick. Per tick:
///
/// 1. estimate angle, velocity and acceleration from the quantised reading (Kalman);
/// 2. render the effect stack (sum, one clamp) and the eq. 3.5 model, add the external torque;
/// 3. the passivity controller adds damping if the rendered environment went active;
/// 4. the supervisor applies soft start / fade, watchdog, ceiling and slew limit;
/// 5. the passivity observer records what was actually sent.
///
/// # Example
///
/// The station's haptic loop, here against the simulated wheel (with a real wheel, `now_ns`
/// comes from the backend's clock, e.g. `evdev_wheel::monotonic_ns()`):
///
/// ```
/// use haptic_wheel::*;
///
/// let mut wheel = ZeroTorqueOnDrop::new(SimWheel::new(SimWheelParams::default()));
/// let cfg = HapticChainConfig {
///     model: Some(SpringDamper { k_nm_per_rad: 0.8, ..Default::default() }),
///     ..HapticChainConfig::for_encoder_step(THESIS_KA_RAD_PER_UNIT)
/// };
/// let mut chain = HapticChain::new(cfg, wheel.max_torque_nm())?;
/// let bump = chain.effects_mut().add(Effect {
///     duration_s: Some(0.2),
///     ..Effect::new(EffectKind::Constant { level_nm: 0.5 })
/// })?;
/// chain.effects_mut().play(bump)?;
/// wheel.set_state(0.3, 0.0);
/// for _ in 0..2000 {
///     let reading = wheel.read().ok();
///     let tel = chain.tick(TickInput { now_ns: wheel.time_ns(), reading, external_nm: 0.0 });
///     wheel.command_torque(tel.torque_nm)?;
///     assert!(tel.torque_nm.abs() <= THESIS_WHEEL_MAX_TORQUE_NM);
///     wheel.advance(1e-3, 0.0); // the patient's hand torque goes here
/// }
/// assert!(wheel.true_angle_rad().abs() < 0.3, "the spring pulled the wheel back");
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug)]
pub struct HapticChain {
    effects: EffectStack,
    model: Option<SpringDamper>,
    passivity: Option<PassivityController>,
    estimator: KalmanEstimator,
    supervisor: Supervisor,
    device_max_nm: f64,
    last_ns: Option<u64>,
    state: WheelState,
    angle_rad: Option<f64>,
}

impl HapticChain {
    /// A chain for a device producing at most `device_max_nm`, with a validated `config`.
    pub fn new(config: HapticChainConfig, device_max_nm: f64) -> Result<Self, WheelError> {
        config.validate(device_max_nm)?;
        Ok(Self {
            effects: EffectStack::new(device_max_nm),
            model: config.model,
            passivity: config.passivity.map(PassivityController::new).transpose()?,
            estimator: KalmanEstimator::new(config.estimator)?,
            supervisor: Supervisor::new(config.safety, device_max_nm)?,
            device_max_nm,
            last_ns: None,
            state: WheelState::default(),
            angle_rad: None,
        })
    }

    /// The effect stack, to add, play, stop and modify effects between ticks.
    pub fn effects_mut(&mut self) -> &mut EffectStack {
        &mut self.effects
    }

    /// The effect stack.
    pub fn effects(&self) -> &EffectStack {
        &self.effects
    }

    /// Replace the haptic model (e.g. a new regimen); validated first.
    pub fn set_model(&mut self, model: Option<SpringDamper>) -> Result<(), WheelError> {
        if let Some(m) = &model {
            m.validate()?;
        }
        self.model = model;
        Ok(())
    }

    /// Replace the effects, model and (if given) ceiling with `regimen`'s, starting every
    /// effect. All or nothing: an invalid regimen is refused and the chain is unchanged.
    /// Does not allocate (the regimen was built beforehand).
    pub fn apply_regimen(&mut self, regimen: &HapticRegimen) -> Result<(), WheelError> {
        regimen.validate(self.device_max_nm)?;
        if let Some(c) = regimen.ceiling_nm {
            self.set_ceiling_nm(c)?;
        }
        self.model = regimen.model;
        self.effects.clear();
        for e in &regimen.effects {
            // Validated above and the stack is empty with room for all of them.
            let id = self
                .effects
                .add(*e)
                .map_err(|err| ConfigError(err.to_string()))?;
            self.effects
                .play(id)
                .map_err(|err| ConfigError(err.to_string()))?;
        }
        Ok(())
    }

    /// Change the per-patient ceiling, never above the device maximum.
    pub fn set_ceiling_nm(&mut self, ceiling_nm: f64) -> Result<(), WheelError> {
        self.supervisor
            .set_ceiling_nm(ceiling_nm, self.device_max_nm)
    }

    /// The ceiling in force, N·m.
    pub fn ceiling_nm(&self) -> f64 {
        self.supervisor.ceiling_nm()
    }

    /// Fade out to zero and stop for good (session end, lost enable, shutdown signal).
    pub fn request_stop(&mut self) {
        self.supervisor.request_stop();
    }

    /// Pause the torque (fade to zero and hold) or resume it (soft start); see
    /// [`Supervisor::set_paused`].
    pub fn set_paused(&mut self, paused: bool) {
        self.supervisor.set_paused(paused);
    }

    /// The latest state estimate.
    pub fn state(&self) -> WheelState {
        self.state
    }

    /// One tick: see the type's documentation. Always returns a finite torque within the
    /// ceiling and slew limit.
    pub fn tick(&mut self, input: TickInput) -> TickTelemetry {
        let dt_s = self
            .last_ns
            .map_or(0.0, |t| input.now_ns.saturating_sub(t) as f64 * 1e-9);
        self.last_ns = Some(input.now_ns);
        let prev = self.state;
        if let Some(r) = input.reading {
            self.state = self.estimator.update(r.angle_rad, dt_s.max(1e-6));
            if r.angle_rad.is_finite() {
                self.angle_rad = Some(r.angle_rad);
            }
        }
        let s = self.state;
        let fx = self.effects.render(input.now_ns, &s);
        let model_nm = self.model.map_or(0.0, |m| m.torque_for(&s));
        let external_nm = input.external_nm;
        let mut requested = fx.torque_nm + model_nm + external_nm;
        let mut passive = fx.condition_nm + model_nm;
        let (mut damping, mut energy) = (0.0, 0.0);
        if let Some(pc) = &mut self.passivity {
            let ceiling = self.supervisor.ceiling_nm();
            let storage = |st: &WheelState| {
                self.effects.storage_j(st) + self.model.map_or(0.0, |m| m.storage_j(st, ceiling))
            };
            // Storage change from the motion only: both states in today's environment.
            let d_storage = storage(&s) - storage(&prev);
            // The quantised reading measures the motion (position-based observer); the
            // estimate stands in when a read failed.
            let angle = self.angle_rad.unwrap_or(s.angle_rad);
            let out = pc.step(requested, angle, s.vel_rad_s, d_storage, dt_s);
            damping = out.damping_nm_s_per_rad;
            energy = out.energy_j;
            passive += out.torque_nm - requested;
            requested = out.torque_nm;
        }
        let sup = self
            .supervisor
            .apply(requested, input.now_ns, input.reading.map(|r| r.t_ns));
        if let Some(pc) = &mut self.passivity {
            // The passive share of what was sent: scaled like the whole request by the soft
            // start / fade and any clipping (same-sign ratio), the whole request's scale
            // otherwise.
            let ratio = if requested.abs() > 1e-9 && sup.torque_nm * requested > 0.0 {
                (sup.torque_nm / requested).clamp(0.0, 1.0)
            } else {
                0.0
            };
            pc.commit(passive * ratio);
        }
        TickTelemetry {
            now_ns: input.now_ns,
            dt_s,
            angle_rad: s.angle_rad,
            vel_rad_s: s.vel_rad_s,
            acc_rad_s2: s.acc_rad_s2,
            effects_nm: fx.torque_nm,
            model_nm,
            external_nm,
            passivity_damping_nm_s_per_rad: damping,
            passivity_energy_j: energy,
            requested_nm: requested,
            torque_nm: sup.torque_nm,
            clipped: fx.clipped || sup.clipped,
            rejected_non_finite: sup.rejected_non_finite,
            safety_scale: sup.scale,
            watchdog: sup.state,
        }
    }
}

/// What a therapist's regimen sets on the haptic chain for one exercise: the effects to
/// play, the eq. 3.5 model and the patient's torque ceiling. Serde (`deny_unknown_fields`)
/// so it travels in the regimen over the network and in TOML; check it with
/// [`HapticRegimen::validate`] before it reaches the haptic thread, then apply it there with
/// [`HapticChain::apply_regimen`] (which validates again and changes nothing on error).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct HapticRegimen {
    /// Effects, all started when the regimen is applied (at most [`EFFECT_SLOTS`]).
    #[schemars(length(max = EFFECT_SLOTS as u32))]
    pub effects: Vec<Effect>,
    /// The spring–mass–damper model, or none.
    pub model: Option<SpringDamper>,
    /// Per-patient ceiling, N·m; `None` keeps the current one. Its maximum is the device's
    /// (the regimen's schema states the strongest wheel's).
    #[schemars(range(min = 0.0))]
    pub ceiling_nm: Option<f64>,
}

impl HapticRegimen {
    /// Check every effect, the model and the ceiling against a device producing at most
    /// `device_max_nm`; the error names the problem.
    pub fn validate(&self, device_max_nm: f64) -> Result<(), ConfigError> {
        if self.effects.len() > EFFECT_SLOTS {
            return Err(ConfigError(format!(
                "regimen.effects has {} effects, allowed at most {EFFECT_SLOTS}",
                self.effects.len()
            )));
        }
        for (i, e) in self.effects.iter().enumerate() {
            e.validate()
                .map_err(|err| ConfigError(format!("regimen.effects[{i}]: {err}")))?;
        }
        if let Some(m) = &self.model {
            m.validate()?;
        }
        if let Some(c) = self.ceiling_nm {
            SafetyConfig {
                ceiling_nm: Some(c),
                ..SafetyConfig::default()
            }
            .validate(device_max_nm)?;
        }
        Ok(())
    }
}

/// Session summary of the haptic loop, accumulated tick by tick without allocation: what
/// the station records next to the per-tick [`TickTelemetry`] (loop timing, clipping time,
/// passivity activity, faults).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct HapticStats {
    /// Ticks seen.
    pub ticks: u64,
    /// Ticks that started later than `late_threshold_ns` after their deadline.
    pub late_ticks: u64,
    /// Largest start lateness, ns.
    pub max_lateness_ns: u64,
    /// Largest time spent inside the tick (read → command), ns.
    pub max_compute_ns: u64,
    /// Total time with the torque clipped (stack clamp, ceiling or slew), s.
    pub clipped_s: f64,
    /// Total time the passivity controller was adding damping, s.
    pub passivity_active_s: f64,
    /// Lowest passivity observer energy seen, J.
    pub min_passivity_energy_j: f64,
    /// Ticks with a watchdog fault.
    pub fault_ticks: u64,
    /// Ticks with a non-finite value rejected.
    pub rejected_ticks: u64,
    /// Largest |torque| sent, N·m.
    pub max_abs_torque_nm: f64,
}

impl HapticStats {
    /// Add one tick: its telemetry, how late it started (`lateness_ns`, now − deadline) and
    /// how long it took (`compute_ns`); a tick counts as late above `late_threshold_ns`.
    pub fn record(
        &mut self,
        t: &TickTelemetry,
        lateness_ns: u64,
        compute_ns: u64,
        late_threshold_ns: u64,
    ) {
        if self.ticks == 0 {
            self.min_passivity_energy_j = t.passivity_energy_j;
        }
        self.ticks += 1;
        self.late_ticks += u64::from(lateness_ns > late_threshold_ns);
        self.max_lateness_ns = self.max_lateness_ns.max(lateness_ns);
        self.max_compute_ns = self.max_compute_ns.max(compute_ns);
        if t.clipped {
            self.clipped_s += t.dt_s;
        }
        if t.passivity_damping_nm_s_per_rad > 0.0 {
            self.passivity_active_s += t.dt_s;
        }
        self.min_passivity_energy_j = self.min_passivity_energy_j.min(t.passivity_energy_j);
        self.fault_ticks += u64::from(t.fault().is_some());
        self.rejected_ticks += u64::from(t.rejected_non_finite);
        self.max_abs_torque_nm = self.max_abs_torque_nm.max(t.torque_nm.abs());
    }

    /// Fraction of the session spent clipped, 0..=1 (0 before the first tick).
    pub fn clipped_fraction(&self, session_s: f64) -> f64 {
        if session_s > 0.0 {
            (self.clipped_s / session_s).clamp(0.0, 1.0)
        } else {
            0.0
        }
    }
}

#[cfg(test)]
mod tests;
