//! The therapist's messages to a patient: written in the console, pushed to the patient's
//! station, and marked seen when the station showed them on the screen.

use serde::Serialize;

use super::{Db, col, new_id, to_i64};
use crate::error::HubError;

/// Most messages [`Db::messages_of`] returns (newest first).
pub const MAX_MESSAGES_LISTED: i64 = 200;

/// One message as the hub stores it.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct PatientMessage {
    /// Its identifier (`m-` and 16 hex digits).
    pub id: String,
    /// The patient it is for.
    pub patient_id: String,
    /// The therapist who wrote it.
    pub therapist_id: String,
    /// The text (plain, one paragraph).
    pub text: String,
    /// When it was written, ms since the Unix epoch.
    pub created_at_ms: i64,
    /// When the hub first queued it for the patient's station, if it did.
    pub delivered_at_ms: Option<i64>,
    /// When the station showed it to the patient (station clock), if it did.
    pub seen_at_ms: Option<i64>,
}

const COLUMNS: &str =
    "id, patient_id, therapist_id, body, created_at_ms, delivered_at_ms, seen_at_ms";

fn message_of(row: &sqlx::any::AnyRow) -> Result<PatientMessage, HubError> {
    Ok(PatientMessage {
        id: col(row, "id")?,
        patient_id: col(row, "patient_id")?,
        therapist_id: col(row, "therapist_id")?,
        text: col(row, "body")?,
        created_at_ms: col(row, "created_at_ms")?,
        delivered_at_ms: col(row, "delivered_at_ms")?,
        seen_at_ms: col(row, "seen_at_ms")?,
    })
}

impl Db {
    /// Stores `text` from `therapist_id` to `patient_id` (checked with
    /// [`netlink::check_message_text`]: an invalid text is [`HubError::Invalid`] naming the
    /// problem).
    pub async fn add_message(
        &self,
        patient_id: &str,
        therapist_id: &str,
        text: &str,
        now_ms: i64,
    ) -> Result<PatientMessage, HubError> {
        netlink::check_message_text(text).map_err(|e| HubError::invalid("text", e.0))?;
        let id = new_id("m-")?;
        sqlx::query(
            "INSERT INTO patient_messages (id, patient_id, therapist_id, body, created_at_ms) \
             VALUES ($1, $2, $3, $4, $5)",
        )
        .bind(&id)
        .bind(patient_id)
        .bind(therapist_id)
        .bind(text)
        .bind(now_ms)
        .execute(self.pool())
        .await
        .map_err(HubError::db("storing a message"))?;
        Ok(PatientMessage {
            id,
            patient_id: patient_id.to_owned(),
            therapist_id: therapist_id.to_owned(),
            text: text.to_owned(),
            created_at_ms: now_ms,
            delivered_at_ms: None,
            seen_at_ms: None,
        })
    }

    /// A patient's messages, newest first (at most [`MAX_MESSAGES_LISTED`]).
    pub async fn messages_of(&self, patient_id: &str) -> Result<Vec<PatientMessage>, HubError> {
        let rows = sqlx::query(sqlx::AssertSqlSafe(format!(
            "SELECT {COLUMNS} FROM patient_messages WHERE patient_id = $1 \
             ORDER BY created_at_ms DESC, id DESC LIMIT {MAX_MESSAGES_LISTED}"
        )))
        .bind(patient_id)
        .fetch_all(self.pool())
        .await
        .map_err(HubError::db("reading messages"))?;
        rows.iter().map(message_of).collect()
    }

    /// A patient's messages not yet seen, oldest first: what the station is sent.
    pub async fn unseen_messages(&self, patient_id: &str) -> Result<Vec<PatientMessage>, HubError> {
        let rows = sqlx::query(sqlx::AssertSqlSafe(format!(
            "SELECT {COLUMNS} FROM patient_messages WHERE patient_id = $1 \
             AND seen_at_ms IS NULL ORDER BY created_at_ms, id LIMIT {MAX_MESSAGES_LISTED}"
        )))
        .bind(patient_id)
        .fetch_all(self.pool())
        .await
        .map_err(HubError::db("reading unseen messages"))?;
        rows.iter().map(message_of).collect()
    }

    /// Notes that message `id` was queued for the patient's station at `now_ms` (the first
    /// time only).
    pub async fn message_delivered(&self, id: &str, now_ms: i64) -> Result<(), HubError> {
        sqlx::query(
            "UPDATE patient_messages SET delivered_at_ms = $1 \
             WHERE id = $2 AND delivered_at_ms IS NULL",
        )
        .bind(now_ms)
        .bind(id)
        .execute(self.pool())
        .await
        .map_err(HubError::db("noting a message delivered"))?;
        Ok(())
    }

    /// Notes that `patient_id`'s station showed message `id` at `seen_unix_ms` (the first
    /// time only). False when the patient has no such message (nothing changed) or it was
    /// already seen.
    pub async fn message_seen(
        &self,
        patient_id: &str,
        id: &str,
        seen_unix_ms: u64,
    ) -> Result<bool, HubError> {
        let seen = to_i64("seen_unix_ms", seen_unix_ms)?;
        let done = sqlx::query(
            "UPDATE patient_messages SET seen_at_ms = $1 \
             WHERE id = $2 AND patient_id = $3 AND seen_at_ms IS NULL",
        )
        .bind(seen)
        .bind(id)
        .bind(patient_id)
        .execute(self.pool())
        .await
        .map_err(HubError::db("noting a message seen"))?;
        Ok(done.rows_affected() > 0)
    }
}
