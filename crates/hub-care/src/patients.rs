//! What `telerehab hub patient …` does to the clinic's database, a function per subcommand:
//! add a patient, issue a pairing code, prescribe a regimen, show a patient's sessions. The
//! station's command parses the arguments and prints; every change is audited here.

use hub_store::HubError;
use hub_store::db::{Db, Patient, Recording, SessionRow, Station};
use std::collections::BTreeMap;

/// How long a pairing code lives, ms (72 h).
pub const PAIRING_TTL_MS: i64 = 72 * 3600 * 1000;

/// A one-time pairing code issued to a patient.
#[derive(Clone, Debug, PartialEq)]
pub struct PairingCode {
    /// The patient's id.
    pub patient_id: String,
    /// The code (single use, valid [`PAIRING_TTL_MS`]).
    pub code: String,
}

/// Everything `hub patient show` says about a patient.
#[derive(Clone, Debug)]
pub struct PatientReport {
    /// The patient.
    pub patient: Patient,
    /// Their stations, newest first (revoked ones included).
    pub stations: Vec<Station>,
    /// Their sessions, newest first.
    pub sessions: Vec<SessionReport>,
    /// Their answers on the sessions' end screens, newest first.
    pub checkins: Vec<hub_store::db::SessionCheckIn>,
    /// The difficulty each adapted session ran at and why, newest first.
    pub difficulty: Vec<hub_store::db::SessionDifficulty>,
}

/// One session of a [`PatientReport`].
#[derive(Clone, Debug)]
pub struct SessionReport {
    /// The session.
    pub session: SessionRow,
    /// Summaries stored.
    pub summaries_stored: usize,
    /// Session time of the last summary stored, s (0 without one).
    pub length_s: f64,
    /// Its recording, if the station announced one.
    pub recording: Option<Recording>,
    /// Its clinical measures, by name.
    pub metrics: BTreeMap<String, f64>,
    /// Each exercise's own results, in course order.
    pub exercises: Vec<hub_store::db::SessionExercise>,
}

/// `hub patient add`: a new patient `pseudonym`, in the care of the therapist with the
/// e-mail `therapist_email` if given, and their first pairing code.
pub async fn add(
    db: &Db,
    pseudonym: &str,
    therapist_email: Option<&str>,
    now_ms: i64,
) -> Result<PairingCode, HubError> {
    let therapist_id = match therapist_email {
        Some(email) => Some(therapist(db, email).await?.id),
        None => None,
    };
    let p = db
        .add_patient(pseudonym, therapist_id.as_deref(), now_ms)
        .await?;
    db.audit("cli", "add_patient", &p.id, pseudonym, now_ms)
        .await?;
    issue_code(db, &p.id, now_ms).await
}

/// `hub patient code`: a new pairing code for the patient `pseudonym`.
pub async fn new_code(db: &Db, pseudonym: &str, now_ms: i64) -> Result<PairingCode, HubError> {
    let p = find(db, pseudonym).await?;
    issue_code(db, &p.id, now_ms).await
}

/// `hub patient regimen`: prescribe the regimen `toml` (read from `origin`, named in its
/// errors) to the patient `pseudonym`, by the therapist with the e-mail `by`; its version.
/// An invalid regimen is refused and nothing is stored.
pub async fn prescribe(
    db: &Db,
    pseudonym: &str,
    toml: &str,
    origin: &str,
    by: &str,
    now_ms: i64,
) -> Result<i64, HubError> {
    let p = find(db, pseudonym).await?;
    let therapist = therapist(db, by).await?;
    let parsed = regimen::Regimen::from_toml(toml, origin).map_err(|e| {
        HubError::refused("regimen", e.to_string(), hub_store::refusal::of_regimen(&e))
    })?;
    let version = db
        .put_regimen(&p.id, toml, parsed.sessions_per_week, &therapist.id, now_ms)
        .await?;
    let detail = format!("version {version}");
    db.audit(&therapist.actor(), "put_regimen", &p.id, &detail, now_ms)
        .await?;
    Ok(version)
}

/// `hub patient show`: the patient `pseudonym`, their stations and sessions (audited).
pub async fn show(db: &Db, pseudonym: &str, now_ms: i64) -> Result<PatientReport, HubError> {
    let patient = find(db, pseudonym).await?;
    let stations = db.stations_of(&patient.id).await?;
    let rows = db.sessions_of(&patient.id).await?;
    db.audit("cli", "show_patient", &patient.id, "", now_ms)
        .await?;
    let mut sessions = Vec::with_capacity(rows.len());
    for session in rows {
        let stored = db.summaries_of(&session.session_id).await?;
        sessions.push(SessionReport {
            summaries_stored: stored.len(),
            length_s: stored.last().map_or(0.0, |x| x.t_s),
            recording: db.recording(&session.session_id).await?,
            metrics: db.metrics_of(&session.session_id).await?,
            exercises: db.exercises_of(&session.session_id).await?,
            session,
        });
    }
    Ok(PatientReport {
        checkins: db.checkins_of(&patient.id).await?,
        difficulty: db.difficulty_of(&patient.id).await?,
        patient,
        stations,
        sessions,
    })
}

/// The patient `pseudonym`.
async fn find(db: &Db, pseudonym: &str) -> Result<Patient, HubError> {
    db.patient_by_pseudonym(pseudonym)
        .await?
        .ok_or_else(|| HubError::NotFound {
            what: "patient",
            id: pseudonym.to_owned(),
        })
}

/// The therapist with the e-mail `email`.
async fn therapist(db: &Db, email: &str) -> Result<hub_store::db::Therapist, HubError> {
    db.therapist_by_email(email)
        .await?
        .ok_or_else(|| HubError::NotFound {
            what: "therapist",
            id: email.to_owned(),
        })
}

/// A new pairing code for the patient `patient_id` (audited).
async fn issue_code(db: &Db, patient_id: &str, now_ms: i64) -> Result<PairingCode, HubError> {
    let code = db
        .create_pairing_code(patient_id, now_ms, PAIRING_TTL_MS)
        .await?;
    db.audit("cli", "pairing_code", patient_id, "", now_ms)
        .await?;
    Ok(PairingCode {
        patient_id: patient_id.to_owned(),
        code,
    })
}

/// `hub export --fhir PSEUDONYM [--lang de]`: the patient's record as a FHIR R4 Bundle
/// ([`crate::fhir::patient_bundle`], the hub's codes at the clinic's `base`, its narratives in
/// `language`, English for none; a language without catalogues is refused), pretty-printed
/// JSON, audited as `export_fhir` by `cli`; and how many sessions it holds.
pub async fn export_fhir(
    db: &Db,
    pseudonym: &str,
    now_ms: i64,
    base: &crate::fhir::FhirBase,
    language: Option<&str>,
) -> Result<(String, usize), HubError> {
    let words = crate::fhir::Words::of(language)?;
    let patient = find(db, pseudonym).await?;
    let (bundle, sessions) = crate::fhir::patient_bundle(db, &patient, now_ms, base, words).await?;
    db.audit(
        "cli",
        "export_fhir",
        &patient.id,
        &crate::fhir::audit_detail(sessions),
        now_ms,
    )
    .await?;
    let text = serde_json::to_string_pretty(&bundle)
        .map_err(|e| HubError::Corrupt(format!("writing the FHIR bundle: {e}")))?;
    Ok((text, sessions))
}
