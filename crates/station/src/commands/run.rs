//! `telerehab run`: a patient session, headless or with the patient's window; the report at
//! its end. The threads, window and signals of the session are [`crate::session`]'s.

use crate::config::StationConfig;
use crate::link::Link;
use crate::record::TickRecord;
use crate::regimen::Regimen;
use crate::render::window::WindowOptions;
use crate::screen::{CourseView, live_screen_state};
use crate::session::signals::install_stop_flag;
use crate::session::{self, BodyKind, SessionOptions, haptic::Pacing};
use anyhow::{Context, bail};
use clap::ValueEnum;
use clock::Clock;
use std::path::PathBuf;
use std::sync::atomic::Ordering;

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

impl RunArgs {
    /// A headless simulated session of `duration_s` at `seed`, real time, no recording or
    /// therapist: the base that the commands built on `run` adjust.
    pub(crate) fn simulated(duration_s: f64, seed: u64) -> Self {
        RunArgs {
            sim: true,
            headless: true,
            config: None,
            duration: Some(duration_s),
            seed: Some(seed),
            exercise: None,
            regimen: None,
            record: None,
            therapist: None,
            therapist_ca: None,
            speed: Speed::Realtime,
            station_id: None,
            patient_id: None,
        }
    }
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

/// Resolve the run's configuration and its regimen (also for the commands built on `run`).
pub(crate) fn plan(args: &RunArgs) -> anyhow::Result<(StationConfig, Option<Regimen>)> {
    let mut cfg = resolve_config(args)?;
    let regimen = args.regimen.as_deref().map(Regimen::load).transpose()?;
    match &regimen {
        Some(r) => {
            cfg.session.exercise = format!("regimen:{}", r.exercises.len());
            if args.duration.is_none() {
                // The regimen ends the session; the duration is only a safety cap then.
                cfg.session.duration_s = 4.0 * 3600.0;
            }
        }
        None => {
            vehicle::ExerciseSpec::from_name(&cfg.session.exercise)?;
        }
    }
    Ok((cfg, regimen))
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

/// Run `telerehab run`: the session, then its report on stdout.
pub fn run(args: RunArgs) -> anyhow::Result<()> {
    let (cfg, regimen) = plan(&args)?;
    let body = if args.sim {
        BodyKind::Simulated
    } else {
        real_body(&args)?
    };
    let pacing = match args.speed {
        Speed::Realtime => Pacing::RealTime,
        Speed::Max => Pacing::Max,
    };
    let controls = session::Controls::with_stop(install_stop_flag()?);
    let view = if args.headless {
        None
    } else {
        Some(CourseView::new(&cfg, regimen.as_ref())?)
    };
    let clock = Clock::real();
    let opts = SessionOptions {
        config: cfg.clone(),
        pacing,
        record: args.record.clone(),
        body,
        regimen,
        isolate_core: !args.headless,
        clock: clock.clone(),
    };
    tracing::info!(
        exercise = %cfg.session.exercise,
        duration_s = cfg.session.duration_s,
        seed = cfg.session.seed,
        simulated = args.sim,
        window = !args.headless,
        "starting session"
    );
    let link = Link::start(&cfg, &clock)?;
    let report = match view {
        None => session::run(&opts, &controls, &mut &link)?,
        Some(view) => {
            // With a window the patient starts the exercise with Space when ready.
            controls.pause.store(true, Ordering::Relaxed);
            let window = WindowOptions::new("telerehab");
            let scene = |rec: &TickRecord| view.scene(rec, live_screen_state(rec));
            session::window::run_with_window(&opts, &controls, scene, &window, &mut &link, true)?.0
        }
    };
    let link_report = link.finish(report.summaries);
    print!("{}", crate::report::render(&report, link_report.as_ref()));
    if let Some(e) = &report.recorder.error {
        bail!("recording failed: {e}");
    }
    Ok(())
}
