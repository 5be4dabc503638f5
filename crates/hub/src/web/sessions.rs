//! One session, its summaries and its movement metrics.

use std::collections::BTreeMap;

use axum::Json;
use axum::extract::rejection::PathRejection;
use axum::extract::{Path, State};
use netlink::Summary;

use super::auth::Authed;
use super::{ApiError, AppState, check_path_id};
use crate::db::{SessionRow, Therapist};

/// The session `id` if `therapist` may see its patient; 404 otherwise.
async fn visible_session(
    state: &AppState,
    therapist: &Therapist,
    id: &str,
) -> Result<SessionRow, ApiError> {
    check_path_id("session id", id)?;
    let not_found = || ApiError::NotFound(format!("no session {id:?}"));
    let session = state.db.session(id).await?.ok_or_else(not_found)?;
    state
        .visible_patient(therapist, &session.patient_id)
        .await
        .map_err(|_| not_found())?;
    Ok(session)
}

pub(crate) async fn one(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    id: Result<Path<String>, PathRejection>,
) -> Result<Json<SessionRow>, ApiError> {
    let Path(id) = id?;
    let session = visible_session(&state, &therapist, &id).await?;
    state
        .audit(&therapist.actor(), "read_session", &session.session_id, "")
        .await?;
    Ok(Json(session))
}

pub(crate) async fn summaries(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    id: Result<Path<String>, PathRejection>,
) -> Result<Json<Vec<Summary>>, ApiError> {
    let Path(id) = id?;
    let session = visible_session(&state, &therapist, &id).await?;
    let summaries = state.db.summaries_of(&session.session_id).await?;
    state
        .audit(
            &therapist.actor(),
            "read_summaries",
            &session.session_id,
            "",
        )
        .await?;
    Ok(Json(summaries))
}

pub(crate) async fn metrics(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    id: Result<Path<String>, PathRejection>,
) -> Result<Json<BTreeMap<String, f64>>, ApiError> {
    let Path(id) = id?;
    let session = visible_session(&state, &therapist, &id).await?;
    let metrics = state.db.metrics_of(&session.session_id).await?;
    state
        .audit(&therapist.actor(), "read_metrics", &session.session_id, "")
        .await?;
    Ok(Json(metrics))
}

/// Largest recording the console replays, bytes (≈ 1.7 h of a compact 1 kHz recording).
pub const MAX_REPLAY_BYTES: u64 = 512 << 20;

/// `GET /api/sessions/{id}/replay`: the session's uploaded recording as the console's replay
/// draws it; 404 until the whole recording has arrived.
pub(crate) async fn replay(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    id: Result<Path<String>, PathRejection>,
) -> Result<Json<serde_json::Value>, ApiError> {
    let Path(id) = id?;
    let session = visible_session(&state, &therapist, &id).await?;
    let reader = state
        .replay
        .clone()
        .ok_or_else(|| ApiError::NotFound("this hub does not offer replays".to_owned()))?;
    let recording = state
        .db
        .recording(&session.session_id)
        .await?
        .filter(|r| r.complete)
        .ok_or_else(|| {
            ApiError::NotFound(format!(
                "the recording of session {:?} has not (fully) arrived yet",
                session.session_id
            ))
        })?;
    state
        .audit(&therapist.actor(), "read_replay", &session.session_id, "")
        .await?;
    let path = std::path::PathBuf::from(&recording.path);
    // A station may upload up to netlink's 16 GiB; the reader holds a recording in memory, so
    // the console replays only what the hub can hold (an hour at 1 kHz is about 300 MB).
    let size = std::fs::metadata(&path).map_or(0, |m| m.len());
    if size > MAX_REPLAY_BYTES {
        return Err(ApiError::Unprocessable(format!(
            "the recording of session {:?} is {} MB, more than the {} MB the console replays",
            session.session_id,
            size >> 20,
            MAX_REPLAY_BYTES >> 20
        )));
    }
    let frames = tokio::task::spawn_blocking(move || reader(&path))
        .await
        .map_err(|_| ApiError::Internal)?
        .map_err(|e| {
            tracing::warn!(session = %session.session_id, "replay unreadable: {e}");
            ApiError::Internal
        })?;
    Ok(Json(frames))
}
