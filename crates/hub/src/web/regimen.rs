//! Reading and prescribing a patient's regimen.

use axum::Json;
use axum::extract::rejection::{JsonRejection, PathRejection};
use axum::extract::{Path, State};
use serde::{Deserialize, Serialize};

use super::auth::Authed;
use super::{ApiError, AppState};
use crate::db::RegimenVersion;

/// Answer of `GET /api/patients/{id}/regimen`.
#[derive(Serialize)]
pub(crate) struct RegimenView {
    /// The newest version, `null` if none was prescribed.
    current: Option<RegimenVersion>,
    /// Every version, oldest first.
    history: Vec<RegimenVersion>,
}

pub(crate) async fn get_regimen(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    id: Result<Path<String>, PathRejection>,
) -> Result<Json<RegimenView>, ApiError> {
    let Path(id) = id?;
    let patient = state.visible_patient(&therapist, &id).await?;
    let history = state.db.regimen_history(&patient.id).await?;
    state
        .audit(&therapist.actor(), "read_regimen", &patient.id, "")
        .await?;
    Ok(Json(RegimenView {
        current: history.last().cloned(),
        history,
    }))
}

/// Body of `PUT /api/patients/{id}/regimen`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct PutRegimen {
    /// The regimen as TOML text.
    toml: String,
}

pub(crate) async fn put_regimen(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    id: Result<Path<String>, PathRejection>,
    body: Result<Json<PutRegimen>, JsonRejection>,
) -> Result<Json<RegimenVersion>, ApiError> {
    let Path(id) = id?;
    let patient = state.visible_patient(&therapist, &id).await?;
    let Json(body) = body?;
    if let Err(reason) = (state.validate_regimen)(&body.toml) {
        state
            .audit(&therapist.actor(), "regimen_rejected", &patient.id, &reason)
            .await?;
        return Err(ApiError::Unprocessable(format!(
            "regimen refused: {reason}"
        )));
    }
    let now = state.now();
    let version = state
        .db
        .put_regimen(&patient.id, &body.toml, &therapist.id, now)
        .await?;
    state
        .audit(
            &therapist.actor(),
            "put_regimen",
            &patient.id,
            &format!("version {version}"),
        )
        .await?;
    let prescribed = RegimenVersion {
        patient_id: patient.id,
        version,
        toml: body.toml,
        prescribed_by: therapist.id,
        prescribed_at_ms: now,
    };
    if let Some(feed) = &state.prescribed {
        // No receiver (no station link running) is not an error: the station fetches the
        // regimen when it next connects.
        let _ = feed.send(prescribed.clone());
    }
    Ok(Json(prescribed))
}
