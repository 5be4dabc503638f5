//! The console API as the hub's tests call it: one request through the router, a login, and
//! the audit log's entries.

use axum::Router;
use axum::body::Body;
use axum::http::{Method, Request, StatusCode, header};
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
    let (live, _) = tokio::sync::broadcast::channel(4);
    hub::web::router(
        hub::web::AppState::new(db.clone(), live).with_clock(std::sync::Arc::new(|| super::T0)),
    )
}

/// One request (a JSON body when given, the cookie when given): the status, the JSON answer
/// (`null` when none) and the session cookie it sets, if any.
pub async fn call(
    app: &Router,
    method: Method,
    uri: &str,
    cookie: Option<&str>,
    body: Option<Value>,
) -> (StatusCode, Value, Option<String>) {
    let mut builder = Request::builder().method(method).uri(uri);
    if let Some(c) = cookie {
        builder = builder.header(header::COOKIE, c);
    }
    let request = match body {
        Some(b) => builder
            .header(header::CONTENT_TYPE, "application/json")
            .body(Body::from(b.to_string())),
        None => builder.body(Body::empty()),
    }
    .unwrap();
    let response = app.clone().oneshot(request).await.unwrap();
    let status = response.status();
    let cookie = response
        .headers()
        .get(header::SET_COOKIE)
        .map(|v| v.to_str().unwrap().split(';').next().unwrap().to_owned());
    let bytes = response.into_body().collect().await.unwrap().to_bytes();
    let value = serde_json::from_slice(&bytes).unwrap_or(Value::Null);
    (status, value, cookie)
}

/// Logs in with [`PASSWORD`] and returns the `Cookie` header value.
pub async fn login(app: &Router, email: &str) -> String {
    let body = json!({"email": email, "password": PASSWORD});
    let (status, value, cookie) = call(app, Method::POST, "/api/login", None, Some(body)).await;
    assert_eq!(status, StatusCode::OK, "{value}");
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
