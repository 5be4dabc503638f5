//! Login, logout, the current therapist, and the admin's audit log view.

use axum::Json;
use axum::extract::rejection::JsonRejection;
use axum::extract::{FromRequestParts, Query, State};
use axum::http::request::Parts;
use axum::http::{HeaderMap, HeaderValue, StatusCode, header};
use axum::response::{IntoResponse, Response};
use serde::Deserialize;

use super::{ApiError, AppState};
use crate::db::{AuditEntry, Therapist};
use crate::error::HubError;

/// Name of the login cookie.
pub const SESSION_COOKIE: &str = "telerehab_session";

/// The logged-in therapist of a request (401 without a valid session cookie).
pub(crate) struct Authed(pub Therapist);

/// The session token in the request's cookies, if any.
fn token_of(headers: &HeaderMap) -> Option<String> {
    headers
        .get_all(header::COOKIE)
        .iter()
        .filter_map(|v| v.to_str().ok())
        .flat_map(|v| v.split(';'))
        .filter_map(|kv| kv.trim().split_once('='))
        .find(|(k, _)| *k == SESSION_COOKIE)
        .map(|(_, v)| v.to_owned())
        .filter(|v| v.len() == 64 && v.bytes().all(|b| b.is_ascii_hexdigit()))
}

impl FromRequestParts<AppState> for Authed {
    type Rejection = ApiError;

    async fn from_request_parts(parts: &mut Parts, state: &AppState) -> Result<Self, ApiError> {
        let unauthorized = || ApiError::Unauthorized("log in first (POST /api/login)".to_owned());
        let token = token_of(&parts.headers).ok_or_else(unauthorized)?;
        match state.db.web_session(&token, state.now()).await? {
            Some(t) => Ok(Self(t)),
            None => Err(unauthorized()),
        }
    }
}

/// Body of `POST /api/login`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct Login {
    email: String,
    password: String,
}

fn cookie(token: &str, max_age_s: i64) -> Result<HeaderValue, ApiError> {
    HeaderValue::from_str(&format!(
        "{SESSION_COOKIE}={token}; Path=/; Max-Age={max_age_s}; HttpOnly; Secure; \
         SameSite=Strict"
    ))
    .map_err(|_| ApiError::Internal)
}

pub(crate) async fn login(
    State(state): State<AppState>,
    body: Result<Json<Login>, JsonRejection>,
) -> Result<Response, ApiError> {
    let Json(login) = body?;
    let now = state.now();
    match state
        .db
        .verify_login(&login.email, &login.password, now)
        .await
    {
        Ok(therapist) => {
            let token = state
                .db
                .create_web_session(&therapist.id, now, state.login_ttl_ms)
                .await?;
            state
                .audit(&therapist.actor(), "login", &therapist.id, "")
                .await?;
            let mut response = Json(therapist).into_response();
            response.headers_mut().insert(
                header::SET_COOKIE,
                cookie(&token, state.login_ttl_ms / 1000)?,
            );
            Ok(response)
        }
        Err(HubError::LoginRefused) => {
            let email: String = login.email.chars().take(254).collect();
            state.audit("web", "login_failed", &email, "").await?;
            Err(HubError::LoginRefused.into())
        }
        Err(e) => Err(e.into()),
    }
}

pub(crate) async fn logout(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    headers: HeaderMap,
) -> Result<Response, ApiError> {
    if let Some(token) = token_of(&headers) {
        state.db.delete_web_session(&token, state.now()).await?;
    }
    state
        .audit(&therapist.actor(), "logout", &therapist.id, "")
        .await?;
    let mut response = StatusCode::NO_CONTENT.into_response();
    response
        .headers_mut()
        .insert(header::SET_COOKIE, cookie("", 0)?);
    Ok(response)
}

pub(crate) async fn me(Authed(therapist): Authed) -> Json<Therapist> {
    Json(therapist)
}

/// Body of `POST /api/me/password`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct PasswordChange {
    current: String,
    new: String,
}

/// Changes the logged-in therapist's password; their other login sessions end.
pub(crate) async fn change_password(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    headers: HeaderMap,
    body: Result<Json<PasswordChange>, JsonRejection>,
) -> Result<Response, ApiError> {
    let Json(change) = body?;
    let token = token_of(&headers).unwrap_or_default();
    let outcome = state
        .db
        .change_password(
            &therapist.email,
            &change.current,
            &change.new,
            &token,
            state.now(),
        )
        .await;
    let action = if outcome.is_ok() {
        "password_changed"
    } else {
        "password_change_refused"
    };
    state
        .audit(&therapist.actor(), action, &therapist.id, "")
        .await?;
    outcome?;
    Ok(StatusCode::NO_CONTENT.into_response())
}

/// Query of `GET /api/audit`.
#[derive(Deserialize)]
pub(crate) struct AuditQuery {
    /// Most entries returned (default 100, at most 10 000).
    limit: Option<i64>,
}

pub(crate) async fn audit_log(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    Query(query): Query<AuditQuery>,
) -> Result<Json<Vec<AuditEntry>>, ApiError> {
    if !therapist.is_admin() {
        return Err(ApiError::Forbidden(
            "the audit log is for administrators".to_owned(),
        ));
    }
    let limit = query.limit.unwrap_or(100);
    state
        .audit(&therapist.actor(), "read_audit", "audit_log", "")
        .await?;
    Ok(Json(state.db.audit_log(limit).await?))
}
