//! Clinical scales of a patient: `GET`, `POST /api/patients/{id}/scales` and `DELETE
//! /api/patients/{id}/scales/{scale_id}`, every one audited.

use axum::Json;
use axum::extract::rejection::{JsonRejection, PathRejection};
use axum::extract::{Path, State};
use axum::http::StatusCode;
use serde::Serialize;

use super::auth::Authed;
use super::{ApiError, AppState, check_path_id};
use hub_store::db::{NewScale, SCALES, ScaleDef, ScaleEntry, check_scale};

/// Answer of `GET /api/patients/{id}/scales`: the entries, oldest first, and the scales the
/// hub records with their bounds (the console's form takes its min and max from them).
#[derive(Serialize)]
pub(crate) struct ScalesAnswer {
    entries: Vec<ScaleEntry>,
    scales: &'static [ScaleDef],
}

/// `GET /api/patients/{id}/scales`.
pub(crate) async fn list(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    id: Result<Path<String>, PathRejection>,
) -> Result<Json<ScalesAnswer>, ApiError> {
    let Path(id) = id?;
    let patient = state.visible_patient(&therapist, &id).await?;
    let entries = state.db.scales_of(&patient.id).await?;
    state
        .audit(&therapist.actor(), "read_scales", &patient.id, "")
        .await?;
    Ok(Json(ScalesAnswer {
        entries,
        scales: &SCALES,
    }))
}

/// `POST /api/patients/{id}/scales`: a new assessment (201 with it), audited. A scale the hub
/// does not record, a date that is not a real day (or in the future) and a score outside its
/// scale's range are refused (400 naming the field and its range), the refusal audited.
pub(crate) async fn post(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    id: Result<Path<String>, PathRejection>,
    body: Result<Json<NewScale>, JsonRejection>,
) -> Result<(StatusCode, Json<ScaleEntry>), ApiError> {
    let Path(id) = id?;
    let patient = state.visible_patient(&therapist, &id).await?;
    let Json(body) = body?;
    if let Err(refused) = check_scale(&body, state.now()) {
        state
            .audit(
                &therapist.actor(),
                "scale_rejected",
                &patient.id,
                &refused.to_string(),
            )
            .await?;
        return Err(refused.into());
    }
    let entry = state
        .db
        .add_scale(&patient.id, &therapist.id, &body, state.now())
        .await?;
    state
        .audit(
            &therapist.actor(),
            "post_scale",
            &patient.id,
            &format!("{} {}", entry.id, entry.words()),
        )
        .await?;
    Ok((StatusCode::CREATED, Json(entry)))
}

/// `DELETE /api/patients/{id}/scales/{scale_id}`: removes a mistaken entry (204), audited
/// with what it held; 404 when the patient has no such entry.
pub(crate) async fn delete(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    ids: Result<Path<(String, String)>, PathRejection>,
) -> Result<StatusCode, ApiError> {
    let Path((id, scale_id)) = ids?;
    let patient = state.visible_patient(&therapist, &id).await?;
    check_path_id("scale id", &scale_id)?;
    let Some(entry) = state.db.delete_scale(&patient.id, &scale_id).await? else {
        return Err(super::not_found(
            "scale",
            format!("patient {id:?} has no clinical scale {scale_id:?}"),
        ));
    };
    state
        .audit(
            &therapist.actor(),
            "delete_scale",
            &patient.id,
            &format!("{} {}", entry.id, entry.words()),
        )
        .await?;
    Ok(StatusCode::NO_CONTENT)
}
