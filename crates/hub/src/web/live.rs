//! Server-Sent Events of a patient's running session.

use std::convert::Infallible;

use axum::extract::rejection::PathRejection;
use axum::extract::{Path, State};
use axum::response::sse::{Event, KeepAlive, Sse};
use netlink::Summary;
use serde::Serialize;
use tokio_stream::Stream;
use tokio_stream::StreamExt as _;
use tokio_stream::wrappers::BroadcastStream;
use tokio_stream::wrappers::errors::BroadcastStreamRecvError;

use super::auth::Authed;
use super::{ApiError, AppState};

/// One summary of a running session, as broadcast by the ingest to the console's live views.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LiveEvent {
    /// The patient exercising.
    pub patient_id: String,
    /// Their session.
    pub session_id: String,
    /// The summary just stored.
    pub summary: Summary,
}

/// `GET /api/patients/{id}/live`: events `summary` (data: a [`LiveEvent`] as JSON) for this
/// patient only, `lagged` (data: how many were skipped) when the client is too slow.
pub(crate) async fn live(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    id: Result<Path<String>, PathRejection>,
) -> Result<Sse<impl Stream<Item = Result<Event, Infallible>>>, ApiError> {
    let Path(id) = id?;
    let patient = state.visible_patient(&therapist, &id).await?;
    // Subscribe before answering, so nothing broadcast after the answer is missed.
    let receiver = state.live.subscribe();
    state
        .audit(&therapist.actor(), "watch_live", &patient.id, "")
        .await?;
    let patient_id = patient.id;
    let stream = BroadcastStream::new(receiver).filter_map(move |message| match message {
        Ok(event) if event.patient_id == patient_id => Some(Ok(
            match Event::default().event("summary").json_data(&event) {
                Ok(e) => e,
                Err(e) => Event::default().event("error").data(e.to_string()),
            },
        )),
        Ok(_) => None,
        Err(BroadcastStreamRecvError::Lagged(n)) => {
            Some(Ok(Event::default().event("lagged").data(n.to_string())))
        }
    });
    Ok(Sse::new(stream).keep_alive(KeepAlive::default()))
}
