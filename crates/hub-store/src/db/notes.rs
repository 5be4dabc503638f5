//! The therapist's notes on a session (migration 0012): the clinic's own record, never sent
//! to the station.

use serde::Serialize;

use super::{Db, col, new_id};
use crate::error::HubError;

/// Most characters in one session note.
pub const MAX_NOTE_CHARS: usize = 2_000;

/// Most notes [`Db::notes_of_session`] returns (oldest first).
pub const MAX_NOTES_LISTED: i64 = 200;

/// One note on a session.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct SessionNote {
    /// Its identifier (`n-` and 16 hex digits).
    pub id: String,
    /// The session it is about.
    pub session_id: String,
    /// The therapist who wrote it.
    pub therapist_id: String,
    /// Their e-mail, when the account still exists (the console names them by it).
    pub therapist_email: Option<String>,
    /// The text (plain; line breaks kept).
    pub text: String,
    /// When it was written, ms since the Unix epoch.
    pub created_at_ms: i64,
}

/// Why `text` cannot be a session note, in words naming the problem: empty (or only spaces),
/// longer than [`MAX_NOTE_CHARS`] characters, or holding control characters other than line
/// breaks and tabs.
pub fn check_note_text(text: &str) -> Result<(), String> {
    if text.trim().is_empty() {
        return Err("the note is empty: write a few words".into());
    }
    let chars = text.chars().count();
    if chars > MAX_NOTE_CHARS {
        return Err(format!(
            "the note has {chars} characters, at most {MAX_NOTE_CHARS} allowed"
        ));
    }
    if text
        .chars()
        .any(|c| c.is_control() && !matches!(c, '\n' | '\r' | '\t'))
    {
        return Err("the note holds control characters: plain text only".into());
    }
    Ok(())
}

impl Db {
    /// Stores `therapist_id`'s note `text` on session `session_id` (checked with
    /// [`check_note_text`]: an invalid one is [`HubError::Invalid`] naming the problem).
    pub async fn add_session_note(
        &self,
        session_id: &str,
        therapist_id: &str,
        text: &str,
        now_ms: i64,
    ) -> Result<SessionNote, HubError> {
        check_note_text(text).map_err(|e| HubError::invalid("text", e))?;
        let id = new_id("n-")?;
        sqlx::query(
            "INSERT INTO session_notes (id, session_id, therapist_id, body, created_at_ms) \
             VALUES ($1, $2, $3, $4, $5)",
        )
        .bind(&id)
        .bind(session_id)
        .bind(therapist_id)
        .bind(text)
        .bind(now_ms)
        .execute(self.pool())
        .await
        .map_err(HubError::db("storing a session note"))?;
        let therapist_email = self.therapist(therapist_id).await?.map(|t| t.email);
        Ok(SessionNote {
            id,
            session_id: session_id.to_owned(),
            therapist_id: therapist_id.to_owned(),
            therapist_email,
            text: text.to_owned(),
            created_at_ms: now_ms,
        })
    }

    /// A session's newest [`MAX_NOTES_LISTED`] notes, oldest first, each with its therapist's
    /// e-mail (a note written after the first 200 is listed, not hidden behind them).
    pub async fn notes_of_session(&self, session_id: &str) -> Result<Vec<SessionNote>, HubError> {
        let rows = sqlx::query(sqlx::AssertSqlSafe(format!(
            "SELECT n.id, n.session_id, n.therapist_id, t.email, n.body, n.created_at_ms \
             FROM session_notes n LEFT JOIN therapists t ON t.id = n.therapist_id \
             WHERE n.session_id = $1 ORDER BY n.created_at_ms DESC, n.id DESC LIMIT {MAX_NOTES_LISTED}"
        )))
        .bind(session_id)
        .fetch_all(self.pool())
        .await
        .map_err(HubError::db("reading session notes"))?;
        rows.iter()
            .rev()
            .map(|row| {
                Ok(SessionNote {
                    id: col(row, "id")?,
                    session_id: col(row, "session_id")?,
                    therapist_id: col(row, "therapist_id")?,
                    therapist_email: col(row, "email")?,
                    text: col(row, "body")?,
                    created_at_ms: col(row, "created_at_ms")?,
                })
            })
            .collect()
    }
}
