//! Reading and prescribing a patient's regimen.

use axum::Json;
use axum::extract::rejection::{JsonRejection, PathRejection};
use axum::extract::{Path, State};
use serde::{Deserialize, Serialize};

use super::Says as _;
use super::auth::Authed;
use super::{ApiError, AppState};
use hub_store::db::RegimenVersion;
use hub_store::refusal::{Code, Why};

/// Answer of `GET /api/patients/{id}/regimen`.
#[derive(Serialize)]
pub(crate) struct RegimenView {
    /// The newest version, `null` if none was prescribed.
    current: Option<RegimenVersion>,
    /// Every version, oldest first.
    history: Vec<RegimenVersion>,
    /// The newest version's TOML as JSON (tables as objects, arrays of tables as arrays), for
    /// the console's form; `null` if none was prescribed.
    current_fields: Option<serde_json::Value>,
    /// The e-mail of the therapist who prescribed the newest version (`null` if none, or the
    /// account is gone): the console names them by it, not by their id.
    current_prescribed_by_email: Option<String>,
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
    let current_fields = history
        .last()
        .and_then(|r| toml::from_str::<toml::Value>(&r.toml).ok())
        .and_then(|v| serde_json::to_value(v).ok());
    let current_prescribed_by_email = match history.last() {
        Some(r) => state.db.therapist(&r.prescribed_by).await?.map(|t| t.email),
        None => None,
    };
    Ok(Json(RegimenView {
        current: history.last().cloned(),
        history,
        current_fields,
        current_prescribed_by_email,
    }))
}

/// The regimen's JSON Schema, derived once from the regimen's types (with the validator's
/// bounds).
static REGIMEN_SCHEMA: std::sync::LazyLock<serde_json::Value> =
    std::sync::LazyLock::new(regimen::Regimen::json_schema);

/// `GET /api/regimen/schema`: the schema the console builds its prescribe form from. No
/// patient data, so not audited; a login is still required, as for every endpoint.
pub(crate) async fn regimen_schema(Authed(_): Authed) -> Json<serde_json::Value> {
    Json(REGIMEN_SCHEMA.clone())
}

/// The presets, derived once from the regimen crate's definitions.
static PRESETS: std::sync::LazyLock<Vec<regimen::presets::PresetView>> =
    std::sync::LazyLock::new(regimen::presets::preset_views);

/// `GET /api/regimen/presets`: easy, medium and hard for every exercise kind, each with its
/// words and the fields it sets (`regimen::presets`), for the prescribe form. No patient data,
/// so not audited; a login is required.
pub(crate) async fn regimen_presets(Authed(_): Authed) -> Json<Vec<regimen::presets::PresetView>> {
    Json(PRESETS.clone())
}

/// Body of `PUT /api/patients/{id}/regimen`: the regimen as TOML text, or as the fields the
/// console's form edits (JSON, written as TOML here); exactly one of the two.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct PutRegimen {
    /// The regimen as TOML text.
    #[serde(default)]
    toml: Option<String>,
    /// The regimen as JSON fields (the shape of `current_fields`).
    #[serde(default)]
    fields: Option<serde_json::Value>,
}

impl PutRegimen {
    /// The regimen's TOML text.
    fn into_toml(self) -> Result<String, ApiError> {
        match (self.toml, self.fields) {
            (Some(text), None) => Ok(text),
            (None, Some(fields)) => {
                let refused = |e: &dyn std::fmt::Display| {
                    ApiError::BadRequest(
                        Why::new(Code::RegimenShape).says(format!("regimen fields: {e}")),
                    )
                };
                let value: toml::Value = serde_json::from_value(fields).map_err(|e| refused(&e))?;
                toml::to_string(&value).map_err(|e| refused(&e))
            }
            _ => Err(ApiError::BadRequest(Why::new(Code::RegimenShape).says(
                "give the regimen as \"toml\" or as \"fields\", not both or neither",
            ))),
        }
    }
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
    let text = body.into_toml()?;
    let parsed = match regimen::Regimen::from_toml(&text, "the prescribed regimen") {
        Ok(parsed) => parsed,
        Err(reason) => {
            // A TOML slip in plain words, naming its line and field; the regimen's own bounds
            // keep their message (it names the field already).
            let (reason, why) = match super::regimen_words::toml_problem(&text) {
                Some(problem) => (problem.words.clone(), problem.why()),
                None => (reason.to_string(), hub_store::refusal::of_regimen(&reason)),
            };
            state
                .audit(&therapist.actor(), "regimen_rejected", &patient.id, &reason)
                .await?;
            return Err(ApiError::Unprocessable(
                why.says(format!("regimen refused: {reason}")),
            ));
        }
    };
    // Never above what the patient's own wheel can give.
    super::wheel_bounds::check(&state, &therapist, &patient, &parsed).await?;
    let now = state.now();
    let version = state
        .db
        .put_regimen(
            &patient.id,
            &text,
            parsed.sessions_per_week,
            &therapist.id,
            now,
        )
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
        toml: text,
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
