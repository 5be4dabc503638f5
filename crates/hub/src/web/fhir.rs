//! `GET /api/patients/{id}/fhir`: the patient's record as a FHIR R4 `Bundle` ([`hub_care::fhir`]),
//! its narratives in the language asked (`?lang=de`, else the therapist's console language, else
//! English), audited.

use axum::extract::rejection::{PathRejection, QueryRejection};
use axum::extract::{Path, Query, State};
use axum::http::{HeaderValue, header};
use axum::response::{IntoResponse, Response};

use super::Says as _;
use super::auth::Authed;
use super::{ApiError, AppState};
use hub_store::HubError;
use hub_store::refusal::{Code, Why};

/// The bundle's query.
#[derive(serde::Deserialize)]
pub(crate) struct FhirQuery {
    /// The narratives' language (`de`); the therapist's console language when absent.
    lang: Option<String>,
}

/// The FHIR JSON media type.
const FHIR_JSON: &str = "application/fhir+json; fhirVersion=4.0";

/// `GET /api/patients/{id}/fhir` (404 for a patient the therapist may not see), audited as
/// `export_fhir` with the number of sessions; a language without catalogues is **400** naming
/// it.
pub(crate) async fn bundle(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    id: Result<Path<String>, PathRejection>,
    query: Result<Query<FhirQuery>, QueryRejection>,
) -> Result<Response, ApiError> {
    let Path(id) = id?;
    let Query(q) = query.map_err(|e| {
        ApiError::BadRequest(Why::field(Code::FieldRefused, "query").says(e.body_text()))
    })?;
    let lang = match q.lang {
        Some(lang) => Some(lang),
        None => state.db.therapist_language(&therapist.id).await?,
    };
    let words = hub_care::fhir::Words::of(lang.as_deref())?;
    let patient = state.visible_patient(&therapist, &id).await?;
    let base = state.fhir_base.as_ref().ok_or_else(|| {
        HubError::Config(
            "this hub has no FHIR address (hub.toml's fhir_base) to export with".into(),
        )
    })?;
    let (bundle, sessions) =
        hub_care::fhir::patient_bundle(&state.db, &patient, state.now(), base, words).await?;
    state
        .audit(
            &therapist.actor(),
            "export_fhir",
            &patient.id,
            &hub_care::fhir::audit_detail(sessions),
        )
        .await?;
    let mut response = axum::Json(bundle).into_response();
    response
        .headers_mut()
        .insert(header::CONTENT_TYPE, HeaderValue::from_static(FHIR_JSON));
    Ok(response)
}
