//! The real wheel on Linux: the kernel force-feedback API (`EV_FF`, `EVIOCSFF`) through the
//! `evdev` crate, behind the [`FfDevice`] seam so that every rule below is tested without
//! hardware ([`fake::FakeFfDevice`]).
//!
//! - **Torque in N·m at the motor.** The kernel's constant-force level (±32767) is a fraction
//!   of the motor's full torque, scaled again by the device-wide gain. The level for a torque
//!   τ is `trunc(τ / (max_torque_nm · gain) · 32767)`, truncated towards zero so the motor
//!   never gives more than τ, and τ is first clamped to the profile's usable maximum. An
//!   unknown wheel's profile assumes the strongest plausible motor and caps the usable torque
//!   ([`DeviceProfile::unknown`]), so a commanded N·m is an upper bound on any real motor.
//! - **Readings.** The angle is the kernel's current axis value (`EVIOCGABS`: no queue, so a
//!   slow reader never sees old angles). The input events are drained (non-blocking) every
//!   read: the reading's time is the kernel's time stamp of the newest event when one
//!   arrived, else the time of the read (no event means no change on a live device). A wheel
//!   that sends no event for `max_silence_ms` while a torque is commanded is a hung device
//!   ([`WheelFault::Silent`]); a value outside the declared axis range is
//!   [`WheelFault::OutOfRange`]; ENODEV is [`WheelFault::Unplugged`]. These errors carry no
//!   heap data: the 1 kHz loop makes them every tick while they last.
//! - **Torque out.** One constant-force effect, updated in place with the same id: the
//!   latest value wins, nothing queues. Updates are throttled to the driver's rate policy
//!   ([`DriverFamily::max_update_rate_hz`](haptic_wheel::DriverFamily)); zero is never throttled,
//!   and a held level above a lowered ceiling comes down at once
//!   ([`Wheel::set_torque_ceiling_nm`]). A zero already held is re-sent on the policy's
//!   schedule like any level; an update is due a tenth of the interval early, so the loop's
//!   wake-up jitter costs no updates. Every update written is counted, with the largest gap between
//!   two ([`Wheel::motor_updates`]): the rate that reaches the motor, which the session
//!   reports.
//!   Every effect has a short replay length and is re-played at half of it, so if this
//!   process hangs the motor stops within one length; if it dies, the kernel erases its
//!   effects when the file closes.
//! - **Firmware conditions** (spring, friction: [`EvdevWheel::upload_condition`]) run inside
//!   the wheel, outside the host's safety chain. Their saturations are capped to the usable
//!   torque, and they play only while the haptic loop says the supervisor is running
//!   ([`Wheel::set_firmware_effects_active`]): a pause, fault, stop or exit stops them.
//! - **Unplugged and plugged back in** ([`EvdevWheel::reopen_with`], [`rejoin`]): the same
//!   wheel (same model; the same unit or port preferred) is found again off the haptic thread,
//!   re-initialised as at open, and driven from zero torque; another model is refused.
//! - On open: gain set from the configuration, autocentre off (it would fight the haptic
//!   models). On drop: torque to zero, effects erased, gain back to full and autocentre to
//!   the configured exit value (the kernel cannot report the previous ones).

pub mod calibrate;
pub mod controls;
pub mod device;
pub mod fake;
pub mod rejoin;

use std::path::{Path, PathBuf};

use clock::Clock;
use evdev::{
    AbsoluteAxisCode, FFCondition, FFEffectData, FFEffectKind, FFEnvelope, FFReplay, FFTrigger,
};

pub use controls::{ControlsLook, PedalAxes, WheelControls, button_pressed_within};
pub use device::{AxisState, EffectSlot, FfDevice, KernelDevice, inspect};

use crate::devices::{DeviceClass, classify};
use haptic_wheel::effects::{Condition, ConditionKind};
use haptic_wheel::profile::DeviceProfile;
use haptic_wheel::wheel::{
    ConfigError, MotorUpdates, Wheel, WheelCapabilities, WheelError, WheelFault, WheelReading,
};
use haptic_wheel::wheel_config::{WheelConfig, usable_max_nm};

/// Linux FF direction for "towards the left" (`0x4000`, 90°, input.h); with a positive level
/// this turns the wheel counter-clockwise, our positive torque. Drivers that disagree are
/// corrected by the profile's `torque_sign`.
const DIRECTION_LEFT: u16 = 0x4000;
/// The unused second axis of a condition effect.
const NO_CONDITION: FFCondition = FFCondition {
    right_saturation: 0,
    left_saturation: 0,
    right_coefficient: 0,
    left_coefficient: 0,
    deadband: 0,
    center: 0,
};
/// Full scale of a Linux FF level or coefficient.
pub const LEVEL_FULL_SCALE: f64 = 32_767.0;
/// Most firmware condition effects the backend keeps (room reserved at open).
const MAX_CONDITIONS: usize = 4;

/// Nanoseconds on the real monotonic clock (the station's [`Clock::real`]).
pub fn monotonic_ns() -> u64 {
    clock::monotonic_ns()
}

/// Device nodes of every force-feedback wheel this process can open, sorted.
pub fn find_wheels() -> Vec<PathBuf> {
    crate::devices::event_nodes()
        .unwrap_or_default()
        .into_iter()
        .filter(|p| matches!(inspect(p), Ok(Some(d)) if d.class == DeviceClass::Wheel))
        .collect()
}

fn io_err(device: &str, source: std::io::Error) -> WheelError {
    WheelError::Io {
        device: device.to_string(),
        source,
    }
}

/// The kernel level (±32767) that makes a motor of `motor_nm` at device gain `gain`
/// (fraction) give at most `torque_nm`, with the profile's `torque_sign`; `torque_nm` is first
/// clamped to ±`usable_nm`. Truncated towards zero: the motor never gives more than asked.
pub fn level_for(torque_nm: f64, usable_nm: f64, motor_nm: f64, gain: f64, sign: f64) -> i16 {
    let frac =
        haptic_wheel::wheel_config::motor_fraction(torque_nm, usable_nm, motor_nm, gain, sign);
    (frac * LEVEL_FULL_SCALE).trunc() as i16
}

/// The device-wide force-feedback controls a wheel has.
#[derive(Clone, Copy, Debug)]
struct Controls {
    gain: bool,
    autocenter: bool,
}

impl Controls {
    /// Set `dev` up as the backend drives it, at open and when the wheel is found again: the
    /// configured gain (where it has a gain control), autocentre off (it would fight the
    /// haptic models), one constant-force effect at zero; that effect's slot.
    fn arm<D: FfDevice>(self, dev: &mut D, config: &WheelConfig) -> std::io::Result<EffectSlot> {
        if self.gain {
            dev.set_gain(config.gain_level())?;
        }
        if self.autocenter {
            dev.set_autocenter(0)?;
        }
        dev.upload(constant_data(0, config.effect_length_ms))
    }
}

/// A force-feedback wheel driven through the Linux kernel FF API (by default the real device
/// node; any [`FfDevice`] in tests).
#[derive(Debug)]
pub struct EvdevWheel<D: FfDevice = KernelDevice> {
    dev: D,
    clock: Clock,
    name: String,
    profile: DeviceProfile,
    config: WheelConfig,
    axis: AbsoluteAxisCode,
    centre: f64,
    ka_rad_per_unit: f64,
    usable_nm: f64,
    constant: EffectSlot,
    conditions: Vec<EffectSlot>,
    firmware_conditions: bool,
    /// The device-wide controls it has, set up at open and again when it is found again.
    controls: Controls,
    conditions_active: bool,
    level: i16,
    min_interval_ns: u64,
    last_update_ns: Option<u64>,
    last_play_ns: Option<u64>,
    /// When the newest input event arrived, monotonic ns.
    last_event_ns: u64,
    /// Since when a non-zero torque has been commanded, monotonic ns.
    torque_since_ns: Option<u64>,
    /// The device went away; every call fails fast from now on (until it is found again,
    /// with [`EvdevWheel::reopen_with`]).
    lost: bool,
    /// The uploaded firmware conditions' parameters, to upload again on a re-opened device.
    condition_data: Vec<FFEffectData>,
    /// A re-opened device: the torque stays zero until zero is commanded once.
    zero_first: bool,
    /// Finds the wheel again when it goes away.
    rejoin: Option<rejoin::Rejoin<D>>,
    /// The constant-force updates written to the device (the achieved rate at the motor).
    updates: MotorUpdates,
}

impl EvdevWheel<KernelDevice> {
    /// Open the wheel at `path` (e.g. `/dev/input/event7`) and arm a zero constant force.
    pub fn open(path: &Path, config: WheelConfig, clock: Clock) -> Result<Self, WheelError> {
        let name_of = path.display().to_string();
        let dev = KernelDevice::open(path).map_err(|e| {
            if e.kind() == std::io::ErrorKind::PermissionDenied {
                io_err(
                    &name_of,
                    std::io::Error::new(
                        e.kind(),
                        format!(
                            "{e}; driving force feedback needs write access: {}",
                            crate::devices::UDEV_HINT
                        ),
                    ),
                )
            } else {
                io_err(&name_of, e)
            }
        })?;
        Self::with_device(dev, &name_of, config, clock)
    }

    /// Open the first wheel found.
    pub fn open_first(config: WheelConfig, clock: Clock) -> Result<Self, WheelError> {
        let path = find_wheels().into_iter().next().ok_or_else(|| {
            WheelError::Disconnected(format!(
                "no force-feedback wheel could be opened; {}",
                crate::devices::UDEV_HINT
            ))
        })?;
        Self::open(&path, config, clock)
    }
}

impl<D: FfDevice> EvdevWheel<D> {
    /// Drive `dev` (named `node` in messages) with `config`; the profile is the configured
    /// one, else the built-in one for its USB id, else an unknown wheel's.
    pub fn with_device(
        mut dev: D,
        node: &str,
        config: WheelConfig,
        clock: Clock,
    ) -> Result<Self, WheelError> {
        config.validate()?;
        let traits = dev.traits();
        if classify(&traits) != Some(DeviceClass::Wheel) {
            return Err(WheelError::Unsupported {
                device: node.to_string(),
                reason: format!(
                    "'{}' lacks constant force or a steering axis (force feedback: [{}], axes: [{}])",
                    traits.name,
                    traits.ff_effects.join(", "),
                    traits.abs_axes.join(", ")
                ),
            });
        }
        let (vendor, product) = dev.usb_id();
        let profile = config.resolve_profile(vendor, product);
        profile.validate()?;
        let axis = rejoin::steering_axis(&traits);
        let info = dev.axis(axis).map_err(|e| io_err(node, e))?;
        let span = f64::from(info.maximum) - f64::from(info.minimum);
        if span <= 0.0 {
            return Err(WheelError::Unsupported {
                device: node.to_string(),
                reason: format!("steering axis has an empty range {span}"),
            });
        }
        // Scale from the device's own axis range (Ka of eq. 3.2 for this wheel).
        let ka_rad_per_unit = 2.0 * profile.half_range_rad / span;
        let centre = 0.5 * (f64::from(info.maximum) + f64::from(info.minimum));
        let rate = config.update_rate_for(profile.driver, profile.max_update_rate_hz);
        let firmware_conditions = traits.ff_effects.contains(&"spring");
        let controls = Controls {
            gain: traits.ff_effects.contains(&"gain"),
            autocenter: traits.ff_effects.contains(&"autocenter"),
        };
        let constant = controls
            .arm(&mut dev, &config)
            .map_err(|e| io_err(node, e))?;
        // Without a gain control the device runs at full gain whatever the configuration says.
        // The gain the device really has is the 16-bit level sent, not the fraction asked.
        let gain = if controls.gain {
            haptic_wheel::wheel_config::quantised_gain(config.gain)
        } else {
            1.0
        };
        let now = clock.now_ns();
        Ok(Self {
            dev,
            name: format!("{} ({node})", traits.name),
            usable_nm: usable_max_nm(&profile, gain),
            profile,
            axis,
            centre,
            ka_rad_per_unit,
            constant,
            conditions: Vec::with_capacity(MAX_CONDITIONS),
            firmware_conditions,
            controls,
            conditions_active: false,
            level: 0,
            min_interval_ns: (1e9 / rate).round() as u64,
            last_update_ns: None,
            last_play_ns: None,
            last_event_ns: now,
            torque_since_ns: None,
            lost: false,
            condition_data: Vec::with_capacity(MAX_CONDITIONS),
            zero_first: false,
            rejoin: None,
            updates: MotorUpdates::default(),
            config: WheelConfig { gain, ..config },
            clock,
        })
    }

    /// The last level sent to the kernel, ±32767.
    pub fn sent_level(&self) -> i16 {
        self.level
    }

    /// The minimum time between torque updates this wheel's rate policy allows, ns.
    pub fn min_update_interval_ns(&self) -> u64 {
        self.min_interval_ns
    }

    /// The device-wide gain in force, fraction of full.
    pub fn gain(&self) -> f64 {
        self.config.gain
    }

    /// The device under the backend (tests inspect a fake through it).
    pub fn device(&self) -> &D {
        &self.dev
    }

    fn lose(&mut self) -> WheelError {
        self.lost = true;
        self.updates.interrupted();
        self.want_rejoin();
        WheelError::Fault(WheelFault::Unplugged)
    }

    /// The kernel level for `torque_nm` N·m with the torque sign `sign` (±1); a lost wheel
    /// is refused, and so is a non-finite torque, with zero sent.
    fn level_within(&mut self, torque_nm: f64, sign: f64) -> Result<i16, WheelError> {
        if self.lost {
            return Err(WheelError::Fault(WheelFault::Unplugged));
        }
        if !torque_nm.is_finite() {
            self.send(0, self.clock.now_ns())?;
            return Err(WheelError::NonFiniteTorque(torque_nm));
        }
        let (usable, motor, gain) = (self.usable_nm, self.profile.max_torque_nm, self.config.gain);
        Ok(level_for(torque_nm, usable, motor, gain, sign))
    }

    fn send(&mut self, level: i16, now_ns: u64) -> Result<(), WheelError> {
        let len = self.config.effect_length_ms;
        if self
            .dev
            .update(self.constant, constant_data(level, len))
            .is_err()
        {
            return Err(self.lose());
        }
        self.updates.written(now_ns);
        if level != 0 && self.level == 0 {
            self.torque_since_ns = Some(now_ns);
        } else if level == 0 {
            self.torque_since_ns = None;
        }
        self.level = level;
        self.last_update_ns = Some(now_ns);
        let rearm_ns = u64::from(len) * 1_000_000 / 2;
        if self
            .last_play_ns
            .is_none_or(|t| now_ns.saturating_sub(t) >= rearm_ns)
        {
            if self.dev.play(self.constant).is_err() {
                return Err(self.lose());
            }
            if self.conditions_active {
                for i in 0..self.conditions.len() {
                    if self.dev.play(self.conditions[i]).is_err() {
                        return Err(self.lose());
                    }
                }
            }
            self.last_play_ns = Some(now_ns);
        }
        Ok(())
    }

    /// Upload a spring or friction condition to the wheel's firmware, with its saturations
    /// capped to `budget_nm` and to the wheel's usable torque. Returns the torque it may add
    /// (its larger saturation): lower the [`HapticChain`](haptic_wheel::HapticChain) ceiling by that
    /// much so host torque + firmware torque stays under the patient's ceiling. It plays only
    /// while [`Wheel::set_firmware_effects_active`] says so, and is erased on drop.
    pub fn upload_condition(&mut self, c: &Condition, budget_nm: f64) -> Result<f64, WheelError> {
        let unsupported = |reason: &str| WheelError::Unsupported {
            device: self.name.clone(),
            reason: reason.to_string(),
        };
        if !self.firmware_conditions {
            return Err(unsupported(
                "the driver offers no firmware condition effects",
            ));
        }
        if self.conditions.len() >= MAX_CONDITIONS {
            return Err(unsupported("four firmware conditions are already uploaded"));
        }
        if !(budget_nm.is_finite() && budget_nm >= 0.0) {
            return Err(ConfigError(format!(
                "condition budget_nm = {budget_nm}, allowed finite and >= 0"
            ))
            .into());
        }
        let budget_nm = budget_nm.min(self.usable_nm);
        // Level 1.0 is the motor's full torque at the gain in force.
        let full_nm = self.profile.max_torque_nm * self.config.gain;
        let half = self.profile.half_range_rad;
        let pos_sat = c.positive_saturation_nm.clamp(0.0, budget_nm);
        let neg_sat = c.negative_saturation_nm.clamp(0.0, budget_nm);
        let coef = |k: f64| -> i16 {
            let units = match c.kind {
                ConditionKind::Spring => k * half / full_nm,
                _ => k / full_nm,
            };
            (units.clamp(-1.0, 1.0) * LEVEL_FULL_SCALE).trunc() as i16
        };
        // Truncated: the firmware never pushes harder than the budget.
        let sat = |s: f64| ((s / full_nm).clamp(0.0, 1.0) * f64::from(u16::MAX)).trunc() as u16;
        let metric_full = match c.kind {
            ConditionKind::Spring => half,
            _ => self.profile.full_scale_velocity_rad_s,
        };
        let cond = FFCondition {
            right_saturation: sat(pos_sat),
            left_saturation: sat(neg_sat),
            right_coefficient: coef(c.positive_coefficient),
            left_coefficient: coef(c.negative_coefficient),
            deadband: ((c.deadband / metric_full).clamp(0.0, 1.0) * LEVEL_FULL_SCALE).round()
                as u16,
            center: ((self.profile.angle_sign * c.offset / metric_full).clamp(-1.0, 1.0)
                * LEVEL_FULL_SCALE)
                .round() as i16,
        };
        let kind = match c.kind {
            ConditionKind::Spring => FFEffectKind::Spring {
                condition: [cond, NO_CONDITION],
            },
            ConditionKind::Friction => FFEffectKind::Friction {
                condition: [cond, NO_CONDITION],
            },
            ConditionKind::Damper | ConditionKind::Inertia => {
                return Err(unsupported(
                    "damper and inertia are rendered on the host (evdev 0.13 cannot upload their coefficients)",
                ));
            }
        };
        let data = FFEffectData {
            direction: DIRECTION_LEFT,
            trigger: FFTrigger::default(),
            replay: FFReplay {
                length: self.config.effect_length_ms,
                delay: 0,
            },
            kind,
        };
        let slot = self.dev.upload(data).map_err(|e| io_err(&self.name, e))?;
        if self.conditions_active {
            self.dev.play(slot).map_err(|e| io_err(&self.name, e))?;
        }
        self.conditions.push(slot);
        self.condition_data.push(data);
        Ok(pos_sat.max(neg_sat))
    }

    /// Erase every firmware condition effect.
    pub fn clear_conditions(&mut self) {
        self.condition_data.clear();
        for slot in self.conditions.drain(..) {
            let _ = self.dev.stop(slot);
            self.dev.erase(slot);
        }
    }
}

fn constant_data(level: i16, length_ms: u16) -> FFEffectData {
    FFEffectData {
        direction: DIRECTION_LEFT,
        trigger: FFTrigger::default(),
        replay: FFReplay {
            length: length_ms,
            delay: 0,
        },
        kind: FFEffectKind::Constant {
            level,
            envelope: FFEnvelope {
                attack_length: 0,
                attack_level: 0,
                fade_length: 0,
                fade_level: 0,
            },
        },
    }
}

impl<D: FfDevice> Wheel for EvdevWheel<D> {
    fn read(&mut self) -> Result<WheelReading, WheelError> {
        // A lost wheel answers again once a re-opened device has been taken.
        if self.lost && !self.try_rejoin() {
            return Err(WheelError::Fault(WheelFault::Unplugged));
        }
        let now = self.clock.now_ns();
        let newest = match self.dev.drain_events() {
            Ok(t) => t,
            Err(_) => return Err(self.lose()),
        };
        if let Some(t) = newest {
            self.last_event_ns = self.clock.monotonic_of(t);
        }
        let info = match self.dev.axis(self.axis) {
            Ok(i) => i,
            Err(_) => return Err(self.lose()),
        };
        if info.value < info.minimum || info.value > info.maximum {
            return Err(WheelError::Fault(WheelFault::OutOfRange));
        }
        // Silent under torque: no event since the torque started or since the last event,
        // whichever is later, for longer than allowed.
        if let Some(since) = self.torque_since_ns {
            let quiet_from = since.max(self.last_event_ns);
            if now.saturating_sub(quiet_from) > u64::from(self.config.max_silence_ms) * 1_000_000 {
                return Err(WheelError::Fault(WheelFault::Silent));
            }
        }
        let value = f64::from(info.value);
        Ok(WheelReading {
            angle_rad: self.profile.angle_sign * self.ka_rad_per_unit * (value - self.centre),
            t_ns: if newest.is_some() {
                self.last_event_ns
            } else {
                now
            },
        })
    }

    fn command_torque(&mut self, torque_nm: f64) -> Result<(), WheelError> {
        let mut level = self.level_within(torque_nm, self.profile.torque_sign)?;
        let now = self.clock.now_ns();
        // A re-opened device gets zero until zero is asked for: never a step on re-open.
        if self.zero_first {
            self.zero_first = level != 0;
            level = 0;
        }
        let stopping = level == 0 && self.level != 0;
        if haptic_wheel::wheel_config::update_due(
            self.last_update_ns,
            now,
            self.min_interval_ns,
            stopping,
        ) {
            self.send(level, now)
        } else {
            Ok(())
        }
    }

    fn set_torque_ceiling_nm(&mut self, ceiling_nm: f64) -> Result<(), WheelError> {
        // The largest level within the ceiling (truncated towards zero like every level).
        let bound = self.level_within(ceiling_nm.abs(), 1.0)?;
        if self.level.unsigned_abs() > bound.unsigned_abs() {
            let now = self.clock.now_ns();
            // A held level over a lowered ceiling goes down at once, whatever the rate policy;
            // the policy's own schedule is kept, so the command's level still follows within
            // one update interval. One extra update per lowering, which is rare.
            let scheduled = self.last_update_ns;
            let sent = self.send(self.level.signum() * bound, now);
            self.last_update_ns = scheduled;
            sent
        } else {
            Ok(())
        }
    }

    fn max_torque_nm(&self) -> f64 {
        self.usable_nm
    }

    fn profile(&self) -> DeviceProfile {
        self.profile.clone()
    }

    fn set_firmware_effects_active(&mut self, active: bool) {
        if active == self.conditions_active || self.lost {
            return;
        }
        self.conditions_active = active;
        for i in 0..self.conditions.len() {
            let slot = self.conditions[i];
            // A failure means the device is gone, which stops its effects too; the next read
            // reports it.
            let _ = if active {
                self.dev.play(slot)
            } else {
                self.dev.stop(slot)
            };
        }
    }

    fn capabilities(&self) -> WheelCapabilities {
        WheelCapabilities {
            name: self.name.clone(),
            max_torque_nm: self.usable_nm,
            half_range_rad: self.profile.half_range_rad,
            angle_resolution_rad: self.ka_rad_per_unit,
            max_update_rate_hz: 1e9 / self.min_interval_ns as f64,
            firmware_conditions: self.firmware_conditions,
        }
    }

    fn motor_updates(&self) -> Option<MotorUpdates> {
        Some(self.updates)
    }
}

impl<D: FfDevice> Drop for EvdevWheel<D> {
    fn drop(&mut self) {
        // Best effort: the device may already be gone, and a gone device applies no torque.
        let _ = self.dev.update(
            self.constant,
            constant_data(0, self.config.effect_length_ms),
        );
        let _ = self.dev.stop(self.constant);
        self.clear_conditions();
        self.dev.erase(self.constant);
        let _ = self.dev.set_gain(u16::MAX);
        let _ = self.dev.set_autocenter(self.config.autocenter_level());
    }
}

#[cfg(test)]
mod tests;
