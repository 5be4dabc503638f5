//! `telerehab` with no arguments (the desktop entry): the patient's first-run pages
//! ([`crate::front_door`]) in a full-screen window, then the session they chose. Without a
//! display it says so and points to `telerehab doctor`.

use crate::commands::run::{self, RunArgs};
use crate::config::StationConfig;
use crate::front_door::checks::check_devices;
use crate::front_door::{Action, FrontDoor, Outcome, TodayPlan, pairing_error_words};
use crate::home::{Home, HomeArg};
use crate::link::hub_status::{HubStatus, check_hub};
use crate::render::StatusLine;
use crate::render::window::{UserRequest, WindowOptions, run_with};
use crate::render::{Scene, ScreenState};
use crate::settings::Settings;
use anyhow::Context;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Duration;

/// What the patient reads when there is no screen to draw on.
pub const NO_DISPLAY: &str = "telerehab shows the patient's session on a screen, and no display \
was found (neither DISPLAY nor WAYLAND_DISPLAY is set). Start it from the desktop (the \
\"telerehab\" entry), or run `telerehab doctor` to check this station, `telerehab --help` for the \
other commands.";

/// Exit status without a display: could not start.
pub const NO_DISPLAY_EXIT: i32 = 2;

/// How long the first-run page waits for the hub's answer.
const HUB_CHECK_TIMEOUT: Duration = Duration::from_secs(10);

/// How often the device check runs while the pages are up.
const CHECK_PERIOD: Duration = Duration::from_secs(2);

/// Whether a window can be opened here.
pub fn has_display() -> bool {
    ["DISPLAY", "WAYLAND_DISPLAY"]
        .iter()
        .any(|v| std::env::var_os(v).is_some_and(|s| !s.is_empty()))
}

/// Today's plan for a paired station: the clinic's regimen kept in `home`, else the
/// station's default exercise.
fn today_plan(home: &Home, cfg: &StationConfig) -> TodayPlan {
    let path = home.regimen_path();
    match regimen::Regimen::load(&path) {
        Ok(r) if path.exists() => TodayPlan::from_regimen(&r),
        _ => TodayPlan::default_drive(&cfg.session.exercise, cfg.session.duration_s),
    }
}

/// `telerehab` with no arguments.
pub fn run() -> anyhow::Result<()> {
    if !has_display() {
        eprintln!("{NO_DISPLAY}");
        std::process::exit(NO_DISPLAY_EXIT);
    }
    let home = Home::resolve(&HomeArg::from_env())?;
    let settings = Settings::load(home.dir())?;
    let cfg = StationConfig::default();
    let mut door = match home.pairing()? {
        Some(_) => FrontDoor::paired_with(today_plan(&home, &cfg)),
        None => FrontDoor::unpaired(settings.clinic_address.as_deref()),
    };
    door.set_rest_today(crate::checkin::care::rest_today(
        &home,
        crate::checkin::care::now_unix_ms(),
    ));
    tracing::info!(home = %home.dir().display(), paired = !door.is_pairing(), "first-run pages");
    match show(door, &home, &cfg, settings.fullscreen)? {
        Outcome::Quit => Ok(()),
        Outcome::Start => run::run(RunArgs::patient(settings.fullscreen)),
        Outcome::TryOut => run::run(RunArgs::try_out(settings.fullscreen)),
    }
}

/// Pairs in the background and tells the pages how it went.
fn spawn_pairing(
    door: &Arc<Mutex<FrontDoor>>,
    home: &Home,
    cfg: &StationConfig,
    address: String,
    code: String,
) {
    let (door, home, cfg) = (Arc::clone(door), home.clone(), cfg.clone());
    std::thread::spawn(move || {
        let result = pair(&home, &address, &code).map(|()| today_plan(&home, &cfg));
        match &result {
            Ok(_) => tracing::info!(hub = %address, "paired from the first-run page"),
            Err(e) => tracing::warn!(hub = %address, "pairing from the first-run page failed: {e}"),
        }
        lock(&door).paired(result);
    });
}

fn pair(home: &Home, address: &str, code: &str) -> Result<(), String> {
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .map_err(|e| format!("This computer could not start its network ({e})."))?;
    let credential = runtime
        .block_on(netlink::pairing::pair(
            address,
            code,
            Duration::from_secs(30),
        ))
        .map_err(|e| pairing_error_words(&e))?;
    let now_ms = clock::Clock::real().unix_ns() / 1_000_000;
    home.save_pairing(address, &credential, now_ms)
        .map(|_| ())
        .map_err(|e| format!("Paired, but this computer could not save it ({e:#})."))
}

fn lock(door: &Mutex<FrontDoor>) -> std::sync::MutexGuard<'_, FrontDoor> {
    door.lock().unwrap_or_else(PoisonError::into_inner)
}

/// A paired station asks its hub once whether it is served (versions) and reachable; the
/// answer becomes a line of today's page. Stores nothing at the hub.
fn ask_the_hub(door: &Mutex<FrontDoor>, home: &Home) {
    let Ok(Some(pairing)) = home.pairing() else {
        return;
    };
    let status = check_hub(home, &pairing, HUB_CHECK_TIMEOUT);
    // The check keeps the clinic's newest pain settings: the therapist may have cleared a
    // pain stop.
    lock(door).set_rest_today(crate::checkin::care::rest_today(
        home,
        crate::checkin::care::now_unix_ms(),
    ));
    let notice = match status {
        HubStatus::Reachable { .. } => return,
        HubStatus::UpdateRequired(message) => StatusLine {
            ok: Some(false),
            text: crate::front_door::sentence(&message),
        },
        HubStatus::Unreachable(why) => {
            tracing::info!("the clinic's hub is not reachable: {why}");
            StatusLine {
                ok: None,
                text: "Your clinic cannot be reached just now: today's session is kept on this \
                       computer and sent later."
                    .into(),
            }
        }
    };
    lock(door).set_notice(Some(notice));
}

/// The device check every [`CHECK_PERIOD`] until `stop`; between checks, a press of a ready
/// wheel's button counts as Space.
fn watch_devices(
    door: &Mutex<FrontDoor>,
    outcome: &Mutex<Option<Outcome>>,
    stop: &AtomicBool,
    cfg: &StationConfig,
) {
    while !stop.load(Ordering::Relaxed) {
        let check = check_devices(&cfg.wheel, cfg.haptic.safety.ceiling_nm);
        lock(door).set_devices(check.lines, check.wheel_ready);
        let wheel = check.wheel_path.filter(|_| check.wheel_ready);
        if wheel_button(wheel.as_deref(), stop)
            && let Action::Done(o) = lock(door).apply(UserRequest::Confirm)
        {
            *outcome.lock().unwrap_or_else(PoisonError::into_inner) = Some(o);
        }
    }
}

/// Waits [`CHECK_PERIOD`] (less if `stop`), watching the wheel at `path` for a button press.
fn wheel_button(path: Option<&str>, stop: &AtomicBool) -> bool {
    let step = Duration::from_millis(250);
    let mut waited = Duration::ZERO;
    while waited < CHECK_PERIOD && !stop.load(Ordering::Relaxed) {
        match path.map(|p| button_pressed_within(p, step)) {
            Some(Ok(true)) => return true,
            Some(Ok(false)) => {}
            // No wheel, or unplugged or unreadable (the next device check says so).
            None | Some(Err(_)) => std::thread::sleep(step),
        }
        waited += step;
    }
    false
}

#[cfg(target_os = "linux")]
fn button_pressed_within(path: &str, window: Duration) -> std::io::Result<bool> {
    haptic_wheel::evdev_wheel::button_pressed_within(std::path::Path::new(path), window)
}

/// Wheels are driven on Linux only.
#[cfg(not(target_os = "linux"))]
fn button_pressed_within(_path: &str, _window: Duration) -> std::io::Result<bool> {
    Ok(false)
}

/// Shows the pages until the patient starts, tries out or closes; the device check runs
/// every [`CHECK_PERIOD`] meanwhile.
fn show(
    door: FrontDoor,
    home: &Home,
    cfg: &StationConfig,
    fullscreen: bool,
) -> anyhow::Result<Outcome> {
    let door = Arc::new(Mutex::new(door));
    let outcome: Mutex<Option<Outcome>> = Mutex::new(None);
    let stop = AtomicBool::new(false);
    let mut options = WindowOptions::new("telerehab");
    options.fullscreen = fullscreen;
    let shown = std::thread::scope(|scope| {
        scope.spawn(|| watch_devices(&door, &outcome, &stop, cfg));
        scope.spawn(|| ask_the_hub(&door, home));
        let mut logged_page = String::new();
        let shown = run_with(
            &options,
            || {
                if outcome
                    .lock()
                    .unwrap_or_else(PoisonError::into_inner)
                    .is_some()
                {
                    return None;
                }
                let page = lock(&door).page();
                if page.title != logged_page {
                    // One line per page shown (tests and support read it).
                    tracing::info!(page = %page.title, "first-run page shown");
                    logged_page.clone_from(&page.title);
                }
                Some(Scene {
                    screen: ScreenState::Welcome(page),
                    ..Scene::default()
                })
            },
            |request| match lock(&door).apply(request) {
                Action::None => {}
                Action::Pair { address, code } => spawn_pairing(&door, home, cfg, address, code),
                Action::Done(o) => {
                    *outcome.lock().unwrap_or_else(PoisonError::into_inner) = Some(o)
                }
            },
        );
        stop.store(true, Ordering::Relaxed);
        shown
    });
    shown
        .map_err(|e| {
            anyhow::anyhow!(
                "{e}. telerehab cannot draw on this computer's screen: install the graphics driver \
             (Debian: `sudo apt install mesa-vulkan-drivers libgl1-mesa-dri`) and run \
             `telerehab doctor`"
            )
        })
        .context("the first-run window")?;
    Ok(outcome
        .into_inner()
        .unwrap_or_else(PoisonError::into_inner)
        .unwrap_or(Outcome::Quit))
}
