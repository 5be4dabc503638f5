//! `telerehab hub`: the clinic's system of record — `init` a data directory, `serve` the
//! stations (mutual TLS) and the therapist console API (HTTPS), add patients (each with a
//! one-time pairing code), show a patient's sessions, revoke a station, add therapists.
//! The database work of `hub patient …` is in `hub_care::patients`: here the arguments are
//! parsed and the answers printed.

pub mod backup;
pub mod care;

use crate::clinic::{Bound, Clinic, ServeOptions};
use anyhow::{Context, bail};
use hub_care::patients;
use hub_store::db::{Db, Role};
use std::io::Write;
use std::path::PathBuf;

/// `telerehab hub`.
#[derive(Debug, clap::Args)]
pub struct HubArgs {
    /// What to do.
    #[command(subcommand)]
    pub command: HubCommand,
}

/// The clinic's data directory and database, shared by every `hub` subcommand.
#[derive(Debug, Clone, clap::Args)]
pub struct DataArgs {
    /// The clinic's data directory (database, CA, hub certificate).
    #[arg(long, value_name = "DIR")]
    pub data: PathBuf,
    /// Database URL (`postgres://…` for PostgreSQL); default the one `hub init` chose.
    #[arg(long, value_name = "URL", env = "TELEREHAB_HUB_DB")]
    pub db: Option<String>,
}

/// `telerehab hub …`.
#[derive(Debug, clap::Subcommand)]
pub enum HubCommand {
    /// Make a clinic: database, CA, hub certificate and the first admin (prints a one-time
    /// password).
    Init {
        /// Data directory and database.
        #[command(flatten)]
        data: DataArgs,
        /// The first admin's e-mail (their login to the console).
        #[arg(long)]
        admin: String,
        /// Names on the hub's certificate, as stations will reach it (repeatable).
        #[arg(long = "name", default_values_t = ["localhost".to_owned(), "127.0.0.1".to_owned()])]
        names: Vec<String>,
    },
    /// Serve stations and the console until SIGINT/SIGTERM.
    Serve {
        /// Data directory and database.
        #[command(flatten)]
        data: DataArgs,
        /// Address for stations, `host:port` (mutual TLS).
        #[arg(long, default_value = "0.0.0.0:7878")]
        stations: String,
        /// Address of the therapists' console API, `host:port` (HTTPS).
        #[arg(long)]
        web: Option<String>,
        /// Most stations connected at once (admitted). Like every cap here, shrunk at start
        /// (with a warning) to fit the open-file limit, which is raised to the hard limit.
        #[arg(long, default_value_t = netlink::therapist::DEFAULT_MAX_CONNECTIONS)]
        max_connections: usize,
        /// Most station-port connections from one address not admitted yet (TLS handshake,
        /// Hello, pairing); admitted stations do not count, so a NAT may hide any number.
        /// Behind a load balancer the address is the client's, from the PROXY protocol header
        /// of a balancer named in hub.toml's `[network] proxy_protocol_from` (docs/DEPLOY.md).
        #[arg(long, default_value_t = netlink::therapist::DEFAULT_MAX_CONNECTIONS_PER_ADDRESS)]
        max_connections_per_address: usize,
        /// Most station-port connections not admitted yet, from all addresses; a new one over
        /// the cap replaces the oldest still waiting for its first frame.
        #[arg(long, default_value_t = netlink::therapist::DEFAULT_MAX_UNAUTHENTICATED)]
        max_unauthenticated: usize,
        /// Print a line for every summary received (a demo; connections, ends and errors are
        /// always printed).
        #[arg(long)]
        print_summaries: bool,
        /// Largest recording file the console replays, MB (a replay is read as a stream in
        /// bounded memory; this bounds the time it takes).
        #[arg(long, default_value_t = crate::web::DEFAULT_MAX_REPLAY_BYTES >> 20)]
        max_replay_mb: u64,
        /// Pain threshold, clinic phone, pairing sheets' address and pain mails.
        #[command(flatten)]
        care: care::CareArgs,
        /// The operator's address, `host:port`, for `/metrics`, `/healthz` and `/readyz` over
        /// plain HTTP (loopback or a management network, never 0.0.0.0); default: hub.toml's
        /// `metrics_listen`, else none.
        #[arg(long, value_name = "HOST:PORT")]
        metrics_listen: Option<String>,
        /// Seconds `/readyz` answers 503 (draining) after SIGTERM while both ports still
        /// serve, so a load balancer moves new clients away first.
        #[arg(long, default_value_t = 0.0)]
        drain_s: f64,
    },
    /// Load test: N simulated stations on loopback against a hub in a child process, in a
    /// fresh clinic (SQLite, or the empty database `--db` names).
    Bench {
        /// Simulated stations.
        #[arg(long, default_value_t = 100)]
        stations: usize,
        /// Summaries per second from each station.
        #[arg(long, default_value_t = 10.0)]
        rate_hz: f64,
        /// Length of the load, s.
        #[arg(long, default_value_t = 20.0)]
        seconds: f64,
        /// Database URL (an empty PostgreSQL database); default SQLite in a temporary clinic.
        #[arg(long)]
        db: Option<String>,
        /// Run the hub on these CPUs only (a `taskset -c` list, e.g. `0`), so that the load
        /// generator (pin it with `taskset -c 1 telerehab hub bench …`) does not share them.
        #[arg(long)]
        hub_cpus: Option<String>,
        /// Runs (each a fresh hub process and new sessions on the same clinic); the report
        /// gives each run and the median and spread (min–max).
        #[arg(long, default_value_t = 3)]
        runs: u32,
        /// Hub processes sharing the database (`--db`, PostgreSQL) behind a TCP balancer
        /// (HAProxy, `mode tcp`, least connections), as a clinic network runs them; their CPU
        /// is reported together.
        #[arg(long, default_value_t = 1)]
        hubs: usize,
    },
    /// A patient's record for an electronic health record: a FHIR R4 `Bundle` (pseudonymous
    /// Patient, the regimen as CarePlan and ServiceRequest, an Observation per session and per
    /// clinical scale, the check-ins as QuestionnaireResponses; the hub's codes under
    /// hub.toml's `fhir_base`; docs/FHIR.md), audited.
    Export {
        /// Data directory and database.
        #[command(flatten)]
        data: DataArgs,
        /// The patient's pseudonym.
        #[arg(long, value_name = "PSEUDONYM")]
        fhir: String,
        /// The language of the bundle's narratives (en, de, es, zh; a region allowed: de-AT);
        /// English when absent.
        #[arg(long, value_name = "LANGUAGE")]
        lang: Option<String>,
        /// The bundle's file (JSON); `-` for standard output.
        #[arg(long, value_name = "FILE")]
        out: PathBuf,
    },
    /// Back the clinic up into one file while the hub serves: the database (SQLite's online
    /// copy or a PostgreSQL dump, one consistent snapshot), the CA and hub certificate, the
    /// erasure ledger and every recording; row counts and checksums in its manifest. Encrypted
    /// (age) to hub.toml's backup_recipients (`hub backup-key` makes the key pair); refused
    /// without one unless `--unencrypted`.
    Backup {
        /// Data directory and database.
        #[command(flatten)]
        data: DataArgs,
        /// The backup file to make (`.tar.zst.age`; `.tar.zst` when unencrypted); never
        /// overwritten.
        #[arg(long, value_name = "FILE")]
        out: PathBuf,
        /// Write it in clear (it holds the CA's key and every patient's data: only for a
        /// disk that is itself encrypted and guarded).
        #[arg(long)]
        unencrypted: bool,
    },
    /// Make the clinic's backup key pair: the identity file (the secret key; keep it offline,
    /// away from this machine: it restores the backups) and its recipient (`age1…`), added to
    /// hub.toml's backup_recipients. Or add a recipient made elsewhere (`age-keygen`).
    BackupKey {
        /// Data directory.
        #[arg(long, value_name = "DIR")]
        data: PathBuf,
        /// The identity file to write (new, 0600).
        #[arg(long, value_name = "FILE", required_unless_present = "recipient")]
        identity_out: Option<PathBuf>,
        /// An existing recipient to add instead (`age1…`).
        #[arg(long, value_name = "AGE1…", conflicts_with = "identity_out")]
        recipient: Option<String>,
    },
    /// Restore a backup into a new data directory (and, for a PostgreSQL backup, the empty
    /// database `--db` names), checking every table's rows and every recording's checksum,
    /// then erasing again every patient erased since (the backup's ledger, the database's
    /// tombstones and `--erasures`).
    Restore {
        /// The backup file.
        #[arg(long, value_name = "FILE")]
        from: PathBuf,
        /// The new data directory (absent or empty).
        #[arg(long, value_name = "DIR")]
        data: PathBuf,
        /// An empty PostgreSQL database for a PostgreSQL backup (`postgres://…`).
        #[arg(long, value_name = "URL")]
        db: Option<String>,
        /// The clinic's backup identity file, for an encrypted backup.
        #[arg(long, value_name = "FILE")]
        identity: Option<PathBuf>,
        /// An erasure ledger to re-apply too (the clinic's current `erasures.ndjson`, or its
        /// copy kept off the machine); repeatable.
        #[arg(long, value_name = "FILE")]
        erasures: Vec<PathBuf>,
    },
    /// Patients.
    #[command(subcommand)]
    Patient(PatientCommand),
    /// Stations.
    #[command(subcommand)]
    Station(StationCommand),
    /// Therapists (console logins).
    #[command(subcommand)]
    Therapist(TherapistCommand),
}

/// `telerehab hub patient …`.
#[derive(Debug, clap::Subcommand)]
pub enum PatientCommand {
    /// Add a patient by pseudonym (never a name) and print a pairing code for their station.
    Add {
        /// Data directory and database.
        #[command(flatten)]
        data: DataArgs,
        /// The clinic's pseudonym, e.g. `P-0042`.
        #[arg(long)]
        pseudonym: String,
        /// The therapist in charge (e-mail); default none (admins see every patient).
        #[arg(long)]
        therapist: Option<String>,
    },
    /// A new pairing code for an existing patient (a new or replaced station).
    Code {
        /// Data directory and database.
        #[command(flatten)]
        data: DataArgs,
        /// The patient's pseudonym.
        pseudonym: String,
    },
    /// Prescribe a regimen (TOML, as `regimens/*.toml`): validated against the station's
    /// safety bounds, stored as a new version, pushed to the patient's station.
    Regimen {
        /// Data directory and database.
        #[command(flatten)]
        data: DataArgs,
        /// The patient's pseudonym.
        pseudonym: String,
        /// The regimen file.
        #[arg(long)]
        file: PathBuf,
        /// The prescribing therapist's e-mail.
        #[arg(long)]
        by: String,
    },
    /// A patient's stations and sessions.
    Show {
        /// Data directory and database.
        #[command(flatten)]
        data: DataArgs,
        /// The patient's pseudonym.
        pseudonym: String,
        /// Print JSON instead of a table.
        #[arg(long)]
        json: bool,
    },
    /// Everything the hub holds about a patient (sessions, summaries, measures, regimens,
    /// messages, recordings, the audit entries about them) in one archive (`.tar.zst`:
    /// `patient.json` and the recordings), for the patient's request; audited.
    Export {
        /// Data directory and database.
        #[command(flatten)]
        data: DataArgs,
        /// The patient's pseudonym.
        pseudonym: String,
        /// The archive to write; never overwritten.
        #[arg(long, value_name = "FILE")]
        out: PathBuf,
    },
    /// Erase everything the hub holds about a patient, recordings included, on their request:
    /// their stations are revoked first; one audit entry records the erasure (how much, none
    /// of the data). Cannot be undone: export first if the patient wants a copy.
    Erase {
        /// Data directory and database.
        #[command(flatten)]
        data: DataArgs,
        /// The patient's pseudonym.
        pseudonym: String,
        /// The pseudonym again, to confirm (asked for on a terminal when absent).
        #[arg(long, value_name = "PSEUDONYM")]
        confirm: Option<String>,
    },
}

/// `telerehab hub station …`.
#[derive(Debug, clap::Subcommand)]
pub enum StationCommand {
    /// Revoke a station: refused from its next frame on.
    Revoke {
        /// Data directory and database.
        #[command(flatten)]
        data: DataArgs,
        /// The station id (`hub patient show` lists them).
        station_id: String,
    },
}

/// `telerehab hub therapist …`.
#[derive(Debug, clap::Subcommand)]
pub enum TherapistCommand {
    /// Add a therapist; prints their one-time password.
    Add {
        /// Data directory and database.
        #[command(flatten)]
        data: DataArgs,
        /// Their e-mail (console login).
        #[arg(long)]
        email: String,
        /// Make them an admin (sees every patient and the audit log).
        #[arg(long)]
        admin: bool,
    },
}

pub(crate) fn now_ms() -> i64 {
    hub_care::live::system_now_ms()
}

/// The runtime every `hub` subcommand runs on: two workers (the hub's threads are named `hub`).
pub fn runtime() -> anyhow::Result<tokio::runtime::Runtime> {
    tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .thread_name("hub")
        .enable_all()
        .build()
        .context("cannot start the hub's runtime")
}

async fn open(data: &DataArgs) -> anyhow::Result<(Clinic, Db)> {
    let clinic = Clinic::at(&data.data);
    let db = clinic.open_db(data.db.as_deref()).await?;
    Ok((clinic, db))
}

/// Run a `hub` subcommand.
pub fn run(args: HubArgs) -> anyhow::Result<()> {
    netlink::server_stop::run_to_stop(runtime()?, async move {
        match args.command {
            HubCommand::Init { data, admin, names } => init(&data, &admin, &names).await,
            HubCommand::Serve {
                data,
                stations,
                web,
                max_connections,
                max_connections_per_address,
                max_unauthenticated,
                print_summaries,
                max_replay_mb,
                care,
                metrics_listen,
                drain_s,
            } => {
                let limits = (max_connections, max_connections_per_address);
                let caps = crate::clinic::HubLimits {
                    max_unauthenticated_stations: max_unauthenticated,
                    ..Default::default()
                };
                let listen = (stations.as_str(), web.as_deref());
                let max_replay_bytes = max_replay_mb.saturating_mul(1 << 20);
                serve(
                    &data,
                    listen,
                    limits,
                    caps,
                    (print_summaries, &care),
                    max_replay_bytes,
                    (metrics_listen.as_deref(), drain_s),
                )
                .await
            }
            HubCommand::Bench {
                stations,
                rate_hz,
                seconds,
                db,
                hub_cpus,
                runs,
                hubs,
            } => {
                let load = BenchLoad {
                    stations,
                    rate_hz,
                    seconds,
                    runs,
                    hubs,
                };
                bench(load, db.as_deref(), hub_cpus.as_deref()).await
            }
            HubCommand::Export {
                data,
                fhir,
                lang,
                out,
            } => backup::export_fhir(&data, &fhir, lang.as_deref(), &out).await,
            HubCommand::Backup {
                data,
                out,
                unencrypted,
            } => backup::backup(&data.data, data.db.as_deref(), &out, unencrypted).await,
            HubCommand::BackupKey {
                data,
                identity_out,
                recipient,
            } => backup::backup_key(&data, identity_out.as_deref(), recipient.as_deref()),
            HubCommand::Restore {
                from,
                data,
                db,
                identity,
                erasures,
            } => {
                let from_ = crate::backup::RestoreFrom {
                    identity: identity.as_deref(),
                    db_url: db.as_deref(),
                    erasures: &erasures,
                };
                backup::restore(&from, &data, from_).await
            }
            HubCommand::Patient(c) => patient(c).await,
            HubCommand::Station(StationCommand::Revoke { data, station_id }) => {
                let (_, db) = open(&data).await?;
                db.revoke_station(&station_id, now_ms()).await?;
                db.audit("cli", "revoke_station", &station_id, "", now_ms())
                    .await?;
                println!("station {station_id} revoked: refused from its next frame on");
                Ok(())
            }
            HubCommand::Therapist(TherapistCommand::Add { data, email, admin }) => {
                let (_, db) = open(&data).await?;
                let password = crate::clinic::one_time_password()?;
                let role = if admin { Role::Admin } else { Role::Therapist };
                let t = db.add_therapist(&email, &password, role, now_ms()).await?;
                db.require_password_change(&t.id).await?;
                db.audit("cli", "add_therapist", &t.actor(), role.as_str(), now_ms())
                    .await?;
                println!(
                    "therapist {email} added ({}); one-time password: {password}",
                    role.as_str()
                );
                Ok(())
            }
        }
    })
}

async fn init(data: &DataArgs, admin: &str, names: &[String]) -> anyhow::Result<()> {
    let clinic = Clinic::at(&data.data);
    let done = clinic
        .init(admin, names, data.db.as_deref(), now_ms())
        .await?;
    println!("clinic created in {}", data.data.display());
    println!("database: {}", redact(&done.database));
    println!("hub certificate names: {}", names.join(", "));
    println!("admin {admin}, one-time password: {}", done.admin_password);
    println!("(shown once; only its hash is stored — change it at first login)");
    println!(
        "to run it as a service: the unit telerehab-hub.service (packaging/ in the sources) serves \
         /var/lib/telerehab-hub as the user telerehab-hub, its addresses in \
         /etc/telerehab/hub.env; `systemctl enable --now telerehab-hub`"
    );
    Ok(())
}

/// A database URL without its password.
fn redact(url: &str) -> String {
    match (url.find("://"), url.rfind('@')) {
        (Some(scheme), Some(at)) if at > scheme => {
            let creds = &url[scheme + 3..at];
            let user = creds.split(':').next().unwrap_or_default();
            format!("{}{user}:***{}", &url[..scheme + 3], &url[at..])
        }
        _ => url.to_owned(),
    }
}

async fn serve(
    data: &DataArgs,
    (stations, web): (&str, Option<&str>),
    max_connections: (usize, usize),
    limits: crate::clinic::HubLimits,
    (print_summaries, care): (bool, &care::CareArgs),
    max_replay_bytes: u64,
    (metrics, drain_s): (Option<&str>, f64),
) -> anyhow::Result<()> {
    let (clinic, db) = open(data).await?;
    // Erasures stay erased: a patient a tombstone names is erased again before anyone is
    // served (nothing to do unless the database came back from an older copy).
    let again = crate::patient_data::tombstones::reapply(&clinic, &db, &[], now_ms()).await?;
    if again.erased > 0 {
        println!(
            "{} erased patients came back with an older database: erased again ({} erasures on record)",
            again.erased, again.tombstones
        );
    }
    let stations = netlink::address::resolve("--stations", stations)?;
    let web = web
        .map(|w| netlink::address::resolve("--web", w))
        .transpose()?;
    let metrics = metrics
        .map(|m| netlink::address::resolve("--metrics-listen", m))
        .transpose()?;
    let drain = std::time::Duration::try_from_secs_f64(drain_s)
        .ok()
        .filter(|d| *d <= std::time::Duration::from_secs(600))
        .ok_or_else(|| anyhow::anyhow!("--drain-s must be 0 to 600 seconds, not {drain_s}"))?;
    let options = ServeOptions {
        stations,
        web,
        max_connections,
        limits,
        max_replay_bytes,
        care: care.config(),
        public_station_address: care.public_station_address.clone(),
        metrics,
        drain,
        ..ServeOptions::new(stations, web)
    };
    let stop = netlink::server_stop::stop_signal()?;
    let shutdown = async move {
        let signal = stop.await;
        println!("{signal}: hub stopping");
        let _ = std::io::stdout().flush();
    };
    let on_bound = |b: Bound| {
        // The first lines say where the hub listens (tests parse them; port 0 picks one).
        println!("stations listening on {} (mutual TLS)", b.stations);
        if let Some(w) = b.web {
            println!("console API on https://{w}/api/");
        }
        if let Some(m) = b.metrics {
            println!("metrics on http://{m}/metrics");
        }
        let _ = std::io::stdout().flush();
    };
    let on_event = move |ev: &netlink::TherapistEvent| {
        if !print_summaries && matches!(ev, netlink::TherapistEvent::Summary { .. }) {
            return;
        }
        println!("{ev}");
        let _ = std::io::stdout().flush();
    };
    crate::clinic::serve(&clinic, db, options, on_bound, on_event, shutdown).await?;
    println!("hub stopped");
    Ok(())
}

/// What `hub bench` loads the hub with.
struct BenchLoad {
    stations: usize,
    rate_hz: f64,
    seconds: f64,
    runs: u32,
    hubs: usize,
}

/// `hub bench`: a fresh clinic, `stations` provisioned, then `runs` runs, each against a new
/// hub child process.
async fn bench(load: BenchLoad, db: Option<&str>, hub_cpus: Option<&str>) -> anyhow::Result<()> {
    let BenchLoad {
        stations,
        rate_hz,
        seconds,
        runs,
        hubs,
    } = load;
    if !((1..=20_000).contains(&stations) && rate_hz > 0.0 && rate_hz <= 1000.0) {
        bail!("--stations must be 1 to 20000 and --rate-hz in (0, 1000]");
    }
    if !(seconds.is_finite() && seconds >= 1.0) {
        bail!("--seconds must be at least 1");
    }
    if !(1..=100).contains(&runs) {
        bail!("--runs must be 1 to 100");
    }
    if !(1..=16).contains(&hubs) {
        bail!("--hubs must be 1 to 16");
    }
    if hubs > 1 && db.is_none() {
        bail!(
            "--hubs {hubs} needs --db: several hubs share one PostgreSQL database (SQLite is one hub's)"
        );
    }
    let tmp = tempfile::tempdir().context("cannot make a temporary clinic")?;
    let data = tmp.path().join("clinic");
    let clinic = Clinic::at(&data);
    clinic
        .init(
            "bench@clinic.example",
            &["localhost".to_owned()],
            db,
            now_ms(),
        )
        .await?;
    let hub_db = clinic.open_db(db).await?;
    println!("provisioning {stations} stations…");
    let provisioned = crate::bench::provision(
        &hub_db,
        &clinic.ca()?,
        "localhost",
        stations,
        &tmp.path().join("stations"),
        now_ms(),
    )
    .await?;
    hub_db.checkpoint().await?;
    let size_before = hub_db.size_bytes().await?;
    hub_db.close().await;
    // The PostgreSQL server's CPU is counted too: it does half of the storing.
    let postmaster = db.and_then(crate::bench::postgres_server);
    if db.is_some() && postmaster.is_none() {
        println!("(the PostgreSQL server's process is not visible here: its CPU is not counted)");
    }
    println!(
        "hub bench: {stations} stations × {rate_hz} Hz for {seconds} s on {}{}{}, {runs} runs",
        if hubs > 1 {
            format!("{hubs} hubs behind HAProxy, ")
        } else {
            String::new()
        },
        if db.is_some() { "PostgreSQL" } else { "SQLite" },
        hub_cpus.map_or(String::new(), |c| format!(", hub on CPUs {c}"))
    );
    let mut figures = Vec::new();
    for run in 0..runs {
        let spec = (data.as_path(), db, hub_cpus, postmaster);
        let f = bench_run(spec, &provisioned, (rate_hz, seconds, hubs), run, stations).await?;
        figures.push(f);
    }
    if runs > 1 {
        print!("{}", crate::bench::describe_runs(&figures));
    }
    let hub_db = clinic.open_db(db).await?;
    hub_db.scrub().await?;
    let grown = hub_db.size_bytes().await? - size_before;
    hub_db.close().await;
    let stored: u64 = figures.iter().map(|f| f.acked).sum();
    if stored > 0 {
        println!(
            "database grew {:.1} MB: {:.0} bytes per summary stored (tables and indexes, no log)",
            grown as f64 / 1e6,
            grown as f64 / stored as f64
        );
    }
    Ok(())
}

/// One hub child process of a bench run and the address its station port listens on.
async fn spawn_bench_hub(
    args: &[&str],
    hub_cpus: Option<&str>,
) -> anyhow::Result<(tokio::process::Child, std::net::SocketAddr)> {
    let exe = std::env::current_exe()?;
    let mut command = match hub_cpus {
        Some(cpus) => {
            let mut c = tokio::process::Command::new("taskset");
            c.args(["-c", cpus]).arg(&exe);
            c
        }
        None => tokio::process::Command::new(&exe),
    };
    let mut child = command
        .args(args)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::null())
        .kill_on_drop(true)
        .spawn()
        .context("cannot start the hub")?;
    let stdout = child.stdout.take().context("hub stdout")?;
    let mut lines = tokio::io::AsyncBufReadExt::lines(tokio::io::BufReader::new(stdout));
    let first = lines.next_line().await?.context("the hub said nothing")?;
    let addr: std::net::SocketAddr = first
        .strip_prefix("stations listening on ")
        .and_then(|r| r.split_whitespace().next())
        .with_context(|| format!("unexpected first line {first:?}"))?
        .parse()?;
    tokio::spawn(async move { while let Ok(Some(_)) = lines.next_line().await {} });
    Ok((child, addr))
}

/// The CPU time (s) of `pids` together and the largest peak RSS (MiB) among them.
fn usage_of(pids: &[u32]) -> Option<(f64, f64)> {
    pids.iter().try_fold((0.0, 0.0_f64), |(cpu, rss), &pid| {
        crate::bench::process_usage(pid).map(|(c, r)| (cpu + c, rss.max(r)))
    })
}

/// One run: `hubs` hub child processes (behind HAProxy when more than one), the load, its
/// figures (printed).
async fn bench_run(
    (data, db, hub_cpus, postmaster): (&std::path::Path, Option<&str>, Option<&str>, Option<u32>),
    provisioned: &[crate::bench::BenchStation],
    (rate_hz, seconds, hubs): (f64, f64, usize),
    run: u32,
    stations: usize,
) -> anyhow::Result<crate::bench::RunFigures> {
    let limit = (stations + 16).to_string();
    let mut args = vec![
        "hub",
        "serve",
        "--data",
        data.to_str().context("temporary path")?,
    ];
    args.extend(["--stations", "127.0.0.1:0", "--max-connections", &limit]);
    args.extend(["--max-connections-per-address", &limit]);
    // Every simulated station connects at once, all from 127.0.0.1 (or from the balancer).
    args.extend(["--max-unauthenticated", &limit]);
    if let Some(url) = db {
        args.extend(["--db", url]);
    }
    let mut children = Vec::with_capacity(hubs);
    let mut addrs = Vec::with_capacity(hubs);
    for _ in 0..hubs {
        let (child, addr) = spawn_bench_hub(&args, hub_cpus).await?;
        children.push(child);
        addrs.push(addr);
    }
    let balancer = if hubs > 1 {
        Some(crate::bench::balancer::Balancer::start(&addrs, stations).await?)
    } else {
        None
    };
    let addr = balancer.as_ref().map_or(addrs[0], |b| b.addr);
    let pids: Vec<u32> = children
        .iter()
        .filter_map(tokio::process::Child::id)
        .collect();
    let balancer_pid = balancer
        .as_ref()
        .and_then(crate::bench::balancer::Balancer::pid);
    let before = usage_of(&pids);
    let each_before: Vec<_> = pids
        .iter()
        .map(|&p| crate::bench::process_usage(p))
        .collect();
    let balancer_before = balancer_pid.and_then(crate::bench::process_usage);
    let generator_before = crate::bench::process_usage(std::process::id());
    let db_before = postmaster.and_then(crate::bench::postgres_cpu_s);
    let report = crate::bench::load_run(
        addr,
        provisioned.to_vec(),
        rate_hz,
        std::time::Duration::from_secs_f64(seconds),
        run + 1,
    )
    .await;
    let after = usage_of(&pids);
    let each_after: Vec<_> = pids
        .iter()
        .map(|&p| crate::bench::process_usage(p))
        .collect();
    let balancer_after = balancer_pid.and_then(crate::bench::process_usage);
    let generator_after = crate::bench::process_usage(std::process::id());
    let db_after = postmaster.and_then(crate::bench::postgres_cpu_s);
    let usage = before.zip(after).map(|(b, a)| (a.0 - b.0, a.1));
    if let Some(b) = balancer {
        b.stop().await;
    }
    for mut child in children {
        let _ = child.kill().await;
    }
    println!("run {}:", run + 1);
    print!(
        "{}",
        crate::bench::describe(&report, seconds, rate_hz, usage)
    );
    let pct = |b: Option<(f64, f64)>, a: Option<(f64, f64)>| {
        b.zip(a).map(|(b, a)| 100.0 * (a.0 - b.0) / seconds)
    };
    if hubs > 1 {
        let each: Vec<String> = each_before
            .iter()
            .zip(&each_after)
            .map(|(b, a)| pct(*b, *a).map_or("?".to_owned(), |p| format!("{p:.0}")))
            .collect();
        println!(
            "each hub's CPU {} % of one core (the balancer's spread)",
            each.join(" / ")
        );
    }
    if let Some(p) = pct(balancer_before, balancer_after) {
        println!("HAProxy CPU {p:.0} % of one core");
    }
    let db_cpu_pct = db_before
        .zip(db_after)
        .map(|(b, a)| 100.0 * (a - b) / seconds);
    if let Some(pct) = db_cpu_pct {
        println!("PostgreSQL server CPU {pct:.0} % of one core (postmaster and its processes)");
    }
    if let Some(p) = pct(generator_before, generator_after) {
        // The latency is measured here: a saturated generator reads its Acks late.
        println!("load generator CPU {p:.0} % of one core (this process)");
    }
    Ok(crate::bench::RunFigures {
        p50_ms: report.latency_ms.0,
        p99_ms: report.latency_ms.1,
        hub_cpu_pct: usage.map_or(f64::NAN, |(cpu, _)| 100.0 * cpu / seconds),
        db_cpu_pct,
        lost: report.sent.saturating_sub(report.acked),
        acked: report.acked,
    })
}

async fn patient(command: PatientCommand) -> anyhow::Result<()> {
    match command {
        PatientCommand::Export {
            data,
            pseudonym,
            out,
        } => backup::export_patient(&data.data, data.db.as_deref(), &pseudonym, &out).await?,
        PatientCommand::Erase {
            data,
            pseudonym,
            confirm,
        } => {
            backup::erase_patient(&data.data, data.db.as_deref(), &pseudonym, confirm).await?;
        }
        PatientCommand::Add {
            data,
            pseudonym,
            therapist,
        } => {
            let (_, db) = open(&data).await?;
            let code = patients::add(&db, &pseudonym, therapist.as_deref(), now_ms()).await?;
            print_code(&code, &pseudonym);
        }
        PatientCommand::Code { data, pseudonym } => {
            let (_, db) = open(&data).await?;
            let code = patients::new_code(&db, &pseudonym, now_ms()).await?;
            print_code(&code, &pseudonym);
        }
        PatientCommand::Regimen {
            data,
            pseudonym,
            file,
            by,
        } => {
            let (_, db) = open(&data).await?;
            let text = std::fs::read_to_string(&file)
                .with_context(|| format!("cannot read {}", file.display()))?;
            let origin = file.display().to_string();
            let version =
                patients::prescribe(&db, &pseudonym, &text, &origin, &by, now_ms()).await?;
            println!(
                "regimen version {version} for {pseudonym}: sent to the station when it next connects"
            );
        }
        PatientCommand::Show {
            data,
            pseudonym,
            json,
        } => {
            let (_, db) = open(&data).await?;
            let report = patients::show(&db, &pseudonym, now_ms()).await?;
            if json {
                println!("{}", serde_json::to_string_pretty(&report_json(&report))?);
            } else {
                print_report(&report, now_ms());
            }
        }
    }
    Ok(())
}

/// `hub patient show --json`.
fn report_json(report: &patients::PatientReport) -> serde_json::Value {
    let rows: Vec<_> = report
        .sessions
        .iter()
        .map(|s| {
            serde_json::json!({
                "session": s.session,
                "summaries_stored": s.summaries_stored,
                "recording": s.recording,
                "metrics": s.metrics,
                "exercises": s.exercises,
            })
        })
        .collect();
    serde_json::json!({
        "patient": report.patient,
        "stations": report.stations,
        "sessions": rows,
        "checkins": report.checkins,
        "difficulty": report.difficulty,
    })
}

/// `hub patient show`, for people.
fn print_report(report: &patients::PatientReport, now_ms: i64) {
    let p = &report.patient;
    println!("patient {} ({})", p.pseudonym, p.id);
    for st in &report.stations {
        let state = if st.is_revoked() { "REVOKED" } else { "active" };
        println!(
            "  station {} {state}, paired {}",
            st.station_id, st.paired_at_ms
        );
    }
    println!(
        "  {:<44} {:<16} {:>10} {:>9} {:>10} {:>9} {:>6}  recording",
        "session", "exercise", "start (ms)", "length s", "summaries", "movements", "SPARC"
    );
    for s in &report.sessions {
        let measure = |name: &str, digits: usize| {
            s.metrics
                .get(name)
                .map_or("-".to_owned(), |v| format!("{v:.digits$}"))
        };
        println!(
            "  {:<44} {:<16} {:>10} {:>9.1} {:>10} {:>9} {:>6}  {}",
            s.session.session_id,
            s.session.exercise,
            s.session.started_unix_ms,
            s.length_s,
            s.summaries_stored,
            measure("movements", 0),
            measure("sparc_median", 2),
            recording_words(s.recording.as_ref(), now_ms)
        );
    }
}

/// A session's recording in `hub patient show` at `now_ms`: none yet, arriving (how much),
/// stopped arriving (nothing noted for [`hub_store::db::RECORDING_STALLED_AFTER_MS`]), or whole.
fn recording_words(recording: Option<&hub_store::db::Recording>, now_ms: i64) -> String {
    let mb = |bytes: i64| bytes as f64 / 1e6;
    match recording {
        None => "-".to_owned(),
        Some(r) if r.complete => format!("{:.1} MB", mb(r.size_bytes)),
        Some(r) => {
            let (got, of) = (mb(r.received_bytes), mb(r.size_bytes));
            match r.last_part_ms.map(|at| now_ms.saturating_sub(at)) {
                Some(silent_ms) if silent_ms > hub_store::db::RECORDING_STALLED_AFTER_MS => {
                    format!(
                        "stopped arriving: {got:.1} of {of:.1} MB, nothing for {} min",
                        silent_ms / 60_000
                    )
                }
                _ => format!("arriving: {got:.1} of {of:.1} MB"),
            }
        }
    }
}

fn print_code(code: &patients::PairingCode, pseudonym: &str) {
    let (patient_id, code) = (&code.patient_id, &code.code);
    println!("patient {pseudonym} ({patient_id})");
    println!("pairing code: {code}  (single use, valid 72 h)");
    println!("on the patient's computer: telerehab pair --hub HUB:7878 --code {code}");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_recording_silent_past_the_limit_is_shown_as_stopped_arriving_not_arriving() {
        let now = 100 * hub_store::db::RECORDING_STALLED_AFTER_MS;
        let mut r = hub_store::db::Recording {
            session_id: "s".to_owned(),
            sha256: "0".repeat(64),
            size_bytes: 7_400_000,
            received_bytes: 3_500_000,
            path: "p".to_owned(),
            complete: false,
            last_part_ms: Some(now - 5_000),
        };
        assert_eq!(recording_words(Some(&r), now), "arriving: 3.5 of 7.4 MB");
        r.last_part_ms = Some(now - 3 * hub_store::db::RECORDING_STALLED_AFTER_MS);
        assert_eq!(
            recording_words(Some(&r), now),
            "stopped arriving: 3.5 of 7.4 MB, nothing for 30 min"
        );
        r.last_part_ms = None;
        assert_eq!(recording_words(Some(&r), now), "arriving: 3.5 of 7.4 MB");
        r.complete = true;
        assert_eq!(recording_words(Some(&r), now), "7.4 MB");
        assert_eq!(recording_words(None, now), "-");
    }
}
