//! Device profiles: named angle and torque scales per wheel model (thesis eq. 3.1–3.3), the
//! toolbox's ±10 000 effect units, and the per-driver torque update rate policy.
//!
//! Everything inside the crate is SI. Device units exist only here and in the backends:
//!
//! - angle: `θ[rad] = Ka · u_angle` (thesis eq. 3.2; the thesis wheel reports ±1000 units
//!   over its 4.5078 rad range, eq. 3.1, so `Ka` = 0.002253 rad/unit);
//! - torque: `τ[N·m] = Kt · u_effect` (thesis eq. 3.3, `Kt` = 1.873e-4 N·m/unit; DirectX and
//!   the thesis toolbox express every force as ±10 000 effect units).
//!
//! How to measure `Ka`, `Kt` and the torque range of a new wheel: `CALIBRATION.md` in this
//! crate.

use serde::{Deserialize, Serialize};

use crate::wheel::WheelError;

/// Full scale of DirectX / thesis-toolbox effect units (forces, coefficients, saturations).
pub const EFFECT_FULL_SCALE_UNITS: f64 = 10_000.0;

/// The kernel driver family that moves a wheel's torque, which sets how often a new torque
/// value can usefully be sent (FIELD-NOTES: "Torque update paths differ by driver").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
#[non_exhaustive]
pub enum DriverFamily {
    /// `hid-pidff` / `hid-universal-pidff` (USB PID: SideWinder, Moza, Simucube, VRS,
    /// OpenFFBoard…): one USB report per constant-force update, ~1 kHz ceiling.
    HidPidff,
    /// `hid-lg4ff` / `new-lg4ff` (G25, G27, G29): a 2 ms timer, 8-bit torque: 500 Hz.
    Lg4ff,
    /// `hid-logitech-hidpp` (G920, G923 Xbox): HID++ reports must be throttled to 3–5 ms.
    Hidpp,
    /// `hid-tmff2` (Thrustmaster T300/T248/TX…): 8 ms, 125 Hz.
    Tmff2,
    /// `hid-fanatec`: 2 ms, 500 Hz.
    Fanatec,
    /// The simulated wheel: as fast as the loop.
    Simulated,
}

impl DriverFamily {
    /// Highest useful rate of new constant-force values, Hz (per-driver rate policy).
    pub fn max_update_rate_hz(self) -> f64 {
        match self {
            Self::HidPidff | Self::Simulated => 1000.0,
            Self::Lg4ff | Self::Fanatec => 500.0,
            Self::Hidpp => 250.0,
            Self::Tmff2 => 125.0,
        }
    }
}

/// Where a profile's motor torque (`max_torque_nm`) comes from. The station states it in
/// `telerehab devices` and the session log, because the safety ceiling in N·m is only as true
/// as this figure.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
#[non_exhaustive]
pub enum TorqueSource {
    /// The maker's published figure for the model (a built-in profile; `reference` cites it).
    Maker,
    /// Measured on this wheel (`telerehab wheel calibrate`, or the hanging-mass procedure of
    /// CALIBRATION.md).
    #[default]
    Measured,
    /// Entered by the patient's clinician from the maker's sheet (`[wheel] rated_torque_nm`).
    Clinician,
    /// Not known: the strongest plausible consumer motor is assumed
    /// ([`ASSUMED_UNKNOWN_MOTOR_NM`]) and the ceiling capped at [`UNKNOWN_WHEEL_CEILING_NM`].
    Assumed,
}

impl TorqueSource {
    /// Plain words for logs and `telerehab devices`.
    pub fn describe(self) -> &'static str {
        match self {
            Self::Maker => "maker's rating",
            Self::Measured => "measured",
            Self::Clinician => "entered by the clinician",
            Self::Assumed => "UNKNOWN wheel: strongest plausible motor assumed",
        }
    }
}

/// Motor torque assumed for a wheel whose rating is not known, N·m: the strongest consumer
/// direct-drive base sold for home use (Simucube 2 Ultimate, 32 N·m peak). Mapping N·m to the
/// kernel's level with this figure means a commanded torque is never *more* than that torque
/// on any plausible motor (on a weaker one it is proportionally less).
pub const ASSUMED_UNKNOWN_MOTOR_NM: f64 = 32.0;

/// Ceiling on an unknown wheel, N·m, whatever the patient's ceiling says: small and safe for a
/// patient's hands even on the strongest motor (a Logitech G29 gives about 2.2 N·m at full
/// force). Enter the rated torque (`[wheel] rated_torque_nm`) or calibrate the wheel to lift it.
pub const UNKNOWN_WHEEL_CEILING_NM: f64 = 1.0;

/// Largest motor torque a profile may state, N·m (above every consumer wheel).
pub const MAX_PROFILE_TORQUE_NM: f64 = 40.0;

/// A wheel model's calibration and limits. Serde so a user's measured profile can live in
/// the station's TOML config; [`DeviceProfile::validate`] names any field out of range.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DeviceProfile {
    /// Model name, for logs and reports.
    pub name: String,
    /// USB vendor id, if the profile is tied to one model.
    pub usb_vendor: Option<u16>,
    /// USB product ids this profile applies to (empty: matched by hand).
    pub usb_products: Vec<u16>,
    /// Driver family, which sets the torque update rate policy.
    pub driver: DriverFamily,
    /// Angle scale `Ka`, rad per device angle unit (thesis eq. 3.2).
    pub ka_rad_per_unit: f64,
    /// Torque scale `Kt`, N·m per effect unit of the ±10 000 scale (thesis eq. 3.3).
    pub kt_nm_per_unit: f64,
    /// Torque the motor produces at full scale (kernel level ±32767, gain 100 %), N·m. The
    /// evdev backend maps N·m to the kernel level with it, so it must not be below the real
    /// motor's: an unknown wheel assumes [`ASSUMED_UNKNOWN_MOTOR_NM`].
    pub max_torque_nm: f64,
    /// Where `max_torque_nm` comes from.
    #[serde(default)]
    pub torque_source: TorqueSource,
    /// The source of the figure (maker's page or sheet, measurement date), for the record.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub reference: String,
    /// Smallest torque step the device resolves, N·m (8-bit drivers: max/127).
    pub torque_step_nm: f64,
    /// Half range of motion (centre to lock), rad.
    pub half_range_rad: f64,
    /// Highest useful torque update rate, Hz.
    pub max_update_rate_hz: f64,
    /// Velocity that DirectX's damper normalises to full scale, rad/s (only for converting
    /// toolbox damper coefficients; not a device limit).
    pub full_scale_velocity_rad_s: f64,
    /// Acceleration that DirectX's inertia effect normalises to full scale, rad/s².
    pub full_scale_acceleration_rad_s2: f64,
    /// `+1.0` if a positive device axis value is a left (counter-clockwise) turn, else `-1.0`.
    pub angle_sign: f64,
    /// `+1.0` if a positive device force turns the wheel left (counter-clockwise), else `-1.0`.
    pub torque_sign: f64,
}

impl DeviceProfile {
    /// The thesis wheel, Microsoft SideWinder Force Feedback Wheel (thesis §3.2.1,
    /// eq. 3.1–3.3): ±1000 angle units over 4.5078 rad, `Kt` = 1.873e-4 N·m/unit, 1.87 N·m.
    pub fn thesis_sidewinder() -> Self {
        Self {
            name: "Microsoft SideWinder Force Feedback Wheel (thesis)".into(),
            usb_vendor: Some(0x045e),
            usb_products: vec![0x0034],
            driver: DriverFamily::HidPidff,
            ka_rad_per_unit: crate::THESIS_KA_RAD_PER_UNIT,
            kt_nm_per_unit: crate::THESIS_KT_NM_PER_UNIT,
            max_torque_nm: crate::THESIS_WHEEL_MAX_TORQUE_NM,
            torque_source: TorqueSource::Measured,
            reference: "Jadhav 2004, §3.2.1, eq. 3.3 and Fig. 3-4 (hanging masses)".into(),
            torque_step_nm: crate::THESIS_KT_NM_PER_UNIT,
            half_range_rad: 1000.0 * crate::THESIS_KA_RAD_PER_UNIT,
            max_update_rate_hz: DriverFamily::HidPidff.max_update_rate_hz(),
            full_scale_velocity_rad_s: 10.0,
            full_scale_acceleration_rad_s2: 100.0,
            angle_sign: 1.0,
            torque_sign: 1.0,
        }
    }

    /// Logitech G29 (and G25/G27 on the same driver): 900° lock to lock, 16-bit encoder,
    /// 8-bit torque, 500 Hz. Nominal torque ~2.2 N·m: measure yours (CALIBRATION.md).
    pub fn logitech_g29() -> Self {
        Self::logitech(
            "Logitech G29 / G27 / G25 (hid-lg4ff)",
            vec![0xc24f, 0xc29b, 0xc299],
            DriverFamily::Lg4ff,
            127.0,
        )
    }

    /// Logitech G920 / G923 Xbox (HID++): 900°, 250 Hz torque updates. Nominal ~2.2 N·m.
    pub fn logitech_g920() -> Self {
        Self::logitech(
            "Logitech G920 / G923 Xbox (hid-logitech-hidpp)",
            vec![0xc262, 0xc26e],
            DriverFamily::Hidpp,
            // HID++ constant force is 16-bit signed.
            32_767.0,
        )
    }

    fn logitech(name: &str, products: Vec<u16>, driver: DriverFamily, torque_levels: f64) -> Self {
        let max_torque_nm = 2.2;
        let half_range_rad = 450f64.to_radians();
        Self {
            name: name.into(),
            usb_vendor: Some(0x046d),
            usb_products: products,
            driver,
            ka_rad_per_unit: 2.0 * half_range_rad / 65_535.0,
            kt_nm_per_unit: max_torque_nm / EFFECT_FULL_SCALE_UNITS,
            max_torque_nm,
            torque_source: TorqueSource::Maker,
            reference: String::new(),
            torque_step_nm: max_torque_nm / torque_levels,
            half_range_rad,
            max_update_rate_hz: driver.max_update_rate_hz(),
            full_scale_velocity_rad_s: 10.0,
            full_scale_acceleration_rad_s2: 100.0,
            angle_sign: -1.0,
            torque_sign: 1.0,
        }
    }

    /// A wheel without a profile, on the kernel driver `driver`. Its motor torque is not known,
    /// so the strongest plausible motor is assumed ([`ASSUMED_UNKNOWN_MOTOR_NM`]) and the
    /// usable torque capped at [`UNKNOWN_WHEEL_CEILING_NM`] ([`DeviceProfile::usable_max_nm`])
    /// until the clinician enters the rated torque or the wheel is calibrated. The angle
    /// scale comes from the device's axis range at open time.
    pub fn unknown(driver: DriverFamily) -> Self {
        let max_torque_nm = ASSUMED_UNKNOWN_MOTOR_NM;
        Self {
            name: "unknown force-feedback wheel".into(),
            usb_vendor: None,
            usb_products: Vec::new(),
            driver,
            ka_rad_per_unit: 2.0 * 450f64.to_radians() / 65_535.0,
            kt_nm_per_unit: max_torque_nm / EFFECT_FULL_SCALE_UNITS,
            max_torque_nm,
            torque_source: TorqueSource::Assumed,
            reference: String::new(),
            torque_step_nm: max_torque_nm / 32_767.0,
            half_range_rad: 450f64.to_radians(),
            max_update_rate_hz: driver.max_update_rate_hz(),
            full_scale_velocity_rad_s: 10.0,
            full_scale_acceleration_rad_s2: 100.0,
            angle_sign: -1.0,
            torque_sign: 1.0,
        }
    }

    /// The most torque the station may ask of this wheel, N·m: the motor's full scale, capped
    /// at [`UNKNOWN_WHEEL_CEILING_NM`] while the rating is only assumed.
    pub fn usable_max_nm(&self) -> f64 {
        match self.torque_source {
            TorqueSource::Assumed => self.max_torque_nm.min(UNKNOWN_WHEEL_CEILING_NM),
            _ => self.max_torque_nm,
        }
    }

    /// This profile with the motor torque a clinician entered from the maker's sheet, N·m.
    pub fn with_rated_torque(mut self, rated_torque_nm: f64) -> Self {
        self.max_torque_nm = rated_torque_nm;
        self.kt_nm_per_unit = rated_torque_nm / EFFECT_FULL_SCALE_UNITS;
        self.torque_step_nm = self.torque_step_nm.min(rated_torque_nm);
        self.torque_source = TorqueSource::Clinician;
        self.reference = "rated torque entered in the station configuration".into();
        self
    }

    /// The simulated wheel with the thesis wheel's scales.
    pub fn simulated(max_torque_nm: f64, half_range_rad: f64) -> Self {
        Self {
            name: "simulated wheel".into(),
            usb_vendor: None,
            usb_products: Vec::new(),
            driver: DriverFamily::Simulated,
            max_torque_nm,
            half_range_rad,
            max_update_rate_hz: DriverFamily::Simulated.max_update_rate_hz(),
            ..Self::thesis_sidewinder()
        }
    }

    /// The built-in profiles of real wheels, most specific first.
    pub fn builtin() -> Vec<DeviceProfile> {
        vec![
            Self::thesis_sidewinder(),
            Self::logitech_g29(),
            Self::logitech_g920(),
        ]
    }

    /// The built-in profile for a USB id; an [`DeviceProfile::unknown`] wheel when none
    /// matches (known vendors with their own drivers get that driver's rate policy).
    pub fn for_usb_id(vendor: u16, product: u16) -> Self {
        if let Some(p) = Self::builtin()
            .into_iter()
            .find(|p| p.usb_vendor == Some(vendor) && p.usb_products.contains(&product))
        {
            return p;
        }
        Self::unknown(match vendor {
            0x044f => DriverFamily::Tmff2,
            0x0eb7 => DriverFamily::Fanatec,
            0x046d => DriverFamily::Lg4ff,
            _ => DriverFamily::HidPidff,
        })
    }

    /// Check every field; the error names the field and its allowed range.
    pub fn validate(&self) -> Result<(), WheelError> {
        fn pos(name: &str, v: f64, hi: f64) -> Result<(), WheelError> {
            if v.is_finite() && v > 0.0 && v <= hi {
                Ok(())
            } else {
                Err(WheelError::InvalidConfig(format!(
                    "profile.{name} = {v}, allowed (0, {hi}]"
                )))
            }
        }
        pos("ka_rad_per_unit", self.ka_rad_per_unit, 1.0)?;
        pos("kt_nm_per_unit", self.kt_nm_per_unit, 0.01)?;
        pos("max_torque_nm", self.max_torque_nm, MAX_PROFILE_TORQUE_NM)?;
        pos("torque_step_nm", self.torque_step_nm, self.max_torque_nm)?;
        pos(
            "half_range_rad",
            self.half_range_rad,
            4.0 * std::f64::consts::PI,
        )?;
        pos("max_update_rate_hz", self.max_update_rate_hz, 10_000.0)?;
        pos(
            "full_scale_velocity_rad_s",
            self.full_scale_velocity_rad_s,
            1000.0,
        )?;
        pos(
            "full_scale_acceleration_rad_s2",
            self.full_scale_acceleration_rad_s2,
            1.0e5,
        )?;
        for (name, v) in [
            ("angle_sign", self.angle_sign),
            ("torque_sign", self.torque_sign),
        ] {
            if v != 1.0 && v != -1.0 {
                return Err(WheelError::InvalidConfig(format!(
                    "profile.{name} = {v}, allowed +1.0 or -1.0"
                )));
            }
        }
        Ok(())
    }

    /// Device angle units to rad (thesis eq. 3.2), including the sign convention.
    pub fn angle_units_to_rad(&self, units: f64) -> f64 {
        self.angle_sign * self.ka_rad_per_unit * units
    }

    /// Effect units (±10 000) to N·m (thesis eq. 3.3).
    pub fn effect_units_to_nm(&self, units: f64) -> f64 {
        self.kt_nm_per_unit * units
    }

    /// N·m to effect units (±10 000), the inverse of [`Self::effect_units_to_nm`].
    pub fn nm_to_effect_units(&self, torque_nm: f64) -> f64 {
        torque_nm / self.kt_nm_per_unit
    }

    /// Torque the device gives at full scale of the ±10 000 effect units, N·m.
    pub fn full_scale_torque_nm(&self) -> f64 {
        self.kt_nm_per_unit * EFFECT_FULL_SCALE_UNITS
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thesis_profile_reproduces_eq_3_1_to_3_3() {
        let p = DeviceProfile::thesis_sidewinder();
        // eq. 3.1: 2π − 2·226/254.6 = 4.5078 rad over 2000 units.
        let range = 2.0 * std::f64::consts::PI - 226.0 * 2.0 / 254.6;
        assert!((range - 4.5078).abs() < 1e-4);
        // Ka is printed to four significant figures in the thesis: 2000·Ka = 4.506.
        assert!((p.angle_units_to_rad(2000.0) - range).abs() < 2e-3);
        // eq. 3.3: 10 000 units ≈ 1.873 N·m, the wheel's 1.87 N·m range.
        assert!((p.effect_units_to_nm(10_000.0) - 1.873).abs() < 1e-12);
        assert!((p.nm_to_effect_units(p.effect_units_to_nm(1234.0)) - 1234.0).abs() < 1e-9);
        p.validate().unwrap();
    }

    #[test]
    fn every_builtin_profile_is_valid() {
        for p in DeviceProfile::builtin() {
            p.validate().unwrap_or_else(|e| panic!("{}: {e}", p.name));
        }
    }

    #[test]
    fn usb_ids_select_the_driver_rate_policy() {
        assert_eq!(
            DeviceProfile::for_usb_id(0x046d, 0xc24f).max_update_rate_hz,
            500.0
        );
        assert_eq!(
            DeviceProfile::for_usb_id(0x046d, 0xc262).max_update_rate_hz,
            250.0
        );
        assert_eq!(
            DeviceProfile::for_usb_id(0x1234, 0x0001).max_update_rate_hz,
            1000.0
        );
        assert_eq!(
            DeviceProfile::for_usb_id(0x044f, 0xb66e).max_update_rate_hz,
            125.0
        );
    }

    #[test]
    fn validate_names_the_bad_field() {
        let p = DeviceProfile {
            kt_nm_per_unit: f64::NAN,
            ..DeviceProfile::thesis_sidewinder()
        };
        let msg = p.validate().unwrap_err().to_string();
        assert!(msg.contains("kt_nm_per_unit"), "{msg}");
        let p = DeviceProfile {
            torque_sign: 0.5,
            ..DeviceProfile::thesis_sidewinder()
        };
        assert!(
            p.validate()
                .unwrap_err()
                .to_string()
                .contains("torque_sign")
        );
    }

    #[test]
    fn profile_round_trips_through_toml() {
        let p = DeviceProfile::logitech_g29();
        let text = toml::to_string(&p).unwrap();
        let back: DeviceProfile = toml::from_str(&text).unwrap();
        assert_eq!(p, back);
    }
}
