//! A patient's per-session measures in one query, for the spreadsheet export
//! (`GET /api/patients/{id}/measures.csv`, `GET /api/measures.csv`).

use std::collections::BTreeMap;

use super::{Db, col};
use crate::error::HubError;

/// Session id → its measures (name → value; units in the names).
pub type MeasuresBySession = BTreeMap<String, BTreeMap<String, f64>>;

impl Db {
    /// Patient `patient_id`'s sessions, oldest first, with every session's measures (what the
    /// spreadsheet and the FHIR export each write a line or an Observation of).
    pub async fn sessions_with_measures(
        &self,
        patient_id: &str,
    ) -> Result<(Vec<super::NamedSession>, MeasuresBySession), HubError> {
        let mut sessions = self.named_sessions_of(patient_id).await?;
        sessions.reverse();
        Ok((sessions, self.measures_of_patient(patient_id).await?))
    }

    /// The names of every measure any session has, sorted.
    pub async fn measure_names(&self) -> Result<Vec<String>, HubError> {
        let rows = sqlx::query("SELECT DISTINCT name FROM session_metrics ORDER BY name")
            .fetch_all(self.pool())
            .await
            .map_err(HubError::db("listing the measures' names"))?;
        rows.iter().map(|r| col(r, "name")).collect()
    }

    /// Every measure of every session of patient `patient_id`, by session.
    pub async fn measures_of_patient(
        &self,
        patient_id: &str,
    ) -> Result<MeasuresBySession, HubError> {
        let rows = sqlx::query(
            "SELECT m.session_id, m.name, m.value FROM session_metrics m \
             JOIN sessions s ON s.session_id = m.session_id WHERE s.patient_id = $1",
        )
        .bind(patient_id)
        .fetch_all(self.pool())
        .await
        .map_err(HubError::db("reading a patient's measures"))?;
        by_session(&rows)
    }

    /// The measures named `names` of every session of patient `patient_id`, by session (what
    /// the caseload's alert rules read, `hub_care::attention::RULE_MEASURES`). The names are
    /// bound as parameters, never written into the SQL.
    pub async fn measures_named_of_patient(
        &self,
        patient_id: &str,
        names: &[&str],
    ) -> Result<MeasuresBySession, HubError> {
        if names.is_empty() {
            return Ok(MeasuresBySession::new());
        }
        let places: Vec<String> = (2..names.len() + 2).map(|i| format!("${i}")).collect();
        // Only numbered placeholders are formatted into the text.
        let sql = format!(
            "SELECT m.session_id, m.name, m.value FROM session_metrics m \
             JOIN sessions s ON s.session_id = m.session_id \
             WHERE s.patient_id = $1 AND m.name IN ({})",
            places.join(", ")
        );
        let mut query = sqlx::query(sqlx::AssertSqlSafe(sql)).bind(patient_id.to_owned());
        for name in names {
            query = query.bind((*name).to_owned());
        }
        let rows = query
            .fetch_all(self.pool())
            .await
            .map_err(HubError::db("reading the measures the alerts need"))?;
        by_session(&rows)
    }
}

/// Rows of `session_id`, `name`, `value` gathered by session.
fn by_session(rows: &[sqlx::any::AnyRow]) -> Result<MeasuresBySession, HubError> {
    let mut by_session = MeasuresBySession::new();
    for row in rows {
        by_session
            .entry(col(row, "session_id")?)
            .or_default()
            .insert(col(row, "name")?, col(row, "value")?);
    }
    Ok(by_session)
}
