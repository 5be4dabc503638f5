//! The standard assessment at the station (issue 42, `exercises::assessment`): whether it is due,
//! and the history that says so.
//!
//! * **Due**: the regimen's `[assessment] every_days` (`regimen::AssessmentSchedule`) against
//!   the last assessment this station ran for the patient. The station decides from its own
//!   history, not the hub's: a session must start without the hub, and the station is where
//!   the assessment runs. A station new to the patient (paired afresh, replaced, its home
//!   wiped) has no history and runs the assessment in its first session: one assessment too
//!   many is harmless, one missed is not.
//! * **History**: `assessments.jsonl` in the station's home, one JSON object a line (when,
//!   patient, protocol, seed), the last [`KEPT`]; a session keeps its line when it ends
//!   without a recorder error and is no try-out.
//! * **Run**: the protocol's entries (`regimen::assessment::entries`, no assistance, the fixed
//!   wheel feel) go first in the session's regimen; the seed of the steps is drawn from the
//!   session's seed and start and is recorded with the regimen, in the history and in the
//!   `Bye`'s tag of each part.

use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The history's file in the home.
pub const HISTORY_FILE: &str = "assessments.jsonl";
/// Assessments the history keeps (the oldest go first).
pub const KEPT: usize = 50;

/// One assessment the station ran.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Entry {
    /// When the session ended, ms since the Unix epoch.
    pub unix_ms: u64,
    /// The patient.
    pub patient_id: String,
    /// The protocol's version.
    pub protocol: u32,
    /// The seed of its steps.
    pub seed: u32,
}

/// The assessment a session runs first.
#[derive(Debug, Clone, PartialEq)]
pub struct Planned {
    /// Its protocol and seed, for the `Bye`.
    pub tag: netlink::AssessmentTag,
    history: Option<PathBuf>,
    patient_id: String,
}

/// The history's file in the home at `dir`.
pub fn history_path(dir: &Path) -> PathBuf {
    dir.join(HISTORY_FILE)
}

/// When the last assessment of `patient_id` kept at `path` ended, ms since the Unix epoch
/// (none if the file is missing or holds none; a line that does not read is skipped).
pub fn last_unix_ms(path: &Path, patient_id: &str) -> Option<u64> {
    let bytes = std::fs::read(path).ok()?;
    netlink::ndjson::read_lines(&bytes[..])
        .filter_map(|(_, l)| netlink::ndjson::parse::<Entry>(&l).ok())
        .filter(|e| e.patient_id == patient_id)
        .map(|e| e.unix_ms)
        .max()
}

/// The seed of a session's steps: the session's seed and start mixed (SplitMix64's
/// finaliser), so that every session steps at other times and a replay of the same session
/// steps at the same.
pub fn seed_of(session_seed: u64, start_unix_ms: u64) -> u32 {
    let mut z = session_seed ^ start_unix_ms.wrapping_mul(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    (z ^ (z >> 31)) as u32
}

impl Planned {
    /// When the regimen schedules the assessment and it is due for `patient_id` at
    /// `now_unix_ms` (by the history in `home_dir`; without a home, always due): the
    /// protocol's entries put first in the regimen, steps drawn from `seed`.
    pub fn plan(
        regimen: &mut Option<regimen::Regimen>,
        home_dir: Option<&Path>,
        patient_id: &str,
        now_unix_ms: u64,
        seed: u32,
    ) -> Option<Self> {
        let r = regimen.as_mut()?;
        let schedule = r.assessment.clone()?;
        let history = home_dir.map(history_path);
        let last = history.as_deref().and_then(|p| last_unix_ms(p, patient_id));
        if !schedule.is_due(last, now_unix_ms) {
            tracing::info!(
                every_days = schedule.every_days,
                "the standard assessment is not due"
            );
            return None;
        }
        let mut exercises = regimen::assessment::entries(seed);
        exercises.append(&mut r.exercises);
        r.exercises = exercises;
        tracing::info!(seed, "the standard assessment runs first");
        Some(Self {
            tag: netlink::AssessmentTag {
                protocol: exercises::assessment::PROTOCOL_VERSION,
                seed,
            },
            history,
            patient_id: patient_id.to_owned(),
        })
    }

    /// [`Self::plan`] for the session of `cfg` started at `start_unix_ms` (its steps' seed
    /// from the session's seed and start, [`seed_of`]); a regimen session's name then counts
    /// the assessment's parts too (`regimen:N`).
    pub fn for_session(
        cfg: &mut crate::config::StationConfig,
        regimen: &mut Option<regimen::Regimen>,
        home_dir: Option<&Path>,
        start_unix_ms: u64,
    ) -> Option<Self> {
        let seed = seed_of(cfg.session.seed, start_unix_ms);
        let planned = Self::plan(
            regimen,
            home_dir,
            &cfg.session.patient_id,
            start_unix_ms,
            seed,
        )?;
        if let Some(r) = regimen
            && cfg.session.exercise.starts_with("regimen:")
        {
            cfg.session.exercise = format!("regimen:{}", r.exercises.len());
        }
        Some(planned)
    }

    /// Keeps the assessment in the history, ended at `unix_ms`. A history that cannot be
    /// written is a warning (the next session then runs the assessment again).
    pub fn remember(&self, unix_ms: u64) {
        let Some(path) = &self.history else {
            return;
        };
        let entry = Entry {
            unix_ms,
            patient_id: self.patient_id.clone(),
            protocol: self.tag.protocol,
            seed: self.tag.seed,
        };
        if let Err(e) = append(path, &entry) {
            tracing::warn!(error = %e, path = %path.display(), "cannot keep the assessment in the history");
        }
    }
}

/// Whether a session's results hold every part of the assessment (a session ended early
/// in it did not assess: the next one runs it again).
pub fn ran_whole(results: &[record::ExerciseResult]) -> bool {
    exercises::ExerciseSpec::assessment_protocol(0)
        .iter()
        .all(|part| results.iter().any(|r| r.kind == part.name()))
}

/// Appends `entry` to the history at `path`, keeping the last [`KEPT`] lines (written whole,
/// atomically, 0600).
fn append(path: &Path, entry: &Entry) -> anyhow::Result<()> {
    crate::files::append_kept(path, entry, KEPT)
}

#[cfg(test)]
mod tests {
    use super::*;

    const DAY_MS: u64 = 86_400_000;

    fn weekly() -> Option<regimen::Regimen> {
        let text = "[assessment]\nevery_days = 7\n[[exercise]]\nkind = \"sine\"\n";
        Some(regimen::Regimen::from_toml(text, "weekly").unwrap())
    }

    #[test]
    fn the_assessment_goes_first_when_due_and_the_history_holds_it_back_for_its_days() {
        let dir = tempfile::tempdir().unwrap();
        let now = 1_800_000_000_000;
        let mut r = weekly();
        let planned = Planned::plan(&mut r, Some(dir.path()), "p1", now, 5).unwrap();
        let names: Vec<String> = r
            .as_ref()
            .unwrap()
            .exercises
            .iter()
            .map(|e| e.exercise.name())
            .collect();
        assert_eq!(names.len(), 7, "{names:?}");
        assert!(
            names[..6].iter().all(|n| n.starts_with("assessment-")),
            "{names:?}"
        );
        assert_eq!(names[6], "sine-road");
        assert_eq!(
            planned.tag,
            netlink::AssessmentTag {
                protocol: 1,
                seed: 5
            }
        );
        planned.remember(now);
        // Six days later: not due, the regimen as prescribed; another patient: due.
        let mut r = weekly();
        assert!(Planned::plan(&mut r, Some(dir.path()), "p1", now + 6 * DAY_MS, 5).is_none());
        assert_eq!(r.unwrap().exercises.len(), 1);
        assert!(Planned::plan(&mut weekly(), Some(dir.path()), "p2", now, 5).is_some());
        // A week later: due again.
        assert!(
            Planned::plan(&mut weekly(), Some(dir.path()), "p1", now + 7 * DAY_MS, 5).is_some()
        );
        // A regimen that schedules none runs none.
        let mut plain =
            Some(regimen::Regimen::from_toml("[[exercise]]\nkind = \"sine\"\n", "x").unwrap());
        assert!(Planned::plan(&mut plain, None, "p1", now, 5).is_none());
        assert_eq!(last_unix_ms(&history_path(dir.path()), "p1"), Some(now));
    }

    #[test]
    fn the_seed_differs_from_session_to_session_and_repeats_for_the_same_one() {
        assert_eq!(seed_of(7, 1_000), seed_of(7, 1_000));
        assert_ne!(seed_of(7, 1_000), seed_of(7, 1_001));
        assert_ne!(seed_of(7, 1_000), seed_of(8, 1_000));
    }
}
