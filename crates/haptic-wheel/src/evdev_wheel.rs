//! The real wheel on Linux: the kernel force-feedback API (`EV_FF`, `EVIOCSFF`) through the
//! `evdev` crate.
//!
//! - The steering angle is read with `EVIOCGABS` (the kernel's current axis value; no event
//!   queue to drain, so a slow reader never sees old angles).
//! - Torque is one constant-force effect, uploaded once and then updated in place with the
//!   same id (`EVIOCSFF`): the latest value wins, nothing queues. Updates are throttled to the
//!   driver's rate policy ([`DriverFamily::max_update_rate_hz`](crate::DriverFamily)); a
//!   value arriving early is dropped and the next call after the interval sends the value
//!   of that moment (the loop calls every tick, so the newest value always goes out).
//!   Zero torque is never throttled.
//! - Every effect has a short replay length (default 100 ms) and is re-played at half that
//!   period, so if this process hangs the motor stops within one length; if it dies, the
//!   kernel erases its effects when the file closes.
//! - On open: FF gain set to the configured value and autocentre off (it would fight the
//!   haptic models). On drop: torque to zero, effects erased, gain back to full and
//!   autocentre to the configured exit value (the kernel cannot report the previous ones).
//! - Spring and friction can also be uploaded to the wheel's firmware
//!   ([`EvdevWheel::upload_condition`]) where the driver supports them; damper and inertia
//!   cannot (the `evdev` 0.13 effect type carries no condition data for them) and are
//!   rendered on the host by the [`EffectStack`](crate::EffectStack).

use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use evdev::{
    AbsInfo, AbsoluteAxisCode, FFCondition, FFEffect, FFEffectCode, FFEffectData, FFEffectKind,
    FFEnvelope, FFReplay, FFTrigger, KeyCode, raw_stream::RawDevice,
};
use serde::{Deserialize, Serialize};

use crate::devices::{DeviceClass, DeviceInfo, DeviceTraits, classify};
use crate::effects::{Condition, ConditionKind};
use crate::profile::DeviceProfile;
use crate::wheel::{Wheel, WheelCapabilities, WheelError, WheelReading};

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
const LEVEL_FULL_SCALE: f64 = 32_767.0;

/// Nanoseconds on the monotonic clock since the first call in this process. The evdev
/// backend stamps readings with it; the station's loop passes the same clock as `now_ns`.
pub fn monotonic_ns() -> u64 {
    static EPOCH: OnceLock<Instant> = OnceLock::new();
    EPOCH.get_or_init(Instant::now).elapsed().as_nanos() as u64
}

/// Settings of the evdev backend (serde, `deny_unknown_fields`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct EvdevWheelConfig {
    /// Replay length of every effect, ms (20..=1000). The motor stops this long after the
    /// last re-arm if the process hangs.
    pub effect_length_ms: u16,
    /// Device-wide FF gain while running, 0..=65535.
    pub gain: u16,
    /// Autocentre strength set on exit, 0..=65535 (0: off).
    pub autocenter_on_exit: u16,
    /// Override the torque update rate, Hz (never above the driver's policy).
    pub update_rate_hz: Option<f64>,
    /// Use this profile instead of the built-in one for the device's USB id.
    pub profile: Option<DeviceProfile>,
}

impl Default for EvdevWheelConfig {
    fn default() -> Self {
        Self {
            effect_length_ms: 100,
            gain: u16::MAX,
            autocenter_on_exit: 0,
            update_rate_hz: None,
            profile: None,
        }
    }
}

impl EvdevWheelConfig {
    /// Check every field; the error names the field and its allowed range.
    pub fn validate(&self) -> Result<(), WheelError> {
        if !(20..=1000).contains(&self.effect_length_ms) {
            return Err(WheelError::InvalidConfig(format!(
                "evdev.effect_length_ms = {}, allowed [20, 1000]",
                self.effect_length_ms
            )));
        }
        if let Some(r) = self.update_rate_hz
            && !(r.is_finite() && r > 0.0 && r <= 10_000.0)
        {
            return Err(WheelError::InvalidConfig(format!(
                "evdev.update_rate_hz = {r}, allowed (0, 10000]"
            )));
        }
        if let Some(p) = &self.profile {
            p.validate()?;
        }
        Ok(())
    }
}

fn axis_name(a: AbsoluteAxisCode) -> &'static str {
    match a {
        AbsoluteAxisCode::ABS_X => "x",
        AbsoluteAxisCode::ABS_Y => "y",
        AbsoluteAxisCode::ABS_Z => "z",
        AbsoluteAxisCode::ABS_RX => "rx",
        AbsoluteAxisCode::ABS_RY => "ry",
        AbsoluteAxisCode::ABS_RZ => "rz",
        AbsoluteAxisCode::ABS_THROTTLE => "throttle",
        AbsoluteAxisCode::ABS_RUDDER => "rudder",
        AbsoluteAxisCode::ABS_WHEEL => "wheel",
        AbsoluteAxisCode::ABS_GAS => "gas",
        AbsoluteAxisCode::ABS_BRAKE => "brake",
        AbsoluteAxisCode::ABS_HAT0X => "hat0x",
        AbsoluteAxisCode::ABS_HAT0Y => "hat0y",
        _ => "other",
    }
}

fn ff_name(c: FFEffectCode) -> &'static str {
    match c {
        FFEffectCode::FF_CONSTANT => "constant",
        FFEffectCode::FF_PERIODIC => "periodic",
        FFEffectCode::FF_RAMP => "ramp",
        FFEffectCode::FF_SPRING => "spring",
        FFEffectCode::FF_FRICTION => "friction",
        FFEffectCode::FF_DAMPER => "damper",
        FFEffectCode::FF_INERTIA => "inertia",
        FFEffectCode::FF_RUMBLE => "rumble",
        FFEffectCode::FF_GAIN => "gain",
        FFEffectCode::FF_AUTOCENTER => "autocenter",
        _ => "other",
    }
}

fn traits_of(dev: &RawDevice) -> DeviceTraits {
    let mut abs_axes: Vec<&'static str> = dev
        .supported_absolute_axes()
        .map(|s| s.iter().map(axis_name).collect())
        .unwrap_or_default();
    abs_axes.retain(|a| *a != "other");
    let mut ff_effects: Vec<&'static str> = dev
        .supported_ff()
        .map(|s| s.iter().map(ff_name).collect())
        .unwrap_or_default();
    ff_effects.retain(|a| *a != "other");
    let gamepad_buttons = dev
        .supported_keys()
        .is_some_and(|k| k.contains(KeyCode::BTN_SOUTH));
    DeviceTraits {
        name: dev.name().unwrap_or("(unnamed)").to_string(),
        ff_effects,
        abs_axes,
        gamepad_buttons,
    }
}

/// Open `path` and describe it; `Ok(None)` for devices the station does not use.
pub fn inspect(path: &Path) -> std::io::Result<Option<DeviceInfo>> {
    let dev = RawDevice::open(path)?;
    let traits = traits_of(&dev);
    let Some(class) = classify(&traits) else {
        return Ok(None);
    };
    let id = dev.input_id();
    let usb_id = Some((id.vendor(), id.product()));
    let profile =
        (class == DeviceClass::Wheel).then(|| DeviceProfile::for_usb_id(id.vendor(), id.product()));
    Ok(Some(DeviceInfo {
        path: path.display().to_string(),
        class,
        traits,
        usb_id,
        profile,
        max_ff_effects: dev.max_ff_effects(),
    }))
}

/// Device nodes of every force-feedback wheel this process can open, sorted.
pub fn find_wheels() -> Vec<PathBuf> {
    let Ok(dir) = std::fs::read_dir("/dev/input") else {
        return Vec::new();
    };
    let mut out: Vec<PathBuf> = dir
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.starts_with("event"))
        })
        .filter(|p| matches!(inspect(p), Ok(Some(d)) if d.class == DeviceClass::Wheel))
        .collect();
    out.sort();
    out
}

fn io_err(device: &str, source: std::io::Error) -> WheelError {
    WheelError::Io {
        device: device.to_string(),
        source,
    }
}

/// A force-feedback wheel driven through the Linux kernel FF API.
#[derive(Debug)]
pub struct EvdevWheel {
    // Effects first: fields drop in order, so they are erased before the device closes.
    constant: FFEffect,
    conditions: Vec<FFEffect>,
    dev: RawDevice,
    name: String,
    profile: DeviceProfile,
    config: EvdevWheelConfig,
    axis: AbsoluteAxisCode,
    centre: f64,
    ka_rad_per_unit: f64,
    level: i16,
    min_interval: Duration,
    last_update: Option<Instant>,
    last_play: Option<Instant>,
    firmware_conditions: bool,
}

impl EvdevWheel {
    /// Open the wheel at `path` (e.g. `/dev/input/event7`) and arm a zero constant force.
    pub fn open(path: &Path, config: EvdevWheelConfig) -> Result<Self, WheelError> {
        config.validate()?;
        let name_of = path.display().to_string();
        // Read-write: force feedback is written to the node (evdev's own `open` would fall
        // back to read-only and fail later, less clearly).
        let file = std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .open(path)
            .map_err(|e| {
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
        let mut dev = RawDevice::from_fd(file.into()).map_err(|e| io_err(&name_of, e))?;
        let traits = traits_of(&dev);
        if classify(&traits) != Some(DeviceClass::Wheel) {
            return Err(WheelError::Unsupported {
                device: name_of,
                reason: format!(
                    "'{}' lacks constant force or a steering axis (force feedback: [{}], axes: [{}])",
                    traits.name,
                    traits.ff_effects.join(", "),
                    traits.abs_axes.join(", ")
                ),
            });
        }
        let id = dev.input_id();
        let profile = match &config.profile {
            Some(p) => p.clone(),
            None => DeviceProfile::for_usb_id(id.vendor(), id.product()),
        };
        let axis = if traits.abs_axes.contains(&"wheel") {
            AbsoluteAxisCode::ABS_WHEEL
        } else {
            AbsoluteAxisCode::ABS_X
        };
        let abs = dev.get_abs_state().map_err(|e| io_err(&name_of, e))?;
        let info = AbsInfo::from(abs[axis.0 as usize]);
        let span = f64::from(info.maximum()) - f64::from(info.minimum());
        if span <= 0.0 {
            return Err(WheelError::Unsupported {
                device: name_of,
                reason: format!("steering axis has an empty range {span}"),
            });
        }
        // Scale from the device's own axis range (Ka of eq. 3.2 for this wheel).
        let ka_rad_per_unit = 2.0 * profile.half_range_rad / span;
        let centre = 0.5 * (f64::from(info.maximum()) + f64::from(info.minimum()));
        let rate = config
            .update_rate_hz
            .map_or(profile.max_update_rate_hz, |r| {
                r.min(profile.max_update_rate_hz)
            });
        let firmware_conditions = traits.ff_effects.contains(&"spring");
        if traits.ff_effects.contains(&"gain") {
            dev.set_ff_gain(config.gain)
                .map_err(|e| io_err(&name_of, e))?;
        }
        if traits.ff_effects.contains(&"autocenter") {
            dev.set_ff_autocenter(0).map_err(|e| io_err(&name_of, e))?;
        }
        let constant = dev
            .upload_ff_effect(constant_data(0, config.effect_length_ms))
            .map_err(|e| io_err(&name_of, e))?;
        Ok(Self {
            dev,
            name: format!("{} ({name_of})", traits.name),
            profile,
            axis,
            centre,
            ka_rad_per_unit,
            constant,
            level: 0,
            min_interval: Duration::from_secs_f64(1.0 / rate),
            last_update: None,
            last_play: None,
            conditions: Vec::new(),
            firmware_conditions,
            config,
        })
    }

    /// Open the first wheel found.
    pub fn open_first(config: EvdevWheelConfig) -> Result<Self, WheelError> {
        let path = find_wheels().into_iter().next().ok_or_else(|| {
            WheelError::Disconnected(format!(
                "no force-feedback wheel could be opened; {}",
                crate::devices::UDEV_HINT
            ))
        })?;
        Self::open(&path, config)
    }

    /// The last level sent to the kernel, ±32767.
    pub fn sent_level(&self) -> i16 {
        self.level
    }

    /// The minimum time between torque updates this wheel's rate policy allows.
    pub fn min_update_interval(&self) -> Duration {
        self.min_interval
    }

    fn level_for(&self, torque_nm: f64) -> i16 {
        let frac = self.profile.torque_sign * torque_nm / self.profile.max_torque_nm;
        (frac.clamp(-1.0, 1.0) * LEVEL_FULL_SCALE).round() as i16
    }

    fn send(&mut self, level: i16, now: Instant) -> Result<(), WheelError> {
        let len = self.config.effect_length_ms;
        self.constant
            .update(constant_data(level, len))
            .map_err(|e| io_err(&self.name, e))?;
        self.level = level;
        self.last_update = Some(now);
        let rearm = Duration::from_millis(u64::from(len) / 2);
        if self
            .last_play
            .is_none_or(|t| now.duration_since(t) >= rearm)
        {
            self.constant.play(1).map_err(|e| io_err(&self.name, e))?;
            for c in &mut self.conditions {
                c.play(1).map_err(|e| io_err(&self.name, e))?;
            }
            self.last_play = Some(now);
        }
        Ok(())
    }

    /// Upload a spring or friction condition to the wheel's firmware, with its saturations
    /// capped to `budget_nm`. Returns the torque budget it may add (its larger saturation):
    /// lower the [`HapticChain`](crate::HapticChain) ceiling by that much so host torque +
    /// firmware torque stays under the patient's ceiling. The effect is re-armed with the
    /// constant force and erased on drop.
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
        if !(budget_nm.is_finite() && budget_nm >= 0.0) {
            return Err(WheelError::InvalidConfig(format!(
                "condition budget_nm = {budget_nm}, allowed finite and >= 0"
            )));
        }
        let max = self.profile.max_torque_nm;
        let half = self.profile.half_range_rad;
        let pos_sat = c.positive_saturation_nm.min(budget_nm);
        let neg_sat = c.negative_saturation_nm.min(budget_nm);
        let coef = |k: f64| -> i16 {
            let units = match c.kind {
                ConditionKind::Spring => k * half / max,
                _ => k / max,
            };
            (units.clamp(-1.0, 1.0) * LEVEL_FULL_SCALE).round() as i16
        };
        let sat = |s: f64| ((s / max).clamp(0.0, 1.0) * f64::from(u16::MAX)).round() as u16;
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
        let mut effect = self
            .dev
            .upload_ff_effect(data)
            .map_err(|e| io_err(&self.name, e))?;
        effect.play(1).map_err(|e| io_err(&self.name, e))?;
        self.conditions.push(effect);
        Ok(pos_sat.max(neg_sat))
    }

    /// Erase every firmware condition effect.
    pub fn clear_conditions(&mut self) {
        // Dropping an FFEffect erases it (EVIOCRMFF).
        self.conditions.clear();
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

impl Wheel for EvdevWheel {
    fn read(&mut self) -> Result<WheelReading, WheelError> {
        let abs = self
            .dev
            .get_abs_state()
            .map_err(|e| WheelError::Disconnected(format!("{}: {e}", self.name)))?;
        let value = f64::from(AbsInfo::from(abs[self.axis.0 as usize]).value());
        Ok(WheelReading {
            angle_rad: self.profile.angle_sign * self.ka_rad_per_unit * (value - self.centre),
            t_ns: monotonic_ns(),
        })
    }

    fn command_torque(&mut self, torque_nm: f64) -> Result<(), WheelError> {
        let now = Instant::now();
        if !torque_nm.is_finite() {
            self.send(0, now)?;
            return Err(WheelError::NonFiniteTorque(torque_nm));
        }
        let level = self.level_for(torque_nm);
        let due = self
            .last_update
            .is_none_or(|t| now.duration_since(t) >= self.min_interval);
        // Zero always goes out at once: stopping is never throttled.
        if due || level == 0 {
            self.send(level, now)
        } else {
            Ok(())
        }
    }

    fn max_torque_nm(&self) -> f64 {
        self.profile.max_torque_nm
    }

    fn profile(&self) -> DeviceProfile {
        self.profile.clone()
    }

    fn capabilities(&self) -> WheelCapabilities {
        WheelCapabilities {
            name: self.name.clone(),
            max_torque_nm: self.profile.max_torque_nm,
            half_range_rad: self.profile.half_range_rad,
            angle_resolution_rad: self.ka_rad_per_unit,
            max_update_rate_hz: 1.0 / self.min_interval.as_secs_f64(),
            firmware_conditions: self.firmware_conditions,
        }
    }
}

impl Drop for EvdevWheel {
    fn drop(&mut self) {
        // Best effort: the device may already be gone, and a gone device applies no torque.
        let _ = self
            .constant
            .update(constant_data(0, self.config.effect_length_ms));
        let _ = self.constant.stop();
        self.conditions.clear();
        let _ = self.dev.set_ff_gain(u16::MAX);
        let _ = self.dev.set_ff_autocenter(self.config.autocenter_on_exit);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn config_validation_names_the_field() {
        let c = EvdevWheelConfig {
            effect_length_ms: 5,
            ..Default::default()
        };
        assert!(
            c.validate()
                .unwrap_err()
                .to_string()
                .contains("effect_length_ms")
        );
        let c = EvdevWheelConfig {
            update_rate_hz: Some(f64::NAN),
            ..Default::default()
        };
        assert!(
            c.validate()
                .unwrap_err()
                .to_string()
                .contains("update_rate_hz")
        );
        EvdevWheelConfig::default().validate().unwrap();
    }

    #[test]
    fn opening_a_missing_device_is_an_io_error_not_a_panic() {
        let err = EvdevWheel::open(
            Path::new("/dev/input/event-does-not-exist"),
            EvdevWheelConfig::default(),
        )
        .unwrap_err();
        assert!(matches!(err, WheelError::Io { .. }), "{err}");
    }

    #[test]
    fn monotonic_clock_never_goes_backwards() {
        let a = monotonic_ns();
        let b = monotonic_ns();
        assert!(b >= a);
    }
}
