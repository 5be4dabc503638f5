//! `telerehab` with no arguments (the desktop entry): the patient's first-run pages
//! ([`crate::front_door`]) in a full-screen window, driven by the wheel (or the keyboard),
//! then the session they chose; after the practice (the try-out) the pages come back.
//! Without a display it says so and points to `telerehab doctor`.
//!
//! `TELEREHAB_LANGUAGE` (a tag, or `en-XA` for the pseudo-locale) puts a language in force
//! for screenshots; a simulated station whose wheel is scripted
//! ([`session::wheel_gestures::SCRIPT_ENV`]) runs the whole first run without devices.

use crate::commands::run::{self, RunArgs};
use crate::front_door::checks::{self, check_devices};
use crate::front_door::{Action, FrontDoor, Outcome, TodayPlan, pairing_error_words, pairing_file};
use crate::home::{Home, HomeArg};
use crate::link::hub_status::{HubStatus, check_hub};
use anyhow::Context;
use render::StatusLine;
use render::window::{WindowOptions, run_with};
use render::{Scene, ScreenState};
use session::config::StationConfig;
use session::settings::Settings;
use session::wheel_gestures::{self, WheelGestures};
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

/// How often today's page asks again for the plan, the therapist's message and the hub.
const PLAN_PERIOD: Duration = Duration::from_secs(30);

/// The environment variable that puts a language in force (screenshots, support).
pub const LANGUAGE_ENV: &str = "TELEREHAB_LANGUAGE";

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
    // The first-run pages speak the kept prescription's language, else the one chosen there.
    choose_language_again(&home);
    let cfg = StationConfig::default();
    let mut door = match home.pairing()? {
        Some(_) => FrontDoor::paired_with(today_plan(&home, &cfg)),
        None => {
            let card = pairing_file::find(&pairing_file::places(home.dir()));
            match &card {
                pairing_file::Found::Card(path, _) => {
                    tracing::info!(card = %path.display(), "the clinic's pairing card was found");
                }
                pairing_file::Found::Unreadable(path, why) => {
                    tracing::warn!(card = %path.display(), "the clinic's pairing card cannot be read: {why}");
                }
                pairing_file::Found::Nothing => {}
            }
            FrontDoor::unpaired(&card, settings.clinic_address.as_deref())
        }
    };
    if settings.language.is_none() {
        door = door.asking_language(i18n::current().tag());
    }
    door.set_rest_today(crate::checkin::care::rest_today(
        &home,
        crate::checkin::care::now_unix_ms(),
    ));
    tracing::info!(home = %home.dir().display(), paired = !door.is_pairing(), "first-run pages");
    let simulated = wheel_gestures::scripted();
    match show(door, &home, &cfg, settings.fullscreen)? {
        Outcome::Quit => Ok(()),
        Outcome::Start => run::run(RunArgs {
            sim: simulated,
            ..RunArgs::patient(settings.fullscreen)
        }),
        Outcome::TryOut => {
            run::run(RunArgs::try_out(settings.fullscreen))?;
            back_to_the_pages()
        }
    }
}

/// After the practice: the first-run pages again, in a fresh process image (one window
/// event loop a process), the scripted wheel read on from where it was.
fn back_to_the_pages() -> anyhow::Result<()> {
    tracing::info!("practice over: back to the first-run pages");
    let exe = std::env::current_exe().context("cannot find this program to show its pages")?;
    let mut again = std::process::Command::new(exe);
    if let Some(offset) = wheel_gestures::script_offset() {
        again.env(wheel_gestures::SCRIPT_FROM_ENV, offset.to_string());
    }
    Err(session::platform::replace_process(again)).context("cannot show the first-run pages again")
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
        .map_err(|e| {
            tracing::warn!("cannot start the network runtime: {e}");
            i18n::tr!("front-error-other")
        })?;
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
        .map_err(|e| {
            tracing::warn!("paired, but the pairing was not saved: {e:#}");
            i18n::tr!("front-error-save")
        })
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
                text: i18n::tr!("front-today-offline"),
            }
        }
    };
    lock(door).set_notice(Some(notice));
}

/// The device check every [`CHECK_PERIOD`] until `stop`; between checks, the wheel's
/// gestures drive the pages (a scripted wheel's too, on a simulated station).
fn watch_devices(
    door: &Arc<Mutex<FrontDoor>>,
    outcome: &Mutex<Option<Outcome>>,
    stop: &AtomicBool,
    (home, cfg): (&Home, &StationConfig),
) {
    let simulated = wheel_gestures::scripted();
    while !stop.load(Ordering::Relaxed) {
        let check = if simulated {
            checks::simulated()
        } else {
            check_devices(&cfg.wheel, cfg.haptic.safety.ceiling_nm)
        };
        lock(door).set_devices(check.lines, check.wheel_ready);
        let node = check.wheel_path.map(std::path::PathBuf::from);
        let mut wheel = WheelGestures::open(node.as_deref());
        let started = std::time::Instant::now();
        while started.elapsed() < CHECK_PERIOD && !stop.load(Ordering::Relaxed) {
            let look = wheel
                .as_mut()
                .map(|w| w.look(Duration::from_millis(50), true));
            let gestures = match look {
                Some(Ok(l)) => l.gestures,
                // Unplugged or unreadable: the next device check says so.
                Some(Err(_)) | None => {
                    std::thread::sleep(Duration::from_millis(250));
                    wheel = None;
                    Vec::new()
                }
            };
            for g in gestures {
                let action = lock(door).wheel(g);
                act(door, outcome, (home, cfg), action);
            }
        }
    }
}

/// Does what the pages ask: store the language, pair, or end with the outcome.
fn act(
    door: &Arc<Mutex<FrontDoor>>,
    outcome: &Mutex<Option<Outcome>>,
    (home, cfg): (&Home, &StationConfig),
    action: Action,
) {
    match action {
        Action::None => {}
        Action::Language(tag) => choose_language(home, &tag),
        Action::Pair { address, code } => spawn_pairing(door, home, cfg, address, code),
        Action::Done(o) => *outcome.lock().unwrap_or_else(PoisonError::into_inner) = Some(o),
    }
}

/// The patient chose `tag` on the first-run page: in force now, and kept in the settings.
fn choose_language(home: &Home, tag: &str) {
    if let Err(e) = i18n::use_language(tag) {
        tracing::warn!("{e}");
        return;
    }
    let saved = Settings::load(home.dir()).and_then(|mut s| {
        s.language = Some(tag.to_owned());
        s.save(home.dir())
    });
    match saved {
        Ok(()) => tracing::info!(language = tag, "language chosen on the first-run page"),
        Err(e) => tracing::warn!("the language chosen is not kept: {e:#}"),
    }
}

/// The language chosen again as at start ([`session::language::choose`]) from the prescription
/// kept in `home` and the first-run choice in its settings; the tag in force.
fn choose_language_again(home: &Home) -> &'static str {
    let kept = regimen::Regimen::load(&home.regimen_path()).ok();
    let chosen = Settings::load(home.dir()).ok().and_then(|s| s.language);
    session::language::choose(kept.as_ref(), chosen.as_deref())
}

/// Today's plan and the therapist's newest message, read again from the home every
/// [`PLAN_PERIOD`] while today's page is up (on the page's opening too), with the hub asked
/// each time.
fn keep_today_fresh(door: &Mutex<FrontDoor>, stop: &AtomicBool, home: &Home, cfg: &StationConfig) {
    let mut last = None;
    let mut shown = None;
    while !stop.load(Ordering::Relaxed) {
        if lock(door).is_today()
            && last.is_none_or(|t: std::time::Instant| t.elapsed() >= PLAN_PERIOD)
        {
            last = Some(std::time::Instant::now());
            ask_the_hub(door, home);
            let plan = today_plan(home, cfg);
            let message = crate::messages::Inbox::load(&home.messages_path())
                .to_show()
                .map(|k| (k.id.clone(), k.text.clone()));
            let now = (plan.clone(), message.as_ref().map(|(id, _)| id.clone()));
            if shown.as_ref() != Some(&now) {
                // A prescription that brings the patient's language puts it in force at once:
                // the page is drawn anew in it (the window asks the catalogues every frame).
                let language = choose_language_again(home);
                // By state, never by words: tests and support follow the page's plan by it.
                tracing::info!(
                    language,
                    prescribed = plan.prescribed,
                    exercises = plan.exercises.len(),
                    total_s = plan.total_s().round(),
                    message_id = message.as_ref().map_or("", |(id, _)| id.as_str()),
                    "today's page plan_changed"
                );
                shown = Some(now);
            }
            let mut d = lock(door);
            d.set_plan(plan);
            d.set_message(message.map(|(_, text)| text));
        }
        std::thread::sleep(Duration::from_millis(200));
    }
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
        scope.spawn(|| watch_devices(&door, &outcome, &stop, (home, cfg)));
        scope.spawn(|| keep_today_fresh(&door, &stop, home, cfg));
        let mut logged_page = "";
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
                if page.id != logged_page {
                    // One line per page shown (tests and support read it).
                    tracing::info!(page_id = %page.id, "first-run page shown");
                    logged_page = page.id;
                }
                Some(Scene {
                    screen: ScreenState::Welcome(page),
                    ..Scene::default()
                })
            },
            |request| {
                let action = lock(&door).apply(request);
                act(&door, &outcome, (home, cfg), action);
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
