//! Patients: pseudonyms only (never a name), each optionally assigned to a therapist.

use serde::Serialize;
use sqlx::any::AnyRow;

use super::{Db, Therapist, col, new_id};
use crate::error::HubError;

/// Longest pseudonym, characters.
pub const MAX_PSEUDONYM_LEN: usize = 64;

/// The window of [`PatientOverview::sessions_last_7_days`], ms.
pub const WEEK_MS: i64 = 7 * 24 * 60 * 60 * 1000;

/// A patient, known to the hub by pseudonym only.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Patient {
    /// Identifier, `p-` + 16 hex digits (what stations send as `patient_id`).
    pub id: String,
    /// The clinic's pseudonym for the patient (1–64 of `A-Z a-z 0-9 . _ -`).
    pub pseudonym: String,
    /// The therapist in charge, if assigned.
    pub therapist_id: Option<String>,
    /// Creation time, ms since the Unix epoch.
    pub created_at_ms: i64,
}

/// A row of a therapist's caseload: the patient and their adherence.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct PatientOverview {
    /// The patient.
    #[serde(flatten)]
    pub patient: Patient,
    /// Start of the most recent session (station clock), ms since the Unix epoch.
    pub last_session_started_ms: Option<i64>,
    /// Sessions started in the 7 days before `now_ms`.
    pub sessions_last_7_days: i64,
}

/// Checks a pseudonym: 1–64 characters of ASCII letters, digits, `.`, `_`, `-`.
pub fn check_pseudonym(pseudonym: &str) -> Result<(), HubError> {
    let ok = !pseudonym.is_empty()
        && pseudonym.len() <= MAX_PSEUDONYM_LEN
        && pseudonym
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '-'));
    if ok {
        Ok(())
    } else {
        Err(HubError::invalid(
            "pseudonym",
            format!(
                "{:?} refused: use 1 to {MAX_PSEUDONYM_LEN} characters of A-Z, a-z, 0-9, \
                 '.', '_', '-' (a pseudonym, never a name)",
                pseudonym.chars().take(80).collect::<String>()
            ),
        ))
    }
}

impl Patient {
    fn from_row(row: &AnyRow) -> Result<Self, HubError> {
        Ok(Self {
            id: col(row, "id")?,
            pseudonym: col(row, "pseudonym")?,
            therapist_id: col(row, "therapist_id")?,
            created_at_ms: col(row, "created_at_ms")?,
        })
    }
}

impl Db {
    /// Adds a patient under `pseudonym`, assigned to `therapist_id` if given.
    pub async fn add_patient(
        &self,
        pseudonym: &str,
        therapist_id: Option<&str>,
        now_ms: i64,
    ) -> Result<Patient, HubError> {
        check_pseudonym(pseudonym)?;
        if let Some(t) = therapist_id
            && self.therapist(t).await?.is_none()
        {
            return Err(HubError::not_found("therapist", t));
        }
        let id = new_id("p-")?;
        sqlx::query(
            "INSERT INTO patients (id, pseudonym, therapist_id, created_at_ms) \
             VALUES ($1, $2, $3, $4)",
        )
        .bind(&id)
        .bind(pseudonym)
        .bind(therapist_id)
        .bind(now_ms)
        .execute(self.pool())
        .await
        .map_err(|e| {
            if HubError::is_unique_violation(&e) {
                HubError::AlreadyExists {
                    what: "patient",
                    id: pseudonym.to_owned(),
                }
            } else {
                HubError::db("adding a patient")(e)
            }
        })?;
        Ok(Patient {
            id,
            pseudonym: pseudonym.to_owned(),
            therapist_id: therapist_id.map(str::to_owned),
            created_at_ms: now_ms,
        })
    }

    /// The patient with this id, if any.
    pub async fn patient(&self, id: &str) -> Result<Option<Patient>, HubError> {
        let row = sqlx::query(
            "SELECT id, pseudonym, therapist_id, created_at_ms FROM patients WHERE id = $1",
        )
        .bind(id)
        .fetch_optional(self.pool())
        .await
        .map_err(HubError::db("reading a patient"))?;
        row.as_ref().map(Patient::from_row).transpose()
    }

    /// The patient with this pseudonym, if any (the pseudonym is checked first).
    pub async fn patient_by_pseudonym(&self, pseudonym: &str) -> Result<Option<Patient>, HubError> {
        check_pseudonym(pseudonym)?;
        let row = sqlx::query(
            "SELECT id, pseudonym, therapist_id, created_at_ms FROM patients \
             WHERE pseudonym = $1",
        )
        .bind(pseudonym)
        .fetch_optional(self.pool())
        .await
        .map_err(HubError::db("reading a patient"))?;
        row.as_ref().map(Patient::from_row).transpose()
    }

    /// The caseload of `therapist` (an admin sees every patient), by pseudonym, each with the
    /// start of their last session and the number of sessions started in the 7 days before
    /// `now_ms`.
    pub async fn patients_for(
        &self,
        therapist: &Therapist,
        now_ms: i64,
    ) -> Result<Vec<PatientOverview>, HubError> {
        const ALL: &str = "SELECT p.id, p.pseudonym, p.therapist_id, p.created_at_ms, \
            (SELECT MAX(s.started_unix_ms) FROM sessions s WHERE s.patient_id = p.id) AS last_start, \
            (SELECT COUNT(*) FROM sessions s WHERE s.patient_id = p.id \
                AND s.started_unix_ms >= $1) AS week_count \
            FROM patients p ORDER BY p.pseudonym";
        const OWN: &str = "SELECT p.id, p.pseudonym, p.therapist_id, p.created_at_ms, \
            (SELECT MAX(s.started_unix_ms) FROM sessions s WHERE s.patient_id = p.id) AS last_start, \
            (SELECT COUNT(*) FROM sessions s WHERE s.patient_id = p.id \
                AND s.started_unix_ms >= $1) AS week_count \
            FROM patients p WHERE p.therapist_id = $2 ORDER BY p.pseudonym";
        let query = if therapist.is_admin() {
            sqlx::query(ALL).bind(now_ms.saturating_sub(WEEK_MS))
        } else {
            sqlx::query(OWN)
                .bind(now_ms.saturating_sub(WEEK_MS))
                .bind(therapist.id.as_str())
        };
        let rows = query
            .fetch_all(self.pool())
            .await
            .map_err(HubError::db("listing patients"))?;
        rows.iter()
            .map(|row| {
                Ok(PatientOverview {
                    patient: Patient::from_row(row)?,
                    last_session_started_ms: col(row, "last_start")?,
                    sessions_last_7_days: col(row, "week_count")?,
                })
            })
            .collect()
    }

    /// True if `therapist` may see `patient`: an admin sees all, a therapist their own.
    pub fn may_see(therapist: &Therapist, patient: &Patient) -> bool {
        therapist.is_admin() || patient.therapist_id.as_deref() == Some(therapist.id.as_str())
    }
}
