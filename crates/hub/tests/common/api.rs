//! The console API as the hub's tests call it: one request through the router, a login, and
//! the audit log's entries.

use axum::Router;
use axum::body::Body;
use axum::http::{HeaderMap, Method, Request, StatusCode, header};
use http_body_util::BodyExt;
use hub::Db;
use serde_json::{Value, json};
use tower::ServiceExt;

/// Every test therapist's password.
pub const PASSWORD: &str = "correct horse battery";

/// A clinician account (`ada@clinic.example`, [`PASSWORD`]) added at [`super::T0`].
pub async fn clinician(db: &Db, email: &str, role: hub::Role) -> hub::Therapist {
    db.add_therapist(email, PASSWORD, role, super::T0)
        .await
        .unwrap()
}

/// The console's router over `db` with its clock stopped at [`super::T0`].
pub fn router_at_t0(db: &Db) -> Router {
    router_with_clock(db, super::clock_at(super::T0).0)
}

/// The console's router over `db` reading the time from `clock`.
pub fn router_with_clock(db: &Db, clock: clock::Clock) -> Router {
    let (live, _) = tokio::sync::broadcast::channel(8);
    hub::web::router(hub::web::AppState::new(db.clone(), live).with_clock(clock))
}

/// A request (a JSON body when given, the cookie when given).
pub fn request(
    method: Method,
    uri: &str,
    cookie: Option<&str>,
    body: Option<Value>,
) -> Request<Body> {
    let mut builder = Request::builder().method(method).uri(uri);
    if let Some(c) = cookie {
        builder = builder.header(header::COOKIE, c);
    }
    match body {
        Some(b) => builder
            .header(header::CONTENT_TYPE, "application/json")
            .body(Body::from(b.to_string())),
        None => builder.body(Body::empty()),
    }
    .unwrap()
}

/// `request` through the router: the status, the headers and the answer (JSON; its text as a
/// string when it is not JSON; `null` when empty).
pub async fn send(app: &Router, request: Request<Body>) -> (StatusCode, HeaderMap, Value) {
    let response = app.clone().oneshot(request).await.unwrap();
    let status = response.status();
    let headers = response.headers().clone();
    let bytes = response.into_body().collect().await.unwrap().to_bytes();
    let value = if bytes.is_empty() {
        Value::Null
    } else {
        serde_json::from_slice(&bytes)
            .unwrap_or_else(|_| Value::String(String::from_utf8_lossy(&bytes).into_owned()))
    };
    (status, headers, value)
}

/// One request ([`request`]): the status, the headers and the answer ([`send`]).
pub async fn exchange(
    app: &Router,
    method: Method,
    uri: &str,
    cookie: Option<&str>,
    body: Option<Value>,
) -> (StatusCode, HeaderMap, Value) {
    send(app, request(method, uri, cookie, body)).await
}

/// One request ([`request`]): the status, the answer ([`send`]) and the session cookie it
/// sets, if any.
pub async fn call(
    app: &Router,
    method: Method,
    uri: &str,
    cookie: Option<&str>,
    body: Option<Value>,
) -> (StatusCode, Value, Option<String>) {
    let (status, headers, value) = exchange(app, method, uri, cookie, body).await;
    let cookie = headers
        .get(header::SET_COOKIE)
        .map(|v| v.to_str().unwrap().split(';').next().unwrap().to_owned());
    (status, value, cookie)
}

/// Logs in with [`PASSWORD`] and returns the `Cookie` header value.
pub async fn login(app: &Router, email: &str) -> String {
    login_with(app, email, PASSWORD).await
}

/// Logs in with `password` and returns the `Cookie` header value.
pub async fn login_with(app: &Router, email: &str, password: &str) -> String {
    let body = json!({"email": email, "password": password});
    let (status, value, cookie) = call(app, Method::POST, "/api/login", None, Some(body)).await;
    assert_eq!(status, StatusCode::OK, "login of {email}: {value}");
    cookie.unwrap()
}

/// The audit log as (actor, action, target).
pub async fn actions(db: &Db) -> Vec<(String, String, String)> {
    db.audit_log(1000)
        .await
        .unwrap()
        .into_iter()
        .map(|e| (e.actor, e.action, e.target))
        .collect()
}
