//! Command-line interface.

use crate::commands::bench::RenderImpact;
use crate::config::StationConfig;
use crate::link::Link;
use crate::record::TickRecord;
use crate::regimen::Regimen;
use crate::render::ScreenState;
use crate::render::window::{UserRequest, WindowOptions, WindowStats};
use crate::screen::CourseView;
use crate::session::{
    self, BodyKind, LiveSummary, SessionObserver, SessionOptions, haptic::Pacing,
};
use anyhow::{Context, bail};
use clap::{Parser, Subcommand, ValueEnum};
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

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
    /// List wheels, pedals, gamepads and IMUs, with each wheel's torque ceiling.
    Devices(crate::commands::devices::DevicesArgs),
    /// Render a simulated session offscreen to PNG frames (the window's drawing code, on
    /// Mesa's software Vulkan/GL where there is no GPU).
    Render(RenderArgs),
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
    /// Measure the whole station (for BENCHMARKS.md).
    Bench(crate::commands::bench::BenchArgs),
    /// Measure a real force-feedback wheel and write its profile (`wheel calibrate`).
    Wheel(crate::commands::wheel::WheelArgs),
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

impl RunArgs {
    /// A headless simulated session of `duration_s` at `seed`, real time, no recording or
    /// therapist: the base that the commands built on `run` adjust.
    fn simulated(duration_s: f64, seed: u64) -> Self {
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

/// `telerehab render`.
#[derive(Debug, clap::Args)]
pub struct RenderArgs {
    /// Exercise to render.
    #[arg(long, default_value = "sine-road", conflicts_with = "regimen")]
    pub exercise: String,
    /// Regimen file to render instead of one exercise.
    #[arg(long)]
    pub regimen: Option<PathBuf>,
    /// Station configuration (TOML).
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// Seed of the simulation.
    #[arg(long, default_value_t = 7)]
    pub seed: u64,
    /// Frames to render.
    #[arg(long, default_value_t = 120)]
    pub frames: usize,
    /// Frames per second of session time.
    #[arg(long, default_value_t = 30.0)]
    pub fps: f64,
    /// Frame size, WIDTHxHEIGHT in pixels.
    #[arg(long, default_value = "1280x720", value_parser = parse_size)]
    pub size: (u32, u32),
    /// Output directory for frame_0000.png, frame_0001.png, …
    #[arg(long)]
    pub out: PathBuf,
}

/// Parse `WIDTHxHEIGHT` (16 to 8192 pixels a side).
pub(crate) fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("size `{s}` is not WIDTHxHEIGHT"))?;
    let parse = |v: &str| {
        v.trim()
            .parse::<u32>()
            .map_err(|e| format!("size `{s}`: {e}"))
    };
    let (w, h) = (parse(w)?, parse(h)?);
    if !(16..=8192).contains(&w) || !(16..=8192).contains(&h) {
        return Err(format!("size `{s}`: each side must be 16 to 8192 pixels"));
    }
    Ok((w, h))
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
        Command::Devices(args) => crate::commands::devices::run(&args),
        Command::Wheel(args) => crate::commands::wheel::run(&args),
        Command::Render(args) => render(args),
        Command::Bench(args) => match args.what {
            crate::commands::bench::BenchCommand::Window(a) => bench_window(a),
        },
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

/// Resolve the run's configuration and its regimen.
fn plan_run(args: &RunArgs) -> anyhow::Result<(StationConfig, Option<Regimen>)> {
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

/// The run's observers: the therapist link and, with a window, the latest tick for the screen
/// (and the on/off phases of `telerehab bench window`).
struct RunObserver<'a> {
    link: &'a Link,
    screen: Option<triple_buffer::Input<TickRecord>>,
    impact: Option<&'a mut RenderImpact>,
}

impl SessionObserver for RunObserver<'_> {
    fn on_tick(&mut self, record: &TickRecord) {
        if let Some(s) = &mut self.screen {
            s.write(*record);
        }
        if let Some(ab) = &mut self.impact {
            ab.on_tick(record);
        }
    }

    fn on_summary(&mut self, summary: &LiveSummary) {
        self.link.send(summary);
    }
}

fn run(args: RunArgs) -> anyhow::Result<()> {
    let (cfg, regimen) = plan_run(&args)?;
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
    let opts = SessionOptions {
        config: cfg.clone(),
        pacing,
        record: args.record.clone(),
        body,
        regimen,
        isolate_core: !args.headless,
    };
    tracing::info!(
        exercise = %cfg.session.exercise,
        duration_s = cfg.session.duration_s,
        seed = cfg.session.seed,
        simulated = args.sim,
        window = !args.headless,
        "starting session"
    );
    let link = Link::start(&cfg)?;
    let report = match view {
        None => session::run(
            &opts,
            &controls,
            &mut RunObserver {
                link: &link,
                screen: None,
                impact: None,
            },
        )?,
        Some(view) => {
            // With a window the patient starts the exercise with Space when ready.
            controls.pause.store(true, Ordering::Relaxed);
            let window = WindowOptions::new("telerehab");
            run_with_window(&opts, &controls, &link, &view, &window, None, true)?.0
        }
    };
    let link_report = link.finish(report.summaries);
    print!("{}", crate::report::render(&report, link_report.as_ref()));
    if let Some(e) = &report.recorder.error {
        bail!("recording failed: {e}");
    }
    Ok(())
}

/// Collects the ticks to draw: one every `every` ticks, `frames` of them, then stops the session.
struct FrameCollector {
    every: u64,
    frames: usize,
    records: Vec<TickRecord>,
    stop: Arc<AtomicBool>,
}

impl SessionObserver for FrameCollector {
    fn on_tick(&mut self, record: &TickRecord) {
        if self.records.len() < self.frames && record.tick.is_multiple_of(self.every) {
            self.records.push(*record);
            if self.records.len() == self.frames {
                self.stop.store(true, Ordering::Relaxed);
            }
        }
    }
}

fn render(args: RenderArgs) -> anyhow::Result<()> {
    anyhow::ensure!(args.frames > 0, "--frames must be at least 1");
    anyhow::ensure!(
        args.fps.is_finite() && (1.0..=240.0).contains(&args.fps),
        "--fps must be 1 to 240"
    );
    let run_args = RunArgs {
        config: args.config.clone(),
        exercise: args.regimen.is_none().then(|| args.exercise.clone()),
        regimen: args.regimen.clone(),
        speed: Speed::Max,
        ..RunArgs::simulated(args.frames as f64 / args.fps + 1.0, args.seed)
    };
    let (cfg, regimen) = plan_run(&run_args)?;
    let view = CourseView::new(&cfg, regimen.as_ref())?;
    let stop = install_stop_flag()?;
    let every = ((cfg.session.loop_rate_hz / args.fps).round() as u64).max(1);
    let mut frames = FrameCollector {
        every,
        frames: args.frames,
        records: Vec::with_capacity(args.frames),
        stop: stop.clone(),
    };
    let opts = SessionOptions {
        config: cfg,
        pacing: Pacing::Max,
        record: None,
        body: BodyKind::Simulated,
        regimen,
        isolate_core: false,
    };
    session::run(&opts, &session::Controls::with_stop(stop), &mut frames)?;
    let scenes = frames
        .records
        .iter()
        .map(|r| view.scene(r, ScreenState::Running));
    let (w, h) = args.size;
    let stats = crate::render::headless_frames(scenes, w, h, &args.out)?;
    println!(
        "rendered {} frames of {w}×{h} to {} on {:?}: {:.1} ms mean, p99 {:.1} ms per frame",
        stats.frames,
        args.out.display(),
        stats.adapter,
        stats.mean_ms,
        stats.p99_ms
    );
    Ok(())
}

/// The session on its own threads, the patient's window on this (the main) thread. The window
/// only reads the latest tick through a wait-free triple buffer, so a slow, minimised or
/// closed window changes nothing in the haptic loop. Without a usable GPU or display the
/// session simply runs headless.
fn run_with_window(
    opts: &SessionOptions,
    controls: &session::Controls,
    link: &Link,
    view: &CourseView,
    window: &WindowOptions,
    impact: Option<&mut RenderImpact>,
    idle_priority: bool,
) -> anyhow::Result<(session::SessionReport, Option<WindowStats>)> {
    // The window and its (possibly software) renderer stay off the haptic thread's core.
    session::haptic::cores::keep_off_the_haptic_core();
    let (input, mut output) = triple_buffer::triple_buffer(&TickRecord::default());
    let done = AtomicBool::new(false);
    std::thread::scope(|scope| {
        let session = std::thread::Builder::new()
            .name("session".into())
            .spawn_scoped(scope, || {
                let r = session::run(
                    opts,
                    controls,
                    &mut RunObserver {
                        link,
                        screen: Some(input),
                        impact,
                    },
                );
                done.store(true, Ordering::Release);
                r
            })
            .context("cannot start the session thread")?;
        // The session's threads are started: from here on, this thread and the renderer's
        // workers take only the CPU time they leave over.
        if idle_priority {
            let idle = session::haptic::request_idle_priority();
            tracing::debug!(idle, "patient window at idle scheduling priority");
        }
        let source = || {
            if done.load(Ordering::Acquire) {
                return None;
            }
            let rec = *output.read();
            Some(view.scene(&rec, crate::screen::live_screen_state(&rec)))
        };
        let on_request = |r: UserRequest| match r {
            UserRequest::Quit => controls.stop.store(true, Ordering::Relaxed),
            UserRequest::TogglePause => {
                controls.pause.fetch_xor(true, Ordering::Relaxed);
            }
        };
        let stats = crate::render::window::run_with(window, source, on_request)
            .inspect_err(|e| {
                tracing::warn!("no patient window ({e}); the session continues headless");
                // Nobody can press Space now: start (or resume) the exercise.
                controls.pause.store(false, Ordering::Relaxed);
            })
            .ok();
        let report = session
            .join()
            .map_err(|_| anyhow::anyhow!("session thread panicked (torque was zeroed)"))??;
        Ok((report, stats))
    })
}

/// `telerehab bench window`: see [`crate::commands::bench`].
fn bench_window(args: crate::commands::bench::BenchWindowArgs) -> anyhow::Result<()> {
    anyhow::ensure!(
        args.phase.is_finite() && args.phase >= 0.5,
        "--phase must be at least 0.5 s"
    );
    anyhow::ensure!(
        args.duration.is_finite() && args.duration >= 6.0 * args.phase,
        "--duration must cover at least six phases (two warm-up, two of each kind)"
    );
    if let Some(fps) = args.max_fps {
        anyhow::ensure!(
            fps.is_finite() && (1.0..=240.0).contains(&fps),
            "--max-fps must be 1 to 240"
        );
    }
    let run_args = RunArgs {
        headless: false,
        exercise: Some(args.exercise.clone()),
        ..RunArgs::simulated(args.duration, args.seed)
    };
    let (cfg, regimen) = plan_run(&run_args)?;
    let view = CourseView::new(&cfg, regimen.as_ref())?;
    let gate = Arc::new(AtomicBool::new(false));
    let rate = cfg.session.loop_rate_hz;
    let mut impact = RenderImpact::new(
        gate.clone(),
        args.phase,
        rate,
        (args.duration * rate) as usize,
    );
    let window = WindowOptions {
        draw_gate: Some(gate),
        max_fps: args.max_fps,
        size: args.size,
        ..WindowOptions::new("telerehab bench")
    };
    let opts = SessionOptions {
        config: cfg.clone(),
        pacing: Pacing::RealTime,
        record: None,
        body: BodyKind::Simulated,
        regimen,
        isolate_core: true,
    };
    let controls = session::Controls::with_stop(install_stop_flag()?);
    let link = Link::start(&cfg)?;
    let (report, stats) = run_with_window(
        &opts,
        &controls,
        &link,
        &view,
        &window,
        Some(&mut impact),
        !args.normal_priority,
    )?;
    link.finish(report.summaries);
    let stats = stats.context("the window did not open (is there a display? try xvfb-run -a)")?;
    if let Some(a) = &stats.adapter {
        println!("adapter: {a}");
    }
    print!("{}", impact.report(Some(stats.frames_drawn)));
    Ok(())
}
