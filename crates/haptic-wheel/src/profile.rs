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
//!
//! # Built-in wheels
//!
//! [`DeviceProfile::builtin`] holds one profile per wheel model from a single table in this
//! module, each with the USB ids its Linux driver matches, the driver family (which sets the
//! torque update rate), the maker's PEAK torque with its source
//! ([`TorqueSource::Maker`] and [`DeviceProfile::reference`]), range and torque resolution.
//! The peak figure matters for safety: the evdev backend maps N·m to the kernel level as
//! `torque / max_torque_nm`, so a figure below the real motor's would make every commanded
//! torque larger at the motor. Where one USB id covers several bases (Fanatec 0eb7:0020,
//! Thrustmaster 044f:b66d, Simagic 0483:0522) the strongest base's figure is used. A wheel
//! not in the table is [`DeviceProfile::unknown`]: strongest plausible motor, capped at
//! [`UNKNOWN_WHEEL_CEILING_NM`].

use serde::{Deserialize, Serialize};

use crate::config_error::ConfigError;

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

    /// Logitech G29: the built-in row for 046d:c24f (hid-lg4ff, 900°, 8-bit torque, 500 Hz).
    pub fn logitech_g29() -> Self {
        Self::for_usb_id(0x046d, 0xc24f)
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

    /// The built-in profiles of real wheels: the thesis wheel, then one profile per row of the
    /// built-in wheel table (module docs: "Built-in wheels"). No two claim the same USB id.
    pub fn builtin() -> Vec<DeviceProfile> {
        std::iter::once(Self::thesis_sidewinder())
            .chain(BUILTIN_WHEELS.iter().map(BuiltinWheel::profile))
            .collect()
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
    pub fn validate(&self) -> Result<(), ConfigError> {
        fn pos(name: &str, v: f64, hi: f64) -> Result<(), ConfigError> {
            if v.is_finite() && v > 0.0 && v <= hi {
                Ok(())
            } else {
                Err(ConfigError(format!(
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
                return Err(ConfigError(format!(
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

/// Torque levels per direction of an 8-bit driver (hid-lg4ff; hid-fanatec on the belt-driven
/// ClubSport bases): the smallest step is the motor's full scale over 127.
const LEVELS_8_BIT: f64 = 127.0;
/// hid-tmff2 halves the kernel's signed 16-bit level (T300 RS protocol): 15 bits.
const LEVELS_TMFF2: f64 = 16_383.0;
/// 16-bit signed (HID++, hid-fanatec high resolution, USB PID as the kernel sees it).
const LEVELS_16_BIT: f64 = 32_767.0;

/// Steering range assumed for direct-drive bases, lock to lock, degrees. Their steering axis
/// spans the angle set in the maker's software (Pit House, FanaLab, SimPro, Cammus), not a
/// fixed one, so the profile can only assume one: set the base to this angle or edit the
/// profile. An overstated range reads every angle too large, which makes a rendered spring
/// stiffer than asked.
const DIRECT_DRIVE_RANGE_DEG: f64 = 900.0;

/// One built-in wheel: a row of [`BUILTIN_WHEELS`].
struct BuiltinWheel {
    name: &'static str,
    vendor: u16,
    /// The product ids the Linux driver matches (empty: none confirmed, matched by hand).
    products: &'static [u16],
    driver: DriverFamily,
    /// The maker's PEAK torque, N·m; where one USB id is shared by several bases, the
    /// strongest of them (the safe direction for the N·m → kernel level mapping).
    peak_nm: f64,
    /// Where `peak_nm` comes from.
    reference: &'static str,
    /// Lock-to-lock range, degrees.
    range_deg: f64,
    /// Torque levels per direction (the resolution of the driver's constant force).
    levels: f64,
}

impl BuiltinWheel {
    fn profile(&self) -> DeviceProfile {
        let half_range_rad = 0.5 * self.range_deg.to_radians();
        DeviceProfile {
            name: self.name.into(),
            usb_vendor: Some(self.vendor),
            usb_products: self.products.to_vec(),
            driver: self.driver,
            // The evdev backend rescales from the axis range it finds; 16-bit by default.
            ka_rad_per_unit: 2.0 * half_range_rad / 65_535.0,
            kt_nm_per_unit: self.peak_nm / EFFECT_FULL_SCALE_UNITS,
            max_torque_nm: self.peak_nm,
            torque_source: TorqueSource::Maker,
            reference: self.reference.into(),
            torque_step_nm: self.peak_nm / self.levels,
            half_range_rad,
            max_update_rate_hz: self.driver.max_update_rate_hz(),
            full_scale_velocity_rad_s: 10.0,
            full_scale_acceleration_rad_s2: 100.0,
            // evdev wheels report a right turn as a larger axis value.
            angle_sign: -1.0,
            torque_sign: 1.0,
        }
    }
}

/// The built-in wheels, one row each.
///
/// USB ids are the ones the Linux drivers match: `hid-ids.h` / `hid-lg.c` / `hid-lg4ff.c`
/// (berarma/new-lg4ff), `hid-logitech-hidpp.c` (G920, G923 Xbox), Kimplul/hid-tmff2
/// `src/hid-tmff2.h`, gotzl/hid-fanatecff `hid-ftec.h`, JacKeTUs/universal-pidff `hid-ids.h`
/// (hid-universal-pidff) and JacKeTUs/simagic-ff `hid-simagic.h`.
///
/// Torque: the maker's peak figure (with a boost kit or mode, the most the base can give).
/// Where one USB id covers several bases, the row takes the strongest of them, so a weaker
/// base gives proportionally less than commanded, never more; a clinician can enter the
/// weaker base's rating (`[wheel] rated_torque_nm`). Figures marked "widely cited" were not
/// checked against the maker's own sheet here.
const BUILTIN_WHEELS: &[BuiltinWheel] = &[
    // ---- Logitech (vendor 046d). Logitech publishes no torque rating for these wheels.
    BuiltinWheel {
        name: "Logitech G29 (PlayStation/PC)",
        vendor: 0x046d,
        products: &[0xc24f],
        driver: DriverFamily::Lg4ff,
        peak_nm: 2.3,
        reference: "widely cited 2.1-2.3 N·m peak (Logitech publishes none); highest used; \
                    verify against the maker's sheet",
        range_deg: 900.0,
        levels: LEVELS_8_BIT,
    },
    BuiltinWheel {
        name: "Logitech G920 (Xbox/PC)",
        vendor: 0x046d,
        products: &[0xc262],
        driver: DriverFamily::Hidpp,
        peak_nm: 2.3,
        reference: "widely cited 2.1-2.3 N·m peak, same motor as the G29 (Logitech publishes \
                    none); highest used; verify against the maker's sheet",
        range_deg: 900.0,
        levels: LEVELS_16_BIT,
    },
    BuiltinWheel {
        // c266: native G923 mode; c267: PlayStation compatibility mode, which new-lg4ff
        // can switch to c266.
        name: "Logitech G923 (PlayStation/PC)",
        vendor: 0x046d,
        products: &[0xc266, 0xc267],
        driver: DriverFamily::Lg4ff,
        peak_nm: 2.3,
        reference: "widely cited 2.2-2.3 N·m peak, G29 motor with TRUEFORCE (Logitech \
                    publishes none); highest used; verify against the maker's sheet",
        range_deg: 900.0,
        levels: LEVELS_8_BIT,
    },
    BuiltinWheel {
        name: "Logitech G923 (Xbox/PC)",
        vendor: 0x046d,
        products: &[0xc26e],
        driver: DriverFamily::Hidpp,
        peak_nm: 2.3,
        reference: "widely cited 2.2-2.3 N·m peak, G920 motor with TRUEFORCE (Logitech \
                    publishes none); highest used; verify against the maker's sheet",
        range_deg: 900.0,
        levels: LEVELS_16_BIT,
    },
    BuiltinWheel {
        name: "Logitech G27",
        vendor: 0x046d,
        products: &[0xc29b],
        driver: DriverFamily::Lg4ff,
        peak_nm: 2.5,
        reference: "widely cited about 2.5 N·m peak, dual motor (Logitech publishes none); \
                    verify against the maker's sheet",
        range_deg: 900.0,
        levels: LEVELS_8_BIT,
    },
    BuiltinWheel {
        name: "Logitech G25",
        vendor: 0x046d,
        products: &[0xc299],
        driver: DriverFamily::Lg4ff,
        peak_nm: 2.5,
        reference: "widely cited about 2.5 N·m peak, G27's dual motor (Logitech publishes \
                    none); verify against the maker's sheet",
        range_deg: 900.0,
        levels: LEVELS_8_BIT,
    },
    // ---- Thrustmaster (vendor 044f). Thrustmaster publishes no N·m ratings for these bases.
    BuiltinWheel {
        // Driven by the out-of-tree hid-t150 driver (scarburato/t150_driver), whose update
        // path FIELD-NOTES does not cover: the slowest policy of the belt wheels is assumed.
        name: "Thrustmaster T150",
        vendor: 0x044f,
        products: &[0xb677],
        driver: DriverFamily::Tmff2,
        peak_nm: 2.5,
        reference: "widely cited 2.0-2.5 N·m peak (Thrustmaster publishes none); highest \
                    used; verify against the maker's sheet",
        range_deg: 1080.0,
        levels: LEVELS_TMFF2,
    },
    BuiltinWheel {
        // The T128 (weaker) shows up with the same id (hid-tmff2 udev rules: "T248 + T128").
        name: "Thrustmaster T248 (also T128)",
        vendor: 0x044f,
        products: &[0xb696],
        driver: DriverFamily::Tmff2,
        peak_nm: 3.5,
        reference: "widely cited 3.5 N·m peak in Boost mode (Thrustmaster publishes none); \
                    verify against the maker's sheet",
        range_deg: 900.0,
        levels: LEVELS_TMFF2,
    },
    BuiltinWheel {
        // b66e: PS3 normal mode, b66f: PS3 advanced (F1) mode. Its PS4 mode (b66d) is shared
        // with the T-GT II: see that row.
        name: "Thrustmaster T300 RS / T300 RS GT (PS3 modes)",
        vendor: 0x044f,
        products: &[0xb66e, 0xb66f],
        driver: DriverFamily::Tmff2,
        peak_nm: 3.9,
        reference: "widely cited 3.9 N·m peak (Thrustmaster publishes none); verify against \
                    the maker's sheet",
        range_deg: 1080.0,
        levels: LEVELS_TMFF2,
    },
    BuiltinWheel {
        // hid-tmff2 README: "The T-GT II ... reuses the T300 USB product ID"; its issue #55
        // shows a T-GT II enumerating as 044f:b66d, the T300 RS's PS4 mode.
        name: "Thrustmaster T-GT II or T300 RS in PS4 mode (shared USB id)",
        vendor: 0x044f,
        products: &[0xb66d],
        driver: DriverFamily::Tmff2,
        peak_nm: 6.0,
        reference: "one USB id for the T-GT II (widely cited 6.0 N·m peak) and the T300 RS \
                    (3.9 N·m): the stronger used; verify against the maker's sheet",
        range_deg: 1080.0,
        levels: LEVELS_TMFF2,
    },
    BuiltinWheel {
        name: "Thrustmaster TX (Xbox/PC)",
        vendor: 0x044f,
        products: &[0xb669],
        driver: DriverFamily::Tmff2,
        peak_nm: 3.9,
        reference: "widely cited 3.9 N·m peak, the T300 RS motor (Thrustmaster publishes \
                    none); verify against the maker's sheet",
        range_deg: 900.0,
        levels: LEVELS_TMFF2,
    },
    BuiltinWheel {
        // No Linux driver matches the first T-GT and its product id could not be confirmed:
        // no USB id, so it is chosen by hand and never matched by id.
        name: "Thrustmaster T-GT",
        vendor: 0x044f,
        products: &[],
        driver: DriverFamily::Tmff2,
        peak_nm: 6.0,
        reference: "widely cited 6.0 N·m peak (Thrustmaster publishes none); verify against \
                    the maker's sheet",
        range_deg: 1080.0,
        levels: LEVELS_TMFF2,
    },
    // ---- Fanatec (vendor 0eb7), hid-fanatec (gotzl/hid-fanatecff), in PC mode.
    BuiltinWheel {
        // hid-fanatecff README: "0EB7:0020 FANATEC CSL DD / DD Pro / ClubSport DD Wheel Base".
        name: "Fanatec CSL DD / Gran Turismo DD Pro / ClubSport DD(+) (shared USB id)",
        vendor: 0x0eb7,
        products: &[0x0020],
        driver: DriverFamily::Fanatec,
        peak_nm: 15.0,
        reference: "one USB id for the CSL DD and GT DD Pro (5 N·m, 8 N·m with the Boost Kit \
                    180) and the ClubSport DD (12 N·m) and DD+ (15 N·m) (Fanatec product \
                    pages as widely cited): the strongest used; verify against the maker's \
                    sheet",
        range_deg: DIRECT_DRIVE_RANGE_DEG,
        levels: LEVELS_16_BIT,
    },
    BuiltinWheel {
        // hid-fanatec sends these belt-driven bases 8-bit forces (no FTEC_HIGHRES) and caps
        // their range at 900°.
        name: "Fanatec ClubSport Wheel Base V2 / V2.5",
        vendor: 0x0eb7,
        products: &[0x0001, 0x0004],
        driver: DriverFamily::Fanatec,
        peak_nm: 8.0,
        reference: "widely cited 8 N·m peak (Fanatec publishes no N·m for the V2/V2.5); \
                    verify against the maker's sheet",
        range_deg: 900.0,
        levels: LEVELS_8_BIT,
    },
    // ---- Direct-drive bases on hid-universal-pidff (USB PID).
    BuiltinWheel {
        // Both ids of each Moza base are in universal-pidff's hid-ids.h (`..._R5`, `..._R5_2`);
        // which firmware or mode the `_2` id is was not confirmed.
        name: "Moza R5",
        vendor: 0x346e,
        products: &[0x0004, 0x0014],
        driver: DriverFamily::HidPidff,
        peak_nm: 5.5,
        reference: "Moza R5 product page as widely cited: 5.5 N·m peak; verify against the \
                    maker's sheet",
        range_deg: DIRECT_DRIVE_RANGE_DEG,
        levels: LEVELS_16_BIT,
    },
    BuiltinWheel {
        name: "Moza R9 (V1/V2)",
        vendor: 0x346e,
        products: &[0x0002, 0x0012],
        driver: DriverFamily::HidPidff,
        peak_nm: 9.0,
        reference: "Moza R9 V2 product page as widely cited: 9 N·m peak; verify against the \
                    maker's sheet",
        range_deg: DIRECT_DRIVE_RANGE_DEG,
        levels: LEVELS_16_BIT,
    },
    BuiltinWheel {
        name: "Moza R12",
        vendor: 0x346e,
        products: &[0x0006, 0x0016],
        driver: DriverFamily::HidPidff,
        peak_nm: 12.0,
        reference: "Moza R12 product page as widely cited: 12 N·m peak; verify against the \
                    maker's sheet",
        range_deg: DIRECT_DRIVE_RANGE_DEG,
        levels: LEVELS_16_BIT,
    },
    BuiltinWheel {
        // Legacy-firmware Simagic bases all enumerate as 0483:0522 (STMicroelectronics' vendor
        // id; JacKeTUs/simagic-ff, a hid-pidff derivative, or plain hid-pidff on old firmware).
        // The id cannot tell an Alpha Mini from an Alpha Ultimate, so the strongest is used.
        name: "Simagic Alpha Mini / M10 / Alpha / Alpha Ultimate (legacy firmware, shared USB id)",
        vendor: 0x0483,
        products: &[0x0522],
        driver: DriverFamily::HidPidff,
        peak_nm: 23.0,
        reference: "one USB id for the Alpha Mini (10 N·m), M10 (10 N·m), Alpha (15 N·m) and \
                    Alpha Ultimate (23 N·m) peak, Simagic figures as widely cited: the \
                    strongest used; verify against the maker's sheet",
        range_deg: DIRECT_DRIVE_RANGE_DEG,
        levels: LEVELS_16_BIT,
    },
    BuiltinWheel {
        name: "Cammus C5",
        vendor: 0x3416,
        products: &[0x0301],
        driver: DriverFamily::HidPidff,
        peak_nm: 5.0,
        reference: "Cammus C5 product page as widely cited: 5 N·m peak; verify against the \
                    maker's sheet",
        range_deg: DIRECT_DRIVE_RANGE_DEG,
        levels: LEVELS_16_BIT,
    },
];

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
    fn profiles_round_trip_through_toml() {
        let mut all = DeviceProfile::builtin();
        all.push(DeviceProfile::unknown(DriverFamily::Tmff2));
        all.push(DeviceProfile::unknown(DriverFamily::Lg4ff).with_rated_torque(2.0));
        for p in all {
            let text = toml::to_string(&p).unwrap();
            let back: DeviceProfile = toml::from_str(&text).unwrap();
            assert_eq!(p, back, "{text}");
        }
    }

    /// The wheels issue 12 lists, looked up by the USB ids their Linux drivers match:
    /// (vendor, product, a word of the profile's name, driver family, least peak N·m).
    const LISTED: &[(u16, u16, &str, DriverFamily, f64)] = &[
        (0x046d, 0xc24f, "G29", DriverFamily::Lg4ff, 2.2),
        (0x046d, 0xc262, "G920", DriverFamily::Hidpp, 2.2),
        (0x046d, 0xc266, "G923", DriverFamily::Lg4ff, 2.2),
        (0x046d, 0xc267, "G923", DriverFamily::Lg4ff, 2.2),
        (0x046d, 0xc26e, "G923", DriverFamily::Hidpp, 2.2),
        (0x046d, 0xc29b, "G27", DriverFamily::Lg4ff, 2.2),
        (0x046d, 0xc299, "G25", DriverFamily::Lg4ff, 2.2),
        (0x044f, 0xb677, "T150", DriverFamily::Tmff2, 2.0),
        (0x044f, 0xb696, "T248", DriverFamily::Tmff2, 3.5),
        (0x044f, 0xb66e, "T300", DriverFamily::Tmff2, 3.9),
        (0x044f, 0xb66f, "T300", DriverFamily::Tmff2, 3.9),
        // Shared by the T300 RS (PS4 mode) and the T-GT II: the T-GT II's 6 N·m.
        (0x044f, 0xb66d, "T-GT II", DriverFamily::Tmff2, 6.0),
        (0x044f, 0xb669, "TX", DriverFamily::Tmff2, 3.9),
        // Shared by the CSL DD (8 N·m with the Boost Kit 180) and the ClubSport DD+ (15).
        (0x0eb7, 0x0020, "CSL DD", DriverFamily::Fanatec, 15.0),
        (0x0eb7, 0x0001, "ClubSport", DriverFamily::Fanatec, 8.0),
        (0x0eb7, 0x0004, "ClubSport", DriverFamily::Fanatec, 8.0),
        (0x346e, 0x0004, "R5", DriverFamily::HidPidff, 5.5),
        (0x346e, 0x0014, "R5", DriverFamily::HidPidff, 5.5),
        (0x346e, 0x0002, "R9", DriverFamily::HidPidff, 9.0),
        (0x346e, 0x0012, "R9", DriverFamily::HidPidff, 9.0),
        (0x346e, 0x0006, "R12", DriverFamily::HidPidff, 12.0),
        (0x346e, 0x0016, "R12", DriverFamily::HidPidff, 12.0),
        // Shared by the Alpha Mini (10 N·m) and the Alpha Ultimate (23).
        (0x0483, 0x0522, "Alpha Mini", DriverFamily::HidPidff, 23.0),
        (0x3416, 0x0301, "Cammus C5", DriverFamily::HidPidff, 5.0),
        (0x045e, 0x0034, "SideWinder", DriverFamily::HidPidff, 1.87),
    ];

    #[test]
    fn each_listed_wheel_is_found_by_its_usb_id() {
        let builtin = DeviceProfile::builtin();
        for &(vendor, product, word, driver, least_nm) in LISTED {
            let p = DeviceProfile::for_usb_id(vendor, product);
            let id = format!("{vendor:04x}:{product:04x}");
            assert!(p.name.contains(word), "{id}: {}", p.name);
            assert_eq!(p.driver, driver, "{id}");
            assert!(p.max_torque_nm >= least_nm, "{id}: {}", p.max_torque_nm);
            assert!(builtin.contains(&p), "{id} is not a built-in row");
        }
        // And every id a built-in claims leads back to that built-in.
        for p in &builtin {
            for &product in &p.usb_products {
                let vendor = p.usb_vendor.expect("a profile with products has a vendor");
                assert_eq!(&DeviceProfile::for_usb_id(vendor, product), p);
            }
        }
    }

    #[test]
    fn no_two_builtins_claim_the_same_usb_id() {
        let mut seen = std::collections::HashMap::new();
        for p in DeviceProfile::builtin() {
            for &product in &p.usb_products {
                let key = (p.usb_vendor.unwrap(), product);
                if let Some(other) = seen.insert(key, p.name.clone()) {
                    panic!("{key:04x?} claimed by {other} and {}", p.name);
                }
            }
        }
        assert!(seen.len() >= LISTED.len());
    }

    #[test]
    fn builtins_state_the_makers_peak_torque_and_cite_it() {
        for p in DeviceProfile::builtin() {
            let expected = if p == DeviceProfile::thesis_sidewinder() {
                TorqueSource::Measured
            } else {
                TorqueSource::Maker
            };
            assert_eq!(p.torque_source, expected, "{}", p.name);
            assert!(!p.reference.trim().is_empty(), "{} cites nothing", p.name);
            assert_eq!(p.usable_max_nm(), p.max_torque_nm, "{}", p.name);
            // A maker's row: ±10 000 effect units span the motor's peak (the thesis wheel's
            // measured Kt gives 1.873 N·m against its 1.87 N·m range, thesis eq. 3.3).
            if expected == TorqueSource::Maker {
                assert!(
                    (p.full_scale_torque_nm() - p.max_torque_nm).abs() < 1e-12,
                    "{}",
                    p.name
                );
            }
        }
    }

    #[test]
    fn each_driver_family_has_the_field_notes_rate_policy() {
        // FIELD-NOTES, "Torque update paths differ by driver".
        assert_eq!(DriverFamily::HidPidff.max_update_rate_hz(), 1000.0);
        assert_eq!(DriverFamily::Lg4ff.max_update_rate_hz(), 500.0); // 2 ms timer
        assert_eq!(DriverFamily::Fanatec.max_update_rate_hz(), 500.0); // 2 ms
        assert_eq!(DriverFamily::Tmff2.max_update_rate_hz(), 125.0); // 8 ms
        let hidpp_period_ms = 1000.0 / DriverFamily::Hidpp.max_update_rate_hz();
        assert!((3.0..=5.0).contains(&hidpp_period_ms)); // throttled to 3–5 ms
        for p in DeviceProfile::builtin() {
            assert_eq!(
                p.max_update_rate_hz,
                p.driver.max_update_rate_hz(),
                "{}",
                p.name
            );
        }
    }

    #[test]
    fn eight_bit_drivers_resolve_a_127th_of_full_scale() {
        for p in DeviceProfile::builtin() {
            if p.driver == DriverFamily::Lg4ff {
                assert!(
                    (p.torque_step_nm - p.max_torque_nm / 127.0).abs() < 1e-12,
                    "{}",
                    p.name
                );
            }
        }
        let g29 = DeviceProfile::logitech_g29();
        assert_eq!(g29.usb_products, vec![0xc24f]);
        assert!((g29.half_range_rad.to_degrees() - 450.0).abs() < 1e-9);
        assert_eq!(g29.angle_sign, -1.0);
    }

    #[test]
    fn an_unknown_wheel_assumes_the_strongest_motor_and_is_capped() {
        let strongest = DeviceProfile::builtin()
            .iter()
            .map(|p| p.max_torque_nm)
            .fold(0.0, f64::max);
        for (vendor, product, driver) in [
            (0x1234, 0x0001, DriverFamily::HidPidff),
            (0x046d, 0xc294, DriverFamily::Lg4ff), // a Logitech wheel in compatibility mode
            (0x044f, 0xb65d, DriverFamily::Tmff2), // a Thrustmaster wheel before its init
            (0x0eb7, 0x0e03, DriverFamily::Fanatec), // CSL Elite: not in the table
            (0x346e, 0x0000, DriverFamily::HidPidff), // Moza R16/R21: not in the table
        ] {
            let p = DeviceProfile::for_usb_id(vendor, product);
            assert_eq!(
                p.torque_source,
                TorqueSource::Assumed,
                "{vendor:04x}:{product:04x}"
            );
            assert_eq!(p.driver, driver);
            assert_eq!(p.usable_max_nm(), 1.0);
            assert!(
                p.max_torque_nm >= strongest,
                "{} < {strongest}",
                p.max_torque_nm
            );
            p.validate().unwrap();
        }
    }
}
