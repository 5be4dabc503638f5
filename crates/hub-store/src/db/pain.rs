//! Pain that reaches someone: the outbox of mails about a check-in's pain at or over the
//! clinic's threshold ([`PainMail`], migration 0021), and the therapist's clearance of a
//! patient to train again after such a pain.

use serde::Serialize;

use super::{Db, col};
use crate::error::HubError;

/// Check-ins received longer ago than this are not mailed when the outbox first sees them
/// (a hub upgraded onto old check-ins does not mail their history), ms: two days.
pub const PAIN_MAIL_LOOKBACK_MS: i64 = 2 * 24 * 3_600_000;

/// One mail about a pain, waiting or sent.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct PainMail {
    /// The session whose check-in reported the pain.
    pub session_id: String,
    /// The patient.
    pub patient_id: String,
    /// The pain reported, 0–10.
    pub pain_0_10: i64,
    /// When the outbox took it, ms since the Unix epoch.
    pub created_at_ms: i64,
    /// Attempts to send it so far.
    pub attempts: i64,
    /// When it is tried next, ms since the Unix epoch.
    pub next_attempt_at_ms: i64,
    /// Why the last attempt failed, if it did.
    pub last_error: Option<String>,
    /// When the SMTP server took it, if it did.
    pub sent_at_ms: Option<i64>,
}

/// The outbox at a glance, for an admin.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize)]
pub struct PainMailStatus {
    /// Mails not yet taken by the SMTP server.
    pub waiting: i64,
    /// Of those, mails that failed at least once.
    pub failing: i64,
    /// The newest failure's reason, if a mail is failing.
    pub last_error: Option<String>,
    /// When a mail was last taken by the SMTP server, ms since the Unix epoch.
    pub last_sent_at_ms: Option<i64>,
}

fn mail_of(row: &sqlx::any::AnyRow) -> Result<PainMail, HubError> {
    Ok(PainMail {
        session_id: col(row, "session_id")?,
        patient_id: col(row, "patient_id")?,
        pain_0_10: col(row, "pain_0_10")?,
        created_at_ms: col(row, "created_at_ms")?,
        attempts: col(row, "attempts")?,
        next_attempt_at_ms: col(row, "next_attempt_at_ms")?,
        last_error: col(row, "last_error")?,
        sent_at_ms: col(row, "sent_at_ms")?,
    })
}

/// Whom a pain mail goes to, in the language they chose for the console.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MailRecipient {
    /// The e-mail address.
    pub email: String,
    /// Their console language (`de`); `None` when they never chose (English).
    pub language: Option<String>,
}

impl Db {
    /// Puts in the outbox every check-in received since `now_ms` − [`PAIN_MAIL_LOOKBACK_MS`]
    /// whose pain is at or over `threshold_0_10` and that is not there yet; how many.
    pub async fn queue_pain_mails(&self, threshold_0_10: u8, now_ms: i64) -> Result<u64, HubError> {
        let done = sqlx::query(
            "INSERT INTO pain_mail_outbox (session_id, patient_id, pain_0_10, created_at_ms, \
             attempts, next_attempt_at_ms) \
             SELECT c.session_id, c.patient_id, c.pain_0_10, $1, 0, $1 FROM session_checkins c \
             WHERE c.pain_0_10 >= $2 AND c.received_at_ms >= $3 AND NOT EXISTS \
             (SELECT 1 FROM pain_mail_outbox o WHERE o.session_id = c.session_id)",
        )
        .bind(now_ms)
        .bind(i64::from(threshold_0_10))
        .bind(now_ms.saturating_sub(PAIN_MAIL_LOOKBACK_MS))
        .execute(self.pool())
        .await
        .map_err(HubError::db("queueing pain mails"))?;
        Ok(done.rows_affected())
    }

    /// The mails due at `now_ms`, oldest first, at most `limit`.
    pub async fn due_pain_mails(&self, now_ms: i64, limit: i64) -> Result<Vec<PainMail>, HubError> {
        let rows = sqlx::query(
            "SELECT session_id, patient_id, pain_0_10, created_at_ms, attempts, \
             next_attempt_at_ms, last_error, sent_at_ms FROM pain_mail_outbox \
             WHERE sent_at_ms IS NULL AND next_attempt_at_ms <= $1 \
             ORDER BY created_at_ms, session_id LIMIT $2",
        )
        .bind(now_ms)
        .bind(limit)
        .fetch_all(self.pool())
        .await
        .map_err(HubError::db("reading the pain mail outbox"))?;
        rows.iter().map(mail_of).collect()
    }

    /// The mail of `session_id` was taken by the SMTP server at `now_ms`.
    pub async fn pain_mail_sent(&self, session_id: &str, now_ms: i64) -> Result<(), HubError> {
        sqlx::query(
            "UPDATE pain_mail_outbox SET sent_at_ms = $1, attempts = attempts + 1, \
             last_error = NULL WHERE session_id = $2",
        )
        .bind(now_ms)
        .bind(session_id)
        .execute(self.pool())
        .await
        .map_err(HubError::db("noting a pain mail sent"))?;
        Ok(())
    }

    /// The mail of `session_id` failed (`error`): tried again at `next_attempt_at_ms`.
    pub async fn pain_mail_failed(
        &self,
        session_id: &str,
        error: &str,
        next_attempt_at_ms: i64,
    ) -> Result<(), HubError> {
        sqlx::query(
            "UPDATE pain_mail_outbox SET attempts = attempts + 1, last_error = $1, \
             next_attempt_at_ms = $2 WHERE session_id = $3",
        )
        .bind(error)
        .bind(next_attempt_at_ms)
        .bind(session_id)
        .execute(self.pool())
        .await
        .map_err(HubError::db("noting a pain mail failed"))?;
        Ok(())
    }

    /// Every mail of the outbox, newest first (at most `limit`).
    pub async fn pain_mails(&self, limit: i64) -> Result<Vec<PainMail>, HubError> {
        let rows = sqlx::query(
            "SELECT session_id, patient_id, pain_0_10, created_at_ms, attempts, \
             next_attempt_at_ms, last_error, sent_at_ms FROM pain_mail_outbox \
             ORDER BY created_at_ms DESC, session_id LIMIT $1",
        )
        .bind(limit)
        .fetch_all(self.pool())
        .await
        .map_err(HubError::db("reading the pain mail outbox"))?;
        rows.iter().map(mail_of).collect()
    }

    /// The outbox at a glance.
    pub async fn pain_mail_status(&self) -> Result<PainMailStatus, HubError> {
        let mut status = PainMailStatus::default();
        for mail in self.pain_mails(1000).await? {
            match mail.sent_at_ms {
                Some(at) => {
                    status.last_sent_at_ms = Some(status.last_sent_at_ms.map_or(at, |s| s.max(at)))
                }
                None => {
                    status.waiting += 1;
                    if mail.attempts > 0 {
                        status.failing += 1;
                        if status.last_error.is_none() {
                            status.last_error = mail.last_error.clone();
                        }
                    }
                }
            }
        }
        Ok(status)
    }

    /// Who is told about `patient_id`'s pain: their therapist, or every admin
    /// when the patient has no therapist.
    pub async fn pain_mail_recipients(
        &self,
        patient_id: &str,
    ) -> Result<Vec<MailRecipient>, HubError> {
        let recipients = |rows: Vec<sqlx::any::AnyRow>| {
            rows.iter()
                .map(|r| {
                    Ok(MailRecipient {
                        email: col(r, "email")?,
                        language: col(r, "language")?,
                    })
                })
                .collect::<Result<Vec<_>, HubError>>()
        };
        let rows = sqlx::query(
            "SELECT t.email, t.language FROM patients p JOIN therapists t \
             ON t.id = p.therapist_id WHERE p.id = $1",
        )
        .bind(patient_id)
        .fetch_all(self.pool())
        .await
        .map_err(HubError::db("reading the patient's therapist"))?;
        let mut to = recipients(rows)?;
        if to.is_empty() {
            let rows = sqlx::query(
                "SELECT email, language FROM therapists WHERE role = 'admin' ORDER BY email",
            )
            .fetch_all(self.pool())
            .await
            .map_err(HubError::db("reading the admins"))?;
            to = recipients(rows)?;
        }
        Ok(to)
    }

    /// `therapist_id` cleared `patient_id` to train again after a pain stop, at `now_ms`.
    pub async fn clear_pain_stop(
        &self,
        patient_id: &str,
        therapist_id: &str,
        now_ms: i64,
    ) -> Result<(), HubError> {
        let mut tx = self
            .pool()
            .begin()
            .await
            .map_err(HubError::db("clearing a pain stop"))?;
        sqlx::query("DELETE FROM pain_clearances WHERE patient_id = $1")
            .bind(patient_id)
            .execute(&mut *tx)
            .await
            .map_err(HubError::db("clearing a pain stop"))?;
        sqlx::query(
            "INSERT INTO pain_clearances (patient_id, cleared_at_ms, therapist_id) \
             VALUES ($1, $2, $3)",
        )
        .bind(patient_id)
        .bind(now_ms)
        .bind(therapist_id)
        .execute(&mut *tx)
        .await
        .map_err(HubError::db("clearing a pain stop"))?;
        tx.commit()
            .await
            .map_err(HubError::db("clearing a pain stop"))
    }

    /// When `patient_id` was last cleared to train again after a pain stop, ms since the
    /// Unix epoch.
    pub async fn pain_cleared_at(&self, patient_id: &str) -> Result<Option<i64>, HubError> {
        let row = sqlx::query("SELECT cleared_at_ms FROM pain_clearances WHERE patient_id = $1")
            .bind(patient_id)
            .fetch_optional(self.pool())
            .await
            .map_err(HubError::db("reading a pain clearance"))?;
        row.map(|r| col(&r, "cleared_at_ms")).transpose()
    }
}
