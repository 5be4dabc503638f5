//! `GET /api/patients/{id}/fhir`: the patient's record as a FHIR R4 `Bundle` ([`crate::fhir`]),
//! audited.

use axum::extract::rejection::PathRejection;
use axum::extract::{Path, State};
use axum::http::{HeaderValue, header};
use axum::response::{IntoResponse, Response};

use super::auth::Authed;
use super::{ApiError, AppState};
use crate::error::HubError;

/// The FHIR JSON media type.
const FHIR_JSON: &str = "application/fhir+json; fhirVersion=4.0";

/// `GET /api/patients/{id}/fhir` (404 for a patient the therapist may not see), audited as
/// `export_fhir` with the number of sessions.
pub(crate) async fn bundle(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    id: Result<Path<String>, PathRejection>,
) -> Result<Response, ApiError> {
    let Path(id) = id?;
    let patient = state.visible_patient(&therapist, &id).await?;
    let base = state.fhir_base.as_ref().ok_or_else(|| {
        HubError::Config(
            "this hub has no FHIR address (hub.toml's fhir_base) to export with".into(),
        )
    })?;
    let (bundle, sessions) =
        crate::fhir::patient_bundle(&state.db, &patient, state.now(), base).await?;
    state
        .audit(
            &therapist.actor(),
            "export_fhir",
            &patient.id,
            &crate::fhir::audit_detail(sessions),
        )
        .await?;
    let mut response = axum::Json(bundle).into_response();
    response
        .headers_mut()
        .insert(header::CONTENT_TYPE, HeaderValue::from_static(FHIR_JSON));
    Ok(response)
}
