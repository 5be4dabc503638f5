//! Each exercise's own results in a session (scores and movement measures per exercise), from
//! the station's `Bye`.

use std::collections::{BTreeMap, VecDeque};

use metrics::change::{Change, History, assessment_change};
use netlink::{AssessmentTag, ExerciseResult};
use serde::Serialize;

use super::{Db, col};
use crate::error::HubError;

/// One exercise of a session as the hub stores and serves it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SessionExercise {
    /// Its place in the session's course, from 0.
    pub index: i64,
    /// Its kind, the regimen's short name (`sine-road`).
    pub kind: String,
    /// Its name as the patient sees it (`Sine road`).
    pub name: String,
    /// The prescribed duration, s.
    pub prescribed_s: f64,
    /// The time it ran, s (pauses left out).
    pub active_s: f64,
    /// Its scores and movement measures, name (unit in the name) → value.
    pub scores: BTreeMap<String, f64>,
    /// The standard assessment it is a part of (protocol and seed); absent for an exercise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub assessment: Option<AssessmentTag>,
}

/// One standard assessment a patient did (the assessment's parts of one session).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Assessment {
    /// The session it ran in.
    pub session_id: String,
    /// When that session started, ms since the Unix epoch.
    pub started_unix_ms: i64,
    /// The protocol's version.
    pub protocol: u32,
    /// The seed its steps were drawn from.
    pub seed: u32,
    /// Its parts, in course order.
    pub parts: Vec<SessionExercise>,
}

/// Assessments a page of [`Db::assessment_page`] holds when the request names no `limit`: a
/// year of weekly ones.
pub const DEFAULT_ASSESSMENT_PAGE: usize = 52;
/// The most assessments a page holds: two years of weekly ones.
pub const MAX_ASSESSMENT_PAGE: usize = 104;
/// The most (protocol, part, measure) histories a patient's verdicts follow: every measure of
/// the words table in every part of a protocol several times over; a part or measure beyond it
/// (from a station gone wrong) gets no change, and memory stays bounded.
const MAX_FOLLOWED: usize = 2_000;

/// One assessment with the change of each of its measures since the patient's first
/// assessment, as known when it was taken.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AssessmentWithChanges {
    /// The assessment.
    #[serde(flatten)]
    pub assessment: Assessment,
    /// Each (part, measure)'s change since the patient's first assessment of the protocol, in
    /// the parts' order, the measures' by key; none on the first.
    pub changes: Vec<MeasureChange>,
}

/// The change of one measure of one part (`metrics::change`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MeasureChange {
    /// The part (`steps`: the part's kind without `assessment-`).
    pub part: String,
    /// The measure's key in the words table.
    pub measure: String,
    /// When the session of the patient's first value of it (the baseline) started, ms since
    /// the Unix epoch.
    pub baseline_started_unix_ms: i64,
    /// The change, its noise band and the verdict.
    #[serde(flatten)]
    pub change: Change,
}

/// Each (protocol, part, measure)'s values so far, oldest first (`metrics::change::History`),
/// with when the first was taken.
#[derive(Default)]
struct Histories(BTreeMap<(u32, String, String), (History, i64)>);

impl Histories {
    /// Reads assessment `a` (the next oldest) and returns its changes.
    fn read(&mut self, a: &Assessment) -> Vec<MeasureChange> {
        let mut changes = Vec::new();
        for part in &a.parts {
            let Some(name) = part.kind.strip_prefix("assessment-") else {
                continue;
            };
            for (measure, value) in &part.scores {
                if metrics::words::measure_words(measure).is_none() {
                    continue;
                }
                let key = (a.protocol, name.to_owned(), measure.clone());
                if !self.0.contains_key(&key) && self.0.len() >= MAX_FOLLOWED {
                    continue;
                }
                let (history, baseline_ms) = self
                    .0
                    .entry(key)
                    .or_insert((History::default(), a.started_unix_ms));
                history.push(*value);
                if let Some(change) = assessment_change(a.protocol, name, measure, history) {
                    changes.push(MeasureChange {
                        part: name.to_owned(),
                        measure: measure.clone(),
                        baseline_started_unix_ms: *baseline_ms,
                        change,
                    });
                }
            }
        }
        changes
    }
}

impl Db {
    /// Stores the exercise results of session `session_id`, replacing any stored before (a
    /// repeated `Bye` stores the same again).
    pub async fn put_exercises(
        &self,
        session_id: &str,
        exercises: &[ExerciseResult],
    ) -> Result<(), HubError> {
        netlink::frame::check_exercise_results(exercises)
            .map_err(|e| HubError::invalid("exercises", e.0))?;
        let context = "storing exercise results";
        let mut tx = self.pool().begin().await.map_err(HubError::db(context))?;
        sqlx::query("DELETE FROM session_exercises WHERE session_id = $1")
            .bind(session_id)
            .execute(&mut *tx)
            .await
            .map_err(HubError::db(context))?;
        for e in exercises {
            let scores = serde_json::to_string(&e.scores)
                .map_err(|err| HubError::invalid("exercises", err.to_string()))?;
            sqlx::query(
                "INSERT INTO session_exercises (session_id, exercise_index, kind, name, \
                 prescribed_s, active_s, scores_json, assessment_protocol, assessment_seed) \
                 VALUES ($1, $2, $3, $4, $5, $6, $7, $8, $9)",
            )
            .bind(session_id)
            .bind(i64::from(e.index))
            .bind(&e.kind)
            .bind(&e.name)
            .bind(e.prescribed_s)
            .bind(e.active_s)
            .bind(scores)
            .bind(e.assessment.map(|a| i64::from(a.protocol)))
            .bind(e.assessment.map(|a| i64::from(a.seed)))
            .execute(&mut *tx)
            .await
            .map_err(HubError::db(context))?;
        }
        tx.commit().await.map_err(HubError::db(context))
    }

    /// A session's exercise results, in course order (none for a session from a station older
    /// than them).
    pub async fn exercises_of(&self, session_id: &str) -> Result<Vec<SessionExercise>, HubError> {
        let rows = sqlx::query(
            "SELECT exercise_index, kind, name, prescribed_s, active_s, scores_json, \
             assessment_protocol, assessment_seed \
             FROM session_exercises WHERE session_id = $1 ORDER BY exercise_index",
        )
        .bind(session_id)
        .fetch_all(self.pool())
        .await
        .map_err(HubError::db("reading exercise results"))?;
        rows.iter().map(exercise_of_row).collect()
    }

    /// The standard assessments patient `patient_id` did, newest first: each session's
    /// assessment parts, with the session's start.
    pub async fn assessments_of(&self, patient_id: &str) -> Result<Vec<Assessment>, HubError> {
        let rows = sqlx::query(ASSESSMENT_ROWS_BEFORE)
            .bind(patient_id)
            .bind(i64::MAX)
            .fetch_all(self.pool())
            .await
            .map_err(HubError::db("reading the assessments"))?;
        let mut out: Vec<Assessment> = Vec::new();
        for row in &rows {
            if let Some(done) = add_row(&mut out, row)? {
                out.push(done);
            }
        }
        out.reverse();
        Ok(out)
    }

    /// One page of patient `patient_id`'s standard assessments, newest first: at most `limit`
    /// (1 to [`MAX_ASSESSMENT_PAGE`]) of those that started before `before_ms` (all if
    /// `None`), each with its measures' changes since the patient's first assessment as known
    /// when it was taken (the newest's: the verdict on the whole history). The rows stream
    /// oldest first through one constant-size history per measure, so memory holds the page
    /// and the histories, never the whole history.
    pub async fn assessment_page(
        &self,
        patient_id: &str,
        before_ms: Option<i64>,
        limit: usize,
    ) -> Result<Vec<AssessmentWithChanges>, HubError> {
        use tokio_stream::StreamExt as _;
        let limit = limit.clamp(1, MAX_ASSESSMENT_PAGE);
        let context = "reading the assessments";
        let mut rows = sqlx::query(ASSESSMENT_ROWS_BEFORE)
            .bind(patient_id)
            .bind(before_ms.unwrap_or(i64::MAX))
            .fetch(self.pool());
        let mut histories = Histories::default();
        let mut page: VecDeque<AssessmentWithChanges> = VecDeque::with_capacity(limit + 1);
        let mut finish = |a: Assessment| {
            let changes = histories.read(&a);
            page.push_back(AssessmentWithChanges {
                assessment: a,
                changes,
            });
            if page.len() > limit {
                page.pop_front();
            }
        };
        // The assessment being read (one session's parts), and the one a new session ends.
        let mut current: Vec<Assessment> = Vec::with_capacity(1);
        while let Some(row) = rows.next().await {
            let row = row.map_err(HubError::db(context))?;
            if let Some(done) = add_row(&mut current, &row)? {
                if let Some(previous) = current.pop() {
                    finish(previous);
                }
                current.push(done);
            }
        }
        if let Some(last) = current.pop() {
            finish(last);
        }
        Ok(page.into_iter().rev().collect())
    }
}

/// Patient `$1`'s assessment parts of sessions started before `$2`, oldest first, each
/// session's parts together in course order (the rows [`add_row`] groups).
const ASSESSMENT_ROWS_BEFORE: &str = "SELECT e.session_id, s.started_unix_ms, e.exercise_index, \
     e.kind, e.name, e.prescribed_s, e.active_s, e.scores_json, e.assessment_protocol, \
     e.assessment_seed FROM session_exercises e \
     JOIN sessions s ON s.session_id = e.session_id \
     WHERE s.patient_id = $1 AND e.assessment_protocol IS NOT NULL \
     AND s.started_unix_ms < $2 \
     ORDER BY s.started_unix_ms, e.session_id, e.exercise_index";

/// Adds an assessment's part row to the last assessment of `out` when it is of the same
/// session; returns the new assessment the row begins otherwise (a row of no assessment adds
/// nothing).
fn add_row(
    out: &mut [Assessment],
    row: &sqlx::any::AnyRow,
) -> Result<Option<Assessment>, HubError> {
    let session_id: String = col(row, "session_id")?;
    let part = exercise_of_row(row)?;
    let Some(tag) = part.assessment else {
        return Ok(None);
    };
    match out.last_mut() {
        Some(a) if a.session_id == session_id => {
            a.parts.push(part);
            Ok(None)
        }
        _ => Ok(Some(Assessment {
            session_id,
            started_unix_ms: col(row, "started_unix_ms")?,
            protocol: tag.protocol,
            seed: tag.seed,
            parts: vec![part],
        })),
    }
}

/// A `session_exercises` row as served.
fn exercise_of_row(row: &sqlx::any::AnyRow) -> Result<SessionExercise, HubError> {
    let scores: String = col(row, "scores_json")?;
    let protocol: Option<i64> = col(row, "assessment_protocol")?;
    let seed: Option<i64> = col(row, "assessment_seed")?;
    let assessment = match (protocol, seed) {
        (Some(p), Some(s)) => Some(AssessmentTag {
            protocol: u32::try_from(p)
                .map_err(|e| HubError::Corrupt(format!("column assessment_protocol: {e}")))?,
            seed: u32::try_from(s)
                .map_err(|e| HubError::Corrupt(format!("column assessment_seed: {e}")))?,
        }),
        _ => None,
    };
    Ok(SessionExercise {
        index: col(row, "exercise_index")?,
        kind: col(row, "kind")?,
        name: col(row, "name")?,
        prescribed_s: col(row, "prescribed_s")?,
        active_s: col(row, "active_s")?,
        scores: serde_json::from_str(&scores)
            .map_err(|e| HubError::Corrupt(format!("column scores_json: {e}")))?,
        assessment,
    })
}
