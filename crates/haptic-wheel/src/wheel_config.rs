//! The `[wheel]` section of the station's configuration: which profile a real wheel uses, the
//! rated torque a clinician enters, and the kernel backend's settings. Pure: loading a profile
//! file is the station's job; this module validates and resolves.

use serde::{Deserialize, Serialize};

use crate::profile::{DeviceProfile, DriverFamily, MAX_PROFILE_TORQUE_NM};
use crate::wheel::ConfigError;

/// Settings of a real force-feedback wheel (serde, `deny_unknown_fields`; every field has a
/// default). See `CALIBRATION.md` for how to fill it in.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct WheelConfig {
    /// A profile file written by `telerehab wheel calibrate` (TOML, the fields of
    /// [`DeviceProfile`]); relative paths are relative to the configuration file. The station
    /// loads it into [`WheelConfig::profile`].
    pub profile_file: Option<std::path::PathBuf>,
    /// A profile written inline (`[wheel.profile]`), instead of the built-in one for the
    /// device's USB id.
    pub profile: Option<DeviceProfile>,
    /// The motor's rated (peak) torque from the maker's sheet, N·m, entered by the patient's
    /// clinician: replaces the profile's figure (and lifts the unknown-wheel cap).
    pub rated_torque_nm: Option<f64>,
    /// Device-wide force-feedback gain while running, fraction of full (0, 1]. The N·m to
    /// kernel level mapping accounts for it.
    pub gain: f64,
    /// Replay length of every effect, ms (20..=1000): the motor stops this long after the last
    /// re-arm if the process hangs.
    pub effect_length_ms: u16,
    /// Torque update rate, Hz; `None` uses the driver's policy, and it is never above it.
    pub update_rate_hz: Option<f64>,
    /// Longest the wheel may send no input event while a non-zero torque is commanded before
    /// its readings count as stale, ms (50..=5000). A motor pushing the rim moves the encoder
    /// within a few ms; silence means a hung device.
    pub max_silence_ms: u32,
    /// Autocentre strength set on exit, fraction of full [0, 1] (0: off).
    pub autocenter_on_exit: f64,
}

impl Default for WheelConfig {
    fn default() -> Self {
        Self {
            profile_file: None,
            profile: None,
            rated_torque_nm: None,
            gain: 1.0,
            effect_length_ms: 100,
            update_rate_hz: None,
            max_silence_ms: 500,
            autocenter_on_exit: 0.0,
        }
    }
}

fn invalid(msg: String) -> ConfigError {
    ConfigError(msg)
}

impl WheelConfig {
    /// Check every field; the error names the field and its allowed range.
    pub fn validate(&self) -> Result<(), ConfigError> {
        if self.profile.is_some() && self.profile_file.is_some() {
            return Err(invalid(
                "wheel.profile and wheel.profile_file are both set; keep one".into(),
            ));
        }
        if let Some(p) = &self.profile {
            p.validate()?;
        }
        if let Some(t) = self.rated_torque_nm
            && !(t.is_finite() && t > 0.0 && t <= MAX_PROFILE_TORQUE_NM)
        {
            return Err(invalid(format!(
                "wheel.rated_torque_nm = {t}, allowed (0, {MAX_PROFILE_TORQUE_NM}]"
            )));
        }
        if !(self.gain.is_finite() && self.gain > 0.0 && self.gain <= 1.0) {
            return Err(invalid(format!(
                "wheel.gain = {}, allowed (0, 1]",
                self.gain
            )));
        }
        if !(20..=1000).contains(&self.effect_length_ms) {
            return Err(invalid(format!(
                "wheel.effect_length_ms = {}, allowed [20, 1000]",
                self.effect_length_ms
            )));
        }
        if let Some(r) = self.update_rate_hz
            && !(r.is_finite() && r > 0.0 && r <= 10_000.0)
        {
            return Err(invalid(format!(
                "wheel.update_rate_hz = {r}, allowed (0, 10000]"
            )));
        }
        if !(50..=5000).contains(&self.max_silence_ms) {
            return Err(invalid(format!(
                "wheel.max_silence_ms = {}, allowed [50, 5000]",
                self.max_silence_ms
            )));
        }
        if !(self.autocenter_on_exit.is_finite() && (0.0..=1.0).contains(&self.autocenter_on_exit))
        {
            return Err(invalid(format!(
                "wheel.autocenter_on_exit = {}, allowed [0, 1]",
                self.autocenter_on_exit
            )));
        }
        Ok(())
    }

    /// The profile for a wheel with USB id `(vendor, product)`: the configured one, else the
    /// built-in one for the id, else an unknown wheel; with the clinician's rated torque when
    /// one is entered.
    pub fn resolve_profile(&self, vendor: u16, product: u16) -> DeviceProfile {
        let p = match &self.profile {
            Some(p) => p.clone(),
            None => DeviceProfile::for_usb_id(vendor, product),
        };
        match self.rated_torque_nm {
            Some(t) => p.with_rated_torque(t),
            None => p,
        }
    }

    /// The device-wide gain as the kernel's 0..=65535.
    pub fn gain_level(&self) -> u16 {
        fraction_level(self.gain)
    }

    /// The autocentre strength on exit as the kernel's 0..=65535.
    pub fn autocenter_level(&self) -> u16 {
        fraction_level(self.autocenter_on_exit)
    }

    /// Torque update rate on a wheel whose driver allows `policy_hz`, Hz.
    pub fn update_rate_for(&self, driver: DriverFamily, policy_hz: f64) -> f64 {
        let policy = policy_hz.min(driver.max_update_rate_hz());
        self.update_rate_hz.map_or(policy, |r| r.min(policy))
    }
}

fn fraction_level(f: f64) -> u16 {
    // Validated to [0, 1]; the cast saturates anyway.
    (f.clamp(0.0, 1.0) * f64::from(u16::MAX)).round() as u16
}

/// The ceiling that holds on a wheel with `profile` at `gain` (fraction), for a patient
/// ceiling `patient_ceiling_nm` (`None`: the device maximum), N·m and as a fraction of the
/// motor's full torque. For logs, `telerehab devices` and the screen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CeilingReport {
    /// The motor's full-scale torque used for the level mapping, N·m (assumed for an unknown
    /// wheel).
    pub motor_nm: f64,
    /// The most torque the station may ask of this wheel, N·m.
    pub usable_max_nm: f64,
    /// The ceiling in force, N·m.
    pub ceiling_nm: f64,
    /// The ceiling as a fraction of the motor's full torque, 0..=1.
    pub fraction_of_motor: f64,
    /// The motor torque is only assumed (unknown wheel).
    pub assumed: bool,
}

impl CeilingReport {
    /// The ceiling on `profile` at `gain` for a patient ceiling `patient_ceiling_nm`.
    pub fn new(profile: &DeviceProfile, gain: f64, patient_ceiling_nm: Option<f64>) -> Self {
        let usable = usable_max_nm(profile, gain);
        Self {
            motor_nm: profile.max_torque_nm,
            usable_max_nm: usable,
            ceiling_nm: usable,
            fraction_of_motor: usable / profile.max_torque_nm,
            assumed: profile.torque_source == crate::profile::TorqueSource::Assumed,
        }
        .with_ceiling(patient_ceiling_nm.unwrap_or(usable))
    }

    /// The same wheel with the ceiling `ceiling_nm` in force (never above the usable maximum),
    /// e.g. after a regimen lowered it.
    pub fn with_ceiling(self, ceiling_nm: f64) -> Self {
        let ceiling_nm = ceiling_nm.clamp(0.0, self.usable_max_nm);
        Self {
            ceiling_nm,
            fraction_of_motor: ceiling_nm / self.motor_nm,
            ..self
        }
    }
}

impl std::fmt::Display for CeilingReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "torque ceiling {:.2} N·m = {:.1} % of the motor's {:.2} N·m{}",
            self.ceiling_nm,
            100.0 * self.fraction_of_motor,
            self.motor_nm,
            if self.assumed {
                " (motor rating UNKNOWN: strongest plausible motor assumed; enter the rated torque from the maker's sheet as [wheel] rated_torque_nm, or with `telerehab wheel calibrate --rated-torque-nm`, to lift the cap)"
            } else {
                ""
            }
        )
    }
}

/// The most torque the station may ask of a wheel with `profile` at device gain `gain`
/// (fraction), N·m: the profile's usable maximum scaled by the gain, as the device gets it
/// (a 16-bit level).
pub fn usable_max_nm(profile: &DeviceProfile, gain: f64) -> f64 {
    profile
        .usable_max_nm()
        .min(profile.max_torque_nm * quantised_gain(gain))
}

/// The share of full scale (−1…1) a backend sends so that a motor of `motor_nm` at device
/// gain `gain` (fraction) gives `torque_nm` with the profile's torque `sign` (±1), after
/// clamping `torque_nm` to ±`usable_nm`: thesis eq. 3.3, `τ = Kt · u`, with `Kt` the motor's
/// full torque at that gain over the device's full scale. 0 for a non-finite torque or a
/// scale that is not positive. Each backend truncates its share of its own full scale
/// (±32 767 on Linux, ±10 000 in DirectInput) towards zero, so the motor never gives more
/// than asked.
pub fn motor_fraction(torque_nm: f64, usable_nm: f64, motor_nm: f64, gain: f64, sign: f64) -> f64 {
    let scale_nm = motor_nm * gain;
    if !(torque_nm.is_finite() && scale_nm.is_finite() && scale_nm > 0.0) {
        return 0.0;
    }
    let tau = torque_nm.clamp(-usable_nm, usable_nm);
    (sign * tau / scale_nm).clamp(-1.0, 1.0)
}

/// An update is due this share of the rate policy's interval early (1/10: 0.2 ms for a G29's
/// 2 ms), to absorb the haptic loop's wake-up jitter; a driver that coalesces within its own
/// timer loses nothing by it.
const WAKE_JITTER_SHARE: u64 = 10;

/// Whether a force update goes out now under a driver's rate policy (both backends): when
/// `min_interval_ns` has passed since the last update (less a tenth of it, `WAKE_JITTER_SHARE`: the loop's
/// ticks wake a few µs early or late, and without it a G29 got 390 updates/s, not 500), or at
/// once when `stopping` (a zero asked for while a non-zero level is held: stopping is never
/// throttled). A zero already held follows the policy like any level (re-sent, and its effect
/// re-armed, on schedule). Plain arithmetic: no allocation, lock or I/O on the 1 kHz path.
pub fn update_due(
    last_update_ns: Option<u64>,
    now_ns: u64,
    min_interval_ns: u64,
    stopping: bool,
) -> bool {
    let interval_ns = min_interval_ns - min_interval_ns / WAKE_JITTER_SHARE;
    stopping || last_update_ns.is_none_or(|t| now_ns.saturating_sub(t) >= interval_ns)
}

/// The gain fraction a device really runs at when asked for `gain`: the 16-bit level sent.
pub fn quantised_gain(gain: f64) -> f64 {
    f64::from(fraction_level(gain)) / f64::from(u16::MAX)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::profile::{ASSUMED_UNKNOWN_MOTOR_NM, TorqueSource, UNKNOWN_WHEEL_CEILING_NM};

    #[test]
    fn validation_names_the_field() {
        for (cfg, field) in [
            (
                WheelConfig {
                    gain: 1.5,
                    ..Default::default()
                },
                "wheel.gain",
            ),
            (
                WheelConfig {
                    rated_torque_nm: Some(f64::NAN),
                    ..Default::default()
                },
                "wheel.rated_torque_nm",
            ),
            (
                WheelConfig {
                    effect_length_ms: 5,
                    ..Default::default()
                },
                "wheel.effect_length_ms",
            ),
            (
                WheelConfig {
                    update_rate_hz: Some(0.0),
                    ..Default::default()
                },
                "wheel.update_rate_hz",
            ),
            (
                WheelConfig {
                    max_silence_ms: 10,
                    ..Default::default()
                },
                "wheel.max_silence_ms",
            ),
            (
                WheelConfig {
                    profile: Some(DeviceProfile::thesis_sidewinder()),
                    profile_file: Some("p.toml".into()),
                    ..Default::default()
                },
                "wheel.profile_file",
            ),
        ] {
            let msg = cfg.validate().unwrap_err().to_string();
            assert!(msg.contains(field), "{msg} should name {field}");
        }
        WheelConfig::default().validate().unwrap();
    }

    #[test]
    fn an_unknown_wheel_is_capped_until_the_clinician_enters_its_rating() {
        let cfg = WheelConfig::default();
        let p = cfg.resolve_profile(0x1234, 0x5678);
        assert_eq!(p.torque_source, TorqueSource::Assumed);
        assert_eq!(p.max_torque_nm, ASSUMED_UNKNOWN_MOTOR_NM);
        let r = CeilingReport::new(&p, 1.0, None);
        assert_eq!(r.ceiling_nm, UNKNOWN_WHEEL_CEILING_NM);
        assert!(r.assumed);
        assert!((r.fraction_of_motor - 1.0 / 32.0).abs() < 1e-12);
        assert!(r.to_string().contains("UNKNOWN"), "{r}");
        // A patient ceiling above the cap does not lift it.
        assert_eq!(CeilingReport::new(&p, 1.0, Some(5.0)).ceiling_nm, 1.0);

        let cfg = WheelConfig {
            rated_torque_nm: Some(8.0),
            ..Default::default()
        };
        let p = cfg.resolve_profile(0x1234, 0x5678);
        assert_eq!(p.torque_source, TorqueSource::Clinician);
        let r = CeilingReport::new(&p, 0.5, Some(3.0));
        assert!((r.usable_max_nm - 4.0).abs() < 1e-3, "gain 50 % of 8 N·m");
        assert_eq!(r.ceiling_nm, 3.0);
        assert!(!r.assumed);
    }
}
