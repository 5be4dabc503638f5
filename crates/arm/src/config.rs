//! The `[arm]` section of the station's configuration: how the IMUs' placement is known, the
//! real patient's arm and seat geometry, the sternum IMU and the trunk threshold. The station's
//! configuration (`session::config`) reads it as its `arm` field; the TOML is the same.

use gyro_imu::ImuError;
use gyro_imu::arm::ArmGeometry;
use serde::{Deserialize, Serialize};

/// How the IMUs' placement on the arm is known.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum MountingMode {
    /// Simulated IMUs strapped on with their axes along the segments' (simulation only).
    #[default]
    Square,
    /// Simulated IMUs strapped on at seeded random rotations, found by the guided procedure
    /// at the start of the session, as with real IMUs.
    Guided,
}

/// The `[arm]` section: arm sensing settings.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ArmConfig {
    /// IMU placement in simulated sessions (real IMUs always run the guided procedure).
    pub sim_mounting: MountingMode,
    /// The real patient's arm and seat geometry (the simulated patient's is `sim_arm`).
    pub geometry: ArmGeometry,
    /// Elbow swivel (rad, positive = elbow out) the real patient holds during the guided
    /// procedure.
    pub swivel_rad: f64,
    /// A third IMU on the sternum measures the trunk (`gyro_imu::trunk`). Simulated sessions
    /// then simulate one (the patient leaning and twisting more the weaker `sim_patient`'s
    /// arm); off by default, and a session without it runs exactly as before.
    pub sternum: bool,
    /// Trunk excursion from the start posture beyond which a moment counts as compensating
    /// and a movement as compensated with the trunk (deg, [3, 45]; 10 by default).
    pub trunk_threshold_deg: f64,
}

impl Default for ArmConfig {
    fn default() -> Self {
        Self {
            sim_mounting: MountingMode::default(),
            geometry: ArmGeometry::default(),
            swivel_rad: 0.35,
            sternum: false,
            trunk_threshold_deg: DEFAULT_TRUNK_THRESHOLD_DEG,
        }
    }
}

/// The default trunk threshold (deg): 10°, about the trunk's own excursion when a healthy
/// adult turns a wheel seated (under 5°, Cirstea & Levin 2000 for reaching) with room for the
/// estimate's 2° and the sway; the therapist lowers it for a patient who should sit still.
pub const DEFAULT_TRUNK_THRESHOLD_DEG: f64 = 10.0;

impl ArmConfig {
    /// Check every field; the error names the field and its allowed range.
    pub fn validate(&self) -> Result<(), ImuError> {
        self.geometry.validate()?;
        if !(self.swivel_rad.is_finite() && self.swivel_rad.abs() <= 1.5) {
            return Err(ImuError::InvalidConfig {
                field: "swivel_rad",
                value: self.swivel_rad,
                allowed: "[-1.5, 1.5] rad",
            });
        }
        if !(self.trunk_threshold_deg.is_finite()
            && (3.0..=45.0).contains(&self.trunk_threshold_deg))
        {
            return Err(ImuError::InvalidConfig {
                field: "trunk_threshold_deg",
                value: self.trunk_threshold_deg,
                allowed: "[3, 45] deg",
            });
        }
        gyro_imu::arm::solve(&self.geometry, 0.0, self.swivel_rad, 0.0).map(|_| ())
    }
}
