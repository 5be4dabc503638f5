//! Needs attention today (issue 41): the caseload with each patient's alerts
//! (`GET /api/patients`, sorted and filtered), one patient's alerts, acknowledging or snoozing
//! one, and the clinic's thresholds (`/api/clinic/settings`). The alerts themselves are
//! [`hub_care::attention`]'s.

use hub_store::refusal::{Code, Why};
use std::collections::BTreeMap;

use axum::Json;
use axum::extract::rejection::{JsonRejection, PathRejection, QueryRejection};
use axum::extract::{Path, Query, State};
use axum::http::StatusCode;
use serde::{Deserialize, Serialize};

use super::Says as _;
use super::auth::Authed;
use super::clinic::admins_only;
use super::{ApiError, AppState};
use hub_care::attention::{Alert, Attention, KIND_ORDER, Thresholds};
use hub_store::db::{NewAck, PatientOverview};
use hub_store::thresholds::{SETTINGS, check_setting};

/// Query of `GET /api/patients`.
#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(crate) struct CaseloadQuery {
    /// `need` (most pressing alert first), `pseudonym` (the default) or `last_session`
    /// (longest without a session first).
    #[serde(default)]
    sort: Option<String>,
    /// Only patients with an alert of this kind needing attention (`pain_high`, …).
    #[serde(default)]
    alert: Option<String>,
    /// `true`: only the therapist's own patients (an admin otherwise sees every patient).
    #[serde(default)]
    mine: Option<bool>,
}

/// A caseload row: the patient's overview and their alerts.
#[derive(Serialize)]
pub(crate) struct CaseloadRow {
    #[serde(flatten)]
    overview: PatientOverview,
    #[serde(flatten)]
    attention: Attention,
    /// When a therapist last allowed the patient to train again after a pain stop
    /// (`POST /api/patients/{id}/pain-clearance`), ms since the Unix epoch.
    pain_cleared_at_ms: Option<i64>,
}

/// `GET /api/patients`: the caseload, each patient with their alerts.
pub(crate) async fn caseload(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    query: Result<Query<CaseloadQuery>, QueryRejection>,
) -> Result<Json<Vec<CaseloadRow>>, ApiError> {
    let Query(query) = query.map_err(|e| {
        ApiError::BadRequest(Why::field(Code::NotOneOf, "query").says(e.body_text()))
    })?;
    let sort = query.sort.as_deref().unwrap_or("pseudonym");
    if !matches!(sort, "need" | "pseudonym" | "last_session") {
        return Err(ApiError::BadRequest(
            Why::field(Code::NotOneOf, "sort").says(format!(
                "invalid sort {sort:?}: use need, pseudonym or last_session"
            )),
        ));
    }
    if let Some(kind) = query.alert.as_deref()
        && !KIND_ORDER.contains(&kind)
    {
        return Err(ApiError::BadRequest(
            Why::field(Code::NotOneOf, "alert").says(format!(
                "invalid alert {kind:?}: use one of {}",
                KIND_ORDER.join(", ")
            )),
        ));
    }
    let now = state.now();
    let thresholds = state.db.thresholds().await?;
    let mut rows = Vec::new();
    for overview in state.db.patients_for(&therapist, now).await? {
        if query.mine == Some(true)
            && overview.patient.therapist_id.as_deref() != Some(therapist.id.as_str())
        {
            continue;
        }
        let attention =
            hub_care::attention::attention_of(&state.db, &overview, &thresholds, now).await?;
        if let Some(kind) = query.alert.as_deref()
            && !attention.attention.iter().any(|a| a.kind == kind)
        {
            continue;
        }
        let pain_cleared_at_ms = state.db.pain_cleared_at(&overview.patient.id).await?;
        rows.push(CaseloadRow {
            overview,
            attention,
            pain_cleared_at_ms,
        });
    }
    match sort {
        "need" => rows.sort_by(|a, b| {
            (a.attention.need_key(), &a.overview.patient.pseudonym)
                .cmp(&(b.attention.need_key(), &b.overview.patient.pseudonym))
        }),
        "last_session" => rows.sort_by(|a, b| {
            (
                a.overview.last_session_started_ms,
                &a.overview.patient.pseudonym,
            )
                .cmp(&(
                    b.overview.last_session_started_ms,
                    &b.overview.patient.pseudonym,
                ))
        }),
        _ => {}
    }
    state
        .audit(
            &therapist.actor(),
            "list_patients",
            "patients",
            &format!("{} patients", rows.len()),
        )
        .await?;
    Ok(Json(rows))
}

/// The alerts of patient `id` now, if `therapist` may see them.
async fn attention_now(
    state: &AppState,
    therapist: &hub_store::db::Therapist,
    id: &str,
) -> Result<(Attention, String), ApiError> {
    let patient = state.visible_patient(therapist, id).await?;
    let now = state.now();
    let row = state
        .db
        .patient_overview(therapist, &patient.id, now)
        .await?
        .ok_or_else(|| super::not_found("patient", format!("no patient {id:?}")))?;
    let thresholds = state.db.thresholds().await?;
    Ok((
        hub_care::attention::attention_of(&state.db, &row, &thresholds, now).await?,
        patient.id,
    ))
}

/// `GET /api/patients/{id}/attention`: the patient's alerts, those kept quiet apart.
pub(crate) async fn one(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    id: Result<Path<String>, PathRejection>,
) -> Result<Json<Attention>, ApiError> {
    let Path(id) = id?;
    let (attention, pid) = attention_now(&state, &therapist, &id).await?;
    state
        .audit(&therapist.actor(), "read_attention", &pid, "")
        .await?;
    Ok(Json(attention))
}

/// Body of `POST /api/patients/{id}/alerts/ack`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct AckBody {
    /// The alert's `key`.
    key: String,
    /// The alert's `fingerprint` as the therapist saw it.
    fingerprint: String,
    /// Why it may stay quiet (1 to 2 000 characters).
    note: String,
    /// Snooze until this time, ms since the Unix epoch; absent: acknowledged (quiet until
    /// something new happens).
    #[serde(default)]
    snooze_until_ms: Option<i64>,
}

/// `POST /api/patients/{id}/alerts/ack`: acknowledges or snoozes one alert, audited; answers
/// the patient's alerts after it. 404 for an alert the patient does not have now, 409 when
/// its evidence changed since the therapist saw it.
pub(crate) async fn ack(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    id: Result<Path<String>, PathRejection>,
    body: Result<Json<AckBody>, JsonRejection>,
) -> Result<Json<Attention>, ApiError> {
    let Path(id) = id?;
    let Json(body) = body?;
    let (attention, pid) = attention_now(&state, &therapist, &id).await?;
    let current: Option<&Alert> = attention
        .attention
        .iter()
        .chain(&attention.quieted)
        .find(|a| a.key == body.key);
    let Some(current) = current else {
        return Err(ApiError::NotFound(Why::new(Code::AlertGone).says(format!(
            "the patient has no alert {:?} now (it may have cleared); reload the caseload",
            body.key
        ))));
    };
    if current.fingerprint != body.fingerprint {
        return Err(ApiError::Rejected(
            StatusCode::CONFLICT,
            Why::new(Code::AlertChanged).says(
                "something new happened since this alert was shown; look at it again \
                 (nothing was recorded)",
            ),
        ));
    }
    let ack = NewAck {
        patient_id: &pid,
        alert_key: &body.key,
        fingerprint: &body.fingerprint,
        until_ms: body.snooze_until_ms,
        note: &body.note,
        therapist_id: &therapist.id,
    };
    state.db.put_alert_ack(&ack, state.now()).await?;
    let (action, until) = match body.snooze_until_ms {
        Some(u) => (
            "snooze_alert",
            format!(" until {}", hub_store::db::iso_utc(u)),
        ),
        None => ("acknowledge_alert", String::new()),
    };
    state
        .audit(
            &therapist.actor(),
            action,
            &pid,
            &format!("{}{until}: {}", body.key, body.note),
        )
        .await?;
    Ok(Json(attention_now(&state, &therapist, &id).await?.0))
}

/// One threshold as `GET /api/clinic/settings` shows it.
#[derive(Serialize)]
pub(crate) struct SettingView {
    key: &'static str,
    value: i64,
    default: i64,
    min: i64,
    max: i64,
    /// When the clinic last changed it, ms since the Unix epoch (`null`: never, the default).
    updated_at_ms: Option<i64>,
    /// Who changed it, by e-mail.
    updated_by_email: Option<String>,
}

/// `GET /api/clinic/settings`: every threshold, its value, default and bounds.
pub(crate) async fn settings(
    State(state): State<AppState>,
    Authed(therapist): Authed,
) -> Result<Json<Vec<SettingView>>, ApiError> {
    let stored = state.db.clinic_settings().await?;
    let mut out = Vec::new();
    for def in SETTINGS {
        let s = stored.get(def.key);
        let by = match s {
            Some(s) => state.db.therapist(&s.updated_by).await?.map(|t| t.email),
            None => None,
        };
        out.push(SettingView {
            key: def.key,
            value: s.map_or(def.default, |s| s.value),
            default: def.default,
            min: def.min,
            max: def.max,
            updated_at_ms: s.map(|s| s.updated_at_ms),
            updated_by_email: by,
        });
    }
    state
        .audit(&therapist.actor(), "read_settings", "clinic_settings", "")
        .await?;
    Ok(Json(out))
}

/// `PUT /api/clinic/settings` (admins): `{"key": value, …}`; every value checked before any
/// is stored (400 naming the first problem, nothing changed), each change audited.
pub(crate) async fn put_settings(
    State(state): State<AppState>,
    Authed(admin): Authed,
    body: Result<Json<BTreeMap<String, i64>>, JsonRejection>,
) -> Result<Json<Thresholds>, ApiError> {
    admins_only(&admin, "changing the clinic's thresholds")?;
    let Json(body) = body?;
    for (key, value) in &body {
        check_setting(key, *value)?;
    }
    let before = state.db.thresholds().await?;
    let before = serde_json::to_value(before).unwrap_or_default();
    for (key, value) in &body {
        state
            .db
            .put_clinic_setting(key, *value, &admin.id, state.now())
            .await?;
        state
            .audit(
                &admin.actor(),
                "change_setting",
                "clinic_settings",
                &format!("{key}: {} → {value}", before[key.as_str()]),
            )
            .await?;
    }
    Ok(Json(state.db.thresholds().await?))
}
