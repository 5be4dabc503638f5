//! The difficulty each session ran at (a regimen with `[difficulty]` adapting it), its change
//! and why, from the station's `Bye` (migration 0009).

use netlink::{DifficultyChange, DifficultyWhy};
use serde::Serialize;

use super::{Db, col};
use crate::error::HubError;

/// One session's difficulty as the hub stores it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SessionDifficulty {
    /// The session.
    pub session_id: String,
    /// The session's start (station clock), ms since the Unix epoch.
    pub started_unix_ms: i64,
    /// The difficulty it ran at, 0–1.
    pub difficulty: f64,
    /// The change from the session before.
    pub change: f64,
    /// Why, in the station's words (English).
    pub reason: String,
    /// The same why for words in any language; `None` from stations older than it.
    pub why: Option<DifficultyWhy>,
    /// The session's success rate, 0–1, if known.
    pub success_rate: Option<f64>,
    /// When the hub received it, ms since the Unix epoch.
    pub received_at_ms: i64,
}

impl Db {
    /// Stores the difficulty of session `session_id` (a repeated `Bye` stores it again).
    pub async fn put_difficulty(
        &self,
        session_id: &str,
        d: &DifficultyChange,
        now_ms: i64,
    ) -> Result<(), HubError> {
        d.validate()
            .map_err(|e| HubError::invalid("difficulty", e.0))?;
        let session = self
            .session(session_id)
            .await?
            .ok_or_else(|| HubError::not_found("session", session_id))?;
        let what = "storing a session's difficulty";
        let mut tx = self.pool().begin().await.map_err(HubError::db(what))?;
        sqlx::query("DELETE FROM session_difficulty WHERE session_id = $1")
            .bind(session_id)
            .execute(&mut *tx)
            .await
            .map_err(HubError::db(what))?;
        // `sqlx::Any` sends a NULL float in a format PostgreSQL refuses for a DOUBLE
        // PRECISION column: an unknown success rate is written as the literal NULL instead.
        let insert = "INSERT INTO session_difficulty (session_id, patient_id, started_unix_ms, \
             difficulty, change, reason, why_json, received_at_ms, success_rate) \
             VALUES ($1, $2, $3, $4, $5, $6, $7, $8, ";
        let sql = sqlx::AssertSqlSafe(match d.success_rate {
            Some(_) => format!("{insert}$9)"),
            None => format!("{insert}NULL)"),
        });
        let why_json = d
            .why
            .as_ref()
            .map(serde_json::to_string)
            .transpose()
            .map_err(|e| HubError::invalid("difficulty", e.to_string()))?;
        let mut query = sqlx::query(sql)
            .bind(session_id)
            .bind(&session.patient_id)
            .bind(session.started_unix_ms)
            .bind(d.difficulty)
            .bind(d.change)
            .bind(&d.reason)
            .bind(why_json)
            .bind(now_ms);
        if let Some(r) = d.success_rate {
            query = query.bind(r);
        }
        query.execute(&mut *tx).await.map_err(HubError::db(what))?;
        tx.commit().await.map_err(HubError::db(what))
    }

    /// A patient's difficulty history, newest session first.
    pub async fn difficulty_of(
        &self,
        patient_id: &str,
    ) -> Result<Vec<SessionDifficulty>, HubError> {
        let rows = sqlx::query(
            "SELECT session_id, started_unix_ms, difficulty, change, reason, why_json, \
             success_rate, received_at_ms FROM session_difficulty WHERE patient_id = $1 \
             ORDER BY started_unix_ms DESC, session_id",
        )
        .bind(patient_id)
        .fetch_all(self.pool())
        .await
        .map_err(HubError::db("reading the difficulty history"))?;
        rows.iter()
            .map(|row| {
                Ok(SessionDifficulty {
                    session_id: col(row, "session_id")?,
                    started_unix_ms: col(row, "started_unix_ms")?,
                    difficulty: col(row, "difficulty")?,
                    change: col(row, "change")?,
                    reason: col(row, "reason")?,
                    why: col::<Option<String>>(row, "why_json")?
                        .and_then(|j| serde_json::from_str(&j).ok()),
                    success_rate: col(row, "success_rate")?,
                    received_at_ms: col(row, "received_at_ms")?,
                })
            })
            .collect()
    }
}
