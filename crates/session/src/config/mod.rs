//! Station configuration: TOML with serde, every field defaulted, unknown fields rejected,
//! and every value validated with a message naming the field and its allowed range.

pub mod faults;

use assist::{AssistSpec, HumanArmParams};
use exercises::VehicleParams;
use gyro_imu::sim::arm::PatientArmConfig;
use haptic_wheel::{PassivityParams, SafetyConfig, SimWheelParams, SpringDamper};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Everything a session needs that is not a device handle.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct StationConfig {
    /// Session length, loop rate, seed.
    pub session: SessionConfig,
    /// Torque limits and the haptic model rendered on the wheel.
    pub haptic: HapticConfig,
    /// Active assistance (none when absent).
    pub assist: Option<AssistSpec>,
    /// The virtual car.
    pub vehicle: VehicleParams,
    /// The simulated wheel (used with `--sim`).
    pub sim_wheel: SimWheelParams,
    /// The simulated patient's arm control (used with `--sim`).
    pub sim_patient: HumanArmParams,
    /// The simulated patient's arm geometry and posture, with IMUs on it (used with `--sim`).
    pub sim_arm: PatientArmConfig,
    /// Arm sensing: IMU mounting and the real patient's arm geometry.
    pub arm: arm::ArmConfig,
    /// The therapist link.
    pub therapist: TherapistLinkConfig,
    /// The real force-feedback wheel: profile, rated torque, gain, effect length, update rate
    /// (see `crates/haptic-wheel/CALIBRATION.md`).
    pub wheel: haptic_wheel::WheelConfig,
    /// Faults injected into a simulated session (`[[faults]]`; `--fault KIND@S` adds more):
    /// see `session::faults`. Ignored by nothing: a real wheel refuses them.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub faults: Vec<faults::FaultSpec>,
}

impl Default for StationConfig {
    fn default() -> Self {
        Self {
            session: SessionConfig::default(),
            haptic: HapticConfig::default(),
            assist: None,
            vehicle: VehicleParams::default(),
            sim_wheel: SimWheelParams::default(),
            sim_patient: default_sim_patient(),
            sim_arm: PatientArmConfig::default(),
            arm: Default::default(),
            therapist: TherapistLinkConfig::default(),
            wheel: haptic_wheel::WheelConfig::default(),
            faults: Vec::new(),
        }
    }
}

/// A healthy adult's simple visual reaction time, s (Woods et al. 2015, Front Hum Neurosci
/// 9:131).
pub const HEALTHY_REACTION_S: f64 = 0.22;

/// The simulated patient holding the wheel: an unimpaired adult arm. The thesis's K_P = 2
/// (Table 5.1) belongs to its J = 10 plant; on a 0.02 kg·m² wheel against a centring spring and
/// road feel of up to ~1 N·m, an arm that keeps the wheel within a few degrees of its aim needs
/// a stiffer grip (arm stiffness of several N·m/rad is typical of the human upper limb). It
/// reacts to an unpredictable jump of its target (the assessment's steps) after a healthy
/// adult's simple visual reaction time, 0.22 s (Woods et al. 2015, Front Hum Neurosci 9:131:
/// 0.21–0.23 s in 1469 adults); without it the steps' reaction time was the 0.05 s feedback
/// delay plus the onset threshold, ~0.07 s, faster than any human's.
pub fn default_sim_patient() -> HumanArmParams {
    HumanArmParams {
        kp_nm_per_rad: 8.0,
        ki_nm_per_rad_s: 4.0,
        kd_nm_s_per_rad: 0.3,
        reaction_s: HEALTHY_REACTION_S,
        ..HumanArmParams::default()
    }
}

/// Session length, loop rate and seed.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SessionConfig {
    /// Session length, s.
    pub duration_s: f64,
    /// Haptic loop rate, Hz.
    pub loop_rate_hz: f64,
    /// Seed of every random source in simulated sessions.
    pub seed: u64,
    /// Exercise name (see `telerehab run --help`). The car's target speed is the exercise's
    /// own `speed_m_s` (a regimen sets it per exercise); `session.speed_m_s`, once validated
    /// here and never read, is retired.
    pub exercise: String,
    /// Patient identifier sent to the therapist (no personal data: a pseudonym;
    /// letters, digits, `_`, `.`, `-`).
    pub patient_id: String,
    /// This station's identifier at the therapist hub (letters, digits, `_`, `.`, `-`).
    pub station_id: String,
    /// A rest the patient asks for (R, or a wheel button) lasts this long, s, in [5, 600].
    pub asked_rest_s: f64,
    /// A pause longer than this ends the session ("paused too long"), s, in [10, 7200].
    pub pause_limit_s: f64,
    /// Whom the session is for in the clinic's words (pseudonym, clinic, therapist), from the
    /// station's pairing: recorded in the session's metadata. Never read from or written to a
    /// configuration file.
    #[serde(skip)]
    pub clinic: Option<record::ClinicNote>,
}

impl Default for SessionConfig {
    fn default() -> Self {
        Self {
            duration_s: 60.0,
            loop_rate_hz: 1000.0,
            seed: 7,
            exercise: "sine-road".into(),
            patient_id: "patient-0".into(),
            station_id: "station-1".into(),
            asked_rest_s: 60.0,
            pause_limit_s: 600.0,
            clinic: None,
        }
    }
}

/// Torque limits and haptic rendering (the `haptic-wheel` chain).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct HapticConfig {
    /// Safety limits: per-patient ceiling (default: the device maximum), slew, soft start,
    /// fade-out, deadline and stale-reading watchdog.
    pub safety: SafetyConfig,
    /// Centring spring–damper (thesis eq. 3.5); all-zero coefficients render nothing.
    pub centring: SpringDamper,
    /// Time-domain passivity controller (Hannaford–Ryu) on the rendered model.
    pub passivity: PassivityParams,
    /// Turn the passivity controller on.
    pub passivity_enabled: bool,
    /// Road feel: wheel torque per kN of front lateral tyre force, N·m/kN (thesis §3.3.4).
    /// The steering ratio is `vehicle.steering_ratio`.
    pub road_feel_nm_per_kn: f64,
    /// How long an unplugged wheel may take to come back, s, in [0, 600]: meanwhile the torque
    /// is zero and the exercise paused; when it answers again the exercise resumes with a soft
    /// start, and when it does not the session ends with the reason (0: at once).
    pub replug_grace_s: f64,
}

impl Default for HapticConfig {
    fn default() -> Self {
        Self {
            safety: SafetyConfig {
                fade_out_s: 0.1,
                ..SafetyConfig::default()
            },
            centring: SpringDamper::default(),
            passivity: PassivityParams::default(),
            passivity_enabled: true,
            road_feel_nm_per_kn: exercises::AligningTorque::default().nm_per_kn,
            replug_grace_s: 30.0,
        }
    }
}

/// The therapist link.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct TherapistLinkConfig {
    /// Therapist hub address `host:port`; empty means no link.
    pub address: String,
    /// PEM file of the certificate authority that signed the hub's certificate; enables TLS.
    pub ca_pem: Option<std::path::PathBuf>,
    /// Name in the hub's certificate (defaults to the host of `address`).
    pub server_name: Option<String>,
    /// This station's certificate (PEM) for hubs that require mutual TLS; with `key_pem`.
    pub cert_pem: Option<std::path::PathBuf>,
    /// This station's private key (PEM); with `cert_pem`.
    pub key_pem: Option<std::path::PathBuf>,
}

/// A configuration problem, naming the field.
#[derive(Debug, thiserror::Error)]
pub enum ConfigError {
    /// The file could not be read.
    #[error("cannot read config file {path}: {source}")]
    Read {
        /// The file.
        path: String,
        /// Why.
        source: std::io::Error,
    },
    /// The TOML did not parse or had unknown fields.
    #[error("config file {path}: {message}")]
    Parse {
        /// The file.
        path: String,
        /// The parser's message (names the field and line).
        message: String,
    },
    /// A section's own validation failed (its message names the field and range).
    #[error("config section [{section}]: {message}")]
    Section {
        /// The TOML section.
        section: String,
        /// The section's message.
        message: String,
    },
    /// A value is outside its allowed range.
    #[error("config field `{field}` = {value} is out of range: allowed {allowed}")]
    OutOfRange {
        /// Dotted field name, e.g. `haptic.ceiling_nm`.
        field: String,
        /// The offending value.
        value: String,
        /// The allowed range, in words.
        allowed: String,
    },
}

fn check(field: &str, value: f64, lo: f64, hi: f64, unit: &str) -> Result<(), ConfigError> {
    if value.is_finite() && value >= lo && value <= hi {
        Ok(())
    } else {
        Err(ConfigError::OutOfRange {
            field: field.into(),
            value: value.to_string(),
            allowed: format!("{lo} to {hi} {unit}"),
        })
    }
}

/// Map a section's own validation error into a [`ConfigError`] naming the section.
fn in_section(section: &str) -> impl Fn(&dyn std::fmt::Display) -> ConfigError + '_ {
    move |e| ConfigError::Section {
        section: section.into(),
        message: e.to_string(),
    }
}

impl StationConfig {
    /// Read and validate a TOML config file, and the wheel profile file it names (relative
    /// to the config file's folder).
    pub fn load(path: &Path) -> Result<Self, ConfigError> {
        let text = std::fs::read_to_string(path).map_err(|source| ConfigError::Read {
            path: path.display().to_string(),
            source,
        })?;
        let mut cfg = Self::from_toml(&text, &path.display().to_string())?;
        if let Some(file) = cfg.wheel.profile_file.take() {
            let file = path.parent().unwrap_or(Path::new(".")).join(file);
            cfg.wheel.profile = Some(load_wheel_profile(&file)?);
        }
        Ok(cfg)
    }

    /// A configuration as a recording keeps it, written by this or another version: read
    /// leniently (`regimen::lenient`: a field this version does not know is dropped, a field
    /// it needs and the text lacks takes the default configuration's value, each named in the
    /// notes), then validated as [`StationConfig::from_toml`] does.
    pub fn from_recorded(text: &str, origin: &str) -> Result<(Self, Vec<String>), ConfigError> {
        let parse_error = |message| ConfigError::Parse {
            path: origin.into(),
            message,
        };
        let defaults = regimen::lenient::defaults_of(&Self::default());
        let read = regimen::lenient::from_toml_lenient::<Self>(text, defaults.as_ref())
            .map_err(parse_error)?;
        read.value.validate()?;
        Ok((read.value, read.notes))
    }

    /// Parse and validate TOML text; `origin` names it in messages.
    pub fn from_toml(text: &str, origin: &str) -> Result<Self, ConfigError> {
        let cfg: Self = toml::from_str(text).map_err(|e| ConfigError::Parse {
            path: origin.into(),
            message: e.to_string(),
        })?;
        cfg.validate()?;
        Ok(cfg)
    }

    /// Check every value against its allowed range. Each crate validates its own section.
    pub fn validate(&self) -> Result<(), ConfigError> {
        let s = &self.session;
        check("session.duration_s", s.duration_s, 0.001, 4.0 * 3600.0, "s")?;
        check("session.loop_rate_hz", s.loop_rate_hz, 100.0, 2000.0, "Hz")?;
        check("session.asked_rest_s", s.asked_rest_s, 5.0, 600.0, "s")?;
        check("session.pause_limit_s", s.pause_limit_s, 10.0, 7200.0, "s")?;
        for (field, value) in [
            ("session.patient_id", &s.patient_id),
            ("session.station_id", &s.station_id),
        ] {
            netlink::frame::check_id(field, value).map_err(|m| in_section("session")(&m))?;
        }
        self.sim_wheel
            .validate()
            .map_err(|e| in_section("sim_wheel")(&e))?;
        let h = &self.haptic;
        h.safety
            .validate(self.sim_wheel.max_torque_nm)
            .map_err(|e| in_section("haptic.safety")(&e))?;
        h.centring
            .validate()
            .map_err(|e| in_section("haptic.centring")(&e))?;
        h.passivity
            .validate()
            .map_err(|e| in_section("haptic.passivity")(&e))?;
        check(
            "haptic.road_feel_nm_per_kn",
            h.road_feel_nm_per_kn,
            0.0,
            2.0,
            "N·m/kN",
        )?;
        check("haptic.replug_grace_s", h.replug_grace_s, 0.0, 600.0, "s")?;
        if let Some(a) = &self.assist {
            a.validate().map_err(|e| in_section("assist")(&e))?;
        }
        faults::validate_all(&self.faults).map_err(|e| in_section("faults")(&e))?;
        self.sim_patient
            .validate()
            .map_err(|e| in_section("sim_patient")(&e))?;
        self.sim_arm
            .validate()
            .map_err(|e| in_section("sim_arm")(&e))?;
        self.arm.validate().map_err(|e| in_section("arm")(&e))?;
        self.vehicle
            .validate()
            .map_err(|e| in_section("vehicle")(&e))?;
        self.wheel.validate().map_err(|e| in_section("wheel")(&e))?;
        Ok(())
    }
}

/// Read and validate a wheel profile file (TOML, the fields of `DeviceProfile`, as
/// `telerehab wheel calibrate` writes it).
pub fn load_wheel_profile(path: &Path) -> Result<haptic_wheel::DeviceProfile, ConfigError> {
    let origin = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|source| ConfigError::Read {
        path: origin.clone(),
        source,
    })?;
    let p: haptic_wheel::DeviceProfile = toml::from_str(&text).map_err(|e| ConfigError::Parse {
        path: origin.clone(),
        message: e.to_string(),
    })?;
    p.validate()
        .map_err(|e| in_section("wheel.profile_file")(&format!("{origin}: {e}")))?;
    Ok(p)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_recorded_configuration_of_another_version_reads_and_names_what_changed() {
        let mut text = toml::to_string(&StationConfig::default()).unwrap();
        text = text.replacen("[session]\n", "[session]\nretired_option = true\n", 1);
        text.push_str("\n[section_of_a_later_version]\nx = 1\n");
        assert!(StationConfig::from_toml(&text, "strict").is_err());
        let (cfg, notes) = StationConfig::from_recorded(&text, "recorded").unwrap();
        assert_eq!(cfg, StationConfig::default());
        assert_eq!(notes.len(), 2, "{notes:?}");
        assert!(notes.iter().any(|n| n.contains("session.retired_option")));
        assert!(
            notes
                .iter()
                .any(|n| n.contains("section_of_a_later_version"))
        );
    }

    #[test]
    fn empty_file_gives_the_defaults() {
        let cfg = StationConfig::from_toml("", "test").unwrap();
        assert_eq!(cfg, StationConfig::default());
    }

    #[test]
    fn unknown_field_is_rejected_by_name() {
        let err =
            StationConfig::from_toml("[haptic.safety]\nceilng_nm = 1.0\n", "test").unwrap_err();
        assert!(err.to_string().contains("ceilng_nm"), "{err}");
    }

    #[test]
    fn ceiling_above_device_maximum_names_field_and_range() {
        let err =
            StationConfig::from_toml("[haptic.safety]\nceiling_nm = 5.0\n", "test").unwrap_err();
        let msg = err.to_string();
        assert!(
            msg.contains("haptic.safety") && msg.contains("ceiling_nm") && msg.contains("1.87"),
            "{msg}"
        );
    }

    #[test]
    fn simulated_patient_is_validated_by_its_own_rules() {
        let err = StationConfig::from_toml("[sim_patient]\ndelay_s = -1.0\n", "test").unwrap_err();
        let msg = err.to_string();
        assert!(
            msg.contains("sim_patient") && msg.contains("delay_s"),
            "{msg}"
        );
    }

    #[test]
    fn injected_faults_are_read_from_the_config_and_checked() {
        let cfg = StationConfig::from_toml(
            "[[faults]]\nkind = \"wheel-stall\"\nat_s = 2.0\nduration_s = 0.3\n",
            "test",
        )
        .unwrap();
        assert_eq!(
            cfg.faults,
            [faults::FaultSpec::parse("wheel-stall@2+0.3").unwrap()]
        );
        let err = StationConfig::from_toml("[[faults]]\nkind = \"wheel-nan\"\nat_s = -1.0\n", "t")
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("[faults]") && err.contains("wheel-nan"),
            "{err}"
        );
    }

    #[test]
    fn nan_value_is_rejected() {
        let err =
            StationConfig::from_toml("[haptic.safety]\nslew_nm_per_s = nan\n", "test").unwrap_err();
        assert!(err.to_string().contains("slew_nm_per_s"), "{err}");
    }

    /// The ```toml blocks of the wheel guide, in order.
    fn calibration_md_toml_blocks() -> Vec<String> {
        let md = include_str!("../../../haptic-wheel/CALIBRATION.md");
        md.split("```toml\n")
            .skip(1)
            .map(|b| b.split("```").next().unwrap_or_default().to_string())
            .collect()
    }

    #[test]
    fn the_wheel_section_documented_in_calibration_md_parses_and_loads_its_profile_file() {
        let blocks = calibration_md_toml_blocks();
        let section = blocks
            .iter()
            .find(|b| b.trim_start().starts_with("[wheel]"))
            .expect("CALIBRATION.md documents a [wheel] section");
        let profile = blocks
            .iter()
            .find(|b| b.trim_start().starts_with("name ="))
            .expect("CALIBRATION.md documents a profile file");
        let cfg = StationConfig::from_toml(section, "CALIBRATION.md").unwrap();
        assert_eq!(cfg.wheel.rated_torque_nm, Some(8.0));
        // The documented profile file, where the documented section points.
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("wheel-profile.toml"), profile).unwrap();
        std::fs::write(dir.path().join("station.toml"), section).unwrap();
        let cfg = StationConfig::load(&dir.path().join("station.toml")).unwrap();
        let p = cfg
            .wheel
            .profile
            .as_ref()
            .expect("the profile file is loaded");
        assert_eq!(p.name, "My wheel");
        // The clinician's rating applies over the file's figure.
        let resolved = cfg.wheel.resolve_profile(0x1234, 0x5678);
        assert_eq!(resolved.max_torque_nm, 8.0);
    }

    #[test]
    fn a_bad_wheel_section_or_profile_file_is_named() {
        let msg = StationConfig::from_toml("[wheel]\ngain = 2.0\n", "test")
            .unwrap_err()
            .to_string();
        assert!(msg.contains("wheel.gain"), "{msg}");
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("p.toml"), "name = \"x\"\n").unwrap();
        std::fs::write(
            dir.path().join("station.toml"),
            "[wheel]\nprofile_file = \"p.toml\"\n",
        )
        .unwrap();
        let msg = StationConfig::load(&dir.path().join("station.toml"))
            .unwrap_err()
            .to_string();
        assert!(msg.contains("p.toml"), "{msg}");
    }
}
