//! Sessions in words (issue 29): each session's exercise by its patient-facing name and its
//! exercise kind (`road`, `dial`, …), so that trends compare like with like and leave out
//! sessions that did not run as prescribed.

use std::collections::BTreeMap;

use serde::Serialize;

use super::{Db, SessionRow, col};
use crate::error::HubError;
pub use regimen::{exercise_kind, plain_name};

/// The kind ([`exercise_kind`]) of every part of the standard assessment.
pub const ASSESSMENT_KIND: &str = "assessment";

/// The `end_reason` of a session that ran as prescribed (the station's
/// `session::end_reason::COMPLETE`).
pub const COMPLETE: &str = "complete";

/// How many earlier sessions of the same kind a trend compares the latest with.
pub const TREND_BASELINE_SESSIONS: usize = 4;

/// A recording on its way whose last part the hub noted longer ago than this, ms, has stopped
/// arriving (its station is offline, or gave up): the console and `hub patient show` say so
/// rather than "arriving". Parts are noted every few seconds while an upload runs
/// (`netlink::therapist::RECORDING_PROGRESS_EVERY`); ten minutes outlasts a station's retries
/// after a hub restart. The console's `replays.js` uses the same figure.
pub const RECORDING_STALLED_AFTER_MS: i64 = 10 * 60 * 1000;

/// A session as the console names it: the stored row plus its exercise in words.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct NamedSession {
    /// The session as stored.
    #[serde(flatten)]
    pub row: SessionRow,
    /// The exercise as the patient saw it: `Sine road`; a regimen session by its exercises
    /// in order (`Dial sine, then Sine road`, as the station reported them, else as the
    /// regimen prescribed last before it lists them), or `A regimen of 2 exercises`.
    pub exercise_name: String,
    /// Each exercise's short name in order (`dial-sine`, `sine-road`), for the console to name
    /// them in its own language; empty when they are not known (`exercise` is then
    /// `regimen:<count>`).
    pub exercise_shorts: Vec<String>,
    /// The kind of exercise, for like-with-like comparisons: `road`, `dial`, another exercise's
    /// own short name, the kinds of a regimen's exercises joined by `+` (`dial+road`), or
    /// `regimen` when they are not known.
    pub exercise_kind: String,
    /// True when the session ended as prescribed (`end_reason` = `complete`); trends count
    /// only these.
    pub ran_as_prescribed: bool,
    /// The prescribed exercise time, s (the sum over the exercises the station reported);
    /// `null` when not reported.
    pub prescribed_s: Option<f64>,
    /// True once the session's recording has fully arrived (every byte, its hash checked):
    /// the console's replay can then open it.
    pub recording_uploaded: bool,
    /// How much of the recording has arrived while its upload is under way, % (0–99, rounded
    /// down); `null` before an upload begins and once it has arrived whole.
    pub recording_arriving_percent: Option<u8>,
    /// While its recording is arriving: when the hub last noted a part of it, ms since the
    /// Unix epoch (`null` when whole, not begun, or not noted). Longer ago than
    /// [`RECORDING_STALLED_AFTER_MS`]: it stopped arriving ([`NamedSession::recording_stalled`]).
    pub recording_last_part_ms: Option<i64>,
    /// How it ended, the one wording every page uses (`Stopped early: wheel unplugged`;
    /// `metrics::words::end_words`).
    pub end_words: String,
    /// How it ended as a stable key (`complete`, `wheel_unplugged`, `running`, …).
    pub end_kind: metrics::words::EndKind,
    /// True when the station's recording stopped before the session did (`end_words` then
    /// adds "; the recording stopped early"; the console words it from `end_kind` and this).
    pub recording_stopped_early: bool,
}

impl NamedSession {
    /// True when its recording is arriving but no part of it was noted for longer than
    /// [`RECORDING_STALLED_AFTER_MS`] before `now_ms` (ms since the Unix epoch).
    pub fn recording_stalled(&self, now_ms: i64) -> bool {
        self.recording_last_part_ms
            .is_some_and(|at| now_ms.saturating_sub(at) > RECORDING_STALLED_AFTER_MS)
    }
}

/// A session's recording as the hub holds it: whole, or its upload under way.
struct Upload {
    size_bytes: i64,
    received_bytes: i64,
    complete: bool,
    last_part_ms: Option<i64>,
}

impl Upload {
    /// How much has arrived, % rounded down (at most 99 until it is whole: the hash is only
    /// checked at the end).
    fn percent(&self) -> u8 {
        let (got, of) = (self.received_bytes.max(0), self.size_bytes.max(1));
        u8::try_from((got.saturating_mul(100) / of).min(99)).unwrap_or(99)
    }
}

/// A session's exercises: each one's short name, patient-facing name and prescribed time, s
/// (unknown when read from the regimen rather than reported by the station).
type Reported = Vec<(String, String, Option<f64>)>;

/// How session `row` ended, as the console words it: unreported when it closed without a
/// reason, else from its station's reason.
pub fn end_kind_of(row: &SessionRow) -> metrics::words::EndKind {
    match (&row.end_reason, row.closed_at_ms) {
        (None, Some(_)) => metrics::words::EndKind::Unreported,
        (reason, _) => metrics::words::EndKind::of(reason.as_deref()),
    }
}

/// Names session `row` from its reported exercises (`kind`, `name`, `prescribed_s`).
/// `upload` is its recording's upload as the hub holds it, if one began.
fn name_session(
    row: SessionRow,
    reported: Option<&Reported>,
    upload: Option<&Upload>,
) -> NamedSession {
    let recording_uploaded = upload.is_some_and(|u| u.complete);
    let arriving = upload.filter(|u| !u.complete);
    let recording_arriving_percent = arriving.map(Upload::percent);
    let recording_last_part_ms = arriving.and_then(|u| u.last_part_ms);
    let ran_as_prescribed = row.end_reason.as_deref() == Some(COMPLETE);
    let recording_stopped_early = row
        .end_reason
        .as_deref()
        .is_some_and(|r| r.contains("recording stopped"));
    let end_kind = end_kind_of(&row);
    let end_words = match end_kind {
        metrics::words::EndKind::Unreported => end_kind.words().to_owned(),
        _ => metrics::words::end_words(row.end_reason.as_deref()),
    };
    let exercise_shorts = match reported {
        Some(list) if !list.is_empty() => list.iter().map(|(k, _, _)| k.clone()).collect(),
        _ if row.exercise.starts_with("regimen:") => Vec::new(),
        _ => vec![row.exercise.clone()],
    };
    let (exercise_name, exercise_kind, prescribed_s) = match reported {
        Some(list) if !list.is_empty() => {
            let names: Vec<&str> = list.iter().map(|(_, n, _)| n.as_str()).collect();
            let mut kinds: Vec<String> = list.iter().map(|(k, _, _)| exercise_kind(k)).collect();
            kinds.sort();
            kinds.dedup();
            // The standard assessment run first is no part of what the exercises compare
            // with (its results are their own, `Db::assessments_of`); a session of it alone
            // is of its own kind.
            if kinds.len() > 1 {
                kinds.retain(|k| k != ASSESSMENT_KIND);
            }
            (
                names.join(", then "),
                kinds.join("+"),
                list.iter().map(|(_, _, s)| *s).sum::<Option<f64>>(),
            )
        }
        _ => match row.exercise.strip_prefix("regimen:") {
            Some(n) => (
                format!(
                    "A regimen of {n} exercise{}",
                    if n == "1" { "" } else { "s" }
                ),
                "regimen".to_owned(),
                None,
            ),
            None => (
                plain_name(&row.exercise),
                exercise_kind(&row.exercise),
                None,
            ),
        },
    };
    NamedSession {
        row,
        exercise_name,
        exercise_shorts,
        exercise_kind,
        ran_as_prescribed,
        prescribed_s,
        recording_uploaded,
        recording_arriving_percent,
        recording_last_part_ms,
        end_words,
        end_kind,
        recording_stopped_early,
    }
}

/// Share of the baseline within which a measure of unknown noise is `"flat"`.
const UNKNOWN_NOISE_SHARE: f64 = 0.02;

/// `"up"`, `"down"` or `"flat"` of `measure` (a words-table key): `newest_first[0]` against
/// the mean of up to [`TREND_BASELINE_SESSIONS`] after it; flat within the measure's
/// measurement noise (the words table's, as the console's trend words use it), within 2 % of
/// the mean when its noise is unknown; `None` without an earlier value.
pub fn trend(measure: &str, newest_first: &[f64]) -> Option<String> {
    let (&last, before) = newest_first.split_first()?;
    let before = &before[..before.len().min(TREND_BASELINE_SESSIONS)];
    if before.is_empty() {
        return None;
    }
    let mean = before.iter().sum::<f64>() / before.len() as f64;
    let band = metrics::words::measure_words(measure)
        .and_then(|w| w.noise)
        .map_or(UNKNOWN_NOISE_SHARE * mean.abs().max(1e-9), |n| {
            n.around(mean)
        });
    let word = if (last - mean).abs() <= band {
        "flat"
    } else if last > mean {
        "up"
    } else {
        "down"
    };
    Some(word.to_owned())
}

/// The sessions a trend compares, newest first: the newest session that ran as prescribed
/// and up to [`TREND_BASELINE_SESSIONS`] earlier ones of its kind that did too.
pub fn like_with_like(newest_first: &[NamedSession]) -> Vec<&NamedSession> {
    let mut done = newest_first.iter().filter(|s| s.ran_as_prescribed);
    let Some(latest) = done.next() else {
        return Vec::new();
    };
    std::iter::once(latest)
        .chain(
            done.filter(|s| s.exercise_kind == latest.exercise_kind)
                .take(TREND_BASELINE_SESSIONS),
        )
        .collect()
}

/// The sessions a trend compares in each exercise kind, newest kind first: for every kind,
/// its newest session that ran as prescribed and up to [`TREND_BASELINE_SESSIONS`] earlier
/// ones of that kind that did too (so a decline in a kind not trained last stays visible).
pub fn like_with_like_by_kind(newest_first: &[NamedSession]) -> Vec<Vec<&NamedSession>> {
    let mut kinds: Vec<Vec<&NamedSession>> = Vec::new();
    for s in newest_first.iter().filter(|s| s.ran_as_prescribed) {
        match kinds
            .iter_mut()
            .find(|k| k[0].exercise_kind == s.exercise_kind)
        {
            Some(k) if k.len() <= TREND_BASELINE_SESSIONS => k.push(s),
            Some(_) => {}
            None => kinds.push(vec![s]),
        }
    }
    kinds
}

/// The trends of one exercise kind (see [`like_with_like_by_kind`]).
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct KindTrends {
    /// The exercise kind (`road`, `dial`, …).
    pub exercise_kind: String,
    /// Each measure's trend: `"up"`, `"down"` or `"flat"`.
    pub trends: BTreeMap<String, String>,
}

impl Db {
    /// The trends of `measures` in every exercise kind with two or more sessions that ran as
    /// prescribed, the kind trained last first; a kind with no trend is left out.
    pub async fn trends_by_kind(
        &self,
        patient_id: &str,
        measures: &[&str],
    ) -> Result<Vec<KindTrends>, HubError> {
        let sessions = self.named_sessions_of(patient_id).await?;
        let mut out = Vec::new();
        for compared in like_with_like_by_kind(&sessions) {
            let trends = self.trends_over(&compared, measures).await?;
            if !trends.is_empty() {
                out.push(KindTrends {
                    exercise_kind: compared[0].exercise_kind.clone(),
                    trends,
                });
            }
        }
        Ok(out)
    }

    /// A patient's sessions in words, newest first: those that count as training (a `Hello`
    /// alone opens a session row but is no training; see [`Db::training_sessions_of`]).
    pub async fn named_sessions_of(&self, patient_id: &str) -> Result<Vec<NamedSession>, HubError> {
        let rows = self.training_sessions_of(patient_id).await?;
        let reported = sqlx::query(
            "SELECT e.session_id, e.kind, e.name, e.prescribed_s FROM session_exercises e \
             JOIN sessions s ON s.session_id = e.session_id WHERE s.patient_id = $1 \
             ORDER BY e.session_id, e.exercise_index",
        )
        .bind(patient_id)
        .fetch_all(self.pool())
        .await
        .map_err(HubError::db("reading the sessions' exercises"))?;
        let mut by_session: BTreeMap<String, Reported> = BTreeMap::new();
        for r in &reported {
            by_session.entry(col(r, "session_id")?).or_default().push((
                col(r, "kind")?,
                col(r, "name")?,
                Some(col(r, "prescribed_s")?),
            ));
        }
        self.regimen_exercises(patient_id, &rows, &mut by_session)
            .await?;
        let uploads = self.uploads_of(patient_id).await?;
        Ok(rows
            .into_iter()
            .map(|row| {
                let reported = by_session.get(&row.session_id);
                let upload = uploads.get(&row.session_id);
                name_session(row, reported, upload)
            })
            .collect())
    }

    /// The recordings of `patient_id`'s sessions the hub holds, whole or arriving.
    async fn uploads_of(&self, patient_id: &str) -> Result<BTreeMap<String, Upload>, HubError> {
        let rows = sqlx::query(
            "SELECT r.session_id, r.size_bytes, r.received_bytes, r.complete, r.last_part_ms \
             FROM recordings r \
             JOIN sessions s ON s.session_id = r.session_id WHERE s.patient_id = $1",
        )
        .bind(patient_id)
        .fetch_all(self.pool())
        .await
        .map_err(HubError::db("reading which recordings have arrived"))?;
        rows.iter()
            .map(|r| {
                let upload = Upload {
                    size_bytes: col(r, "size_bytes")?,
                    received_bytes: col(r, "received_bytes")?,
                    complete: col::<i64>(r, "complete")? != 0,
                    last_part_ms: col(r, "last_part_ms")?,
                };
                Ok((col(r, "session_id")?, upload))
            })
            .collect()
    }

    /// Fills in, for the regimen sessions (`regimen:N`) whose station reported no exercises,
    /// the exercises of the regimen version prescribed last before the session started, when
    /// it has the session's N of them.
    async fn regimen_exercises(
        &self,
        patient_id: &str,
        rows: &[SessionRow],
        by_session: &mut BTreeMap<String, Reported>,
    ) -> Result<(), HubError> {
        let unnamed: Vec<&SessionRow> = rows
            .iter()
            .filter(|r| {
                r.exercise.starts_with("regimen:") && !by_session.contains_key(&r.session_id)
            })
            .collect();
        if unnamed.is_empty() {
            return Ok(());
        }
        let history = self.regimen_history(patient_id).await?;
        for row in unnamed {
            let Some(version) = history
                .iter()
                .rev()
                .find(|v| v.prescribed_at_ms <= row.started_unix_ms)
            else {
                continue;
            };
            let Ok((regimen, _)) = regimen::Regimen::from_recorded(&version.toml, "a regimen")
            else {
                continue;
            };
            let count = row.exercise.trim_start_matches("regimen:");
            if count != regimen.exercises.len().to_string() {
                continue;
            }
            let list = regimen
                .exercises
                .iter()
                .map(|e| {
                    let short = e.exercise.name();
                    (short.clone(), plain_name(&short), None)
                })
                .collect();
            by_session.insert(row.session_id.clone(), list);
        }
        Ok(())
    }

    /// The trends of `measures` like with like (see [`like_with_like`]), with the kind of
    /// exercise they compare; no trend for a measure fewer than two of those sessions have.
    pub async fn like_with_like_trends(
        &self,
        patient_id: &str,
        measures: &[&str],
    ) -> Result<(BTreeMap<String, String>, Option<String>), HubError> {
        let sessions = self.named_sessions_of(patient_id).await?;
        let compared = like_with_like(&sessions);
        let trends = self.trends_over(&compared, measures).await?;
        Ok((trends, compared.first().map(|s| s.exercise_kind.clone())))
    }

    /// The trend of each of `measures` over the sessions `compared` (newest first); a measure
    /// fewer than two of them have is left out.
    async fn trends_over(
        &self,
        compared: &[&NamedSession],
        measures: &[&str],
    ) -> Result<BTreeMap<String, String>, HubError> {
        let mut series: BTreeMap<&str, Vec<f64>> = BTreeMap::new();
        for s in compared {
            let metrics = self.metrics_of(&s.row.session_id).await?;
            for m in measures {
                if let Some(&v) = metrics.get(*m) {
                    series.entry(m).or_default().push(v);
                }
            }
        }
        Ok(series
            .into_iter()
            .filter_map(|(name, v)| Some((name.to_owned(), trend(name, &v)?)))
            .collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exercise_names_read_as_the_patient_sees_them() {
        assert_eq!(plain_name("sine-road"), "Sine road");
        assert_eq!(plain_name("dial-sine"), "Dial sine");
        assert_eq!(exercise_kind("sine-road"), "road");
        assert_eq!(exercise_kind("slalom"), "road");
        assert_eq!(exercise_kind("clothoid"), "road");
        assert_eq!(exercise_kind("dial-sine"), "dial");
        assert_eq!(exercise_kind("grip"), "grip");
    }

    #[test]
    fn a_trend_is_the_latest_against_the_mean_of_up_to_four_before() {
        let t = |v: &[f64]| trend("pct_in_lane", v);
        assert_eq!(t(&[10.0]), None);
        assert_eq!(t(&[11.0, 10.0]).as_deref(), Some("up"));
        assert_eq!(t(&[9.0, 10.0, 10.0]).as_deref(), Some("down"));
        assert_eq!(t(&[10.1, 10.0]).as_deref(), Some("flat"));
        // The sixth value (100) is beyond the four compared.
        assert_eq!(
            t(&[11.0, 10.0, 10.0, 10.0, 10.0, 100.0]).as_deref(),
            Some("up")
        );
    }

    #[test]
    fn a_change_within_a_measures_known_noise_is_flat_as_the_console_says() {
        let noise = metrics::words::measure_words("sparc_median")
            .and_then(|w| w.noise)
            .expect("SPARC's measured noise (smallest real difference)");
        let half = noise.around(-2.0);
        assert!(half > 0.1, "{half}");
        // 2 % would call these a change; SPARC's measured noise does not.
        assert_eq!(
            trend("sparc_median", &[-2.0 + 0.5 * half, -2.0]).as_deref(),
            Some("flat")
        );
        assert_eq!(
            trend("sparc_median", &[-2.0 + 1.5 * half, -2.0]).as_deref(),
            Some("up")
        );
    }
}
