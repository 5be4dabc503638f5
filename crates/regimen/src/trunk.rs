//! The gentle trunk cue the therapist sets: the `[trunk]` table prescribed with the exercises.
//!
//! ```toml
//! [trunk]
//! cue_deg = 15   # 5–45: "Sit back up straight." once the trunk stays this far from its start
//! ```
//!
//! With a sternum IMU (the station's `[arm] sternum`), the station says a short sentence
//! when the trunk's flexion, lean or rotation from the exercise's start posture stays beyond
//! `cue_deg` for a moment (the station's `arm::trunk_cue`: its dwell, hysteresis and rate
//! limit). Absent: no cue. Never during the standard assessment, whose protocol is the same
//! for every patient. The cue never changes the torque.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// The smallest cue threshold a regimen may set, deg: above what the trunk estimate's error
/// (≤ 2° RMS per axis, `gyro_imu::trunk`) and quiet sitting's sway could reach by
/// themselves, so a patient who sits still is never told to sit up.
pub const MIN_CUE_DEG: f64 = 5.0;
/// The largest cue threshold a regimen may set, deg: beyond it the trunk is far outside any
/// posture the wheel asks for, and the cue would come too late to be of use.
pub const MAX_CUE_DEG: f64 = 45.0;

/// The `[trunk]` table: when the station cues the patient to sit up.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TrunkCue {
    /// The trunk's excursion from the start posture (flexion, lean or rotation, deg, 5–45)
    /// that, held for a moment, brings the gentle cue to sit up straight.
    #[schemars(range(min = MIN_CUE_DEG, max = MAX_CUE_DEG))]
    pub cue_deg: f64,
}

impl TrunkCue {
    /// Checks `cue_deg`; the message names the key and its range.
    pub fn validate(&self) -> Result<(), String> {
        if self.cue_deg.is_finite() && (MIN_CUE_DEG..=MAX_CUE_DEG).contains(&self.cue_deg) {
            return Ok(());
        }
        Err(format!(
            "trunk.cue_deg = {}, allowed {MIN_CUE_DEG} to {MAX_CUE_DEG} deg",
            self.cue_deg
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cue_threshold_is_accepted_at_its_bounds_and_refused_beyond_naming_the_key() {
        for ok in [MIN_CUE_DEG, 15.0, MAX_CUE_DEG] {
            TrunkCue { cue_deg: ok }.validate().unwrap();
        }
        for bad in [4.9, 45.1, 0.0, -10.0, f64::NAN, f64::INFINITY] {
            let msg = TrunkCue { cue_deg: bad }.validate().unwrap_err();
            assert!(
                msg.contains("trunk.cue_deg") && msg.contains("5 to 45 deg"),
                "{msg}"
            );
        }
    }

    #[test]
    fn a_regimen_reads_its_trunk_table_and_refuses_a_cue_out_of_bounds_or_misspelt() {
        let text = "[trunk]\ncue_deg = 15.0\n[[exercise]]\nkind = \"dial\"\n";
        let r = crate::Regimen::from_toml(text, "cued").unwrap();
        assert_eq!(r.trunk, Some(TrunkCue { cue_deg: 15.0 }));
        let back = crate::Regimen::from_toml(&toml::to_string(&r).unwrap(), "again").unwrap();
        assert_eq!(back.trunk, r.trunk, "the table survives a round trip");
        let none = crate::Regimen::from_toml("[[exercise]]\nkind = \"dial\"\n", "plain").unwrap();
        assert_eq!(none.trunk, None, "absent: no cue");
        let err = crate::Regimen::from_toml(&text.replace("15.0", "60.0"), "far")
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("trunk.cue_deg = 60") && err.contains("5 to 45 deg"),
            "{err}"
        );
        let typo = crate::Regimen::from_toml(&text.replace("cue_deg", "cue_degs"), "typo");
        assert!(typo.unwrap_err().to_string().contains("cue_degs"));
    }
}
