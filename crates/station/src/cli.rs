//! Command-line interface.

use crate::config::StationConfig;
use crate::session::{self, BodyKind, SessionOptions, haptic::Pacing};
use anyhow::{Context, bail};
use clap::{Parser, Subcommand, ValueEnum};
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

/// telerehab: home upper-limb rehabilitation with a force-feedback steering wheel.
#[derive(Debug, Parser)]
#[command(name = "telerehab", version, about, long_about = None)]
pub struct Cli {
    /// Log filter (e.g. `info`, `debug`, `station=trace`); overrides RUST_LOG.
    #[arg(long, global = true)]
    pub log: Option<String>,
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Run a patient session.
    Run(RunArgs),
    /// Run the therapist hub: receive live summaries from stations and store them.
    Therapist(TherapistArgs),
    /// List wheels, pedals, gamepads and IMUs.
    Devices,
    /// Finish the MCAP recording of a killed session into a complete file.
    Recover {
        /// The recording left by the killed session.
        input: PathBuf,
        /// Where to write the finished file.
        #[arg(long)]
        out: PathBuf,
    },
    /// Run the vehicle model offline on a CSV of driver inputs.
    Vehicle(crate::commands::vehicle::VehicleArgs),
}

/// Loop pacing.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Speed {
    /// 1 kHz on the wall clock.
    Realtime,
    /// As fast as the machine allows (simulation only; same results as real time).
    Max,
}

/// `telerehab run`.
#[derive(Debug, clap::Args)]
pub struct RunArgs {
    /// Use the simulated wheel, arm and patient instead of real devices.
    #[arg(long)]
    pub sim: bool,
    /// Open no window.
    #[arg(long)]
    pub headless: bool,
    /// Station configuration (TOML); command-line flags override it.
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// Session length, s.
    #[arg(long)]
    pub duration: Option<f64>,
    /// Seed for every random source of the simulation.
    #[arg(long)]
    pub seed: Option<u64>,
    /// Exercise to run, repeated to fill the session (one of: straight-road, sine-road,
    /// triangle-road, clothoid-road, sharp-turns, s-bend, lane-change, slalom, dial-sine,
    /// dial-multi-sine, dial-step, dial-ramp, dial-chirp).
    #[arg(long, conflicts_with = "regimen")]
    pub exercise: Option<String>,
    /// Regimen file (TOML): the prescribed exercises in order, with their haptic and
    /// assistance settings (see regimens/*.toml).
    #[arg(long)]
    pub regimen: Option<PathBuf>,
    /// Record the session to this MCAP file.
    #[arg(long)]
    pub record: Option<PathBuf>,
    /// Therapist hub address, `host:port`.
    #[arg(long)]
    pub therapist: Option<String>,
    /// PEM file of the CA that signed the hub's certificate (enables TLS).
    #[arg(long)]
    pub therapist_ca: Option<PathBuf>,
    /// Loop pacing.
    #[arg(long, value_enum, default_value_t = Speed::Realtime)]
    pub speed: Speed,
    /// This station's identifier at the therapist hub.
    #[arg(long)]
    pub station_id: Option<String>,
    /// The patient's pseudonymous identifier.
    #[arg(long)]
    pub patient_id: Option<String>,
}

/// `telerehab therapist`.
#[derive(Debug, clap::Args)]
pub struct TherapistArgs {
    /// Address to listen on, `host:port`.
    #[arg(long, default_value = "127.0.0.1:7878")]
    pub listen: String,
    /// Directory where each session's summaries are stored.
    #[arg(long)]
    pub store: PathBuf,
    /// Certificate chain (PEM) of this hub; with `--tls-key` enables TLS.
    #[arg(long, requires = "tls_key")]
    pub tls_cert: Option<PathBuf>,
    /// Private key (PEM) of this hub.
    #[arg(long, requires = "tls_cert")]
    pub tls_key: Option<PathBuf>,
}

/// Parse the command line and run it.
pub fn main() -> anyhow::Result<()> {
    let cli = Cli::parse();
    init_tracing(cli.log.as_deref());
    match cli.command {
        Command::Run(args) => run(args),
        Command::Therapist(args) => crate::therapist::run(args),
        Command::Devices => crate::devices::run(),
        Command::Recover { input, out } => {
            let r = crate::recover::recover(&input, &out)?;
            println!(
                "recovered {} messages on {} channels into {}{}",
                r.messages,
                r.channels,
                out.display(),
                r.stopped_at
                    .map(|e| format!(" (the truncated tail was dropped: {e})"))
                    .unwrap_or_default()
            );
            Ok(())
        }
        Command::Vehicle(args) => crate::commands::vehicle::run(args),
    }
}

fn init_tracing(filter: Option<&str>) {
    use tracing_subscriber::EnvFilter;
    let filter = match filter {
        Some(f) => EnvFilter::new(f),
        None => EnvFilter::try_from_default_env().unwrap_or_else(|_| EnvFilter::new("info")),
    };
    let _ = tracing_subscriber::fmt()
        .with_env_filter(filter)
        .with_writer(std::io::stderr)
        .try_init();
}

/// Merge the config file and the flags into one validated configuration.
pub fn resolve_config(args: &RunArgs) -> anyhow::Result<StationConfig> {
    let mut cfg = match &args.config {
        Some(path) => StationConfig::load(path)?,
        None => StationConfig::default(),
    };
    if let Some(d) = args.duration {
        cfg.session.duration_s = d;
    }
    if let Some(s) = args.seed {
        cfg.session.seed = s;
    }
    if let Some(e) = &args.exercise {
        cfg.session.exercise = e.clone();
    }
    if let Some(id) = &args.station_id {
        cfg.session.station_id = id.clone();
    }
    if let Some(id) = &args.patient_id {
        cfg.session.patient_id = id.clone();
    }
    if let Some(t) = &args.therapist {
        cfg.therapist.address = t.clone();
    }
    if let Some(ca) = &args.therapist_ca {
        cfg.therapist.ca_pem = Some(ca.clone());
    }
    cfg.validate().context("invalid settings")?;
    Ok(cfg)
}

/// Stop flag set by SIGINT/SIGTERM; a second signal exits at once (the kernel then stops
/// every force-feedback effect of the closed device).
pub fn install_stop_flag() -> anyhow::Result<Arc<AtomicBool>> {
    use signal_hook::consts::{SIGINT, SIGTERM};
    let stop = Arc::new(AtomicBool::new(false));
    for sig in [SIGINT, SIGTERM] {
        signal_hook::flag::register_conditional_shutdown(sig, 130, stop.clone())
            .context("cannot install the signal handler")?;
        signal_hook::flag::register(sig, stop.clone())
            .context("cannot install the signal handler")?;
    }
    Ok(stop)
}

/// Real devices: a force-feedback wheel through the Linux kernel FF API, in real time.
#[cfg(target_os = "linux")]
fn real_body(args: &RunArgs) -> anyhow::Result<BodyKind> {
    if args.speed == Speed::Max {
        bail!("--speed max is for simulated sessions (add --sim): a real wheel runs in real time");
    }
    Ok(BodyKind::RealWheel)
}

/// Real devices are driven through the Linux kernel FF API only.
#[cfg(not(target_os = "linux"))]
fn real_body(_args: &RunArgs) -> anyhow::Result<BodyKind> {
    bail!(
        "real force-feedback wheels are supported on Linux only; add --sim for a simulated session"
    )
}

fn run(args: RunArgs) -> anyhow::Result<()> {
    let mut cfg = resolve_config(&args)?;
    let regimen = args
        .regimen
        .as_deref()
        .map(crate::regimen::Regimen::load)
        .transpose()?;
    if let Some(r) = &regimen {
        cfg.session.exercise = format!("regimen:{}", r.exercises.len());
        if args.duration.is_none() {
            // The regimen ends the session; the duration is only a safety cap then.
            cfg.session.duration_s = 4.0 * 3600.0;
        }
    } else {
        vehicle::ExerciseSpec::from_name(&cfg.session.exercise)?;
    }
    let body = if args.sim {
        BodyKind::Simulated
    } else {
        real_body(&args)?
    };
    if !args.headless {
        tracing::warn!("the patient window is not available in this build; running headless");
    }
    let pacing = match args.speed {
        Speed::Realtime => Pacing::RealTime,
        Speed::Max => Pacing::Max,
    };
    let stop = install_stop_flag()?;
    let opts = SessionOptions {
        config: cfg.clone(),
        pacing,
        record: args.record.clone(),
        body,
        regimen,
    };
    tracing::info!(
        exercise = %cfg.session.exercise,
        duration_s = cfg.session.duration_s,
        seed = cfg.session.seed,
        simulated = args.sim,
        "starting session"
    );
    let link = crate::link::Link::start(&cfg)?;
    let report = session::run(&opts, stop, |s| link.send(s))?;
    let link_report = link.finish(report.summaries);
    print!("{}", crate::report::render(&report, link_report.as_ref()));
    if let Some(e) = &report.recorder.error {
        bail!("recording failed: {e}");
    }
    Ok(())
}
