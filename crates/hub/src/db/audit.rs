//! The audit log: who read or changed what, when.

use std::sync::atomic::{AtomicU64, Ordering};

use serde::Serialize;

use super::{Db, col, hex, random_bytes};
use crate::error::HubError;

/// Longest stored detail text, characters (longer text is cut).
pub const MAX_DETAIL_CHARS: usize = 1024;

/// One audit log entry.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct AuditEntry {
    /// Identifier: the time, zero-padded, a counter and a random suffix (sorts by time).
    pub id: String,
    /// When, ms since the Unix epoch.
    pub at_ms: i64,
    /// Who: `therapist:<id>`, `station:<id>`, `cli`, `web` (not yet logged in).
    pub actor: String,
    /// What, e.g. `read_patient`, `put_regimen`, `login_failed`.
    pub action: String,
    /// On what, e.g. a patient or session id.
    pub target: String,
    /// Free text for humans.
    pub detail: String,
}

static AUDIT_COUNTER: AtomicU64 = AtomicU64::new(0);

fn clip(text: &str) -> String {
    text.chars()
        .take(MAX_DETAIL_CHARS)
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect()
}

impl Db {
    /// Appends an entry to the audit log.
    pub async fn audit(
        &self,
        actor: &str,
        action: &str,
        target: &str,
        detail: &str,
        now_ms: i64,
    ) -> Result<(), HubError> {
        // Time, then a per-process counter (entries of the same millisecond keep their order),
        // then random bits (several hub processes on one PostgreSQL database).
        let n = AUDIT_COUNTER.fetch_add(1, Ordering::Relaxed);
        let id = format!(
            "{:016}-{n:012}-{}",
            now_ms.max(0),
            hex(&random_bytes::<4>()?)
        );
        sqlx::query(
            "INSERT INTO audit_log (id, at_ms, actor, action, target, detail) \
             VALUES ($1, $2, $3, $4, $5, $6)",
        )
        .bind(id)
        .bind(now_ms)
        .bind(clip(actor))
        .bind(clip(action))
        .bind(clip(target))
        .bind(clip(detail))
        .execute(self.pool())
        .await
        .map_err(HubError::db("writing the audit log"))?;
        Ok(())
    }

    /// The newest `limit` entries of the audit log, newest first.
    pub async fn audit_log(&self, limit: i64) -> Result<Vec<AuditEntry>, HubError> {
        let rows = sqlx::query(
            "SELECT id, at_ms, actor, action, target, detail FROM audit_log \
             ORDER BY at_ms DESC, id DESC LIMIT $1",
        )
        .bind(limit.clamp(0, 10_000))
        .fetch_all(self.pool())
        .await
        .map_err(HubError::db("reading the audit log"))?;
        rows.iter()
            .map(|row| {
                Ok(AuditEntry {
                    id: col(row, "id")?,
                    at_ms: col(row, "at_ms")?,
                    actor: col(row, "actor")?,
                    action: col(row, "action")?,
                    target: col(row, "target")?,
                    detail: col(row, "detail")?,
                })
            })
            .collect()
    }
}
