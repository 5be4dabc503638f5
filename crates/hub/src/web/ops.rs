//! What a clinic network's operator and its load balancer ask the hub (docs/OPERATING.md):
//!
//! - `GET /healthz`: liveness — the process answers (200, no check behind it).
//! - `GET /readyz`: readiness — the database answers a query within [`READY_DB_TIMEOUT`], the
//!   recordings directory takes a new file, an S3 recording store answers within
//!   [`READY_STORE_TIMEOUT`], and the hub is not draining before a shutdown;
//!   else 503 with a JSON body naming what is not ready. Results are reused for
//!   [`READY_REUSE`], so a flood of probes costs one check a second.
//! - `GET /metrics`: the Prometheus text format ([`hub_care::telemetry`]), only on the operator's
//!   own plain-HTTP listener ([`serve_operator`]), never on the console's public port.
//!
//! None needs a login, and none says anything about a patient.

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use axum::Router;
use axum::extract::{Request, State};
use axum::http::{HeaderValue, StatusCode, header};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use serde::Serialize;

use super::AppState;
use hub_care::recordings::RecordingStore;
use hub_care::telemetry::{ReplayOutcome, Telemetry};
use hub_store::HubError;
use hub_store::db::Db;

/// Longest the readiness check waits for the database's answer.
pub const READY_DB_TIMEOUT: Duration = Duration::from_secs(1);

/// Longest the readiness check waits for an S3 recording store's answer (its own retries
/// included: a store failing for longer than this is not ready).
pub const READY_STORE_TIMEOUT: Duration = Duration::from_secs(2);

/// How long a readiness result is reused.
pub const READY_REUSE: Duration = Duration::from_secs(1);

/// What `/readyz` checks, shared by the console's port and the operator's.
#[derive(Debug)]
pub struct Readiness {
    db: Db,
    /// `DATA/recordings`, when the hub stores recordings or partial uploads there.
    recordings: Option<PathBuf>,
    /// The recording store, checked for an answer when it is S3.
    store: Option<RecordingStore>,
    draining: AtomicBool,
    last: tokio::sync::Mutex<Option<(Instant, Vec<String>)>>,
}

impl Readiness {
    /// Readiness of a hub over `db`, checking that `recordings` (if any) takes new files and
    /// that `store` (if any) answers.
    pub fn new(db: Db, recordings: Option<PathBuf>, store: Option<RecordingStore>) -> Self {
        Self {
            db,
            recordings,
            store,
            draining: AtomicBool::new(false),
            last: tokio::sync::Mutex::new(None),
        }
    }

    /// From now on `/readyz` answers 503 (draining): a load balancer sends no new clients
    /// while open requests and connections finish.
    pub fn start_draining(&self) {
        self.draining.store(true, Ordering::Relaxed);
    }

    /// What is not ready now (empty: ready), in the operator's words.
    pub async fn not_ready(&self) -> Vec<String> {
        let mut last = self.last.lock().await;
        let mut problems = match &*last {
            Some((at, problems)) if at.elapsed() < READY_REUSE => problems.clone(),
            _ => {
                let problems = self.check().await;
                *last = Some((Instant::now(), problems.clone()));
                problems
            }
        };
        drop(last);
        if self.draining.load(Ordering::Relaxed) {
            problems.push("draining: the hub is shutting down".to_owned());
        }
        problems
    }

    async fn check(&self) -> Vec<String> {
        let mut problems = Vec::new();
        let query = sqlx::query_scalar::<_, i32>("SELECT 1").fetch_one(self.db.pool());
        match tokio::time::timeout(READY_DB_TIMEOUT, query).await {
            Ok(Ok(_)) => {}
            Ok(Err(e)) => problems.push(format!("database: {e}")),
            Err(_) => problems.push(format!(
                "database: no answer within {} ms",
                READY_DB_TIMEOUT.as_millis()
            )),
        }
        if let Some(dir) = self.recordings.clone() {
            let writable = tokio::task::spawn_blocking(move || writable(&dir)).await;
            match writable {
                Ok(Ok(())) => {}
                Ok(Err(e)) => problems.push(format!("recordings: {e}")),
                Err(e) => problems.push(format!("recordings: the check failed: {e}")),
            }
        }
        if let Some(store) = &self.store
            && let Err(e) = store.answers(READY_STORE_TIMEOUT).await
        {
            problems.push(format!("recording store: {e}"));
        }
        problems
    }
}

/// Whether `dir` (made if missing) takes a new file: one is made and removed.
fn writable(dir: &std::path::Path) -> Result<(), String> {
    std::fs::create_dir_all(dir)
        .and_then(|()| tempfile::Builder::new().prefix(".ready-").tempfile_in(dir))
        .map(drop)
        .map_err(|e| format!("{} takes no new file: {e}", dir.display()))
}

#[derive(Serialize)]
struct Live {
    status: &'static str,
}

/// `GET /healthz`.
pub(crate) async fn healthz() -> Response {
    axum::Json(Live { status: "alive" }).into_response()
}

#[derive(Serialize)]
struct Ready {
    status: &'static str,
    /// What is not ready (empty when ready).
    not_ready: Vec<String>,
}

/// `GET /readyz`.
pub(crate) async fn readyz(State(state): State<AppState>) -> Response {
    let not_ready = state.readiness.not_ready().await;
    let (status, word) = if not_ready.is_empty() {
        (StatusCode::OK, "ready")
    } else {
        (StatusCode::SERVICE_UNAVAILABLE, "not ready")
    };
    let body = Ready {
        status: word,
        not_ready,
    };
    (status, axum::Json(body)).into_response()
}

/// `GET /metrics`.
async fn metrics(State(state): State<AppState>) -> Response {
    let text = state.telemetry.encode(Some(&state.db));
    let mut response = text.into_response();
    response.headers_mut().insert(
        header::CONTENT_TYPE,
        HeaderValue::from_static(hub_care::telemetry::CONTENT_TYPE),
    );
    response
}

/// The operator's routes: `/metrics`, `/healthz`, `/readyz`.
pub fn operator_router(state: AppState) -> Router {
    Router::new()
        .route("/metrics", get(metrics))
        .route("/healthz", get(healthz))
        .route("/readyz", get(readyz))
        .layer(axum::middleware::from_fn_with_state(
            state.clone(),
            count_requests,
        ))
        .with_state(state)
}

/// Serves [`operator_router`] over plain HTTP on `listener` until `shutdown` completes. The
/// listener must be bound to a specific address (loopback, or the operator's management
/// network), never to every interface: the checks are `hub serve`'s ([`check_operator_address`]).
pub async fn serve_operator(
    listener: tokio::net::TcpListener,
    state: AppState,
    shutdown: impl Future<Output = ()> + Send + 'static,
) -> Result<(), HubError> {
    let local = listener
        .local_addr()
        .map_err(|e| HubError::io("reading the metrics address", e))?;
    check_operator_address(local)?;
    tracing::info!(address = %local, "metrics and health checks listening (plain HTTP)");
    axum::serve(listener, operator_router(state))
        .with_graceful_shutdown(shutdown)
        .await
        .map_err(|e| HubError::io(format!("serving metrics on {local}"), e))
}

/// Refuses to serve `/metrics` on every interface (`0.0.0.0`, `[::]`): it is plain HTTP without
/// a login, for loopback or a management network's own address only.
pub fn check_operator_address(addr: std::net::SocketAddr) -> Result<(), HubError> {
    if addr.ip().is_unspecified() {
        return Err(HubError::Config(format!(
            "metrics_listen {addr} would serve /metrics on every interface; give loopback \
             (127.0.0.1:9464) or the management network's own address"
        )));
    }
    Ok(())
}

/// The route group of a request path, for `http_requests_total{route}`: a closed set, so no
/// id in a path ever becomes a label.
pub(crate) fn route_group(path: &str) -> &'static str {
    let api = path.strip_prefix("/api/");
    match path {
        "/" => return "console",
        "/metrics" => return "metrics",
        "/healthz" | "/readyz" | "/api/health" => return "health",
        _ => {}
    }
    if path.starts_with("/console/") {
        return "console";
    }
    let Some(api) = api else {
        return "unknown";
    };
    let first = api.split('/').next().unwrap_or_default();
    if api.ends_with("/replay") {
        "replay"
    } else if api.ends_with("/live") {
        "live"
    } else if api.ends_with(".csv") || api.ends_with("/fhir") {
        "export"
    } else {
        match first {
            "login" | "logout" | "me" => "auth",
            "patients" => "patients",
            "sessions" => "sessions",
            "audit" => "audit",
            "clinic" | "therapists" | "stations" => "clinic",
            "regimen" | "measures" => "words",
            _ => "unknown",
        }
    }
}

/// Counts each answered request by route group and status class, and each replay by outcome.
pub(crate) async fn count_requests(
    State(state): State<AppState>,
    request: Request,
    next: Next,
) -> Response {
    let group = route_group(request.uri().path());
    let started = Instant::now();
    let response = next.run(request).await;
    let status = response.status();
    let telemetry: &Arc<Telemetry> = &state.telemetry;
    telemetry.http_request(group, status.as_u16(), started.elapsed().as_secs_f64());
    if group == "replay" {
        telemetry.replay(match status.as_u16() {
            200..=299 => ReplayOutcome::Started,
            500 => ReplayOutcome::Failed,
            _ => ReplayOutcome::Refused,
        });
    }
    response
}

#[cfg(test)]
mod tests {
    use super::route_group;

    #[test]
    fn paths_fall_into_a_closed_set_of_route_groups_without_their_ids() {
        for (path, group) in [
            ("/", "console"),
            ("/console/app.js", "console"),
            ("/readyz", "health"),
            ("/api/health", "health"),
            ("/api/login", "auth"),
            ("/api/me/password", "auth"),
            ("/api/patients/p-1/live", "live"),
            ("/api/sessions/s-1/replay", "replay"),
            ("/api/patients/p-1/measures.csv", "export"),
            ("/api/patients/p-1/fhir", "export"),
            ("/api/patients/p-1", "patients"),
            ("/api/sessions/s-1/notes", "sessions"),
            ("/api/stations/st-1/revoke", "clinic"),
            ("/api/regimen/schema", "words"),
            ("/api/nothing-here", "unknown"),
            ("/wp-login.php", "unknown"),
        ] {
            assert_eq!(route_group(path), group, "{path}");
        }
    }
}
