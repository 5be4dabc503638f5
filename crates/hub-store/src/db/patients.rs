//! Patients: pseudonyms only (never a name), each optionally assigned to a therapist.

use serde::Serialize;
use sqlx::any::AnyRow;
use std::collections::BTreeMap;

use super::{Db, Therapist, col, new_id};
use crate::error::HubError;
use crate::refusal::{Code, Why};

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
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PatientOverview {
    /// The patient.
    #[serde(flatten)]
    pub patient: Patient,
    /// Start of the most recent session (station clock), ms since the Unix epoch.
    pub last_session_started_ms: Option<i64>,
    /// Sessions started in the 7 days before `now_ms` that count as training (a summary
    /// stored or measures reported; a `Hello` alone does not count).
    pub sessions_last_7_days: i64,
    /// Sessions a week the current regimen asks for (its `sessions_per_week`), if it says.
    pub sessions_per_week_prescribed: Option<i64>,
    /// Active exercise minutes (pauses and rests not counted: the sessions' `active_s`) of
    /// the sessions started in the 7 days before `now_ms`.
    pub active_minutes_last_7_days: f64,
    /// Repetitions in the sessions started in the 7 days before `now_ms`: their discrete
    /// wheel movements (the sessions' `movements` measure), the dose's count beside its time.
    pub repetitions_last_7_days: i64,
    /// Active minutes a week the current regimen asks for: its planned session length times
    /// its `sessions_per_week`, if it says.
    pub minutes_per_week_prescribed: Option<f64>,
    /// Trends of the main measures (`pct_in_lane`, `wheel_rom_deg`, `sparc_median`; for all
    /// three, up is better): `"up"`, `"down"` or `"flat"` (within the measure's measurement noise,
    /// 2 % when unknown: `db::words::trend`), like with like: the
    /// last session that ran as prescribed (`end_reason` = `complete`) against the mean of up
    /// to four before it of the same exercise kind that did too; absent with fewer than two
    /// such sessions having the measure.
    pub trends: BTreeMap<String, String>,
    /// The exercise kind the trends compare (`road`, `dial`, …, as the sessions'
    /// `exercise_kind`); `null` when no session ran as prescribed.
    pub trend_exercise_kind: Option<String>,
    /// The same trends in every exercise kind with two or more sessions that ran as
    /// prescribed, the kind trained last first (the caseload's Trend column: a decline in a
    /// kind not trained last stays visible).
    pub trends_by_kind: Vec<super::words::KindTrends>,
    /// What the therapist should look at, in plain words: missed sessions against the
    /// prescription, a safety fault, clipped torque or lost arm sensors in the last session.
    pub alerts: Vec<String>,
}

/// The measures the caseload shows a trend of (for each, up is better).
pub const TREND_MEASURES: [&str; 3] = ["pct_in_lane", "wheel_rom_deg", "sparc_median"];

/// The patient's week against the prescription.
struct Week {
    sessions: i64,
    prescribed: Option<i64>,
    active_min: f64,
    prescribed_min: Option<f64>,
}

/// What the last session's measures say that a caseload alert needs.
struct LastSession {
    faults: Option<f64>,
    clipped_pct: Option<f64>,
    sensors_lost: Option<f64>,
}

/// The caseload row's alerts, from its counts and its last session's measures.
fn alerts(week: &Week, last_start: Option<i64>, last: LastSession) -> Vec<String> {
    let mut out = Vec::new();
    match (week.prescribed, last_start) {
        (_, None) => out.push("no session yet".to_owned()),
        (Some(p), _) if week.sessions < p => {
            out.push(format!("{} of {p} sessions this week", week.sessions));
        }
        (None, _) if week.sessions == 0 => out.push("no session in the last 7 days".to_owned()),
        _ => {}
    }
    // Enough sessions, but short ones: the minutes tell.
    if let Some(p) = week.prescribed_min
        && last_start.is_some()
        && week.prescribed.is_none_or(|n| week.sessions >= n)
        && week.active_min < 0.9 * p
    {
        out.push(format!(
            "{:.0} of {p:.0} active minutes this week",
            week.active_min
        ));
    }
    if last.faults.is_some_and(|f| f > 0.0) {
        out.push("safety stop in the last session (torque faded out on a fault)".to_owned());
    }
    if last.clipped_pct.is_some_and(|c| c >= 5.0) {
        out.push("torque held at the ceiling for 5 % or more of the last session".to_owned());
    }
    if last.sensors_lost.is_some_and(|l| l > 0.0) {
        out.push("arm sensors lost in the last session (no joint angles)".to_owned());
    }
    out
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
        Err(HubError::refused(
            "pseudonym",
            format!(
                "{:?} refused: use 1 to {MAX_PSEUDONYM_LEN} characters of A-Z, a-z, 0-9, \
                 '.', '_', '-' (a pseudonym, never a name)",
                pseudonym.chars().take(80).collect::<String>()
            ),
            Why::new(Code::BadPseudonym).with("max", MAX_PSEUDONYM_LEN),
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
        .map_err(HubError::inserting(
            "patient",
            pseudonym,
            "adding a patient",
        ))?;
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

    /// Every patient, by pseudonym (no overview: for going through them one by one).
    pub async fn all_patients(&self) -> Result<Vec<Patient>, HubError> {
        let rows = sqlx::query(
            "SELECT id, pseudonym, therapist_id, created_at_ms FROM patients ORDER BY pseudonym",
        )
        .fetch_all(self.pool())
        .await
        .map_err(HubError::db("listing patients"))?;
        rows.iter().map(Patient::from_row).collect()
    }

    /// The caseload of `therapist` (an admin sees every patient), by pseudonym, each with the
    /// start of their last session and the number of sessions started in the 7 days before
    /// `now_ms`.
    pub async fn patients_for(
        &self,
        therapist: &Therapist,
        now_ms: i64,
    ) -> Result<Vec<PatientOverview>, HubError> {
        self.overviews(therapist, "", now_ms).await
    }

    /// The caseload row of patient `patient_id` as [`Db::patients_for`] makes it, if
    /// `therapist` may see them.
    pub async fn patient_overview(
        &self,
        therapist: &Therapist,
        patient_id: &str,
        now_ms: i64,
    ) -> Result<Option<PatientOverview>, HubError> {
        if patient_id.is_empty() {
            return Ok(None);
        }
        Ok(self.overviews(therapist, patient_id, now_ms).await?.pop())
    }

    /// The caseload rows of `therapist`, of patient `only` (all when empty).
    async fn overviews(
        &self,
        therapist: &Therapist,
        only: &str,
        now_ms: i64,
    ) -> Result<Vec<PatientOverview>, HubError> {
        // Only sessions that count as training (a Hello alone is not one).
        const CASELOAD: &str = "SELECT p.id, p.pseudonym, p.therapist_id, p.created_at_ms, \
            (SELECT MAX(s.started_unix_ms) FROM sessions s WHERE s.patient_id = p.id \
                AND {training}) AS last_start, \
            (SELECT COUNT(*) FROM sessions s WHERE s.patient_id = p.id \
                AND s.started_unix_ms >= $1 AND {training}) AS week_count, \
            (SELECT r.sessions_per_week FROM regimens r WHERE r.patient_id = p.id \
                ORDER BY r.version DESC LIMIT 1) AS prescribed_per_week, \
            (SELECT r.planned_session_s FROM regimens r WHERE r.patient_id = p.id \
                ORDER BY r.version DESC LIMIT 1) AS planned_session_s, \
            (SELECT SUM(m.value) FROM session_metrics m JOIN sessions s \
                ON s.session_id = m.session_id WHERE s.patient_id = p.id \
                AND s.started_unix_ms >= $1 AND m.name = 'active_s') AS week_active_s, \
            (SELECT SUM(m.value) FROM session_metrics m JOIN sessions s \
                ON s.session_id = m.session_id WHERE s.patient_id = p.id \
                AND s.started_unix_ms >= $1 AND m.name = 'movements') AS week_movements, \
            (SELECT m.value FROM session_metrics m WHERE m.name = 'watchdog_fault_ticks' \
                AND m.session_id = (SELECT s.session_id FROM sessions s WHERE s.patient_id = p.id \
                    AND {training} ORDER BY s.started_unix_ms DESC LIMIT 1)) AS last_faults, \
            (SELECT m.value FROM session_metrics m WHERE m.name = 'clipped_pct' \
                AND m.session_id = (SELECT s.session_id FROM sessions s WHERE s.patient_id = p.id \
                    AND {training} ORDER BY s.started_unix_ms DESC LIMIT 1)) AS last_clipped, \
            (SELECT m.value FROM session_metrics m WHERE m.name = 'arm_sensors_lost' \
                AND m.session_id = (SELECT s.session_id FROM sessions s WHERE s.patient_id = p.id \
                    AND {training} ORDER BY s.started_unix_ms DESC LIMIT 1)) AS last_sensors_lost \
            FROM patients p WHERE ($2 = '' OR p.therapist_id = $2) AND ($3 = '' OR p.id = $3) \
            ORDER BY p.pseudonym";
        // An admin sees every patient (an empty therapist id matches all).
        let own = if therapist.is_admin() {
            ""
        } else {
            therapist.id.as_str()
        };
        let sql = CASELOAD.replace("{training}", super::TRAINING_SESSION_SQL);
        let query = sqlx::query(sqlx::AssertSqlSafe(sql))
            .bind(now_ms.saturating_sub(WEEK_MS))
            .bind(own)
            .bind(only);
        let rows = query
            .fetch_all(self.pool())
            .await
            .map_err(HubError::db("listing patients"))?;
        let mut out: Vec<PatientOverview> = rows
            .iter()
            .map(|row| {
                let last_start: Option<i64> = col(row, "last_start")?;
                let week: i64 = col(row, "week_count")?;
                // Stored from the parsed regimen when it was prescribed (migration 0004).
                let prescribed: Option<i64> = col(row, "prescribed_per_week")?;
                // Stored from the parsed regimen when it was prescribed (migration 0010).
                let planned_s: Option<f64> = col(row, "planned_session_s")?;
                let active_s: Option<f64> = col(row, "week_active_s")?;
                let movements: Option<f64> = col(row, "week_movements")?;
                let week = Week {
                    sessions: week,
                    prescribed,
                    active_min: active_s.unwrap_or(0.0) / 60.0,
                    prescribed_min: planned_s.zip(prescribed).map(|(s, n)| s / 60.0 * n as f64),
                };
                Ok(PatientOverview {
                    patient: Patient::from_row(row)?,
                    last_session_started_ms: last_start,
                    sessions_last_7_days: week.sessions,
                    sessions_per_week_prescribed: prescribed,
                    active_minutes_last_7_days: week.active_min,
                    // A count stored as a measure's f64: whole, within i64.
                    repetitions_last_7_days: movements.unwrap_or(0.0).round() as i64,
                    minutes_per_week_prescribed: week.prescribed_min,
                    trends: BTreeMap::new(),
                    trend_exercise_kind: None,
                    trends_by_kind: Vec::new(),
                    alerts: alerts(
                        &week,
                        last_start,
                        LastSession {
                            faults: col(row, "last_faults")?,
                            clipped_pct: col(row, "last_clipped")?,
                            sensors_lost: col(row, "last_sensors_lost")?,
                        },
                    ),
                })
            })
            .collect::<Result<_, HubError>>()?;
        for o in &mut out {
            (o.trends, o.trend_exercise_kind) = self
                .like_with_like_trends(&o.patient.id, &TREND_MEASURES)
                .await?;
            o.trends_by_kind = self.trends_by_kind(&o.patient.id, &TREND_MEASURES).await?;
            // The patient's own word after the last session (migration 0006).
            o.alerts.extend(self.pain_alert_of(&o.patient.id).await?);
        }
        Ok(out)
    }

    /// True if `therapist` may see `patient`: an admin sees all, a therapist their own.
    pub fn may_see(therapist: &Therapist, patient: &Patient) -> bool {
        therapist.is_admin() || patient.therapist_id.as_deref() == Some(therapist.id.as_str())
    }
}
