//! Login, logout, the current therapist, password changes, the audit log view, and the audit
//! of every refusal.
//!
//! Login throttling (growing delays per address, per account and per device cookie; see
//! `hub_store::db::logins` for the design and its justification against OWASP's Authentication
//! Cheat Sheet) and the bounded hashing pool live in the database layer; this module adds the
//! HTTP side: the client's address, the device cookie, `429` with `Retry-After`.

use hub_store::refusal::{Code, Why};
use std::net::{IpAddr, SocketAddr};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use axum::Json;
use axum::extract::rejection::JsonRejection;
use axum::extract::{ConnectInfo, FromRequestParts, Query, Request, State};
use axum::http::request::Parts;
use axum::http::{Extensions, HeaderMap, HeaderValue, StatusCode, header};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};
use serde::{Deserialize, Serialize};

use super::Says as _;
use super::{ApiError, AppState};
use hub_store::HubError;
use hub_store::db::{AuditCursor, AuditEntry, AuditFilter, DEVICE_TTL_MS, LoginAttempt, Therapist};

/// Name of the login cookie.
pub const SESSION_COOKIE: &str = "telerehab_session";

/// Name of the device cookie: set at a successful login, sent only to `/api/login`; a
/// browser holding one is throttled on its own, not by its account's failures elsewhere.
pub const DEVICE_COOKIE: &str = "telerehab_device";

/// How long a throttled or refused-as-busy login waits before its 429 is sent, ms: a client
/// that retries at once cannot turn refusals into a request flood.
const THROTTLED_ANSWER_DELAY_MS: u64 = 500;

/// Endpoints a therapist with a one-time password may use.
const ONE_TIME_PASSWORD_PATHS: &[&str] = &[
    "/api/me",
    "/api/me/password",
    "/api/me/language",
    "/api/logout",
];

/// The logged-in therapist of a request (401 without a valid session cookie; 403 while the
/// password is a one-time one, except on [`ONE_TIME_PASSWORD_PATHS`]).
pub(crate) struct Authed(pub Therapist);

/// Who made a request, filled in by [`Authed`] for [`audit_refusals`].
#[derive(Clone, Default)]
struct ActorSlot(Arc<Mutex<Option<String>>>);

/// A cookie's value in the request's headers, if any (64 hex digits only).
fn cookie_of(headers: &HeaderMap, name: &str) -> Option<String> {
    headers
        .get_all(header::COOKIE)
        .iter()
        .filter_map(|v| v.to_str().ok())
        .flat_map(|v| v.split(';'))
        .filter_map(|kv| kv.trim().split_once('='))
        .find(|(k, _)| *k == name)
        .map(|(_, v)| v.to_owned())
        .filter(|v| v.len() == 64 && v.bytes().all(|b| b.is_ascii_hexdigit()))
}

/// The session token in the request's cookies, if any.
pub(crate) fn token_of(headers: &HeaderMap) -> Option<String> {
    cookie_of(headers, SESSION_COOKIE)
}

/// The client's address, when the server put it in the request (`ConnectInfo`).
pub(crate) fn client_ip(extensions: &Extensions) -> Option<IpAddr> {
    extensions
        .get::<ConnectInfo<SocketAddr>>()
        .map(|ConnectInfo(addr)| addr.ip())
}

/// A request's source as the audit log names it and its refusal limiter counts it: the
/// address, an IPv6 one as its /64 (one host holds a whole /64, so changing address within it
/// must not buy a fresh allowance of audit writes).
fn source_of(extensions: &Extensions) -> String {
    client_ip(extensions).map_or_else(
        || "unknown address".to_owned(),
        |ip| {
            let key = hub_store::db::address_key(ip);
            key.strip_prefix("addr:").unwrap_or(&key).to_owned()
        },
    )
}

impl FromRequestParts<AppState> for Authed {
    type Rejection = ApiError;

    async fn from_request_parts(parts: &mut Parts, state: &AppState) -> Result<Self, ApiError> {
        let unauthorized = || {
            ApiError::Unauthorized(
                Why::new(Code::LogInFirst).says("log in first (POST /api/login)"),
            )
        };
        let token = token_of(&parts.headers).ok_or_else(unauthorized)?;
        let therapist = state
            .db
            .web_session(&token, state.now())
            .await?
            .ok_or_else(unauthorized)?;
        if let Some(slot) = parts.extensions.get::<ActorSlot>()
            && let Ok(mut actor) = slot.0.lock()
        {
            *actor = Some(therapist.actor());
        }
        if therapist.must_change_password && !ONE_TIME_PASSWORD_PATHS.contains(&parts.uri.path()) {
            return Err(ApiError::Forbidden(Why::new(Code::OneTimePassword).says(
                "your password is a one-time password: change it first (POST /api/me/password)",
            )));
        }
        Ok(Self(therapist))
    }
}

/// Middleware: every refusal of an API request — 401, 403, 404 and 429 — is audited
/// (rate-limited per client address, per therapist and in all: `Db::audit_account_refusal`);
/// the login endpoint audits its own refusals with the e-mail tried.
pub(crate) async fn audit_refusals(
    State(state): State<AppState>,
    mut request: Request,
    next: Next,
) -> Response {
    let path = request.uri().path().to_owned();
    let method = request.method().clone();
    let source = source_of(request.extensions());
    let slot = ActorSlot::default();
    request.extensions_mut().insert(slot.clone());
    let response = next.run(request).await;
    let status = response.status();
    let refused = matches!(
        status,
        StatusCode::UNAUTHORIZED
            | StatusCode::FORBIDDEN
            | StatusCode::NOT_FOUND
            | StatusCode::TOO_MANY_REQUESTS
    );
    if refused && path.starts_with("/api/") && path != "/api/login" {
        let actor = slot
            .0
            .lock()
            .ok()
            .and_then(|a| a.clone())
            .unwrap_or_else(|| "web".to_owned());
        let action = format!("refused_{}", status.as_u16());
        let target: String = path.chars().take(200).collect();
        let detail = format!("{method} {target}");
        let account = (actor != "web").then_some(actor.as_str());
        if let Err(e) = state
            .db
            .audit_account_refusal(
                &actor,
                &action,
                &target,
                &detail,
                &source,
                account,
                state.now(),
            )
            .await
        {
            tracing::error!("cannot audit a refusal: {e}");
        }
    }
    response
}

/// Body of `POST /api/login`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct Login {
    email: String,
    password: String,
}

fn cookie(name: &str, token: &str, path: &str, max_age_s: i64) -> Result<HeaderValue, ApiError> {
    HeaderValue::from_str(&format!(
        "{name}={token}; Path={path}; Max-Age={max_age_s}; HttpOnly; Secure; SameSite=Strict"
    ))
    .map_err(|_| ApiError::Internal)
}

fn session_cookie(token: &str, max_age_s: i64) -> Result<HeaderValue, ApiError> {
    cookie(SESSION_COOKIE, token, "/", max_age_s)
}

/// Audits a refused login or password check (rate-limited) and turns it into the answer; a
/// throttled one is answered after [`THROTTLED_ANSWER_DELAY_MS`].
async fn refused_login(
    state: &AppState,
    extensions: &Extensions,
    actor: &str,
    email: &str,
    error: HubError,
) -> ApiError {
    let action = match &error {
        HubError::LoginRefused => "login_failed",
        HubError::Throttled { .. } => "login_throttled",
        _ => return error.into(),
    };
    let email: String = email.chars().take(254).collect();
    let detail = match &error {
        HubError::Throttled { reason, .. } => reason.clone(),
        _ => String::new(),
    };
    // The account the refusal concerns, for the per-account limit on audit entries: the
    // e-mail tried (as the login compares it) or the therapist whose password check failed.
    let account = email.trim().to_lowercase();
    if let Err(e) = state
        .db
        .audit_account_refusal(
            actor,
            action,
            &email,
            &detail,
            &source_of(extensions),
            Some(&account),
            state.now(),
        )
        .await
    {
        tracing::error!("cannot audit a refused login: {e}");
    }
    if matches!(error, HubError::Throttled { .. }) {
        tokio::time::sleep(Duration::from_millis(THROTTLED_ANSWER_DELAY_MS)).await;
    }
    error.into()
}

pub(crate) async fn login(
    State(state): State<AppState>,
    headers: HeaderMap,
    extensions: Extensions,
    body: Result<Json<Login>, JsonRejection>,
) -> Result<Response, ApiError> {
    let Json(login) = body?;
    let now = state.now();
    let device = cookie_of(&headers, DEVICE_COOKIE);
    let attempt = LoginAttempt {
        email: &login.email,
        password: &login.password,
        address: client_ip(&extensions),
        device: device.as_deref(),
    };
    let ok = match state.db.login(attempt, now).await {
        Ok(ok) => ok,
        Err(e) => return Err(refused_login(&state, &extensions, "web", &login.email, e).await),
    };
    let therapist = ok.therapist;
    let token = state
        .db
        .create_web_session(&therapist.id, now, state.login_ttl_ms)
        .await?;
    state
        .audit(&therapist.actor(), "login", &therapist.id, "")
        .await?;
    let mut response = Json(&therapist).into_response();
    let set = response.headers_mut();
    set.append(
        header::SET_COOKIE,
        session_cookie(&token, state.login_ttl_ms / 1000)?,
    );
    if !ok.known_device {
        let device = state.db.create_device(&therapist.id, now).await?;
        set.append(
            header::SET_COOKIE,
            cookie(DEVICE_COOKIE, &device, "/api/login", DEVICE_TTL_MS / 1000)?,
        );
    }
    Ok(response)
}

/// True for a request a cross-site or `no-cors` page cannot send: `Content-Type:
/// application/json` is not one of the CORS-safelisted types, so a `no-cors` fetch or a form
/// cannot set it.
fn is_json_request(headers: &HeaderMap) -> bool {
    headers
        .get(header::CONTENT_TYPE)
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.split(';').next())
        .is_some_and(|v| v.trim().eq_ignore_ascii_case("application/json"))
}

pub(crate) async fn logout(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    headers: HeaderMap,
) -> Result<Response, ApiError> {
    if !is_json_request(&headers) {
        return Err(ApiError::Rejected(
            StatusCode::UNSUPPORTED_MEDIA_TYPE,
            Why::new(Code::BodyNotJson).says(
                "logout needs `Content-Type: application/json` (so that no other page can log \
                 you out)",
            ),
        ));
    }
    if let Some(token) = token_of(&headers) {
        state.db.delete_web_session(&token, state.now()).await?;
    }
    state
        .audit(&therapist.actor(), "logout", &therapist.id, "")
        .await?;
    let mut response = StatusCode::NO_CONTENT.into_response();
    response
        .headers_mut()
        .insert(header::SET_COOKIE, session_cookie("", 0)?);
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

/// Changes the logged-in therapist's password. Every login session of theirs ends, this one
/// too: the answer sets a new session cookie (and live streams opened before end).
pub(crate) async fn change_password(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    headers: HeaderMap,
    extensions: Extensions,
    body: Result<Json<PasswordChange>, JsonRejection>,
) -> Result<Response, ApiError> {
    let Json(change) = body?;
    let device = cookie_of(&headers, DEVICE_COOKIE);
    let attempt = LoginAttempt {
        email: &therapist.email,
        password: &change.current,
        address: client_ip(&extensions),
        device: device.as_deref(),
    };
    let outcome = state
        .db
        .change_password_from(attempt, &change.new, state.now(), state.login_ttl_ms)
        .await;
    let token = match outcome {
        Ok(token) => token,
        Err(e @ (HubError::LoginRefused | HubError::Throttled { .. })) => {
            let actor = therapist.actor();
            return Err(refused_login(&state, &extensions, &actor, &therapist.id, e).await);
        }
        Err(e) => {
            state
                .audit(
                    &therapist.actor(),
                    "password_change_refused",
                    &therapist.id,
                    &e.to_string(),
                )
                .await?;
            return Err(e.into());
        }
    };
    state
        .audit(&therapist.actor(), "password_changed", &therapist.id, "")
        .await?;
    let mut response = StatusCode::NO_CONTENT.into_response();
    response.headers_mut().insert(
        header::SET_COOKIE,
        session_cookie(&token, state.login_ttl_ms / 1000)?,
    );
    Ok(response)
}

/// Query of `GET /api/audit`.
#[derive(Deserialize)]
pub(crate) struct AuditQuery {
    /// Most entries returned (default 100, at most 10 000).
    limit: Option<i64>,
    /// Only entries of this time (ms) or older — with `before_id`, the `next` cursor of the
    /// previous page.
    before_ms: Option<i64>,
    /// With `before_ms`: among entries of that millisecond, only those with a smaller id.
    before_id: Option<String>,
    /// Only entries by this actor (`therapist:<id>`, `station:<id>`, `cli`, `web`).
    actor: Option<String>,
    /// Only entries of this action (`put_regimen`, …).
    action: Option<String>,
    /// Only entries about this target (a patient's id, a session's id, …).
    target: Option<String>,
}

/// Answer of `GET /api/audit`.
#[derive(Serialize)]
pub(crate) struct AuditAnswer {
    entries: Vec<AuditEntry>,
    /// Query parameters of the next (older) page; `null` on the last one.
    next: Option<AuditCursor>,
}

pub(crate) async fn audit_log(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    Query(query): Query<AuditQuery>,
) -> Result<Json<AuditAnswer>, ApiError> {
    if !therapist.is_admin() {
        return Err(ApiError::Forbidden(
            Why::new(Code::AdminOnly).says("the audit log is for administrators"),
        ));
    }
    let now = state.now();
    // Counts of suppressed refusals whose minute is over are written before the log is read.
    state.db.flush_refusal_audits(now).await?;
    let before = query.before_ms.map(|before_ms| AuditCursor {
        before_ms,
        // Ids start with the zero-padded time, so "~" sorts after every id of that ms.
        before_id: query.before_id.clone().unwrap_or_else(|| "~".to_owned()),
    });
    state
        .audit(&therapist.actor(), "read_audit", "audit_log", "")
        .await?;
    let page = state
        .db
        .audit_page_where(
            before.as_ref(),
            query.limit.unwrap_or(100),
            &AuditFilter {
                actor: query.actor.filter(|v| !v.is_empty()),
                action: query.action.filter(|v| !v.is_empty()),
                target: query.target.filter(|v| !v.is_empty()),
            },
        )
        .await?;
    Ok(Json(AuditAnswer {
        entries: page.entries,
        next: page.next,
    }))
}
