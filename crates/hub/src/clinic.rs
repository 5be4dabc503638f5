//! A clinic's hub on disk and running: `hub init` makes the data directory (database, CA,
//! hub certificate, first admin), `hub serve` runs the station link (mutual TLS) and the
//! console API (HTTPS) over it.
//!
//! ```text
//! DATA/hub.toml            names on the hub's certificate, database URL (default: hub.db),
//!                          clinic name, FHIR base (`fhir_base`), recording store
//!                          (`[recordings]`, default: DATA/recordings), the operator's
//!                          `metrics_listen` address (none by default), the load
//!                          balancers whose PROXY headers are read (`[network]`)
//! DATA/hub.db              SQLite database (0600), unless `database` names PostgreSQL
//! DATA/tls/ca.crt, ca.key  the clinic's CA (key 0600)
//! DATA/tls/hub.crt, hub.key  the hub's certificate, signed by the CA (key 0600)
//! ```

use std::fs::OpenOptions;
use std::future::Future;
use std::io::Write;
use std::net::SocketAddr;
use std::os::unix::fs::{DirBuilderExt, OpenOptionsExt};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use netlink::pki::{CertAndKey, ClinicCa};
use netlink::{ServerTls, TherapistConfig, TherapistEvent, TherapistServer};
use serde::{Deserialize, Serialize};
use tokio::sync::broadcast;

use crate::web::{self, AppState};
use hub_care::fanout::{Fanout, Note};
use hub_care::ingest::{DbStore, Ingest, REVOCATION_POLL};
use hub_care::limits::ConnectionBudget;
use hub_care::live::{LiveEvent, unix_ms};
use hub_care::telemetry::{Telemetry, sample_pool};
use hub_store::HubError;
use hub_store::db::{Db, RegimenVersion, Role};

/// `DATA/hub.toml`.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ClinicConfig {
    /// Names (DNS or IP literals) on the hub's certificate; stations check the first.
    pub names: Vec<String>,
    /// Database URL; empty means `DATA/hub.db` (SQLite).
    #[serde(default)]
    pub database: String,
    /// The clinic's name as its printouts carry it (`clinic_name = "Rehab Clinic Nord"`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub clinic_name: Option<String>,
    /// The canonical base of the hub's FHIR code systems, questionnaire and identifier
    /// systems (`fhir_base = "https://fhir.clinic.example/telerehab"`); absent: `https://NAME/fhir`
    /// of the first name ([`hub_care::fhir::FhirBase`], docs/FHIR.md).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fhir_base: Option<String>,
    /// The age recipients (`age1…`, X25519) `hub backup` encrypts to (`hub backup-key` adds
    /// one); their identity files are kept offline and restore the backups.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub backup_recipients: Vec<String>,
    /// Where `/metrics`, `/healthz` and `/readyz` are served over plain HTTP for the clinic's
    /// operator (`metrics_listen = "127.0.0.1:9464"`); absent: not served (the console's port
    /// still answers `/healthz` and `/readyz`). Off by default because two hubs on one
    /// machine would fight over a fixed port, and never on every interface (`0.0.0.0`): the
    /// counts need no login, so they belong on loopback or a management network
    /// (docs/OPERATING.md).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub metrics_listen: Option<SocketAddr>,
    /// Where recordings are kept (`[recordings]`, [`hub_care::recordings::RecordingsConfig`]);
    /// absent: `DATA/recordings`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub recordings: Option<hub_care::recordings::RecordingsConfig>,
    /// How the hub's ports are reached (`[network]`, [`NetworkConfig`]); absent: directly.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub network: Option<NetworkConfig>,
}

/// `hub.toml`'s `[network]`: how clients reach the hub's ports.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NetworkConfig {
    /// The load balancers (addresses or networks, `["10.0.0.11", "10.0.0.0/24"]`) whose
    /// connections to the station port and the console's start with a PROXY protocol header
    /// (HAProxy's `send-proxy-v2`) naming the client; the client's address then drives every
    /// per-address guard and audit line. A connection from them without a valid header within
    /// the handshake timeout is closed; from any other address a header is never read.
    /// Default none (docs/DEPLOY.md, "Client addresses").
    #[serde(default)]
    pub proxy_protocol_from: netlink::proxy_protocol::TrustedProxies,
}

impl ClinicConfig {
    /// A clinic's configuration with its `names` and `database` and nothing else set (what
    /// `hub init` writes; every other setting absent, i.e. its default).
    pub fn new(names: Vec<String>, database: String) -> Self {
        Self {
            names,
            database,
            clinic_name: None,
            fhir_base: None,
            backup_recipients: Vec::new(),
            metrics_listen: None,
            recordings: None,
            network: None,
        }
    }

    /// The peers whose PROXY protocol headers are read (`[network] proxy_protocol_from`).
    pub fn proxy_protocol_from(&self) -> netlink::proxy_protocol::TrustedProxies {
        self.network
            .as_ref()
            .map(|n| n.proxy_protocol_from.clone())
            .unwrap_or_default()
    }

    /// The clinic's FHIR base: `fhir_base`, else `https://NAME/fhir` of the first name; an
    /// error naming `hub.toml`'s `fhir_base` when it is not an address.
    pub fn fhir_base(&self) -> Result<hub_care::fhir::FhirBase, HubError> {
        match self.fhir_base.as_deref() {
            Some(b) => hub_care::fhir::FhirBase::parse(b, "hub.toml's fhir_base"),
            None => {
                hub_care::fhir::FhirBase::of_hub_name(self.names.first().map_or("", String::as_str))
            }
        }
    }
}

/// What `hub init` made.
#[derive(Debug, Clone)]
pub struct Initialised {
    /// The first admin's one-time password (printed once, stored only as an argon2 hash).
    pub admin_password: String,
    /// The database URL in use.
    pub database: String,
}

/// A clinic's data directory.
#[derive(Debug, Clone)]
pub struct Clinic {
    dir: PathBuf,
}

fn io(what: &str, path: &Path) -> impl Fn(std::io::Error) -> HubError + use<> {
    HubError::io_at(what, path)
}

/// Writes a new file, 0600, refusing to replace one.
fn write_new_private(path: &Path, text: &str) -> Result<(), HubError> {
    let mut f = OpenOptions::new()
        .write(true)
        .create_new(true)
        .mode(0o600)
        .open(path)
        .map_err(io("creating", path))?;
    f.write_all(text.as_bytes())
        .and_then(|()| f.sync_all())
        .map_err(io("writing", path))
}

impl Clinic {
    /// The clinic whose data directory is `dir`.
    pub fn at(dir: impl Into<PathBuf>) -> Self {
        Self { dir: dir.into() }
    }

    /// The data directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    fn tls(&self, name: &str) -> PathBuf {
        self.dir.join("tls").join(name)
    }

    /// Reads `DATA/hub.toml`.
    pub fn config(&self) -> Result<ClinicConfig, HubError> {
        let path = self.dir.join("hub.toml");
        let text = std::fs::read_to_string(&path).map_err(|e| {
            HubError::Config(format!(
                "{} cannot be read ({e}); run `telerehab hub init --data {}` first",
                path.display(),
                self.dir.display()
            ))
        })?;
        toml::from_str(&text).map_err(|e| HubError::Config(format!("{}: {e}", path.display())))
    }

    /// The database URL: `override_url`, else the configured one, else `DATA/hub.db`.
    pub fn database_url(&self, override_url: Option<&str>) -> Result<String, HubError> {
        if let Some(url) = override_url.filter(|u| !u.is_empty()) {
            return Ok(url.to_owned());
        }
        let configured = self.config()?.database;
        if configured.is_empty() {
            Ok(self.sqlite_url())
        } else {
            Ok(configured)
        }
    }

    fn sqlite_url(&self) -> String {
        format!("sqlite://{}?mode=rwc", self.dir.join("hub.db").display())
    }

    /// Opens the database (migrations applied).
    pub async fn open_db(&self, override_url: Option<&str>) -> Result<Db, HubError> {
        Db::open(&self.database_url(override_url)?).await
    }

    /// Makes a new clinic: directories (0700), CA and hub certificate (keys 0600), the
    /// database and its first admin. Refuses a directory that already holds a clinic.
    pub async fn init(
        &self,
        admin_email: &str,
        names: &[String],
        database: Option<&str>,
        now_ms: i64,
    ) -> Result<Initialised, HubError> {
        if self.dir.join("hub.toml").exists() {
            return Err(HubError::Config(format!(
                "{} already holds a clinic (hub.toml); nothing was changed",
                self.dir.display()
            )));
        }
        if names.is_empty() {
            return Err(HubError::Config(
                "the hub needs at least one name for its certificate".into(),
            ));
        }
        let tls_dir = self.dir.join("tls");
        std::fs::DirBuilder::new()
            .recursive(true)
            .mode(0o700)
            .create(&tls_dir)
            .map_err(io("creating", &tls_dir))?;
        let ca = ClinicCa::create(&names[0]).map_err(|e| HubError::Config(e.to_string()))?;
        let hub = ca
            .issue_server(names)
            .map_err(|e| HubError::Config(e.to_string()))?;
        write_new_private(&self.tls("ca.crt"), &ca.pem().cert_pem)?;
        write_new_private(&self.tls("ca.key"), &ca.pem().key_pem)?;
        write_new_private(&self.tls("hub.crt"), &hub.cert_pem)?;
        write_new_private(&self.tls("hub.key"), &hub.key_pem)?;
        let config = ClinicConfig::new(names.to_vec(), database.unwrap_or_default().to_owned());
        let url = match database.filter(|d| !d.is_empty()) {
            Some(u) => u.to_owned(),
            None => self.sqlite_url(),
        };
        let db = Db::open(&url).await?;
        let admin_password = one_time_password()?;
        let admin = db
            .add_therapist(admin_email, &admin_password, Role::Admin, now_ms)
            .await?;
        db.require_password_change(&admin.id).await?;
        db.audit("cli", "hub_init", &admin.actor(), &names.join(","), now_ms)
            .await?;
        db.close().await;
        let text = toml::to_string(&config).map_err(|e| HubError::Config(e.to_string()))?;
        write_new_private(&self.dir.join("hub.toml"), &text)?;
        Ok(Initialised {
            admin_password,
            database: url,
        })
    }

    /// The recording store `hub.toml` configures (`[recordings]`), else `DATA/recordings`; a
    /// bad or missing setting is an error naming it.
    pub fn recordings(&self) -> Result<hub_care::recordings::RecordingStore, HubError> {
        hub_care::recordings::RecordingStore::open(&self.dir, self.config()?.recordings.as_ref())
    }

    /// The clinic's CA.
    pub fn ca(&self) -> Result<ClinicCa, HubError> {
        let read = |name: &str| {
            let path = self.tls(name);
            std::fs::read_to_string(&path).map_err(io("reading", &path))
        };
        ClinicCa::load(CertAndKey {
            cert_pem: read("ca.crt")?,
            key_pem: read("ca.key")?,
        })
        .map_err(|e| HubError::Config(e.to_string()))
    }

    /// The station link's TLS: the hub's certificate, stations' certificates from the CA.
    pub fn server_tls(&self) -> ServerTls {
        ServerTls {
            cert_pem_path: self.tls("hub.crt"),
            key_pem_path: self.tls("hub.key"),
            client_ca_pem_path: Some(self.tls("ca.crt")),
        }
    }
}

pub use hub_store::db::one_time_password;

/// Where `hub serve` listens.
#[derive(Clone)]
pub struct ServeOptions {
    /// Stations' address (mutual TLS).
    pub stations: SocketAddr,
    /// Console API's address (HTTPS), if served.
    pub web: Option<SocketAddr>,
    /// The clock: the product's one injectable clock.
    pub clock: clock::Clock,
    /// Most simultaneous station connections, and from one address.
    pub max_connections: (usize, usize),
    /// Caps on connections nobody has authenticated yet and the console's deadlines; with
    /// `max_connections`, fitted to the open-file limit at start ([`hub_care::limits`]).
    pub limits: HubLimits,
    /// Largest recording file the console replays, bytes ([`web::DEFAULT_MAX_REPLAY_BYTES`]).
    pub max_replay_bytes: u64,
    /// Summaries taken from one station a second over all its connections
    /// ([`netlink::therapist::station_limits::SUMMARY_PACE_PER_S`]; tests lower it).
    pub summary_pace_per_s: u32,
    /// Pain threshold, clinic phone, console URL and mail ([`hub_care::care`]); its
    /// `public_station_address` is settled at start from `public_station_address`.
    pub care: hub_care::care::CareConfig,
    /// `--public-station-address`: what pairing sheets print (else the station listener's,
    /// when it is a specific address other than loopback).
    pub public_station_address: Option<String>,
    /// `--metrics-listen`: the operator's plain-HTTP address for `/metrics`, `/healthz` and
    /// `/readyz`; `None`: `hub.toml`'s `metrics_listen`, else not served.
    pub metrics: Option<SocketAddr>,
    /// `--drain-s`: how long `/readyz` answers 503 (draining) once shutdown is asked, while
    /// both ports still serve, before they stop: a load balancer's check interval or two.
    pub drain: std::time::Duration,
}

/// Connection caps and deadlines of `hub serve` besides [`ServeOptions::max_connections`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct HubLimits {
    /// Station-port connections not admitted yet (TLS handshake, Hello, pairing), in all.
    pub max_unauthenticated_stations: usize,
    /// The console's port.
    pub web: web::WebLimits,
}

impl Default for HubLimits {
    fn default() -> Self {
        Self {
            max_unauthenticated_stations: netlink::therapist::DEFAULT_MAX_UNAUTHENTICATED,
            web: web::WebLimits::default(),
        }
    }
}

impl ServeOptions {
    /// Options with the documented defaults: the system clock, netlink's connection caps,
    /// [`HubLimits::default`] and the default replay size limit.
    pub fn new(stations: SocketAddr, web: Option<SocketAddr>) -> Self {
        Self {
            stations,
            web,
            clock: clock::Clock::real(),
            max_connections: (
                netlink::therapist::DEFAULT_MAX_CONNECTIONS,
                netlink::therapist::DEFAULT_MAX_CONNECTIONS_PER_ADDRESS,
            ),
            limits: HubLimits::default(),
            max_replay_bytes: web::DEFAULT_MAX_REPLAY_BYTES,
            summary_pace_per_s: netlink::therapist::station_limits::SUMMARY_PACE_PER_S as u32,
            care: hub_care::care::CareConfig::default(),
            public_station_address: None,
            metrics: None,
            drain: std::time::Duration::ZERO,
        }
    }
}

impl std::fmt::Debug for ServeOptions {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ServeOptions")
            .field("stations", &self.stations)
            .field("web", &self.web)
            .finish_non_exhaustive()
    }
}

/// The addresses `hub serve` bound (useful with port 0).
#[derive(Debug, Clone, Copy)]
pub struct Bound {
    /// Stations' address.
    pub stations: SocketAddr,
    /// Console's address.
    pub web: Option<SocketAddr>,
    /// The operator's `/metrics` address.
    pub metrics: Option<SocketAddr>,
    /// The connection caps in force, fitted to the open-file limit.
    pub budget: ConnectionBudget,
}

/// The console's listener on `addr`, if the hub serves the console.
async fn bind_web(addr: Option<SocketAddr>) -> Result<Option<tokio::net::TcpListener>, HubError> {
    match addr {
        Some(addr) => tokio::net::TcpListener::bind(addr)
            .await
            .map(Some)
            .map_err(|e| HubError::io(format!("listening on {addr}"), e)),
        None => Ok(None),
    }
}

/// Runs the hub until `shutdown` completes: `on_bound` once listening, `on_event` for every
/// station event (one line each for the operator).
pub async fn serve(
    clinic: &Clinic,
    db: Db,
    options: ServeOptions,
    on_bound: impl FnOnce(Bound),
    mut on_event: impl FnMut(&TherapistEvent) + Send,
    shutdown: impl Future<Output = ()> + Send,
) -> Result<(), HubError> {
    let config = clinic.config()?;
    options.care.validate()?;
    let fhir_base = config.fhir_base()?;
    let recordings = clinic.recordings()?;
    let telemetry = Arc::new(Telemetry::new());
    let store = Arc::new(
        DbStore::new_counted(
            db.clone(),
            clinic.ca()?,
            config.names[0].clone(),
            recordings.clone(),
            options.clock.clone(),
            telemetry.clone(),
        )
        // A station's check is answered with the patient's care too (its threshold and phone;
        // the pairing sheets' address, settled below, is not part of it).
        .with_care(options.care.clone()),
    );
    store.refresh_revoked().await?;
    options
        .care
        .seed_pain_threshold(&db, unix_ms(&options.clock))
        .await?;
    let (budget, web_limits) = fit_to_fd_limit(&options);
    let (server, mut events) = TherapistServer::bind_with_store(
        link_config(&options, clinic, &budget, &config),
        Arc::new(Ingest(store.clone())),
    )
    .await
    .map_err(|e| HubError::Config(format!("station link: {e}")))?;
    let (live, _) = broadcast::channel::<LiveEvent>(1024);
    let (prescribed, mut prescriptions) = broadcast::channel::<RegimenVersion>(64);
    let (cleared, mut clearances) = broadcast::channel::<String>(64);
    let (fanout, mut from_other_hubs) = Fanout::start(&db).unzip(); // several hubs on PostgreSQL
    let web_listener = bind_web(options.web).await?;
    let web_addr = web_listener.as_ref().and_then(|l| l.local_addr().ok());
    let care = Arc::new(settle_care(
        &options,
        server.local_addr(),
        web_addr,
        &config.names[0],
    ));
    let state = AppState::new(db.clone(), live.clone())
        .with_clock(options.clock.clone())
        .with_prescribed_feed(prescribed)
        .with_care(care.clone(), Some(cleared))
        .with_replay_max_bytes(options.max_replay_bytes)
        .with_recordings(recordings.clone())
        .with_clinic_name(config.clinic_name.clone())
        .with_fhir_base(fhir_base)
        .with_operator(telemetry.clone(), Some(recordings.clone()));
    let readiness = state.readiness.clone();
    let (stop_operator, operator) =
        spawn_operator(options.metrics.or(config.metrics_listen), state.clone()).await?;
    let (stop_web, web_task) = spawn_console(clinic, web_listener, state, web_limits, &config)?;
    on_bound(Bound {
        stations: server.local_addr(),
        web: web_addr,
        metrics: operator.as_ref().map(|(addr, _)| *addr),
        budget,
    });
    let pool_sampler = tokio::spawn(sample_pool(db.clone(), telemetry.clone()));
    let mut revocation = tokio::time::interval(REVOCATION_POLL);
    let mut sweep = tokio::time::interval(hub_care::uploads::PARTIAL_UPLOAD_SWEEP);
    let mut housekeeping = tokio::time::interval(HOUSEKEEPING);
    let staging = recordings.staging_dir().to_owned();
    let mailer = tokio::spawn(hub_care::pain_mail::run(
        db.clone(),
        care.clone(),
        options.clock.clone(),
        telemetry.clone(),
    ));
    let mut shutdown = std::pin::pin!(shutdown);
    // Armed when shutdown is asked: `/readyz` says draining until it fires.
    let mut drained = std::pin::pin!(tokio::time::sleep(std::time::Duration::ZERO));
    let mut draining = false;
    loop {
        tokio::select! {
            () = &mut shutdown, if !draining => {
                readiness.start_draining();
                if options.drain.is_zero() {
                    break;
                }
                tracing::info!(drain_s = options.drain.as_secs_f64(), "draining before shutdown");
                draining = true;
                drained.as_mut().reset(tokio::time::Instant::now() + options.drain);
            }
            () = &mut drained, if draining => break,
            _ = revocation.tick() => {
                if let Err(e) = store.refresh_revoked().await {
                    tracing::error!("cannot re-read revoked stations: {e}");
                }
                count_connections(&telemetry, &server);
            }
            _ = housekeeping.tick() => housekeep(&db, unix_ms(&options.clock)).await,
            _ = sweep.tick() => expire_partial_uploads(staging.clone()).await,
            Ok(regimen) = prescriptions.recv() => prescribed_here(&server, &db, fanout.as_ref(), regimen).await,
            Ok(patient) = clearances.recv() => cleared_here(&server, &db, &care, fanout.as_ref(), patient).await,
            Some(note) = next_note(&mut from_other_hubs) => on_other_hubs_note(note, &server, &db, &care, &live).await,
            Some(event) = events.recv() => {
                on_event(&event);
                count_event(&telemetry, &server, &event);
                if let TherapistEvent::Connected { hello, .. } = &event {
                    // First: a station that checks in before today's page knows at once.
                    push_care(&server, &db, &care, &hello.station_id, &hello.patient_id).await;
                }
                on_station_event(&event, &server, &db, (&live, fanout.as_ref()), unix_ms(&options.clock)).await;
            }
        }
    }
    mailer.abort();
    pool_sampler.abort();
    let _ = stop_operator.send(());
    let stopped = stop_ports(server, stop_web, web_task).await;
    if let Some((_, task)) = operator {
        task.abort();
    }
    let _ = tokio::time::timeout(std::time::Duration::from_millis(500), db.close()).await;
    stopped
}

/// Stops both ports together, within [`STOP_WITHIN`] less the database's half second: open
/// requests and station connections get the time left to finish; what a station was not
/// acknowledged it sends again.
async fn stop_ports(
    server: TherapistServer,
    stop_web: tokio::sync::oneshot::Sender<()>,
    web_task: Option<tokio::task::JoinHandle<Result<(), HubError>>>,
) -> Result<(), HubError> {
    let _ = stop_web.send(());
    let web_stopped = async {
        match web_task {
            Some(task) => match task.await {
                Ok(r) => r,
                Err(e) => {
                    tracing::error!("console API task failed: {e}");
                    Ok(())
                }
            },
            None => Ok(()),
        }
    };
    // The connections get STOP_WITHIN less a margin, so the database is closed in any case.
    let connections = STOP_WITHIN - std::time::Duration::from_millis(500);
    let stopped = tokio::time::timeout(connections, async {
        let (web, ()) = tokio::join!(web_stopped, server.shutdown(connections));
        web
    })
    .await;
    match stopped {
        Ok(web) => web,
        Err(_) => {
            tracing::warn!("the hub stopped before every connection had closed");
            Ok(())
        }
    }
}

/// `hub serve`'s housekeeping at `now` (ms): an attack that never succeeds must not grow the
/// throttle table or hold back the suppressed-refusal counts until the next refusal.
async fn housekeep(db: &Db, now: i64) {
    if let Err(e) = db.purge_throttles(now).await {
        tracing::warn!("cannot purge login throttles: {e}");
    }
    if let Err(e) = db.purge_pairing_windows(now).await {
        tracing::warn!("cannot purge pairing attempt counts: {e}");
    }
    if let Err(e) = db.flush_refusal_audits(now).await {
        tracing::warn!("cannot write suppressed refusal counts: {e}");
    }
}

/// Remove the partial uploads under `recordings` nobody has resumed for too long.
async fn expire_partial_uploads(recordings: PathBuf) {
    let expired = tokio::task::spawn_blocking(move || {
        hub_care::uploads::expire_partial_uploads(
            &recordings,
            hub_care::uploads::PARTIAL_UPLOAD_MAX_AGE,
            std::time::SystemTime::now(),
        )
    })
    .await;
    if let Ok(Err(e)) = expired {
        tracing::warn!("cannot expire partial uploads: {e}");
    }
}

/// A station's `event`: a summary goes to the console's live feed `live.0` and to the other
/// hubs' (`live.1`, several hubs on PostgreSQL); a station that connects gets its patient's
/// unseen messages and latest regimen.
async fn on_station_event(
    event: &TherapistEvent,
    server: &TherapistServer,
    db: &Db,
    live: (&broadcast::Sender<LiveEvent>, Option<&Fanout>),
    now_ms: i64,
) {
    match event {
        TherapistEvent::Summary {
            patient_id,
            summary,
            ..
        } => {
            let event = LiveEvent {
                patient_id: patient_id.clone(),
                session_id: summary.session_id.clone(),
                summary: summary.clone(),
            };
            let _ = live.0.send(event.clone());
            tell_other_hubs(live.1, Note::Live { event });
        }
        TherapistEvent::Connected { hello, .. } => {
            // Before the regimen: a station that waits for its prescription has its
            // messages by then.
            push_messages(server, db, hello, now_ms).await;
            if let Ok(Some(regimen)) = db.latest_regimen(&hello.patient_id).await {
                push_regimen(server, db, &regimen).await;
            }
        }
        _ => {}
    }
}

/// A regimen prescribed on this hub's console: pushed to the patient's stations connected here
/// and told to the other hubs for theirs.
async fn prescribed_here(
    server: &TherapistServer,
    db: &Db,
    fanout: Option<&Fanout>,
    regimen: RegimenVersion,
) {
    push_regimen(server, db, &regimen).await;
    let patient_id = regimen.patient_id;
    tell_other_hubs(fanout, Note::Regimen { patient_id });
}

/// A pain alert of `patient_id` cleared on this hub's console: told to their stations
/// connected here and to the other hubs for theirs.
async fn cleared_here(
    server: &TherapistServer,
    db: &Db,
    care: &hub_care::care::CareConfig,
    fanout: Option<&Fanout>,
    patient_id: String,
) {
    push_care_to_patient(server, db, care, &patient_id).await;
    tell_other_hubs(fanout, Note::PainCleared { patient_id });
}

/// Tells the other hubs of the clinic `note` (several hubs on PostgreSQL; nothing to tell
/// on SQLite, `fanout` is `None`).
fn tell_other_hubs(fanout: Option<&Fanout>, note: Note) {
    if let Some(fanout) = fanout {
        fanout.publish(note);
    }
}

/// The next note of the other hubs; never, on SQLite.
async fn next_note(notes: &mut Option<tokio::sync::mpsc::Receiver<Note>>) -> Option<Note> {
    match notes {
        Some(notes) => notes.recv().await,
        None => std::future::pending().await,
    }
}

/// What another hub told this one: a summary goes to the live views open here; a regimen or
/// a cleared pain alert to the patient's stations connected here.
async fn on_other_hubs_note(
    note: Note,
    server: &TherapistServer,
    db: &Db,
    care: &hub_care::care::CareConfig,
    live: &broadcast::Sender<LiveEvent>,
) {
    match note {
        Note::Live { event } => {
            let _ = live.send(event);
        }
        Note::LiveStored {
            patient_id,
            session_id,
            seq,
        } => match db.summary(&session_id, seq).await {
            Ok(Some(summary)) => {
                let _ = live.send(LiveEvent {
                    patient_id,
                    session_id,
                    summary,
                });
            }
            Ok(None) => tracing::warn!(%session_id, seq, "another hub's summary is not stored"),
            Err(e) => tracing::warn!("cannot read another hub's summary: {e}"),
        },
        Note::Regimen { patient_id } => {
            if let Ok(Some(regimen)) = db.latest_regimen(&patient_id).await {
                push_regimen(server, db, &regimen).await;
            }
        }
        Note::PainCleared { patient_id } => {
            push_care_to_patient(server, db, care, &patient_id).await;
        }
    }
}

/// Sets the gauges of station connections from the link's own tables.
fn count_connections(telemetry: &Telemetry, server: &TherapistServer) {
    telemetry.set_station_connections(
        server.connected_stations().len(),
        server.unauthenticated_connections(),
    );
}

/// Counts what the station link reports: connections in and out, refusals before admission
/// (one by one as `protocol_error`, the rest in the link's summaries as `before_admission`).
fn count_event(telemetry: &Telemetry, server: &TherapistServer, event: &TherapistEvent) {
    match event {
        TherapistEvent::Connected { .. } | TherapistEvent::Disconnected { .. } => {
            count_connections(telemetry, server);
        }
        TherapistEvent::ProtocolError { .. } => telemetry.station_refused("protocol_error"),
        TherapistEvent::Refused { count, .. } => {
            telemetry.station_refused_by("before_admission", *count);
        }
        _ => {}
    }
}

/// The operator's listener at `addr` (none without one), serving `/metrics`, `/healthz` and
/// `/readyz` over plain HTTP, and the sender that stops it.
#[allow(clippy::type_complexity)]
async fn spawn_operator(
    addr: Option<SocketAddr>,
    state: AppState,
) -> Result<
    (
        tokio::sync::oneshot::Sender<()>,
        Option<(SocketAddr, tokio::task::JoinHandle<Result<(), HubError>>)>,
    ),
    HubError,
> {
    let (stop, stopped) = tokio::sync::oneshot::channel::<()>();
    let Some(addr) = addr else {
        return Ok((stop, None));
    };
    web::check_operator_address(addr)?;
    let listener = tokio::net::TcpListener::bind(addr)
        .await
        .map_err(|e| HubError::io(format!("listening for metrics on {addr}"), e))?;
    let bound = listener
        .local_addr()
        .map_err(|e| HubError::io("reading the metrics address", e))?;
    let task = tokio::spawn(web::serve_operator(listener, state, async {
        let _ = stopped.await;
    }));
    Ok((stop, Some((bound, task))))
}

/// How often `hub serve` forgets stale login throttles and writes the counts of refusals
/// left out of the audit log.
pub const HOUSEKEEPING: std::time::Duration = std::time::Duration::from_secs(60);

/// Longest `hub serve` takes to stop once asked (connections closing, the database closed).
pub const STOP_WITHIN: std::time::Duration = std::time::Duration::from_secs(3);

/// The console's HTTPS API on `listener` (none without one), reading the PROXY headers of the
/// balancers `config` trusts, and the sender that stops it.
#[allow(clippy::type_complexity)]
fn spawn_console(
    clinic: &Clinic,
    listener: Option<tokio::net::TcpListener>,
    state: AppState,
    limits: web::WebLimits,
    config: &ClinicConfig,
) -> Result<
    (
        tokio::sync::oneshot::Sender<()>,
        Option<tokio::task::JoinHandle<Result<(), HubError>>>,
    ),
    HubError,
> {
    let (stop, stopped) = tokio::sync::oneshot::channel::<()>();
    let Some(listener) = listener else {
        return Ok((stop, None));
    };
    let acceptor = web::acceptor_from_pem(&clinic.tls("hub.crt"), &clinic.tls("hub.key"))?;
    // Behind a balancer: each browser's own address, from its PROXY header.
    let listener = netlink::proxy_protocol::ProxiedListener::new(
        listener,
        config.proxy_protocol_from(),
        std::time::Duration::from_millis(limits.tls_handshake_timeout_ms),
        "console port",
    );
    let task = tokio::spawn(web::serve_with_limits(
        listener,
        Some(acceptor),
        state,
        limits,
        async {
            let _ = stopped.await;
        },
    ));
    Ok((stop, Some(task)))
}

/// The station link's settings: the port, the clinic's TLS, the connection budget.
fn link_config(
    options: &ServeOptions,
    clinic: &Clinic,
    budget: &ConnectionBudget,
    clinic_config: &ClinicConfig,
) -> TherapistConfig {
    let mut config =
        TherapistConfig::new(options.stations, clinic.dir(), Some(clinic.server_tls()));
    config.max_connections = budget.stations;
    config.max_connections_per_address = options.max_connections.1;
    config.max_unauthenticated = budget.stations_unauthenticated;
    config.summary_pace_per_s = options.summary_pace_per_s;
    config.proxy_protocol_from = clinic_config.proxy_protocol_from();
    config
}

/// Raises the open-file limit and fits the connection caps of `options` under it (warning if
/// they had to shrink): the station port's and the console's.
fn fit_to_fd_limit(options: &ServeOptions) -> (ConnectionBudget, web::WebLimits) {
    let fd_limit = hub_care::limits::raise_fd_limit().unwrap_or_else(|e| {
        tracing::warn!("{e}");
        hub_care::limits::fd_limit()
    });
    let web = options.limits.web;
    let wanted = ConnectionBudget {
        stations: options.max_connections.0,
        stations_unauthenticated: options.limits.max_unauthenticated_stations,
        web_connections: if options.web.is_some() {
            web.max_connections
        } else {
            0
        },
        web_unanswered: if options.web.is_some() {
            web.max_unanswered.min(web.max_connections)
        } else {
            0
        },
    };
    let (budget, warning) = wanted.fit(fd_limit);
    if let Some(w) = warning {
        tracing::warn!("{w}");
    }
    tracing::info!(?fd_limit, ?budget, "connection caps");
    let web = web::WebLimits {
        max_connections: budget.web_connections.max(1),
        max_unanswered: budget.web_unanswered.max(1),
        ..web
    };
    (budget, web)
}

/// Sends the patient's unseen messages to the station of `hello`, oldest first, if its
/// connection speaks a protocol version that knows them (an older station is sent none).
async fn push_messages(server: &TherapistServer, db: &Db, hello: &netlink::Hello, now_ms: i64) {
    for frame in hub_care::news::unseen_messages(db, &hello.patient_id).await {
        let id = frame.id.clone();
        match server.send_message(&hello.station_id, frame) {
            Ok(true) => {
                tracing::info!(station = %hello.station_id, message = %id, "message pushed");
                if let Err(e) = db.message_delivered(&id, now_ms).await {
                    tracing::warn!("cannot note message {id} delivered: {e}");
                }
            }
            Ok(false) => {
                tracing::info!(
                    station = %hello.station_id,
                    "the station's protocol version has no messages; {id} not sent"
                );
                return;
            }
            Err(e) => {
                tracing::debug!(station = %hello.station_id, "message not pushed now: {e}");
                return;
            }
        }
    }
}

/// The clinic's care settings in force: the options' with the pairing sheets' station address
/// settled against the station listener `stations`, and the console's URL for mails (given,
/// else `https://NAME:PORT` of the hub's first certificate name and the console's port).
fn settle_care(
    options: &ServeOptions,
    stations: SocketAddr,
    web: Option<SocketAddr>,
    name: &str,
) -> hub_care::care::CareConfig {
    let mut care = options.care.clone();
    care.public_station_address =
        hub_care::care::public_station_address(options.public_station_address.as_deref(), stations);
    match &care.public_station_address {
        Ok(a) => tracing::info!("pairing sheets print the station address {a}"),
        Err(why) => tracing::warn!("pairing sheets cannot print a station address: {why}"),
    }
    if care.console_url.is_none() {
        care.console_url = web.map(|w| format!("https://{name}:{}", w.port()));
    }
    care
}

/// Sends the clinic's pain settings, with the patient's clearance, to the connected station
/// `station_id` if its protocol version knows them.
async fn push_care(
    server: &TherapistServer,
    db: &Db,
    care: &hub_care::care::CareConfig,
    station_id: &str,
    patient_id: &str,
) {
    let frame = hub_care::news::care_frame(db, care, patient_id).await;
    match server.send_care(station_id, frame) {
        Ok(true) => tracing::debug!(station = %station_id, "pain settings pushed"),
        Ok(false) => tracing::debug!(
            station = %station_id,
            "the station's protocol version has no pain settings; not sent"
        ),
        Err(e) => tracing::debug!(station = %station_id, "pain settings not pushed now: {e}"),
    }
}

/// Sends the clinic's pain settings to every connected station of `patient_id` (after the
/// therapist cleared a pain stop).
async fn push_care_to_patient(
    server: &TherapistServer,
    db: &Db,
    care: &hub_care::care::CareConfig,
    patient_id: &str,
) {
    let Ok(stations) = db.stations_of(patient_id).await else {
        return;
    };
    for station in stations.iter().filter(|s| !s.is_revoked()) {
        push_care(server, db, care, &station.station_id, patient_id).await;
    }
}

/// Sends `regimen` to every connected station of its patient (a station not connected gets
/// it when it next connects).
async fn push_regimen(server: &TherapistServer, db: &Db, regimen: &RegimenVersion) {
    let Ok(stations) = db.stations_of(&regimen.patient_id).await else {
        return;
    };
    let frame = hub_care::news::regimen_frame(db, regimen).await;
    for station in stations.iter().filter(|s| !s.is_revoked()) {
        match server.send_regimen(&station.station_id, frame.clone()) {
            Ok(()) => {
                tracing::info!(station = %station.station_id, version = regimen.version, "regimen pushed")
            }
            Err(e) => tracing::debug!(station = %station.station_id, "regimen not pushed now: {e}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::ClinicConfig;

    #[test]
    fn the_trusted_balancers_are_read_from_network_and_a_bad_one_is_named() {
        let base = "names = [\"hub.clinic.example\"]\n";
        let none: ClinicConfig = toml::from_str(base).unwrap();
        assert!(none.proxy_protocol_from().is_empty());
        let with: ClinicConfig = toml::from_str(&format!(
            "{base}[network]\nproxy_protocol_from = [\"10.0.0.5\", \"10.0.1.0/24\"]\n"
        ))
        .unwrap();
        let trusted = with.proxy_protocol_from();
        assert!(trusted.trusts("10.0.1.77".parse().unwrap()));
        assert!(!trusted.trusts("10.0.0.6".parse().unwrap()));
        // Written back as it was read.
        let again: ClinicConfig = toml::from_str(&toml::to_string(&with).unwrap()).unwrap();
        assert_eq!(again, with);
        let e = toml::from_str::<ClinicConfig>(&format!(
            "{base}[network]\nproxy_protocol_from = [\"0.0.0.0/0\"]\n"
        ))
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("proxy_protocol_from")
                && e.contains("`0.0.0.0/0` would trust every address"),
            "{e}"
        );
        let e = toml::from_str::<ClinicConfig>(&format!("{base}[network]\nproxy_from = []\n"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("proxy_from"), "{e}");
    }

    #[test]
    fn the_clinics_fhir_base_is_its_configured_one_else_of_the_hubs_name() {
        let mut config = ClinicConfig::new(vec!["hub.clinic.example".into()], String::new());
        assert_eq!(
            config.fhir_base().unwrap().to_string(),
            "https://hub.clinic.example/fhir"
        );
        let v6 = hub_care::fhir::FhirBase::of_hub_name("::1").unwrap();
        assert_eq!(v6.to_string(), "https://[::1]/fhir");
        config.fhir_base = Some("https://fhir.clinic.example/rehab".into());
        assert_eq!(
            config.fhir_base().unwrap().questionnaire("session-checkin"),
            "https://fhir.clinic.example/rehab/Questionnaire/session-checkin"
        );
        config.fhir_base = Some("fhir.clinic.example".into());
        let e = config.fhir_base().unwrap_err().to_string();
        assert!(
            e.contains("hub.toml's fhir_base") && e.contains("https://"),
            "{e}"
        );
    }
}
