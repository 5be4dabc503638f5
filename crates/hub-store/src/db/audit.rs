//! The audit log: who read or changed what, when.

use std::sync::atomic::{AtomicU64, Ordering};

use serde::{Deserialize, Serialize};

use super::{Db, col, hex, random_bytes};
use crate::error::HubError;

/// Longest stored detail text, characters (longer text is cut).
pub const MAX_DETAIL_CHARS: usize = 1024;

/// Most entries in one page of the audit log.
pub const MAX_AUDIT_PAGE: i64 = 10_000;

/// Where a page of the audit log starts: entries strictly older than this one.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct AuditCursor {
    /// The time of the last entry of the previous page, ms since the Unix epoch.
    pub before_ms: i64,
    /// Its id (entries of the same millisecond are ordered by id).
    pub before_id: String,
}

/// A page of the audit log, newest first.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct AuditPage {
    /// The entries.
    pub entries: Vec<AuditEntry>,
    /// The next (older) page's cursor; `None` on the last page.
    pub next: Option<AuditCursor>,
}

/// Which entries of the audit log a page keeps: each field set must match exactly (`None`:
/// any).
#[derive(Debug, Clone, Default, PartialEq, Eq, Deserialize)]
pub struct AuditFilter {
    /// Who (`therapist:<id>`, `station:<id>`, …).
    pub actor: Option<String>,
    /// What (`put_regimen`, …).
    pub action: Option<String>,
    /// On what (a patient's id, a session's id, …).
    pub target: Option<String>,
}

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
        audit_on(self.pool(), actor, action, target, detail, now_ms).await
    }

    /// The newest `limit` entries of the audit log, newest first.
    pub async fn audit_log(&self, limit: i64) -> Result<Vec<AuditEntry>, HubError> {
        Ok(self.audit_page(None, limit).await?.entries)
    }

    /// One page of the audit log, newest first: at most `limit` (1 to [`MAX_AUDIT_PAGE`])
    /// entries older than `before` (all if `None`), and the cursor of the next page. Paging by
    /// time and id keeps every entry reachable however fast new ones arrive.
    pub async fn audit_page(
        &self,
        before: Option<&AuditCursor>,
        limit: i64,
    ) -> Result<AuditPage, HubError> {
        self.audit_page_where(before, limit, &AuditFilter::default())
            .await
    }

    /// [`Db::audit_page`] of the entries `filter` keeps (each of its fields set must match
    /// exactly).
    pub async fn audit_page_where(
        &self,
        before: Option<&AuditCursor>,
        limit: i64,
        filter: &AuditFilter,
    ) -> Result<AuditPage, HubError> {
        let limit = limit.clamp(1, MAX_AUDIT_PAGE);
        let mut conditions = Vec::new();
        let mut binds: Vec<String> = Vec::new();
        let mut placeholder = 0;
        let mut next = || {
            placeholder += 1;
            format!("${placeholder}")
        };
        let mut before_ms = None;
        if let Some(cursor) = before {
            let (ms, id) = (next(), next());
            conditions.push(format!("(at_ms < {ms} OR (at_ms = {ms} AND id < {id}))"));
            before_ms = Some(cursor.before_ms);
            binds.push(cursor.before_id.clone());
        }
        for (column, value) in [
            ("actor", &filter.actor),
            ("action", &filter.action),
            ("target", &filter.target),
        ] {
            if let Some(value) = value {
                conditions.push(format!("{column} = {}", next()));
                binds.push(value.clone());
            }
        }
        let limit_at = next();
        let condition = if conditions.is_empty() {
            String::new()
        } else {
            format!("WHERE {}", conditions.join(" AND "))
        };
        let sql = format!(
            "SELECT id, at_ms, actor, action, target, detail FROM audit_log {condition} \
             ORDER BY at_ms DESC, id DESC LIMIT {limit_at}"
        );
        let mut query = sqlx::query(sqlx::AssertSqlSafe(sql));
        if let Some(ms) = before_ms {
            query = query.bind(ms);
        }
        for value in binds {
            query = query.bind(value);
        }
        let rows = query
            .bind(limit + 1)
            .fetch_all(self.pool())
            .await
            .map_err(HubError::db("reading the audit log"))?;
        let mut entries = rows
            .iter()
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
            .collect::<Result<Vec<_>, HubError>>()?;
        let more = entries.len() > usize::try_from(limit).unwrap_or(usize::MAX);
        entries.truncate(usize::try_from(limit).unwrap_or(usize::MAX));
        let next = more
            .then(|| entries.last())
            .flatten()
            .map(|last| AuditCursor {
                before_ms: last.at_ms,
                before_id: last.id.clone(),
            });
        Ok(AuditPage { entries, next })
    }
}

/// Writes an audit entry with `executor`: the pool, or a transaction whose change the entry
/// must stand or fall with.
pub(crate) async fn audit_on<'e, E>(
    executor: E,
    actor: &str,
    action: &str,
    target: &str,
    detail: &str,
    now_ms: i64,
) -> Result<(), HubError>
where
    E: sqlx::Executor<'e, Database = sqlx::Any>,
{
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
    .execute(executor)
    .await
    .map_err(HubError::db("writing the audit log"))?;
    Ok(())
}
