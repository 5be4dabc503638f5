//! `telerehab run`: a patient session, headless or with the patient's window; the report at
//! its end. The threads, window and signals of the session are [`session`]'s.

use crate::home::{Home, HomeArg};
use crate::link::Link;
use anyhow::{Context, bail};
use clap::ValueEnum;
use clock::Clock;
use regimen::Regimen;
use render::window::WindowOptions;
use report::terminal::render as end_report;
use session::config::StationConfig;
use session::signals::install_stop_flag;
use session::{self, BodyKind, SessionOptions, SessionReport, haptic::Pacing};
use std::path::PathBuf;
use std::sync::atomic::Ordering;
use std::time::Duration;

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
    /// dial-multi-sine, dial-step, dial-ramp, dial-chirp, strength, haptic-sweep).
    #[arg(long, conflicts_with = "regimen")]
    pub exercise: Option<String>,
    /// Regimen file (TOML): the prescribed exercises in order, with their haptic and
    /// assistance settings (see regimens/*.toml).
    #[arg(long)]
    pub regimen: Option<PathBuf>,
    /// Record the session to this MCAP file.
    #[arg(long)]
    pub record: Option<PathBuf>,
    /// Record nothing, not even into a paired home (so nothing is uploaded): for simulated
    /// sessions whose results are all in the summaries and the `Bye` (`hub cohort`).
    #[arg(long, conflicts_with = "record")]
    pub no_record: bool,
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
    /// The station's home (pairing, summary queue, recordings).
    #[command(flatten)]
    pub home: HomeArg,
    /// Inject a fault into the simulated session (repeatable): `KIND@SECONDS` or
    /// `KIND@SECONDS+DURATION`, e.g. `wheel-stall@5+0.3` (kinds: wheel-unplug, wheel-nan,
    /// wheel-stall, haptic-stall, disk-full, imu-unplug, imu-nan). Needs --sim.
    #[arg(long = "fault", value_name = "KIND@SECONDS", value_parser = session::faults::FaultSpec::parse)]
    pub faults: Vec<session::faults::FaultSpec>,
    /// Open the patient's window in a window rather than full screen, the default (F11
    /// toggles it).
    #[arg(long = "windowed", action = clap::ArgAction::SetFalse)]
    pub fullscreen: bool,
    /// A short practice on the simulated wheel: neither recorded nor sent to the clinic, the
    /// station's home untouched (the first-run page's F2). Implies --sim; 60 s unless
    /// --duration says otherwise.
    #[arg(long, conflicts_with_all = ["record", "therapist", "regimen"])]
    pub try_out: bool,
    /// After the last exercise the window shows the results and asks three optional
    /// questions (pain, tiredness, difficulty), each page waiting at most this long, s; 0
    /// shows no end screen (nor does a try-out, or a session stopped early).
    #[arg(long, value_name = "S", default_value_t = crate::checkin::DEFAULT_QUESTION_TIMEOUT_S)]
    pub checkin_timeout_s: u64,
}

/// How long a try-out lasts unless `--duration` says otherwise, s.
pub const TRY_OUT_S: f64 = 60.0;

impl RunArgs {
    /// A headless simulated session of `duration_s` at `seed`, real time, no recording or
    /// therapist: the base that the commands built on `run` adjust.
    pub fn simulated(duration_s: f64, seed: u64) -> Self {
        RunArgs {
            sim: true,
            headless: true,
            config: None,
            duration: Some(duration_s),
            seed: Some(seed),
            exercise: None,
            regimen: None,
            record: None,
            no_record: false,
            therapist: None,
            therapist_ca: None,
            speed: Speed::Realtime,
            station_id: None,
            patient_id: None,
            home: HomeArg::default(),
            faults: Vec::new(),
            fullscreen: false,
            try_out: false,
            checkin_timeout_s: crate::checkin::DEFAULT_QUESTION_TIMEOUT_S,
        }
    }

    /// Today's session on the real devices with the patient's window, as the first-run page
    /// starts it: the paired station's regimen, recording and hub.
    pub(crate) fn patient(fullscreen: bool) -> Self {
        RunArgs {
            sim: false,
            headless: false,
            duration: None,
            seed: None,
            fullscreen,
            home: HomeArg::from_env(),
            ..Self::simulated(0.0, 0)
        }
    }

    /// The first-run page's try-out: a short simulated session with the window.
    pub(crate) fn try_out(fullscreen: bool) -> Self {
        RunArgs {
            headless: false,
            duration: None,
            seed: None,
            fullscreen,
            try_out: true,
            ..Self::simulated(0.0, 0)
        }
    }
}

/// What the station's home adds to a run: the paired hub (unless a therapist is named) with
/// this station's identity, a recording by default, and the on-disk queue.
#[derive(Debug, Default)]
pub(crate) struct HomePlan {
    /// The home, when the run uses it (paired, or named by `--home`/`TELEREHAB_HOME`).
    pub home: Option<Home>,
    /// Where the session is recorded when `--record` is not given (paired stations).
    pub default_recording: Option<PathBuf>,
}

/// Most recordings a paired station keeps in its home; the oldest go first.
const RECORDINGS_KEPT: usize = 200;

/// Applies the station's home to `cfg`: a paired station talks to its hub with its own
/// certificate and records every session.
fn apply_home(args: &RunArgs, cfg: &mut StationConfig) -> anyhow::Result<HomePlan> {
    if args.try_out {
        // A practice: nothing recorded, queued or sent.
        return Ok(HomePlan::default());
    }
    let home = match Home::resolve(&args.home) {
        Ok(h) => h,
        // No home anywhere (no $HOME, no --home): an unpaired session still runs.
        Err(e) if args.home.home.is_none() => {
            tracing::debug!("no station home: {e:#}");
            return Ok(HomePlan::default());
        }
        Err(e) => return Err(e),
    };
    let Some(pairing) = home.pairing()? else {
        // Named explicitly: the queue lives there even without a pairing.
        let home = args.home.home.is_some().then_some(home);
        return Ok(HomePlan {
            home,
            default_recording: None,
        });
    };
    home.check_private()?;
    if cfg.therapist.address.is_empty() {
        let tls = home.client_tls(&pairing);
        cfg.therapist.address = pairing.hub.clone();
        cfg.therapist.ca_pem = Some(tls.ca_pem_path);
        cfg.therapist.server_name = Some(pairing.server_name.clone());
        if let Some(id) = tls.identity {
            cfg.therapist.cert_pem = Some(id.cert_pem_path);
            cfg.therapist.key_pem = Some(id.key_pem_path);
        }
        cfg.session.station_id = pairing.station_id.clone();
        cfg.session.patient_id = pairing.patient_id.clone();
        cfg.session.clinic = Some(pairing.clinic_note());
    }
    let dir = home.recordings_dir();
    crate::home::private_dir(&dir)?;
    prune_recordings(&dir, RECORDINGS_KEPT - 1);
    let stamp = humantime::format_rfc3339_millis(std::time::SystemTime::now())
        .to_string()
        .replace(':', "-");
    Ok(HomePlan {
        default_recording: Some(dir.join(format!("session-{stamp}.mcap"))),
        home: Some(home),
    })
}

/// The session's log file in the home (paired, or named by `--home`), named as its recording
/// (`session-<time>.log`); `None` without a home. A log that cannot be written is a warning,
/// never a reason not to run.
fn start_session_log(home: &HomePlan) -> Option<crate::logging::SessionLog> {
    let dir = home.home.as_ref()?.dir();
    let name = home
        .default_recording
        .as_deref()
        .and_then(|r| r.file_stem())
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| {
            let stamp = humantime::format_rfc3339_millis(std::time::SystemTime::now());
            format!("session-{}", stamp.to_string().replace(':', "-"))
        });
    match crate::logging::SessionLog::start(dir, &name) {
        Ok(log) => {
            tracing::info!(path = %log.path().display(), "session log");
            Some(log)
        }
        Err(e) => {
            tracing::warn!("{e:#}");
            None
        }
    }
}

/// Removes the oldest `.mcap` files of `dir` beyond `keep` (names sort by time).
fn prune_recordings(dir: &std::path::Path, keep: usize) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    let mut files: Vec<PathBuf> = entries
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "mcap"))
        .collect();
    files.sort();
    let excess = files.len().saturating_sub(keep);
    for old in &files[..excess] {
        match std::fs::remove_file(old) {
            Ok(()) => tracing::info!(path = %old.display(), "oldest recording removed (retention)"),
            Err(e) => tracing::warn!(path = %old.display(), "cannot remove an old recording: {e}"),
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
    cfg.faults.extend(args.faults.iter().copied());
    if !args.sim && !cfg.faults.is_empty() {
        bail!(
            "injected faults are for simulated sessions: add --sim (a real wheel fails by itself)"
        );
    }
    cfg.validate().context("invalid settings")?;
    Ok(cfg)
}

/// The session runs `regimen`: it names the session's exercise, and it ends the session (the
/// duration is only a safety cap then, unless `--duration` was given).
fn follow_regimen(cfg: &mut StationConfig, regimen: &Regimen, args: &RunArgs) {
    cfg.session.exercise = format!("regimen:{}", regimen.exercises.len());
    if args.duration.is_none() {
        cfg.session.duration_s = 4.0 * 3600.0;
    }
}

/// Resolve the run's configuration and its regimen (also for the commands built on `run`).
pub fn plan(args: &RunArgs) -> anyhow::Result<(StationConfig, Option<Regimen>)> {
    let mut cfg = resolve_config(args)?;
    let regimen = args.regimen.as_deref().map(Regimen::load).transpose()?;
    match &regimen {
        Some(r) => follow_regimen(&mut cfg, r, args),
        None => {
            exercises::ExerciseSpec::from_name(&cfg.session.exercise)?;
        }
    }
    Ok((cfg, regimen))
}

/// Real devices: a force-feedback wheel (the Linux kernel FF API; DirectInput 8 on Windows),
/// in real time.
#[cfg(any(target_os = "linux", windows))]
fn real_body(args: &RunArgs) -> anyhow::Result<BodyKind> {
    if args.speed == Speed::Max {
        bail!("--speed max is for simulated sessions (add --sim): a real wheel runs in real time");
    }
    Ok(BodyKind::RealWheel)
}

/// Real devices are driven on Linux and Windows only.
#[cfg(not(any(target_os = "linux", windows)))]
fn real_body(_args: &RunArgs) -> anyhow::Result<BodyKind> {
    bail!(
        "real force-feedback wheels are supported on Linux and Windows only; add --sim for a simulated session"
    )
}

/// The end screen of a windowed session (none for a try-out or with `--checkin-timeout-s 0`):
/// its results against those the home keeps in `results_path`.
fn end_screen(
    args: &RunArgs,
    results_path: Option<&std::path::Path>,
) -> Option<impl Fn(&SessionReport) -> session::window::wire::EndScreen + Sync + use<>> {
    if args.try_out || args.checkin_timeout_s == 0 {
        return None;
    }
    let before = results_path
        .map(crate::checkin::load_results)
        .unwrap_or_default();
    let question_timeout_s = args.checkin_timeout_s;
    let care_path = results_path
        .and_then(std::path::Path::parent)
        .map(|dir| Home::at(dir).care_path());
    Some(move |report: &SessionReport| {
        // Read when the session ends: the hub sends its settings when the link connects.
        let care = care_path
            .as_deref()
            .map(crate::checkin::care::CareSettings::load)
            .unwrap_or_default();
        session::window::wire::EndScreen {
            lines: crate::checkin::end_lines(
                &crate::checkin::EndResults::of(report),
                &before,
                report.haptic.wheel_fault,
            ),
            question_timeout_s,
            pain_threshold_0_10: care.pain_threshold_0_10,
            clinic_phone: care.clinic_phone,
            stopped_early: crate::checkin::wheel_stopped(report.haptic.wheel_fault),
        }
    })
}

/// A session on the real devices with the patient's window and no usable wheel: the reason
/// and what to do, on the screen in plain words until a key is pressed (and in the terminal),
/// then the error. Without a display, only the error.
/// With a wheel, its input node (its buttons start, pause and resume).
fn no_wheel_no_mystery(cfg: &StationConfig) -> anyhow::Result<Option<PathBuf>> {
    let check = crate::front_door::checks::check_devices(&cfg.wheel, cfg.haptic.safety.ceiling_nm);
    if check.wheel_ready {
        return Ok(check.wheel_path.map(PathBuf::from));
    }
    let mut page = crate::screen::cannot_start_page(&check.lines);
    page.keys = vec![i18n::tr!("cannot-start-close-key")];
    page.id = "cannot-start";
    let scene = render::Scene {
        screen: render::ScreenState::Welcome(page),
        ..render::Scene::default()
    };
    let closed = std::cell::Cell::new(false);
    let mut window = WindowOptions::new("telerehab");
    window.fullscreen = true;
    // A wheel plugged in while the page is up closes it and the session starts: the patient
    // needs no key (the page is checked again every 2 s).
    let mut last_check = std::time::Instant::now();
    let mut plugged_in = None;
    let shown = render::window::run_with(
        &window,
        || {
            if last_check.elapsed() >= Duration::from_secs(2) {
                last_check = std::time::Instant::now();
                let again = crate::front_door::checks::check_devices(
                    &cfg.wheel,
                    cfg.haptic.safety.ceiling_nm,
                );
                if again.wheel_ready {
                    plugged_in = Some(again.wheel_path.map(PathBuf::from));
                }
            }
            (!closed.get() && plugged_in.is_none()).then(|| scene.clone())
        },
        |_| closed.set(true),
    );
    if let Some(path) = plugged_in {
        tracing::info!("a wheel was plugged in while the page said none: starting");
        return Ok(path);
    }
    if let Err(e) = shown {
        tracing::warn!("cannot show why the session cannot start: {e}");
    }
    let why: Vec<&str> = check
        .lines
        .iter()
        .filter(|l| l.ok == Some(false))
        .map(|l| l.text.as_str())
        .collect();
    bail!("the session cannot start: {}", why.join(" "))
}

/// The session with the patient's window (the exercise waits for Space, a wheel or gamepad
/// button), then its end screen when it ran to its end.
fn windowed(
    args: &RunArgs,
    opts: &SessionOptions,
    controls: &session::Controls,
    link: &Link,
    wheel_node: Option<&std::path::Path>,
    results_path: Option<&std::path::Path>,
) -> anyhow::Result<(SessionReport, Option<session::window::WindowAccount>)> {
    controls.pause.store(true, Ordering::Relaxed);
    let mut window = WindowOptions::new("telerehab");
    window.fullscreen = args.fullscreen;
    let end = end_screen(args, results_path);
    let buttons_done = std::sync::atomic::AtomicBool::new(false);
    std::thread::scope(|scope| {
        // The wheel's and a gamepad's buttons do what Space does.
        let buttons = std::thread::Builder::new()
            .name("buttons".into())
            .spawn_scoped(scope, || {
                session::buttons::watch(controls, wheel_node, &buttons_done);
            });
        // The therapist's message: said seen as soon as the window has drawn it.
        let seen = scope.spawn(|| tell_message_seen(controls, link, &buttons_done));
        let r = session::window::run_with_window_and_end_screen(
            opts,
            controls,
            &window,
            &mut &*link,
            true,
            end.as_ref().map(|f| f as _),
        );
        buttons_done.store(true, Ordering::Release);
        let _ = seen.join();
        if let Ok(b) = buttons {
            let _ = b.join();
        }
        r
    })
}

/// Waits (until `done`) for the patient window to have drawn the therapist's message, then
/// tells the link; at once if it was drawn just before `done`.
fn tell_message_seen(
    controls: &session::Controls,
    link: &Link,
    done: &std::sync::atomic::AtomicBool,
) {
    loop {
        let finished = done.load(Ordering::Acquire);
        let at_ms = controls.message_shown_unix_ms.load(Ordering::Acquire);
        if at_ms > 0 {
            link.message_shown(at_ms);
            return;
        }
        if finished {
            return;
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// Keeps this session's results in the home for the next end screen's comparison.
fn keep_results(path: &std::path::Path, report: &SessionReport) {
    let now = crate::checkin::EndResults::of(report);
    let before = crate::checkin::load_results(path);
    if let Err(e) = crate::checkin::save_results(path, &now, &before) {
        tracing::warn!("the session's results are not kept for the next end screen: {e:#}");
    }
}

/// How long a session waits, before it starts, for the prescription the hub sends when the
/// station connects (it pushes the patient's current regimen at once); after that the kept one
/// runs.
pub const PRESCRIPTION_WAIT: Duration = Duration::from_secs(3);

/// Start the therapist link and settle the session's prescription: a `--regimen` or
/// `--exercise` given runs as given; otherwise the regimen the hub sends within
/// [`PRESCRIPTION_WAIT`] of the start (kept in the home for the sessions after), else the one
/// kept from an earlier session, else the configured exercise. Says which ran (the log, and
/// the line returned for the report).
fn link_with_prescription(
    args: &RunArgs,
    cfg: &mut StationConfig,
    regimen: &mut Option<Regimen>,
    home: &HomePlan,
    clock: &Clock,
) -> anyhow::Result<(Link, Option<String>)> {
    let asks_hub = regimen.is_none() && args.exercise.is_none();
    let kept = match &home.home {
        Some(h) if asks_hub && h.regimen_path().exists() => {
            // The clinic's prescription, kept from an earlier session (validated again here).
            let r = Regimen::load(&h.regimen_path())?;
            follow_regimen(cfg, &r, args);
            name_prescriber(cfg, h);
            *regimen = Some(r);
            Some(h.regimen_path())
        }
        _ => None,
    };
    // The hub bounds the patient's prescriptions by the wheel it is told of.
    let wheel = (!cfg.therapist.address.is_empty())
        .then(|| crate::link::wheel::for_hub(cfg, args.sim))
        .flatten();
    let mut link = Link::start_with_wheel(cfg, clock, home.home.as_ref(), wheel)?;
    let (Some(h), true) = (&home.home, asks_hub) else {
        return Ok((link, None));
    };
    let said = match link.await_prescription(PRESCRIPTION_WAIT) {
        Some(fresh) => match Regimen::from_toml(&fresh.toml, &fresh.id) {
            Ok(r) => {
                if let Err(e) = h.keep_regimen(&fresh) {
                    tracing::warn!("regimen {} not kept for later sessions: {e:#}", fresh.id);
                }
                follow_regimen(cfg, &r, args);
                name_prescriber(cfg, h);
                link.set_exercise(&cfg.session.exercise);
                *regimen = Some(r);
                format!("{} from the hub, received before the start", fresh.id)
            }
            Err(e) => {
                tracing::warn!("regimen {} from the hub refused: {e}", fresh.id);
                format!("{} from the hub refused ({e}); the kept one runs", fresh.id)
            }
        },
        None => match &kept {
            Some(path) => format!(
                "kept {} (the hub sent none within {} s)",
                path.display(),
                PRESCRIPTION_WAIT.as_secs()
            ),
            None => format!(
                "none from the hub within {} s: exercise {}",
                PRESCRIPTION_WAIT.as_secs(),
                cfg.session.exercise
            ),
        },
    };
    tracing::info!(prescription = %said, "the session's prescription");
    Ok((link, Some(said)))
}

/// The clinic's session note names who prescribed the regimen the session runs (the kept
/// one's prescriber, as the hub said), for the recording and its report.
fn name_prescriber(cfg: &mut StationConfig, home: &Home) {
    if let (Some(note), Some(by)) = (cfg.session.clinic.as_mut(), home.regimen_prescriber()) {
        note.therapist = by;
    }
}

/// The session's standard assessment, first in it when its regimen's `[assessment]` makes it
/// due by the history in the home (`session::assessment`).
fn plan_assessment(
    cfg: &mut StationConfig,
    regimen: &mut Option<Regimen>,
    home: &HomePlan,
    clock: &Clock,
) -> Option<session::assessment::Planned> {
    let home_dir = home.home.as_ref().map(Home::dir);
    session::assessment::Planned::for_session(cfg, regimen, home_dir, clock.unix_ns() / 1_000_000)
}

/// Each exercise's results for the session's `Bye`, the assessment's parts tagged; the
/// assessment kept in the home's history when `keep` (no try-out), the session ran without a
/// recorder error and every part of it ran.
fn settle_exercises(
    link: &mut Link,
    report: &SessionReport,
    assessment: Option<&session::assessment::Planned>,
    keep: bool,
) {
    let rec = &report.recorder;
    link.set_exercises(&rec.exercises, assessment.map(|a| a.tag));
    // A session ended early in the assessment did not assess: the next one runs it again.
    if let Some(a) = assessment
        && keep
        && rec.error.is_none()
        && session::assessment::ran_whole(&rec.exercises)
    {
        a.remember(netlink::frame::unix_ms_now());
    }
}

/// After a session that adapted its difficulty: the difficulty and the session's success rate
/// go in its `Bye`, and (`keep`) into the home's history with the check-in's answer; the
/// report's line.
fn settle_difficulty(
    adapted: &crate::adapt::Adapted,
    link: &mut Link,
    report: &SessionReport,
    checkin: Option<&netlink::CheckIn>,
    keep: bool,
) -> String {
    let success_rate = crate::adapt::success_rate(report);
    link.set_difficulty(&adapted.decision.change_for_hub(success_rate));
    if keep {
        let felt = checkin.and_then(|c| c.difficulty.as_deref());
        adapted.remember(success_rate, felt, netlink::frame::unix_ms_now());
    }
    let rate = success_rate.map_or(String::new(), |r| format!(", success {:.0} %", r * 100.0));
    format!(
        "difficulty          {:.2} ({}){rate}",
        adapted.decision.difficulty, adapted.decision.reason
    )
}

/// Who holds the wheel, and the real wheel's input node for its buttons and pedals (a
/// windowed session on a real wheel; one that cannot start says why on the screen).
fn body_and_wheel_node(
    args: &RunArgs,
    cfg: &StationConfig,
) -> anyhow::Result<(BodyKind, Option<PathBuf>)> {
    let body = if args.sim {
        BodyKind::Simulated
    } else {
        real_body(args)?
    };
    let wheel_node = if !args.sim && !args.headless {
        no_wheel_no_mystery(cfg)?
    } else {
        None
    };
    Ok((body, wheel_node))
}

/// Where the session records: `--record`, else the paired home's recordings; nowhere with
/// `--no-record`.
fn recording_path(args: &RunArgs, home: &HomePlan) -> Option<PathBuf> {
    if args.no_record {
        return None;
    }
    args.record
        .clone()
        .or_else(|| home.default_recording.clone())
}

/// Run `telerehab run`: the session, then its report on stdout.
pub fn run(mut args: RunArgs) -> anyhow::Result<()> {
    if args.try_out {
        args.sim = true;
        args.duration = args.duration.or(Some(TRY_OUT_S));
    }
    let (mut cfg, mut regimen) = plan(&args)?;
    let home = apply_home(&args, &mut cfg)?;
    let clock = Clock::real();
    let session_log = start_session_log(&home);
    let (mut link, prescription) =
        link_with_prescription(&args, &mut cfg, &mut regimen, &home, &clock)?;
    // The patient's language: the prescription's, else the first-run choice, else the system's.
    session::language::choose_at(home.home.as_ref().map(Home::dir), regimen.as_ref());
    cfg.validate().context("invalid settings")?;
    // A regimen with `[difficulty]` runs at the difficulty the patient's history calls for.
    let adapted = crate::adapt::Adapted::plan(
        &mut regimen,
        home.home.as_ref().map(Home::dir),
        &cfg.session.patient_id,
    );
    let assessment = plan_assessment(&mut cfg, &mut regimen, &home, &clock);
    let (body, wheel_node) = body_and_wheel_node(&args, &cfg)?;
    let pacing = match args.speed {
        Speed::Realtime => Pacing::RealTime,
        Speed::Max => Pacing::Max,
    };
    let mut controls = session::Controls::with_stop(install_stop_flag()?);
    *controls.practice.get_mut() = args.try_out;
    if !args.headless {
        // Only a window can show it (and so only a window's session says it was seen).
        *controls
            .message
            .get_mut()
            .unwrap_or_else(std::sync::PoisonError::into_inner) = link.message_for_start();
    }
    let opts = SessionOptions {
        config: cfg.clone(),
        pacing,
        record: recording_path(&args, &home),
        body,
        regimen,
        isolate_core: !args.headless,
        difficulty: adapted.as_ref().map(|a| a.decision.note()),
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
    link.session_starts_now(&clock);
    let mut window_restarts = 0;
    let mut checkin = None;
    let results_path = home.home.as_ref().map(|h| h.dir().join("results.json"));
    let report = if args.headless {
        session::run(&opts, &controls, &mut &link)?
    } else {
        let (report, account) = windowed(
            &args,
            &opts,
            &controls,
            &link,
            wheel_node.as_deref(),
            results_path.as_deref(),
        )?;
        window_restarts = account.as_ref().map_or(0, |a| a.restarts);
        checkin = account.and_then(|a| a.checkin);
        report
    };
    if let Some(c) = &checkin {
        link.set_checkin(c);
        if let Some(h) = &home.home {
            crate::checkin::care::note_pain(h, c);
        }
    }
    settle_exercises(&mut link, &report, assessment.as_ref(), !args.try_out);
    let difficulty_line = adapted.as_ref().map(|a| {
        let keep = report.recorder.error.is_none() && !args.try_out;
        settle_difficulty(a, &mut link, &report, checkin.as_ref(), keep)
    });
    if let Some(path) = &results_path
        && report.recorder.error.is_none()
        && !args.try_out
    {
        keep_results(path, &report);
    }
    // A finished recording is uploaded, also one the recorder stopped and finished early
    // because its disk ran low (the hub keeps it off that disk); a file left unfinished by a
    // write error is not (`telerehab recover` finishes it first).
    let recorded = opts
        .record
        .as_deref()
        .filter(|_| report.recorder.mcap_bytes.is_some());
    let end_reason = report.end_reason();
    tracing::info!(reason = %end_reason, "session ended");
    let link_report = link.finish(
        report.summaries,
        &report.recorder.measures.named,
        recorded,
        &end_reason,
    );
    print!("{}", end_report(&report, link_report.as_ref()));
    if let Some(p) = &prescription {
        println!("prescription        {p}");
    }
    if let Some(log) = &session_log {
        println!("session log         {}", log.path().display());
    }
    if let Some(line) = &difficulty_line {
        println!("{line}");
    }
    if let Some(words) = checkin.as_ref().and_then(crate::checkin::answers_words) {
        println!("check-in            {words}");
    }
    if window_restarts > 0 {
        println!(
            "patient window      restarted {window_restarts} time(s) after it died or hung (the exercise paused each time)"
        );
    }
    if let Some(e) = &report.recorder.error {
        bail!("recording failed: {e}");
    }
    Ok(())
}
