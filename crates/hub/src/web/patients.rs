//! One patient and their sessions (the caseload is `attention::caseload`).

use axum::Json;
use axum::extract::rejection::PathRejection;
use axum::extract::{Path, State};
use serde::Serialize;

use super::auth::Authed;
use super::{ApiError, AppState};
use crate::db::{NamedSession, Patient, PatientWheel, Station};

/// Answer of `GET /api/patients/{id}`.
#[derive(Serialize)]
pub(crate) struct PatientDetail {
    #[serde(flatten)]
    patient: Patient,
    stations: Vec<Station>,
    /// The wheel the patient's stations last told the hub of (`null`: none yet), with
    /// `stated_ceiling_nm`, the ceiling as the console states it.
    wheel: Option<WheelView>,
}

/// The patient's wheel as `GET /api/patients/{id}` shows it.
#[derive(Serialize)]
pub(crate) struct WheelView {
    #[serde(flatten)]
    wheel: PatientWheel,
    /// The effective ceiling cut to 0.01 N·m: the form's maximum for every torque bound.
    stated_ceiling_nm: f64,
}

pub(crate) async fn one(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    id: Result<Path<String>, PathRejection>,
) -> Result<Json<PatientDetail>, ApiError> {
    let Path(id) = id?;
    let patient = state.visible_patient(&therapist, &id).await?;
    let stations = state.db.stations_of(&patient.id).await?;
    let wheel = state
        .db
        .wheel_of(&patient.id)
        .await?
        .map(|wheel| WheelView {
            stated_ceiling_nm: super::wheel_bounds::stated_ceiling_nm(&wheel),
            wheel,
        });
    state
        .audit(&therapist.actor(), "read_patient", &patient.id, "")
        .await?;
    Ok(Json(PatientDetail {
        patient,
        stations,
        wheel,
    }))
}

pub(crate) async fn sessions(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    id: Result<Path<String>, PathRejection>,
) -> Result<Json<Vec<NamedSession>>, ApiError> {
    let Path(id) = id?;
    let patient = state.visible_patient(&therapist, &id).await?;
    let sessions = state.db.named_sessions_of(&patient.id).await?;
    state
        .audit(&therapist.actor(), "read_sessions", &patient.id, "")
        .await?;
    Ok(Json(sessions))
}

/// `GET /api/patients/{id}/checkins`: the patient's end-of-session answers, newest first.
pub(crate) async fn checkins(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    id: Result<Path<String>, PathRejection>,
) -> Result<Json<Vec<crate::db::SessionCheckIn>>, ApiError> {
    let Path(id) = id?;
    let patient = state.visible_patient(&therapist, &id).await?;
    let checkins = state.db.checkins_of(&patient.id).await?;
    state
        .audit(&therapist.actor(), "read_checkins", &patient.id, "")
        .await?;
    Ok(Json(checkins))
}

/// `GET /api/patients/{id}/assessments`: the standard assessments the patient did, newest
/// first, each with its parts' results (never mixed into the exercise trends).
pub(crate) async fn assessments(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    id: Result<Path<String>, PathRejection>,
) -> Result<Json<Vec<crate::db::Assessment>>, ApiError> {
    let Path(id) = id?;
    let patient = state.visible_patient(&therapist, &id).await?;
    let assessments = state.db.assessments_of(&patient.id).await?;
    state
        .audit(&therapist.actor(), "read_assessments", &patient.id, "")
        .await?;
    Ok(Json(assessments))
}

/// `GET /api/patients/{id}/difficulty`: the difficulty each session ran at, its change and
/// why, newest first (sessions whose regimen adapts it).
pub(crate) async fn difficulty(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    id: Result<Path<String>, PathRejection>,
) -> Result<Json<Vec<crate::db::SessionDifficulty>>, ApiError> {
    let Path(id) = id?;
    let patient = state.visible_patient(&therapist, &id).await?;
    let history = state.db.difficulty_of(&patient.id).await?;
    state
        .audit(&therapist.actor(), "read_difficulty", &patient.id, "")
        .await?;
    Ok(Json(history))
}
