//! The clinic's daily work from the browser, as `telerehab hub …` does it on the command line:
//! add a patient (with their first pairing code), a new pairing code, add a therapist (with a
//! one-time password), list the therapists, revoke a station. Every change is audited with the
//! therapist who made it.
//!
//! Who may: an admin does all of it; a therapist adds patients into their own care, issues
//! codes for and revokes the stations of their own patients (someone else's answer 404, as
//! everywhere); therapists are the admins' to add and list (403 otherwise).

use axum::Json;
use axum::extract::rejection::{JsonRejection, PathRejection};
use axum::extract::{Path, State};
use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use serde::{Deserialize, Serialize};

use super::Says as _;
use super::auth::Authed;
use super::{ApiError, AppState, check_path_id};
use hub_care::patients::PAIRING_TTL_MS;
use hub_store::HubError;
use hub_store::db::{Patient, Role, Station, Therapist};
use hub_store::refusal::{Code, Why};

/// A 409 for a pseudonym or e-mail already taken; other errors as usual.
fn taken(e: HubError) -> ApiError {
    match e {
        HubError::AlreadyExists { what, .. } => ApiError::Rejected(
            StatusCode::CONFLICT,
            Why::new(Code::AlreadyExists)
                .with("what", what)
                .says(format!("{e}; choose another (nothing was changed)")),
        ),
        other => other.into(),
    }
}

pub(super) fn admins_only(therapist: &Therapist, what: &str) -> Result<(), ApiError> {
    if therapist.is_admin() {
        Ok(())
    } else {
        Err(ApiError::Forbidden(
            Why::new(Code::AdminOnly).says(format!("{what} is for administrators")),
        ))
    }
}

/// The body `{}` of a change that needs no input: being JSON, no cross-site form can send it
/// (415 otherwise), as `POST /api/logout` requires.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct NoInput {}

/// A pairing code as the console prints it.
#[derive(Serialize)]
pub(crate) struct Pairing {
    /// `XXXX-XXXX`, single use.
    code: String,
    /// When it stops pairing, ms since the Unix epoch.
    expires_at_ms: i64,
    /// The address stations at home connect to, for the sheet (`hub serve
    /// --public-station-address`); `null` when the hub knows none a station at home can
    /// reach.
    station_address: Option<String>,
    /// Why there is no `station_address`, in plain words (`null` when there is one).
    station_address_problem: Option<String>,
}

/// A new pairing code for `patient` (audited `pairing_code`).
async fn issue_code(
    state: &AppState,
    by: &Therapist,
    patient: &Patient,
) -> Result<Pairing, ApiError> {
    let now = state.now();
    let code = state
        .db
        .create_pairing_code(&patient.id, now, PAIRING_TTL_MS)
        .await?;
    state
        .audit(&by.actor(), "pairing_code", &patient.id, "")
        .await?;
    let (station_address, station_address_problem) = match &state.care.public_station_address {
        Ok(a) => (Some(a.clone()), None),
        Err(why) => (None, Some(why.clone())),
    };
    Ok(Pairing {
        code,
        expires_at_ms: now.saturating_add(PAIRING_TTL_MS),
        station_address,
        station_address_problem,
    })
}

/// Body of `POST /api/patients`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct NewPatient {
    pseudonym: String,
    /// The therapist in charge, by e-mail: an admin may name anyone or nobody; a therapist
    /// only themselves (the default).
    #[serde(default)]
    therapist_email: Option<String>,
}

/// Answer of `POST /api/patients` (201).
#[derive(Serialize)]
pub(crate) struct AddedPatient {
    patient: Patient,
    pairing: Pairing,
}

/// `POST /api/patients`: a new patient and their first pairing code.
pub(crate) async fn add_patient(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    body: Result<Json<NewPatient>, JsonRejection>,
) -> Result<Response, ApiError> {
    let Json(new) = body?;
    let named = new
        .therapist_email
        .as_deref()
        .map(str::trim)
        .filter(|e| !e.is_empty());
    let in_care_of = match (therapist.is_admin(), named) {
        (true, None) => None,
        (true, Some(email)) => Some(
            state
                .db
                .therapist_by_email(email)
                .await?
                .ok_or_else(|| {
                    ApiError::BadRequest(Why::new(Code::NoTherapistEmail).says(format!(
                        "invalid therapist_email: no therapist has the e-mail {email:?}"
                    )))
                })?
                .id,
        ),
        (false, Some(email)) if !email.eq_ignore_ascii_case(&therapist.email) => {
            return Err(ApiError::Forbidden(Why::new(Code::OwnCareOnly).says(
                "a therapist adds patients into their own care; an administrator can assign \
                 another therapist",
            )));
        }
        (false, _) => Some(therapist.id.clone()),
    };
    let patient = state
        .db
        .add_patient(new.pseudonym.trim(), in_care_of.as_deref(), state.now())
        .await
        .map_err(taken)?;
    state
        .audit(
            &therapist.actor(),
            "add_patient",
            &patient.id,
            &patient.pseudonym,
        )
        .await?;
    let pairing = issue_code(&state, &therapist, &patient).await?;
    Ok((StatusCode::CREATED, Json(AddedPatient { patient, pairing })).into_response())
}

/// `POST /api/patients/{id}/pairing-code`: a new code for a new or replaced station.
pub(crate) async fn new_code(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    id: Result<Path<String>, PathRejection>,
    body: Result<Json<NoInput>, JsonRejection>,
) -> Result<Json<Pairing>, ApiError> {
    let Path(id) = id?;
    let Json(NoInput {}) = body?;
    let patient = state.visible_patient(&therapist, &id).await?;
    Ok(Json(issue_code(&state, &therapist, &patient).await?))
}

/// `POST /api/stations/{id}/revoke`: the station is refused from its next frame on.
pub(crate) async fn revoke_station(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    id: Result<Path<String>, PathRejection>,
    body: Result<Json<NoInput>, JsonRejection>,
) -> Result<Json<Station>, ApiError> {
    let Path(id) = id?;
    let Json(NoInput {}) = body?;
    check_path_id("station id", &id)?;
    let not_found = || super::not_found("station", format!("no station {id:?}"));
    let station = state.db.station(&id).await?.ok_or_else(not_found)?;
    // Someone else's patient's station is answered like one that does not exist.
    state
        .visible_patient(&therapist, &station.patient_id)
        .await
        .map_err(|_| not_found())?;
    state.db.revoke_station(&id, state.now()).await?;
    state
        .audit(
            &therapist.actor(),
            "revoke_station",
            &id,
            &station.patient_id,
        )
        .await?;
    Ok(Json(state.db.station(&id).await?.ok_or_else(not_found)?))
}

/// Body of `POST /api/therapists`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct NewTherapist {
    email: String,
    /// Make them an admin (sees every patient and the audit log).
    #[serde(default)]
    admin: bool,
}

/// Answer of `POST /api/therapists` (201): the account and its one-time password, shown once.
#[derive(Serialize)]
pub(crate) struct AddedTherapist {
    therapist: Therapist,
    one_time_password: String,
}

/// `POST /api/therapists` (admins): a new account with a one-time password to change at the
/// first login, as `hub therapist add`.
pub(crate) async fn add_therapist(
    State(state): State<AppState>,
    Authed(admin): Authed,
    body: Result<Json<NewTherapist>, JsonRejection>,
) -> Result<Response, ApiError> {
    admins_only(&admin, "adding a therapist")?;
    let Json(new) = body?;
    let password = hub_store::db::one_time_password()?;
    let role = if new.admin {
        Role::Admin
    } else {
        Role::Therapist
    };
    let mut added = state
        .db
        .add_therapist(&new.email, &password, role, state.now())
        .await
        .map_err(taken)?;
    state.db.require_password_change(&added.id).await?;
    added.must_change_password = true;
    state
        .audit(
            &admin.actor(),
            "add_therapist",
            &added.actor(),
            role.as_str(),
        )
        .await?;
    let answer = AddedTherapist {
        therapist: added,
        one_time_password: password,
    };
    Ok((StatusCode::CREATED, Json(answer)).into_response())
}

/// `GET /api/therapists` (admins): every account, by e-mail.
pub(crate) async fn therapists(
    State(state): State<AppState>,
    Authed(admin): Authed,
) -> Result<Json<Vec<Therapist>>, ApiError> {
    admins_only(&admin, "the list of therapists")?;
    let list = state.db.therapists().await?;
    state
        .audit(&admin.actor(), "list_therapists", "therapists", "")
        .await?;
    Ok(Json(list))
}
