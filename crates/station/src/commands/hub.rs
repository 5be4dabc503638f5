//! `telerehab hub`: the clinic's system of record — `init` a data directory, `serve` the
//! stations (mutual TLS) and the therapist console API (HTTPS), add patients (each with a
//! one-time pairing code), show a patient's sessions, revoke a station, add therapists.

use anyhow::{Context, bail};
use hub::clinic::{Bound, Clinic, ServeOptions};
use hub::db::{Db, Role};
use std::io::Write;
use std::path::PathBuf;
use std::sync::Arc;

/// How long a pairing code lives, ms (72 h).
const PAIRING_TTL_MS: i64 = 72 * 3600 * 1000;

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

fn now_ms() -> i64 {
    hub::web::system_now_ms()
}

fn runtime() -> anyhow::Result<tokio::runtime::Runtime> {
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
    runtime()?.block_on(async move {
        match args.command {
            HubCommand::Init { data, admin, names } => init(&data, &admin, &names).await,
            HubCommand::Serve {
                data,
                stations,
                web,
            } => serve(&data, &stations, web.as_deref()).await,
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
                let password = hub::clinic::one_time_password()?;
                let role = if admin { Role::Admin } else { Role::Therapist };
                let t = db.add_therapist(&email, &password, role, now_ms()).await?;
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

async fn serve(data: &DataArgs, stations: &str, web: Option<&str>) -> anyhow::Result<()> {
    let (clinic, db) = open(data).await?;
    let stations = crate::link::resolve("--stations", stations)?;
    let web = web.map(|w| crate::link::resolve("--web", w)).transpose()?;
    let options = ServeOptions {
        stations,
        web,
        validate_regimen: Arc::new(|text: &str| {
            crate::regimen::Regimen::from_toml(text, "the prescribed regimen")
                .map(drop)
                .map_err(|e| e.to_string())
        }),
        now_ms: Arc::new(now_ms),
    };
    let mut sigterm = tokio::signal::unix::signal(tokio::signal::unix::SignalKind::terminate())
        .context("cannot install the SIGTERM handler")?;
    let shutdown = async move {
        tokio::select! {
            _ = tokio::signal::ctrl_c() => {}
            _ = sigterm.recv() => {}
        }
    };
    let on_bound = |b: Bound| {
        // The first lines say where the hub listens (tests parse them; port 0 picks one).
        println!("stations listening on {} (mutual TLS)", b.stations);
        if let Some(w) = b.web {
            println!("console API on https://{w}/api/");
        }
        let _ = std::io::stdout().flush();
    };
    let on_event = |ev: &netlink::TherapistEvent| {
        println!("{ev}");
        let _ = std::io::stdout().flush();
    };
    hub::clinic::serve(&clinic, db, options, on_bound, on_event, shutdown).await?;
    println!("hub stopped");
    Ok(())
}

async fn patient(command: PatientCommand) -> anyhow::Result<()> {
    match command {
        PatientCommand::Add {
            data,
            pseudonym,
            therapist,
        } => {
            let (_, db) = open(&data).await?;
            let therapist_id = match &therapist {
                Some(email) => Some(
                    db.therapist_by_email(email)
                        .await?
                        .with_context(|| format!("no therapist {email}"))?
                        .id,
                ),
                None => None,
            };
            let p = db
                .add_patient(&pseudonym, therapist_id.as_deref(), now_ms())
                .await?;
            db.audit("cli", "add_patient", &p.id, &pseudonym, now_ms())
                .await?;
            print_code(&db, &p.id, &pseudonym).await
        }
        PatientCommand::Code { data, pseudonym } => {
            let (_, db) = open(&data).await?;
            let p = find(&db, &pseudonym).await?;
            print_code(&db, &p.id, &pseudonym).await
        }
        PatientCommand::Show {
            data,
            pseudonym,
            json,
        } => {
            let (_, db) = open(&data).await?;
            let p = find(&db, &pseudonym).await?;
            let stations = db.stations_of(&p.id).await?;
            let sessions = db.sessions_of(&p.id).await?;
            db.audit("cli", "show_patient", &p.id, "", now_ms()).await?;
            if json {
                let mut rows = Vec::with_capacity(sessions.len());
                for s in &sessions {
                    let stored = db.summaries_of(&s.session_id).await?.len();
                    rows.push(serde_json::json!({ "session": s, "summaries_stored": stored }));
                }
                let out =
                    serde_json::json!({ "patient": p, "stations": stations, "sessions": rows });
                println!("{}", serde_json::to_string_pretty(&out)?);
                return Ok(());
            }
            println!("patient {} ({})", p.pseudonym, p.id);
            for st in &stations {
                let state = if st.is_revoked() { "REVOKED" } else { "active" };
                println!(
                    "  station {} {state}, paired {}",
                    st.station_id, st.paired_at_ms
                );
            }
            println!(
                "  {:<44} {:<16} {:>10} {:>9} {:>10}",
                "session", "exercise", "start (ms)", "length s", "summaries"
            );
            for s in &sessions {
                let stored = db.summaries_of(&s.session_id).await?;
                let length_s = stored.last().map_or(0.0, |x| x.t_s);
                println!(
                    "  {:<44} {:<16} {:>10} {:>9.1} {:>10}",
                    s.session_id,
                    s.exercise,
                    s.started_unix_ms,
                    length_s,
                    stored.len()
                );
            }
            Ok(())
        }
    }
}

async fn find(db: &Db, pseudonym: &str) -> anyhow::Result<hub::db::Patient> {
    match db.patient_by_pseudonym(pseudonym).await? {
        Some(p) => Ok(p),
        None => bail!("no patient with pseudonym {pseudonym:?}"),
    }
}

async fn print_code(db: &Db, patient_id: &str, pseudonym: &str) -> anyhow::Result<()> {
    let code = db
        .create_pairing_code(patient_id, now_ms(), PAIRING_TTL_MS)
        .await?;
    db.audit("cli", "pairing_code", patient_id, "", now_ms())
        .await?;
    println!("patient {pseudonym} ({patient_id})");
    println!("pairing code: {code}  (single use, valid 72 h)");
    println!("on the patient's computer: telerehab pair --hub HUB:7878 --code {code}");
    Ok(())
}
