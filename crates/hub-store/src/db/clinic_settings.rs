//! The clinic's settings (migration 0020): the caseload's alert thresholds
//! ([`crate::thresholds`]), stored only once the clinic changes one.
//!
//! Other parts read the pain threshold with [`pain_threshold`].

use std::collections::BTreeMap;

use super::{Db, col};
use crate::error::HubError;
use crate::thresholds::{PAIN_THRESHOLD, Thresholds, check_setting};

/// The clinic's pain threshold on the 0–10 scale: pain at or over it in a check-in is an
/// urgent alert on the caseload (default 7, see docs/DESIGN.md "Needs attention today").
pub async fn pain_threshold(db: &Db) -> Result<i64, HubError> {
    Ok(db.thresholds().await?.pain_threshold_0_10)
}

/// A setting the clinic changed: its value, when and by whom.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct StoredSetting {
    /// The value.
    pub value: i64,
    /// When it was last changed, ms since the Unix epoch.
    pub updated_at_ms: i64,
    /// Who changed it (a therapist id).
    pub updated_by: String,
}

impl Db {
    /// The settings the clinic changed, by key.
    pub async fn clinic_settings(&self) -> Result<BTreeMap<String, StoredSetting>, HubError> {
        let rows = sqlx::query("SELECT key, value, updated_at_ms, updated_by FROM clinic_settings")
            .fetch_all(self.pool())
            .await
            .map_err(HubError::db("reading the clinic's settings"))?;
        rows.iter()
            .map(|r| {
                Ok((
                    col(r, "key")?,
                    StoredSetting {
                        value: col(r, "value")?,
                        updated_at_ms: col(r, "updated_at_ms")?,
                        updated_by: col(r, "updated_by")?,
                    },
                ))
            })
            .collect()
    }

    /// The alert thresholds in force (the clinic's values over the defaults).
    pub async fn thresholds(&self) -> Result<Thresholds, HubError> {
        let stored = self.clinic_settings().await?;
        Ok(Thresholds::from_values(|k| stored.get(k).map(|s| s.value)))
    }

    /// The clinic's pain threshold (0–10); see [`pain_threshold`].
    pub async fn pain_threshold(&self) -> Result<i64, HubError> {
        Ok(self
            .clinic_settings()
            .await?
            .get(PAIN_THRESHOLD)
            .map_or(Thresholds::default().pain_threshold_0_10, |s| s.value))
    }

    /// Sets setting `key` to `value` (checked: a known key within its bounds, else
    /// [`HubError::Invalid`] naming both) as therapist `by` at `now_ms`.
    pub async fn put_clinic_setting(
        &self,
        key: &str,
        value: i64,
        by: &str,
        now_ms: i64,
    ) -> Result<(), HubError> {
        check_setting(key, value)?;
        let mut tx = self
            .pool()
            .begin()
            .await
            .map_err(HubError::db("changing a setting"))?;
        sqlx::query("DELETE FROM clinic_settings WHERE key = $1")
            .bind(key)
            .execute(&mut *tx)
            .await
            .map_err(HubError::db("changing a setting"))?;
        sqlx::query(
            "INSERT INTO clinic_settings (key, value, updated_at_ms, updated_by) \
             VALUES ($1, $2, $3, $4)",
        )
        .bind(key)
        .bind(value)
        .bind(now_ms)
        .bind(by)
        .execute(&mut *tx)
        .await
        .map_err(HubError::db("changing a setting"))?;
        tx.commit()
            .await
            .map_err(HubError::db("changing a setting"))
    }
}
