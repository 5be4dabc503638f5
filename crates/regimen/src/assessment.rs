//! When the standard assessment (`exercises::assessment`) is due: the `[assessment]` table the
//! therapist prescribes with the exercises.
//!
//! ```toml
//! [assessment]
//! every_days = 7   # 1–90: the station runs the assessment first in a session this often
//! ```
//!
//! The station decides whether it is due from its own history of the assessments it ran
//! for this patient (the station's `assessment` module): a session must start without the
//! hub, and the station is where the assessment runs. A station new to the patient (paired
//! afresh, or replaced) has no history and runs it in its first session.

/// The protocol the schedule runs (its parts and fixed settings), for the regimen's readers
/// (the hub's exports define it from these constants).
pub use exercises::assessment as protocol;
use haptic_wheel::{HapticRegimen, SpringDamper};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::RegimenEntry;

/// Fewest days between two assessments a regimen may ask for.
pub const MIN_EVERY_DAYS: u32 = 1;
/// Most days between two assessments a regimen may ask for (about three months).
pub const MAX_EVERY_DAYS: u32 = 90;

/// Milliseconds in a day.
const DAY_MS: u64 = 86_400_000;

/// The `[assessment]` table: how often the station runs the standard assessment.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct AssessmentSchedule {
    /// Days from one assessment to the next (1–90): the station runs it first in the first
    /// session this many days or more after the last one.
    #[schemars(range(min = MIN_EVERY_DAYS, max = MAX_EVERY_DAYS))]
    pub every_days: u32,
}

impl AssessmentSchedule {
    /// Checks `every_days`; the message names the field and its range.
    pub fn validate(&self) -> Result<(), String> {
        if (MIN_EVERY_DAYS..=MAX_EVERY_DAYS).contains(&self.every_days) {
            return Ok(());
        }
        Err(format!(
            "assessment.every_days = {}, allowed {MIN_EVERY_DAYS} to {MAX_EVERY_DAYS} days",
            self.every_days
        ))
    }

    /// Whether a session starting at `now_unix_ms` runs the assessment, the last one having
    /// ended at `last_unix_ms` (none yet: due). A clock set back before the last one is
    /// not due (the assessment ran "later").
    pub fn is_due(&self, last_unix_ms: Option<u64>, now_unix_ms: u64) -> bool {
        last_unix_ms.is_none_or(|last| {
            now_unix_ms.saturating_sub(last) >= u64::from(self.every_days) * DAY_MS
        })
    }
}

/// The protocol's entries as the station runs them, in order, steps drawn from `seed`: no
/// assistance (whatever the station's settings), the protocol's fixed wheel feel, no rest
/// but the card between parts.
pub fn entries(seed: u32) -> Vec<RegimenEntry> {
    let feel = HapticRegimen {
        model: Some(SpringDamper {
            k_nm_per_rad: protocol::WHEEL_SPRING_NM_PER_RAD,
            b_nm_s_per_rad: protocol::WHEEL_DAMPER_NM_S_PER_RAD,
            i_kg_m2: protocol::WHEEL_INERTIA_KG_M2,
            centre_rad: 0.0,
        }),
        ..HapticRegimen::default()
    };
    exercises::ExerciseSpec::assessment_protocol(seed)
        .into_iter()
        .map(|exercise| RegimenEntry {
            exercise,
            haptic: Some(feel.clone()),
            assist: None,
            rest_s: None,
            pedals: false,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_assessment_is_due_first_time_and_after_its_days_and_not_before() {
        let weekly = AssessmentSchedule { every_days: 7 };
        let now = 1_800_000_000_000;
        assert!(weekly.is_due(None, now));
        assert!(!weekly.is_due(Some(now - 6 * DAY_MS), now));
        assert!(weekly.is_due(Some(now - 7 * DAY_MS), now));
        assert!(!weekly.is_due(Some(now + DAY_MS), now), "a clock set back");
        for bad in [0, 91] {
            let msg = AssessmentSchedule { every_days: bad }
                .validate()
                .unwrap_err();
            assert!(
                msg.contains("every_days") && msg.contains("1 to 90"),
                "{msg}"
            );
        }
    }

    #[test]
    fn a_regimen_reads_its_assessment_table_and_refuses_a_schedule_out_of_bounds() {
        let text = "[assessment]\nevery_days = 14\n[[exercise]]\nkind = \"dial\"\n";
        let r = crate::Regimen::from_toml(text, "weekly").unwrap();
        assert_eq!(r.assessment, Some(AssessmentSchedule { every_days: 14 }));
        let err = crate::Regimen::from_toml(&text.replace("14", "365"), "yearly")
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("every_days = 365") && err.contains("1 to 90"),
            "{err}"
        );
        let typo = crate::Regimen::from_toml(&text.replace("every_days", "every_day"), "typo");
        assert!(typo.unwrap_err().to_string().contains("every_day"));
    }

    #[test]
    fn the_entries_have_no_assistance_and_the_fixed_feel_and_validate() {
        let entries = entries(9);
        assert_eq!(entries.len(), exercises::AssessmentPart::ALL.len());
        for e in &entries {
            assert!(e.assist.is_none() && e.rest_s.is_none() && !e.pedals);
            e.exercise.validate().unwrap();
            let h = e.haptic.as_ref().unwrap();
            h.validate(crate::MAX_DEVICE_TORQUE_NM).unwrap();
            assert_eq!(
                h.model.unwrap().b_nm_s_per_rad,
                protocol::WHEEL_DAMPER_NM_S_PER_RAD
            );
        }
    }
}
