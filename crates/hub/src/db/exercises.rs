//! Each exercise's own results in a session (scores and movement measures per exercise), from
//! the station's `Bye`.

use std::collections::BTreeMap;

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
        let rows = sqlx::query(
            "SELECT e.session_id, s.started_unix_ms, e.exercise_index, e.kind, e.name, \
             e.prescribed_s, e.active_s, e.scores_json, e.assessment_protocol, \
             e.assessment_seed FROM session_exercises e \
             JOIN sessions s ON s.session_id = e.session_id \
             WHERE s.patient_id = $1 AND e.assessment_protocol IS NOT NULL \
             ORDER BY s.started_unix_ms DESC, e.session_id, e.exercise_index",
        )
        .bind(patient_id)
        .fetch_all(self.pool())
        .await
        .map_err(HubError::db("reading the assessments"))?;
        let mut out: Vec<Assessment> = Vec::new();
        for row in &rows {
            let session_id: String = col(row, "session_id")?;
            let part = exercise_of_row(row)?;
            let Some(tag) = part.assessment else {
                continue;
            };
            match out.last_mut() {
                Some(a) if a.session_id == session_id => a.parts.push(part),
                _ => out.push(Assessment {
                    session_id,
                    started_unix_ms: col(row, "started_unix_ms")?,
                    protocol: tag.protocol,
                    seed: tag.seed,
                    parts: vec![part],
                }),
            }
        }
        Ok(out)
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
