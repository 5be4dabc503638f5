//! Pain that reaches someone, in the console's API: a therapist clears a patient to train
//! again after a pain stop (`POST /api/patients/{id}/pain-clearance`, pushed to the patient's
//! station), and admins see whether the pain mails go out (`GET /api/clinic/pain-mail`).

use axum::Json;
use axum::extract::rejection::{JsonRejection, PathRejection};
use axum::extract::{Path, State};
use serde::Serialize;

use super::auth::Authed;
use super::clinic::{NoInput, admins_only};
use super::{ApiError, AppState};
use hub_store::db::PainMailStatus;

/// Answer of `POST /api/patients/{id}/pain-clearance`.
#[derive(Serialize)]
pub(crate) struct Cleared {
    /// When the patient was cleared, ms since the Unix epoch.
    cleared_at_ms: i64,
}

/// `POST /api/patients/{id}/pain-clearance` (body `{}`): the patient may train again today
/// after a pain at or over the clinic's threshold; audited `pain_clearance` and pushed to the
/// patient's connected stations (a station not connected hears it when it next checks in).
pub(crate) async fn clear(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    id: Result<Path<String>, PathRejection>,
    body: Result<Json<NoInput>, JsonRejection>,
) -> Result<Json<Cleared>, ApiError> {
    let Path(id) = id?;
    let patient = state.visible_patient(&therapist, &id).await?;
    let Json(NoInput {}) = body?;
    let now = state.now();
    state
        .db
        .clear_pain_stop(&patient.id, &therapist.id, now)
        .await?;
    state
        .audit(&therapist.actor(), "pain_clearance", &patient.id, "")
        .await?;
    if let Some(feed) = &state.pain_cleared {
        let _ = feed.send(patient.id.clone());
    }
    Ok(Json(Cleared { cleared_at_ms: now }))
}

/// Answer of `GET /api/clinic/pain-mail`.
#[derive(Serialize)]
pub(crate) struct PainMailState {
    /// Mail is configured (`hub serve --smtp-url`).
    configured: bool,
    /// The pain threshold in force, 0–10.
    pain_threshold_0_10: u8,
    /// The outbox.
    #[serde(flatten)]
    outbox: PainMailStatus,
}

/// `GET /api/clinic/pain-mail` (admins): whether pain mails go out — mails waiting, failing,
/// the last error and when one was last sent.
pub(crate) async fn mail_status(
    State(state): State<AppState>,
    Authed(therapist): Authed,
) -> Result<Json<PainMailState>, ApiError> {
    admins_only(&therapist, "the pain mail's state")?;
    Ok(Json(PainMailState {
        configured: state.care.smtp.is_some(),
        pain_threshold_0_10: state.care.pain_threshold_in(&state.db).await,
        outbox: state.db.pain_mail_status().await?,
    }))
}
