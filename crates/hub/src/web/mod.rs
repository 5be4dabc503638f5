//! The therapist console's HTTPS JSON API (axum), documented in `crates/hub/API.md`.
//!
//! - [`router`] builds the routes over an [`AppState`]; [`serve`] runs them over TLS (or
//!   plain HTTP on a loopback address only, for development and tests).
//! - Authentication: `POST /api/login` sets an HttpOnly, Secure, SameSite=Strict cookie
//!   holding a random 256-bit token; the database keeps only its SHA-256.
//! - Authorisation: an admin sees every patient, a therapist their own; anyone else's patient
//!   is answered 404, exactly like a patient that does not exist.
//! - Every read of patient data and every change is written to the audit log.

mod assessment_sheet;
mod attention;
mod auth;
mod clinic;
mod console;
mod fhir;
mod language;
mod live;
mod measure_words;
mod messages;
mod notes;
mod ops;
mod pain;
mod patients;
mod regimen;
mod regimen_words;
mod scales;
mod serve;
mod sessions;
mod spreadsheet;
mod wheel_bounds;

use std::sync::Arc;

use axum::Json;
use axum::Router;
use axum::extract::DefaultBodyLimit;
use axum::http::{HeaderValue, StatusCode, header};
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use serde::Serialize;
use tokio::sync::broadcast;

use hub_store::HubError;
use hub_store::db::{Db, Patient, RegimenVersion, Therapist};
use hub_store::refusal::{Code, Why};

pub use auth::DEVICE_COOKIE;
pub use auth::SESSION_COOKIE;
/// A running session's events and the hub's wall clock live in `hub_care::live`, below the
/// web (the ingest and the fan-out send them); the API streams them and names them here.
pub use hub_care::live::{LiveEvent, system_now_ms, unix_ms};
pub use live::{
    LIVE_DELAYED_MS, LIVE_RECHECK_MS, MAX_LIVE_STREAMS_PER_ACCOUNT, MAX_LIVE_STREAMS_PER_LOGIN,
};
pub use ops::{
    READY_DB_TIMEOUT, READY_REUSE, READY_STORE_TIMEOUT, Readiness, check_operator_address,
    operator_router, serve_operator,
};
pub use serve::{
    SHUTDOWN_GRACE_S, TLS_HANDSHAKE_TIMEOUT_S, acceptor_from_pem, serve, serve_router,
};
pub use serve::{WebLimits, serve_router_with_limits, serve_with_limits};
pub use sessions::{
    DEFAULT_MAX_REPLAY_BYTES, DEFAULT_REPLAY_CPU_S, REPLAY_QUEUE_WAIT_S, REPLAY_STALL_S,
    REPLAYS_AT_ONCE, ReplayTurns,
};

/// Largest request body accepted, bytes.
pub const MAX_BODY_BYTES: usize = 64 * 1024;

/// Default lifetime of a console login, ms (8 hours).
pub const DEFAULT_LOGIN_TTL_MS: i64 = 8 * 60 * 60 * 1000;

/// What every request handler shares.
#[derive(Clone)]
pub struct AppState {
    /// The system of record.
    pub db: Db,
    /// Summaries of running sessions, as the ingest receives them (`/api/patients/{id}/live`).
    pub live: broadcast::Sender<LiveEvent>,
    /// The clock: the product's one injectable clock (a mock in tests).
    pub clock: clock::Clock,
    /// Lifetime of a console login, ms.
    pub login_ttl_ms: i64,
    /// Where a newly prescribed regimen is announced (the hub pushes it to the patient's
    /// station if connected); `None` when no station link runs.
    pub prescribed: Option<broadcast::Sender<RegimenVersion>>,
    /// Open live streams per login (by token hash) and per therapist, for
    /// [`MAX_LIVE_STREAMS_PER_LOGIN`] and [`MAX_LIVE_STREAMS_PER_ACCOUNT`].
    pub live_streams: live::StreamCounts,
    /// Where the recordings are kept (`None`: this console replays none).
    pub recordings: Option<hub_care::recordings::RecordingStore>,
    /// Largest recording file replayed, bytes.
    pub replay_max_bytes: u64,
    /// Replays being prepared, per hub and per therapist.
    pub replay_turns: Arc<ReplayTurns>,
    /// CPU time one replay's decoding may take, s.
    pub replay_cpu_s: f64,
    /// What a replayed file's chunks may declare (`None`: what a station writes, for files
    /// up to `replay_max_bytes`: [`record::CostLimits::for_files_up_to`]).
    pub replay_cost_limits: Option<record::CostLimits>,
    /// The clinic's name for its printouts (`hub.toml`'s `clinic_name`), if set.
    pub clinic_name: Option<String>,
    /// The canonical base of the FHIR export's own codes (`hub.toml`'s `fhir_base`); `None`:
    /// the export is refused (a hub that `hub serve` runs always has one).
    pub fhir_base: Option<hub_care::fhir::FhirBase>,
    /// The clinic's pain threshold, phone, station address and mail ([`hub_care::care`]).
    pub care: Arc<hub_care::care::CareConfig>,
    /// Where a therapist's clearance after a pain stop is announced (patient id; the hub
    /// pushes it to the patient's connected stations); `None` when no station link runs.
    pub pain_cleared: Option<broadcast::Sender<String>>,
    /// The hub's metrics (`/metrics` on the operator's listener; requests and replays counted
    /// here).
    pub telemetry: Arc<hub_care::telemetry::Telemetry>,
    /// What `/readyz` checks.
    pub readiness: Arc<Readiness>,
}

impl AppState {
    /// State with the system clock and [`DEFAULT_LOGIN_TTL_MS`].
    pub fn new(db: Db, live: broadcast::Sender<LiveEvent>) -> Self {
        Self {
            live,
            clock: clock::Clock::real(),
            login_ttl_ms: DEFAULT_LOGIN_TTL_MS,
            prescribed: None,
            live_streams: live::StreamCounts::default(),
            recordings: None,
            replay_max_bytes: DEFAULT_MAX_REPLAY_BYTES,
            replay_turns: Arc::default(),
            replay_cpu_s: DEFAULT_REPLAY_CPU_S,
            replay_cost_limits: None,
            clinic_name: None,
            fhir_base: None,
            care: Arc::default(),
            pain_cleared: None,
            telemetry: Arc::default(),
            readiness: Arc::new(Readiness::new(db.clone(), None, None)),
            db,
        }
    }

    /// The same state counting in `telemetry` and checking, for readiness, that the
    /// `recordings` store (if any) answers and that its local directory takes new files
    /// (partial uploads grow there whatever the store).
    pub fn with_operator(
        mut self,
        telemetry: Arc<hub_care::telemetry::Telemetry>,
        recordings: Option<hub_care::recordings::RecordingStore>,
    ) -> Self {
        self.telemetry = telemetry;
        let staging = recordings.as_ref().map(|r| r.staging_dir().to_path_buf());
        self.readiness = Arc::new(Readiness::new(self.db.clone(), staging, recordings));
        self
    }

    /// The same state naming the clinic `name` on its printouts.
    pub fn with_clinic_name(mut self, name: Option<String>) -> Self {
        self.clinic_name = name.filter(|n| !n.trim().is_empty());
        self
    }

    /// The same state exporting FHIR with its codes at `base`.
    pub fn with_fhir_base(mut self, base: hub_care::fhir::FhirBase) -> Self {
        self.fhir_base = Some(base);
        self
    }

    /// The same state giving each replay at most `cpu_s` CPU-seconds, and reading files
    /// within `limits` (`None`: a station's, [`record::CostLimits::for_files_up_to`]).
    pub fn with_replay_budget(mut self, cpu_s: f64, limits: Option<record::CostLimits>) -> Self {
        self.replay_cpu_s = cpu_s;
        self.replay_cost_limits = limits;
        self
    }

    /// What one replay may cost.
    fn replay_budget(&self) -> sessions::ReplayBudget {
        sessions::ReplayBudget {
            limits: self
                .replay_cost_limits
                .unwrap_or_else(|| record::CostLimits::for_files_up_to(self.replay_max_bytes)),
            cpu_s: self.replay_cpu_s,
        }
    }

    /// The same state replaying the recordings `store` keeps.
    pub fn with_recordings(mut self, store: hub_care::recordings::RecordingStore) -> Self {
        self.recordings = Some(store);
        self
    }

    /// The same state replaying recording files of at most `bytes`.
    pub fn with_replay_max_bytes(mut self, bytes: u64) -> Self {
        self.replay_max_bytes = bytes;
        self
    }

    /// The same state with the clinic's pain, pairing and mail settings, announcing each
    /// clearance after a pain stop on `cleared`.
    pub fn with_care(
        mut self,
        care: Arc<hub_care::care::CareConfig>,
        cleared: Option<broadcast::Sender<String>>,
    ) -> Self {
        self.care = care;
        self.pain_cleared = cleared;
        self
    }

    /// The same state announcing each new regimen on `feed`.
    pub fn with_prescribed_feed(mut self, feed: broadcast::Sender<RegimenVersion>) -> Self {
        self.prescribed = Some(feed);
        self
    }

    /// The same state with another clock.
    pub fn with_clock(mut self, clock: clock::Clock) -> Self {
        self.clock = clock;
        self
    }

    /// The time, ms since the Unix epoch.
    fn now(&self) -> i64 {
        unix_ms(&self.clock)
    }

    /// Writes an audit entry; a failure is logged, and fails the request (an unaudited read
    /// of patient data is not served).
    async fn audit(
        &self,
        actor: &str,
        action: &str,
        target: &str,
        detail: &str,
    ) -> Result<(), ApiError> {
        self.db
            .audit(actor, action, target, detail, self.now())
            .await
            .map_err(ApiError::from)
    }

    /// The patient `id` if `therapist` may see it; 400 for a malformed id, 404 for a patient
    /// that does not exist or is someone else's.
    async fn visible_patient(&self, therapist: &Therapist, id: &str) -> Result<Patient, ApiError> {
        check_path_id("patient id", id)?;
        match self.db.patient(id).await? {
            Some(p) if Db::may_see(therapist, &p) => Ok(p),
            _ => Err(not_found("patient", format!("no patient {id:?}"))),
        }
    }
}

impl std::fmt::Debug for AppState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("AppState")
            .field("db", &self.db)
            .field("login_ttl_ms", &self.login_ttl_ms)
            .finish_non_exhaustive()
    }
}

/// The API's routes over `state`.
pub fn router(state: AppState) -> Router {
    Router::new()
        .route("/", get(console::index))
        .route("/console/{*path}", get(console::asset))
        .route("/api/health", get(health))
        .route("/healthz", get(ops::healthz))
        .route("/readyz", get(ops::readyz))
        .route("/api/login", post(auth::login))
        .route("/api/logout", post(auth::logout))
        .route("/api/me", get(auth::me))
        .route("/api/me/password", post(auth::change_password))
        .route(
            "/api/me/language",
            get(language::get_language).put(language::put_language),
        )
        .route("/api/audit", get(auth::audit_log))
        .route(
            "/api/patients",
            get(attention::caseload).post(clinic::add_patient),
        )
        .route("/api/patients/{id}", get(patients::one))
        .route("/api/patients/{id}/attention", get(attention::one))
        .route("/api/patients/{id}/alerts/ack", post(attention::ack))
        .route(
            "/api/clinic/settings",
            get(attention::settings).put(attention::put_settings),
        )
        .route("/api/patients/{id}/sessions", get(patients::sessions))
        .route("/api/patients/{id}/checkins", get(patients::checkins))
        .route("/api/patients/{id}/difficulty", get(patients::difficulty))
        .route("/api/patients/{id}/assessments", get(patients::assessments))
        .route(
            "/api/patients/{id}/messages",
            get(messages::list).post(messages::post),
        )
        .route(
            "/api/patients/{id}/regimen",
            get(regimen::get_regimen).put(regimen::put_regimen),
        )
        .route(
            "/api/patients/{id}/scales",
            get(scales::list).post(scales::post),
        )
        .route(
            "/api/patients/{id}/scales/{scale_id}",
            axum::routing::delete(scales::delete),
        )
        .route(
            "/api/patients/{id}/measures.csv",
            get(spreadsheet::patient_csv),
        )
        .route("/api/measures.csv", get(spreadsheet::caseload_csv))
        .route(
            "/api/patients/{id}/assessments.csv",
            get(assessment_sheet::patient_csv),
        )
        .route("/api/measures/words", get(measure_words::measure_words))
        .route("/api/clinic/name", get(measure_words::clinic_name))
        .route("/api/patients/{id}/fhir", get(fhir::bundle))
        .route("/api/regimen/schema", get(regimen::regimen_schema))
        .route("/api/regimen/presets", get(regimen::regimen_presets))
        .route("/api/patients/{id}/live", get(live::live))
        .route("/api/sessions/{id}", get(sessions::one))
        .route("/api/sessions/{id}/summaries", get(sessions::summaries))
        .route("/api/sessions/{id}/metrics", get(sessions::metrics))
        .route("/api/sessions/{id}/exercises", get(sessions::exercises))
        .route(
            "/api/sessions/{id}/notes",
            get(notes::list).post(notes::post),
        )
        .route("/api/sessions/{id}/replay", get(sessions::replay))
        .route("/api/patients/{id}/pairing-code", post(clinic::new_code))
        .route("/api/stations/{id}/revoke", post(clinic::revoke_station))
        .route("/api/patients/{id}/pain-clearance", post(pain::clear))
        .route("/api/clinic/pain-mail", get(pain::mail_status))
        .route(
            "/api/therapists",
            get(clinic::therapists).post(clinic::add_therapist),
        )
        .fallback(|| async {
            ApiError::NotFound(Why::new(Code::NoEndpoint).says("no such endpoint"))
        })
        .layer(axum::middleware::from_fn_with_state(
            state.clone(),
            auth::audit_refusals,
        ))
        .layer(axum::middleware::map_response(security_headers))
        .layer(DefaultBodyLimit::max(MAX_BODY_BYTES))
        .layer(axum::middleware::from_fn_with_state(
            state.clone(),
            ops::count_requests,
        ))
        .with_state(state)
}

async fn security_headers(mut response: Response) -> Response {
    let headers = response.headers_mut();
    headers.insert(header::CACHE_CONTROL, HeaderValue::from_static("no-store"));
    headers.insert(
        header::X_CONTENT_TYPE_OPTIONS,
        HeaderValue::from_static("nosniff"),
    );
    headers.insert(
        header::STRICT_TRANSPORT_SECURITY,
        HeaderValue::from_static("max-age=31536000"),
    );
    headers.insert(
        header::CONTENT_SECURITY_POLICY,
        HeaderValue::from_static(console::CONTENT_SECURITY_POLICY),
    );
    headers.insert(header::X_FRAME_OPTIONS, HeaderValue::from_static("DENY"));
    headers.insert(
        header::REFERRER_POLICY,
        HeaderValue::from_static("no-referrer"),
    );
    response
}

#[derive(Serialize)]
struct Health {
    status: &'static str,
}

async fn health() -> Json<Health> {
    Json(Health { status: "ok" })
}

/// 404 for `what` (patient, station, session, scale, alert), in `english`.
fn not_found(what: &'static str, english: String) -> ApiError {
    ApiError::NotFound(Why::new(Code::NotFound).with("what", what).says(english))
}

/// Checks an id taken from the URL (netlink's identifier rule), 400 naming it otherwise.
fn check_path_id(what: &str, id: &str) -> Result<(), ApiError> {
    netlink::frame::check_id(what, id)
        .map_err(|e| ApiError::BadRequest(Why::field(Code::BadId, what).says(e)))
}

/// A refusal's words: the hub's English sentence (`error`) and why, for the console's words in
/// any language (`why`, [`hub_store::refusal`]).
#[derive(Debug)]
pub(crate) struct Said {
    english: String,
    why: Why,
}

/// A [`Why`] given the hub's English sentence for it (`Why` is the store's; the sentence and
/// the answer it makes are the API's).
pub(crate) trait Says {
    /// This reason with the hub's English sentence for it.
    fn says(self, english: impl Into<String>) -> Said;
}

impl Says for Why {
    fn says(self, english: impl Into<String>) -> Said {
        Said {
            english: english.into(),
            why: self,
        }
    }
}

/// An error answer: the status and `{"error": "<message>", "why": {"code": …, "args": …}}`.
#[derive(Debug)]
pub(crate) enum ApiError {
    /// 401: not logged in, or login refused.
    Unauthorized(Said),
    /// 403: logged in but not allowed (admin-only endpoints).
    Forbidden(Said),
    /// 404.
    NotFound(Said),
    /// 400: malformed input.
    BadRequest(Said),
    /// 422: well-formed but refused (a regimen outside the safety bounds).
    Unprocessable(Said),
    /// 429 with `Retry-After` (s): throttled or too busy; nothing was done.
    TooManyRequests(Said, i64),
    /// 503 with `Retry-After` (s): the hub's shared capacity stayed busy; nothing was done.
    Unavailable(Said, i64),
    /// A body axum's JSON extractor refused (malformed or wrong shape 400, wrong content type
    /// 415, over [`MAX_BODY_BYTES`] 413), or a conflict (409), with that status.
    Rejected(StatusCode, Said),
    /// 500: details are logged, not shown.
    Internal,
}

#[derive(Serialize)]
struct ErrorBody<'a> {
    error: &'a str,
    why: &'a Why,
}

impl IntoResponse for ApiError {
    fn into_response(self) -> Response {
        let (status, said, retry_after_s) = match self {
            Self::Unauthorized(m) => (StatusCode::UNAUTHORIZED, m, None),
            Self::Forbidden(m) => (StatusCode::FORBIDDEN, m, None),
            Self::NotFound(m) => (StatusCode::NOT_FOUND, m, None),
            Self::BadRequest(m) => (StatusCode::BAD_REQUEST, m, None),
            Self::Unprocessable(m) => (StatusCode::UNPROCESSABLE_ENTITY, m, None),
            Self::TooManyRequests(m, s) => (StatusCode::TOO_MANY_REQUESTS, m, Some(s)),
            Self::Unavailable(m, s) => (StatusCode::SERVICE_UNAVAILABLE, m, Some(s)),
            Self::Rejected(status, m) => (status, m, None),
            Self::Internal => (
                StatusCode::INTERNAL_SERVER_ERROR,
                Why::new(Code::Internal).says("internal error; the hub's log has the details"),
                None,
            ),
        };
        let body = ErrorBody {
            error: &said.english,
            why: &said.why,
        };
        let mut response = (status, Json(body)).into_response();
        if let Some(retry_after_s) = retry_after_s {
            response
                .headers_mut()
                .insert(header::RETRY_AFTER, HeaderValue::from(retry_after_s));
        }
        response
    }
}

impl From<HubError> for ApiError {
    fn from(e: HubError) -> Self {
        let Some(why) = e.why() else {
            tracing::error!(error = %e, "request failed");
            return Self::Internal;
        };
        let said = why.says(e.to_string());
        match e {
            HubError::NotFound { .. } => Self::NotFound(said),
            HubError::LoginRefused => Self::Unauthorized(said),
            HubError::Throttled { retry_after_ms, .. } => {
                Self::TooManyRequests(said, ((retry_after_ms + 999) / 1000).max(1))
            }
            HubError::AlreadyExists { .. } => Self::Rejected(StatusCode::CONFLICT, said),
            _ => Self::BadRequest(said),
        }
    }
}

impl From<axum::extract::rejection::JsonRejection> for ApiError {
    fn from(rejection: axum::extract::rejection::JsonRejection) -> Self {
        // axum answers 422 for JSON of the wrong shape; this API keeps 422 for "well-formed
        // but refused" (a regimen outside the bounds), so a malformed body is a 400.
        let status = match rejection.status() {
            StatusCode::UNPROCESSABLE_ENTITY => StatusCode::BAD_REQUEST,
            other => other,
        };
        let code = match status {
            StatusCode::PAYLOAD_TOO_LARGE => Code::BodyTooLarge,
            StatusCode::UNSUPPORTED_MEDIA_TYPE => Code::BodyNotJson,
            _ => Code::BodyMalformed,
        };
        Self::Rejected(status, Why::new(code).says(rejection.body_text()))
    }
}

impl From<axum::extract::rejection::PathRejection> for ApiError {
    fn from(rejection: axum::extract::rejection::PathRejection) -> Self {
        Self::BadRequest(Why::new(Code::NoEndpoint).says(rejection.body_text()))
    }
}
