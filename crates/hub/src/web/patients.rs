//! One patient and their sessions (the caseload is `attention::caseload`).

use axum::Json;
use axum::extract::rejection::{PathRejection, QueryRejection};
use axum::extract::{Path, Query, State};
use serde::{Deserialize, Serialize};

use super::Says as _;
use super::auth::Authed;
use super::{ApiError, AppState};
use hub_store::db::{
    AssessmentWithChanges, DEFAULT_ASSESSMENT_PAGE, MAX_ASSESSMENT_PAGE, NamedSession, Patient,
    PatientWheel, Station,
};
use hub_store::refusal::{Code, Why};

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
) -> Result<Json<Vec<hub_store::db::SessionCheckIn>>, ApiError> {
    let Path(id) = id?;
    let patient = state.visible_patient(&therapist, &id).await?;
    let checkins = state.db.checkins_of(&patient.id).await?;
    state
        .audit(&therapist.actor(), "read_checkins", &patient.id, "")
        .await?;
    Ok(Json(checkins))
}

/// Query of `GET /api/patients/{id}/assessments`.
#[derive(Deserialize)]
pub(crate) struct AssessmentsQuery {
    /// Only assessments whose session started before this time, ms since the Unix epoch (the
    /// last `started_unix_ms` of the previous page).
    before: Option<i64>,
    /// Most assessments returned (default [`DEFAULT_ASSESSMENT_PAGE`], at most
    /// [`MAX_ASSESSMENT_PAGE`]).
    limit: Option<i64>,
}

/// `GET /api/patients/{id}/assessments`: the standard assessments the patient did, newest
/// first, a page at a time, each with its parts' results (never mixed into the exercise
/// trends) and each measure's change since the patient's first assessment told from
/// measurement noise (`metrics::change`, from the whole history before it).
pub(crate) async fn assessments(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    id: Result<Path<String>, PathRejection>,
    query: Result<Query<AssessmentsQuery>, QueryRejection>,
) -> Result<Json<Vec<AssessmentWithChanges>>, ApiError> {
    let Path(id) = id?;
    let Query(query) = query.map_err(|e| {
        ApiError::BadRequest(Why::field(Code::FieldRefused, "query").says(e.body_text()))
    })?;
    let max = MAX_ASSESSMENT_PAGE as i64;
    let limit = query.limit.unwrap_or(DEFAULT_ASSESSMENT_PAGE as i64);
    if !(1..=max).contains(&limit) {
        return Err(ApiError::BadRequest(
            Why::field(Code::OutOfRange, "limit")
                .with("min", 1)
                .with("max", max)
                .says(format!("limit {limit} refused: it must be from 1 to {max}")),
        ));
    }
    if let Some(before) = query.before.filter(|b| *b < 0) {
        return Err(ApiError::BadRequest(
            Why::field(Code::OutOfRange, "before")
                .with("min", 0)
                .with("max", i64::MAX)
                .says(format!(
                    "before {before} refused: it must be a time in ms since the Unix epoch (0 or more)"
                )),
        ));
    }
    let patient = state.visible_patient(&therapist, &id).await?;
    let page = state
        .db
        .assessment_page(&patient.id, query.before, limit as usize)
        .await?;
    state
        .audit(&therapist.actor(), "read_assessments", &patient.id, "")
        .await?;
    Ok(Json(page))
}

/// `GET /api/patients/{id}/difficulty`: the difficulty each session ran at, its change and
/// why, newest first (sessions whose regimen adapts it).
pub(crate) async fn difficulty(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    id: Result<Path<String>, PathRejection>,
) -> Result<Json<Vec<hub_store::db::SessionDifficulty>>, ApiError> {
    let Path(id) = id?;
    let patient = state.visible_patient(&therapist, &id).await?;
    let history = state.db.difficulty_of(&patient.id).await?;
    state
        .audit(&therapist.actor(), "read_difficulty", &patient.id, "")
        .await?;
    Ok(Json(history))
}
