//! The therapist's messages to a patient: `POST` and `GET /api/patients/{id}/messages`.

use axum::Json;
use axum::extract::rejection::{JsonRejection, PathRejection};
use axum::extract::{Path, State};
use axum::http::StatusCode;
use serde::Deserialize;

use super::Says as _;
use super::auth::Authed;
use super::{ApiError, AppState};
use hub_store::db::PatientMessage;

/// Body of `POST /api/patients/{id}/messages`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct PostMessage {
    /// The message: plain text, 1 to 500 characters, no control characters.
    text: String,
}

/// `GET /api/patients/{id}/messages`: the patient's messages, newest first, with when each
/// was sent and seen.
pub(crate) async fn list(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    id: Result<Path<String>, PathRejection>,
) -> Result<Json<Vec<PatientMessage>>, ApiError> {
    let Path(id) = id?;
    let patient = state.visible_patient(&therapist, &id).await?;
    let messages = state.db.messages_of(&patient.id).await?;
    state
        .audit(&therapist.actor(), "read_messages", &patient.id, "")
        .await?;
    Ok(Json(messages))
}

/// `POST /api/patients/{id}/messages`: a new message for the patient (201 with it), shown on
/// the start card of their next session. A text that is empty, too long or holds control
/// characters is refused (400, naming the problem) and the refusal audited.
pub(crate) async fn post(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    id: Result<Path<String>, PathRejection>,
    body: Result<Json<PostMessage>, JsonRejection>,
) -> Result<(StatusCode, Json<PatientMessage>), ApiError> {
    let Path(id) = id?;
    let patient = state.visible_patient(&therapist, &id).await?;
    let Json(body) = body?;
    if let Err(e) = netlink::check_message_text(&body.text) {
        state
            .audit(&therapist.actor(), "message_rejected", &patient.id, &e.0)
            .await?;
        let why = hub_store::refusal::of_text("text", &body.text, netlink::MAX_MESSAGE_TEXT_CHARS);
        return Err(ApiError::BadRequest(why.says(e.0)));
    }
    let message = state
        .db
        .add_message(&patient.id, &therapist.id, &body.text, state.now())
        .await?;
    state
        .audit(
            &therapist.actor(),
            "post_message",
            &patient.id,
            &format!(
                "message {} ({} characters)",
                message.id,
                body.text.chars().count()
            ),
        )
        .await?;
    Ok((StatusCode::CREATED, Json(message)))
}
