//! The therapist's notes on a session: `POST` and `GET /api/sessions/{id}/notes`.

use axum::Json;
use axum::extract::rejection::{JsonRejection, PathRejection};
use axum::extract::{Path, State};
use axum::http::StatusCode;
use serde::Deserialize;

use super::Says as _;
use super::auth::Authed;
use super::sessions::visible_session;
use super::{ApiError, AppState};
use hub_store::db::{SessionNote, check_note_text};

/// Body of `POST /api/sessions/{id}/notes`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct PostNote {
    /// The note: plain text, 1 to 2 000 characters, line breaks allowed.
    text: String,
}

/// `GET /api/sessions/{id}/notes`: the session's notes, oldest first, each with who wrote it
/// and when (404 for a session of a patient the therapist may not see).
pub(crate) async fn list(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    id: Result<Path<String>, PathRejection>,
) -> Result<Json<Vec<SessionNote>>, ApiError> {
    let Path(id) = id?;
    let session = visible_session(&state, &therapist, &id).await?;
    let notes = state.db.notes_of_session(&session.session_id).await?;
    state
        .audit(&therapist.actor(), "read_notes", &session.session_id, "")
        .await?;
    Ok(Json(notes))
}

/// `POST /api/sessions/{id}/notes`: a new note on the session (201 with it), audited with
/// its therapist. A text that is empty, too long or holds control characters is refused (400,
/// naming the problem) and the refusal audited.
pub(crate) async fn post(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    id: Result<Path<String>, PathRejection>,
    body: Result<Json<PostNote>, JsonRejection>,
) -> Result<(StatusCode, Json<SessionNote>), ApiError> {
    let Path(id) = id?;
    let session = visible_session(&state, &therapist, &id).await?;
    let Json(body) = body?;
    if let Err(e) = check_note_text(&body.text) {
        state
            .audit(&therapist.actor(), "note_rejected", &session.session_id, &e)
            .await?;
        let why = hub_store::refusal::of_text("text", &body.text, hub_store::db::MAX_NOTE_CHARS);
        return Err(ApiError::BadRequest(why.says(e)));
    }
    let note = state
        .db
        .add_session_note(&session.session_id, &therapist.id, &body.text, state.now())
        .await?;
    state
        .audit(
            &therapist.actor(),
            "post_note",
            &session.session_id,
            &format!(
                "note {} ({} characters)",
                note.id,
                body.text.chars().count()
            ),
        )
        .await?;
    Ok((StatusCode::CREATED, Json(note)))
}
