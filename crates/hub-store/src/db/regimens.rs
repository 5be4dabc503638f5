//! Prescribed regimens: every change is a new version, the history is kept.

use serde::Serialize;
use sqlx::any::AnyRow;

use super::{Db, check_id, col};
use crate::error::HubError;

/// Longest regimen text, bytes.
pub const MAX_REGIMEN_BYTES: usize = 64 * 1024;

/// One version of a patient's regimen.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct RegimenVersion {
    /// The patient.
    pub patient_id: String,
    /// Version number, 1 for the first, increasing by one.
    pub version: i64,
    /// The regimen as TOML text (validated by the caller against the station's safety bounds).
    pub toml: String,
    /// Id of the therapist who prescribed it.
    pub prescribed_by: String,
    /// When, ms since the Unix epoch.
    pub prescribed_at_ms: i64,
}

impl RegimenVersion {
    fn from_row(row: &AnyRow) -> Result<Self, HubError> {
        Ok(Self {
            patient_id: col(row, "patient_id")?,
            version: col(row, "version")?,
            toml: col(row, "toml")?,
            prescribed_by: col(row, "prescribed_by")?,
            prescribed_at_ms: col(row, "prescribed_at_ms")?,
        })
    }
}

const COLUMNS: &str = "patient_id, version, toml, prescribed_by, prescribed_at_ms";

impl Db {
    /// Stores `toml` as the next version of the patient's regimen, prescribed by therapist
    /// `by` at `now_ms`, with the `sessions_per_week` the caller parsed from it
    /// (`regimen::Regimen::sessions_per_week`; the caseload reads it); returns the new version
    /// number. The text is not interpreted here.
    pub async fn put_regimen(
        &self,
        patient_id: &str,
        toml: &str,
        sessions_per_week: Option<u32>,
        by: &str,
        now_ms: i64,
    ) -> Result<i64, HubError> {
        check_id("patient_id", patient_id)?;
        if toml.len() > MAX_REGIMEN_BYTES || toml.contains('\0') {
            return Err(HubError::invalid(
                "regimen",
                format!("must be text of at most {MAX_REGIMEN_BYTES} bytes without NUL"),
            ));
        }
        if self.patient(patient_id).await?.is_none() {
            return Err(HubError::not_found("patient", patient_id));
        }
        // One statement computes and inserts the next version; two concurrent writers on
        // PostgreSQL can compute the same one: the loser hits the primary key and retries.
        let mut attempts = 0;
        loop {
            attempts += 1;
            let result: Result<i64, sqlx::Error> = sqlx::query_scalar(
                "INSERT INTO regimens (patient_id, version, toml, prescribed_by, \
                 prescribed_at_ms, sessions_per_week) \
                 SELECT $1, COALESCE(MAX(version), 0) + 1, $2, $3, $4, $5 FROM regimens \
                 WHERE patient_id = $1 RETURNING version",
            )
            .bind(patient_id)
            .bind(toml)
            .bind(by)
            .bind(now_ms)
            .bind(sessions_per_week.map(i64::from))
            .fetch_one(self.pool())
            .await;
            match result {
                Ok(version) => {
                    self.set_planned_session_s(patient_id, version, toml)
                        .await?;
                    return Ok(version);
                }
                Err(e) if HubError::is_unique_violation(&e) && attempts < 5 => continue,
                Err(e) => return Err(HubError::db("storing a regimen")(e)),
            }
        }
    }

    /// Fills `sessions_per_week` of regimens stored before migration 0004 (the column is NULL
    /// there) with the regimen's own parser; a regimen that does not mention it, or no longer
    /// parses, keeps NULL. Run by [`Db::open`] once, when it applies migration 4.
    pub(crate) async fn fill_sessions_per_week(&self) -> Result<(), HubError> {
        let rows = sqlx::query(
            "SELECT patient_id, version, toml FROM regimens \
             WHERE sessions_per_week IS NULL AND toml LIKE '%sessions_per_week%'",
        )
        .fetch_all(self.pool())
        .await
        .map_err(HubError::db(
            "reading regimens to fill in sessions_per_week",
        ))?;
        for row in &rows {
            let text: String = col(row, "toml")?;
            let Some(n) = regimen::Regimen::from_toml(&text, "a stored regimen")
                .ok()
                .and_then(|r| r.sessions_per_week)
            else {
                continue;
            };
            let (patient_id, version): (String, i64) =
                (col(row, "patient_id")?, col(row, "version")?);
            sqlx::query(
                "UPDATE regimens SET sessions_per_week = $1 WHERE patient_id = $2 AND version = $3",
            )
            .bind(i64::from(n))
            .bind(patient_id)
            .bind(version)
            .execute(self.pool())
            .await
            .map_err(HubError::db("filling in sessions_per_week"))?;
        }
        Ok(())
    }

    /// Stores the planned session length of regimen `version` of `patient_id` (its `toml`),
    /// which the caseload reads for adherence in minutes; left NULL for a text the parser
    /// refuses (nothing is bound as NULL: `sqlx::Any` cannot type it on PostgreSQL).
    async fn set_planned_session_s(
        &self,
        patient_id: &str,
        version: i64,
        toml: &str,
    ) -> Result<(), HubError> {
        let Some(planned_s) = planned_session_s(toml) else {
            return Ok(());
        };
        sqlx::query(
            "UPDATE regimens SET planned_session_s = $1 WHERE patient_id = $2 AND version = $3",
        )
        .bind(planned_s)
        .bind(patient_id)
        .bind(version)
        .execute(self.pool())
        .await
        .map_err(HubError::db("storing a regimen's planned length"))?;
        Ok(())
    }

    /// Fills `planned_session_s` of regimens stored before migration 0010.
    pub(crate) async fn fill_planned_session_s(&self) -> Result<(), HubError> {
        let rows = sqlx::query(
            "SELECT patient_id, version, toml FROM regimens WHERE planned_session_s IS NULL",
        )
        .fetch_all(self.pool())
        .await
        .map_err(HubError::db(
            "reading regimens to fill in their planned length",
        ))?;
        for row in &rows {
            let (patient_id, version, toml): (String, i64, String) = (
                col(row, "patient_id")?,
                col(row, "version")?,
                col(row, "toml")?,
            );
            self.set_planned_session_s(&patient_id, version, &toml)
                .await?;
        }
        Ok(())
    }

    /// The newest regimen of a patient, if any.
    pub async fn latest_regimen(
        &self,
        patient_id: &str,
    ) -> Result<Option<RegimenVersion>, HubError> {
        let sql = sqlx::AssertSqlSafe(format!(
            "SELECT {COLUMNS} FROM regimens WHERE patient_id = $1 \
             ORDER BY version DESC LIMIT 1"
        ));
        let row = sqlx::query(sql)
            .bind(patient_id)
            .fetch_optional(self.pool())
            .await
            .map_err(HubError::db("reading a regimen"))?;
        row.as_ref().map(RegimenVersion::from_row).transpose()
    }

    /// Every regimen version of a patient, oldest first.
    pub async fn regimen_history(&self, patient_id: &str) -> Result<Vec<RegimenVersion>, HubError> {
        let sql = sqlx::AssertSqlSafe(format!(
            "SELECT {COLUMNS} FROM regimens WHERE patient_id = $1 ORDER BY version"
        ));
        let rows = sqlx::query(sql)
            .bind(patient_id)
            .fetch_all(self.pool())
            .await
            .map_err(HubError::db("reading regimen history"))?;
        rows.iter().map(RegimenVersion::from_row).collect()
    }
}

/// The planned session length of a regimen's text, s (`None` if it does not parse).
fn planned_session_s(toml: &str) -> Option<f64> {
    regimen::Regimen::from_recorded(toml, "a stored regimen")
        .ok()?
        .0
        .planned_duration_s()
        .ok()
}
