//! Every screen a patient sees, drawn by the window's own drawing code offscreen at the
//! window's 1280×720, in English, the pseudo-locale (accented, 40 % longer) and every language
//! the station speaks: the first run (language, pairing from the clinic's card, by the wheel,
//! refused), today's page (and the rest-today page after a pain stop), the arm sensors'
//! set-up, the cards before and between exercises, the running exercise (also as practice and
//! with a neglected left side, and with the cue to sit up), pause, "end now?", the unplugged wheel and arm sensor, the
//! session that cannot start, and each page of the check-in (results, pain unanswered and
//! chosen, effort, difficulty, the pain stop, thanks).
//!
//! Each screen in each language must draw differently from its English frame (its words come
//! from the catalogues: a literal left in English would draw the same). With
//! `TELEREHAB_SCREENSHOTS=DIR` each is saved as `DIR/<language>/<nn>-<screen>.png`; the docs'
//! set is `docs/screenshots/patient/` (docs/SCREENS.md), written by
//! `TELEREHAB_SCREENSHOTS=docs/screenshots/patient cargo test -p station --test every_screen`
//! and looked at for clipped or overlapping text.

mod common;

use common::tick;

use record::TickRecord;
use regimen::{NeglectedSide, Regimen};
use render::window::UserRequest;
use render::{Scene, ScreenState, StatusLine, layout};
use session::config::StationConfig;
use session::wheel_gestures::Gesture;
use session::{BreakKind, BreakNow, PauseChoice, wheel_cards};
use station::checkin::CheckInFlow;
use station::checkin::care::{CareSettings, rest_today_page};
use station::checkin::results::{EndResults, end_lines, result_lines};
use station::front_door::pairing_file::{Found, PairingCard};
use station::front_door::{FrontDoor, TodayPlan};
use station::screen::{CourseView, WindowState, cannot_start_page};
use std::time::{Duration, Instant};

const W: u32 = 1280;
const H: u32 = 720;

/// A page of the first run or a wheel card, as the window draws it.
fn page(screen: ScreenState) -> Scene {
    Scene {
        screen,
        ..Scene::default()
    }
}

fn card(code: Option<&str>) -> Found {
    Found::Card(
        "/media/stick/telerehab-pairing.toml".into(),
        PairingCard {
            clinic_address: "clinic.example.org".into(),
            code: code.map(str::to_owned),
        },
    )
}

/// The first-run pages: the language, the clinic's card, a code entered sign by sign with the
/// wheel and refused, the card's own code being tried.
fn first_run() -> Vec<(&'static str, Scene)> {
    let welcome = |d: &FrontDoor| page(ScreenState::Welcome(d.page()));
    let language =
        FrontDoor::paired_with(TodayPlan::default_drive("sine", 60.0)).asking_language("en");
    let with_card = FrontDoor::unpaired(&card(Some("7KQ2-M9XD")), None);
    let mut connecting = with_card.clone();
    connecting.wheel(Gesture::Press);
    let mut by_wheel = FrontDoor::unpaired(&card(None), None);
    let alphabet = netlink::pairing::CODE_ALPHABET;
    let mut sign = 0usize;
    let mut entered = None;
    for (n, g) in "7KQ2M9XD".chars().enumerate() {
        if n == 5 {
            entered = Some(by_wheel.clone()); // five signs of eight taken
        }
        let to = alphabet.iter().position(|&b| char::from(b) == g).unwrap();
        let by = to as i32 - sign as i32;
        for _ in 0..by.unsigned_abs() {
            by_wheel.wheel(Gesture::Turn(by.signum()));
        }
        sign = to;
        by_wheel.wheel(Gesture::Press);
    }
    let entered = entered.unwrap();
    by_wheel.paired(Err(i18n::tr!("front-error-refused")));
    assert_eq!(
        by_wheel.page_id(),
        "pairing-code",
        "a refused code stays on the page"
    );
    vec![
        ("language", welcome(&language)),
        ("pairing-card", welcome(&with_card)),
        ("connecting", welcome(&connecting)),
        ("pairing-code-by-wheel", welcome(&entered)),
        ("pairing-code-refused", welcome(&by_wheel)),
        (
            "pairing-no-card",
            welcome(&FrontDoor::unpaired(&Found::Nothing, None)),
        ),
    ]
}

/// Today's page with the plan, a message, the checked wheel and the choice moved to the
/// practice; and the page that says to rest today after a pain stop.
fn today(regimen: &Regimen) -> Vec<(&'static str, Scene)> {
    let mut today = FrontDoor::paired_with(TodayPlan::from_regimen(regimen));
    today.set_devices(
        vec![StatusLine {
            ok: Some(true),
            text: i18n::tr!("front-device-wheel", name = "Logitech G29"),
        }],
        true,
    );
    today.set_message(Some("今天做得很好。Μπράβο! Gut gemacht.".into()));
    let first = page(ScreenState::Welcome(today.page()));
    today.wheel(Gesture::Turn(1));
    let practice = page(ScreenState::Welcome(today.page()));
    let care = CareSettings {
        clinic_phone: Some("+49 30 1234567".into()),
        ..CareSettings::default()
    };
    today.set_rest_today(Some(rest_today_page(&care)));
    vec![
        ("today", first),
        ("today-practice-chosen", practice),
        (
            "today-rest-after-pain",
            page(ScreenState::Welcome(today.page())),
        ),
    ]
}

/// The session's screens, from the arm sensors' set-up to the session that cannot start.
fn session(regimen: &Regimen) -> Vec<(&'static str, Scene)> {
    let mut view = CourseView::new(&StationConfig::default(), Some(regimen)).unwrap();
    view.set_message(Some("Well done this week · 做得很好".into()));
    let plain = WindowState::default();
    let with = |kind| WindowState {
        brk: BreakNow {
            kind,
            left_s: 27.0,
            ..BreakNow::default()
        },
        ..plain
    };
    let scene = |rec: &TickRecord, w: &WindowState| view.scene(rec, view.screen_state(rec, w));
    let mut hold_still = tick(500, 0, 0.0, true);
    hold_still.arm = Some(record::ArmSample {
        setup: record::ArmSetup::HoldStill,
        setup_remaining_s: 3.0,
        ..Default::default()
    });
    let mut driving = tick(9000, 0, 8.0, false);
    driving.vehicle = Some(record::VehicleSample {
        ux_m_s: 12.0,
        ..Default::default()
    });
    let running = view.scene(&driving, ScreenState::Running);
    let mut practice = running.clone();
    wheel_cards::mark_practice(&mut practice);
    let check = station::front_door::checks::check_devices(
        &StationConfig::default().wheel,
        StationConfig::default().haptic.safety.ceiling_nm,
    );
    vec![
        ("arm-sensors-hold-still", scene(&hold_still, &plain)),
        ("next-exercise", scene(&tick(0, 0, 0.0, true), &plain)),
        ("running", running),
        ("running-practice", practice),
        (
            "rest-countdown",
            scene(&tick(40_000, 1, 60.0, true), &with(BreakKind::Prescribed)),
        ),
        (
            "ready-after-rest",
            scene(&tick(90_000, 1, 90.0, true), &with(BreakKind::Ready)),
        ),
        (
            "paused",
            page(ScreenState::Welcome(wheel_cards::paused_card(
                PauseChoice::Rest,
            ))),
        ),
        (
            "end-confirmation",
            scene(
                &tick(9000, 0, 8.0, false),
                &WindowState {
                    confirming_end: true,
                    ..plain
                },
            ),
        ),
        (
            "wheel-unplugged",
            page(ScreenState::Welcome(wheel_cards::unplugged(23.4))),
        ),
        (
            "arm-sensor-unplugged",
            page(ScreenState::Welcome(wheel_cards::arm_sensor_unplugged(
                23.4,
            ))),
        ),
        (
            "cannot-start",
            page(ScreenState::Welcome(cannot_start_page(&check.lines))),
        ),
    ]
}

/// The check-in's pages, walked as the patient walks them with the wheel's keys.
fn check_in() -> Vec<(&'static str, Scene)> {
    let now = Instant::now();
    let results = result_lines(
        &EndResults {
            active_s: 270.0,
            pct_in_lane: Some(91.0),
            dial_error_deg: Some(4.2),
        },
        &[EndResults {
            active_s: 240.0,
            pct_in_lane: Some(84.0),
            dial_error_deg: Some(6.0),
        }],
    );
    let new = || {
        CheckInFlow::new(results.clone(), Duration::from_secs(120), now)
            .with_care(7, Some("+49 30 1234567".into()))
    };
    let shown = |f: &CheckInFlow| page(ScreenState::CheckIn(f.page()));
    let mut flow = new();
    let mut pages = vec![("checkin-results", shown(&flow))];
    flow.apply(UserRequest::Confirm, now);
    pages.push(("checkin-pain-unanswered", shown(&flow)));
    for _ in 0..=4 {
        flow.apply(UserRequest::SeekForward, now);
    }
    pages.push(("checkin-pain-chosen", shown(&flow)));
    flow.apply(UserRequest::Confirm, now);
    for _ in 0..=6 {
        flow.apply(UserRequest::SeekForward, now);
    }
    pages.push(("checkin-effort", shown(&flow)));
    flow.apply(UserRequest::Confirm, now);
    for _ in 0..=2 {
        flow.apply(UserRequest::SeekForward, now);
    }
    pages.push(("checkin-difficulty", shown(&flow)));
    flow.apply(UserRequest::Confirm, now);
    assert_eq!(flow.page_id(), "thanks");
    pages.push(("checkin-thanks", shown(&flow)));
    let mut stop = new();
    stop.apply(UserRequest::Confirm, now);
    for _ in 0..=8 {
        stop.apply(UserRequest::SeekForward, now);
    }
    stop.apply(UserRequest::Confirm, now);
    assert_eq!(stop.page_id(), "pain-stop");
    pages.push(("checkin-pain-stop", shown(&stop)));
    // A session the wheel ended (it stopped taking the force commands): said first.
    let stopped = end_lines(
        &EndResults {
            active_s: 95.0,
            pct_in_lane: Some(88.0),
            dial_error_deg: None,
        },
        &[],
        Some(haptic_wheel::WheelFault::CommandsRefused),
    );
    let wheel_stopped =
        CheckInFlow::new(stopped, Duration::from_secs(120), now).stopped_early(true);
    pages.push(("checkin-results-wheel-stopped", shown(&wheel_stopped)));
    pages
}

/// Every patient screen in the language in force, with the side the layout keeps clear:
/// (name, neglected side, scene).
fn screens() -> Vec<(&'static str, NeglectedSide, Scene)> {
    let text = "[[exercise]]\nkind = \"sine\"\nduration_s = 90.0\nrest_s = 60.0\n\n\
                [[exercise]]\nkind = \"dial\"\nduration_s = 60.0\n\n\
                [[exercise]]\nkind = \"slalom\"\nduration_s = 60.0\npedals = true\n";
    let regimen = Regimen::from_toml(text, "screens").unwrap();
    let none = |(name, scene)| (name, NeglectedSide::None, scene);
    let mut all: Vec<_> = first_run().into_iter().map(none).collect();
    all.extend(today(&regimen).into_iter().map(none));
    let session = session(&regimen);
    for (name, scene) in &session {
        if matches!(*name, "next-exercise" | "running") {
            let neglect = match *name {
                "next-exercise" => "next-exercise-neglect-left",
                _ => "running-neglect-left",
            };
            all.push((neglect, NeglectedSide::Left, scene.clone()));
        }
    }
    all.extend(session.into_iter().map(none));
    all.extend(check_in().into_iter().map(none));
    // Last, so the earlier screens keep their numbers: the gentle cue to sit up over the
    // running exercise, and where a patient who neglects the left side looks.
    let cued = trunk_cue(&regimen);
    all.push(("running-trunk-cue", NeglectedSide::None, cued.clone()));
    all.push(("running-trunk-cue-neglect-left", NeglectedSide::Left, cued));
    all
}

/// The running road while the station cues the patient to sit up (the trunk stayed leant
/// past the therapist's threshold: `arm::trunk_cue`).
fn trunk_cue(regimen: &Regimen) -> Scene {
    let view = CourseView::new(&StationConfig::default(), Some(regimen)).unwrap();
    let mut rec = tick(9000, 0, 8.0, false);
    rec.vehicle = Some(record::VehicleSample {
        ux_m_s: 12.0,
        ..Default::default()
    });
    rec.arm = Some(record::ArmSample {
        setup: record::ArmSetup::Tracking,
        trunk_tracked: true,
        trunk_lean_rad: 14f64.to_radians(),
        trunk_cues: 1,
        trunk_cue_shown: true,
        ..Default::default()
    });
    view.scene(&rec, ScreenState::Running)
}

#[test]
fn every_patient_screen_draws_in_every_language_in_words_other_than_englishs() {
    let Some(mut renderer) = common::renderer_or_skip(W, H) else {
        return;
    };
    let out = std::env::var_os("TELEREHAB_SCREENSHOTS").map(std::path::PathBuf::from);
    let mut english = Vec::new();
    let mut order: Vec<&str> = i18n::LANGUAGES.to_vec();
    order.push(i18n::PSEUDO);
    assert_eq!(
        order[0], "en",
        "English is drawn first, to compare the others with"
    );
    let mut same = Vec::new();
    for language in order {
        i18n::use_language(language).unwrap();
        for (n, (name, side, scene)) in screens().into_iter().enumerate() {
            scene.validate().unwrap();
            layout::set_neglected_side(side);
            let rgba = renderer.render_to_rgba(&scene).unwrap();
            layout::set_neglected_side(NeglectedSide::None);
            assert_eq!(rgba.len(), (W * H * 4) as usize);
            if language == "en" {
                english.push(rgba.clone());
            } else if english[n] == rgba {
                same.push(format!("{language}: {name}"));
            }
            if let Some(dir) = &out {
                let dir = dir.join(language);
                std::fs::create_dir_all(&dir).unwrap();
                let path = dir.join(format!("{:02}-{name}.png", n + 1));
                render::save_png(&path, &rgba, W, H).unwrap();
            }
        }
    }
    i18n::use_language("en").unwrap();
    assert!(
        same.is_empty(),
        "these screens draw exactly as in English (words outside the catalogues?): {same:?}"
    );
}
