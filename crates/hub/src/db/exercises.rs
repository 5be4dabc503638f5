//! Each exercise's own results in a session (scores and movement measures per exercise), from
//! the station's `Bye`.

use std::collections::BTreeMap;

use netlink::ExerciseResult;
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
                 prescribed_s, active_s, scores_json) VALUES ($1, $2, $3, $4, $5, $6, $7)",
            )
            .bind(session_id)
            .bind(i64::from(e.index))
            .bind(&e.kind)
            .bind(&e.name)
            .bind(e.prescribed_s)
            .bind(e.active_s)
            .bind(scores)
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
            "SELECT exercise_index, kind, name, prescribed_s, active_s, scores_json \
             FROM session_exercises WHERE session_id = $1 ORDER BY exercise_index",
        )
        .bind(session_id)
        .fetch_all(self.pool())
        .await
        .map_err(HubError::db("reading exercise results"))?;
        rows.iter()
            .map(|row| {
                let scores: String = col(row, "scores_json")?;
                Ok(SessionExercise {
                    index: col(row, "exercise_index")?,
                    kind: col(row, "kind")?,
                    name: col(row, "name")?,
                    prescribed_s: col(row, "prescribed_s")?,
                    active_s: col(row, "active_s")?,
                    scores: serde_json::from_str(&scores)
                        .map_err(|e| HubError::Corrupt(format!("column scores_json: {e}")))?,
                })
            })
            .collect()
    }
}
