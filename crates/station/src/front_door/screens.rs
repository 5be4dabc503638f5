//! The screenshots of the pages the wheel drives (docs/screenshots/wheel-*.png), drawn by the
//! window's own drawing code offscreen at the window's 1280×720, in English and in the
//! pseudo-locale. Run on purpose (it sets the process's language):
//! `cargo test -p station --lib front_door::screens -- --ignored --test-threads=1`
//! (`TELEREHAB_SCREENSHOTS=DIR` writes elsewhere than docs/screenshots).

use super::*;
use crate::config::StationConfig;
use crate::render::{Renderer, Scene, ScreenState, save_png};
use crate::screen::{CourseView, WindowState};
use crate::session::{BreakKind, BreakNow, wheel_cards};

#[allow(clippy::field_reassign_with_default)] // a tick built field by field reads best
fn pages() -> Vec<(&'static str, ScreenState)> {
    let welcome = |w: Welcome| ScreenState::Welcome(w);
    let card = pairing_file::Found::Card(
        "/media/stick/telerehab-pairing.toml".into(),
        pairing_file::PairingCard {
            clinic_address: "clinic.example.org".into(),
            code: None,
        },
    );
    let language = FrontDoor::paired_with(TodayPlan::default_drive("sine", 60.0))
        .asking_language("en")
        .page();
    let with_card = FrontDoor::unpaired(
        &pairing_file::Found::Card(
            "/media/stick/telerehab-pairing.toml".into(),
            pairing_file::PairingCard {
                clinic_address: "clinic.example.org".into(),
                code: Some("7KQ2-M9XD".into()),
            },
        ),
        None,
    )
    .page();
    let mut code = FrontDoor::unpaired(&card, None);
    for g in "7KQ2M9XD".chars() {
        let to = alphabet().iter().position(|&b| char::from(b) == g).unwrap();
        let from = match &code.page {
            Page::Pairing(p) => p.sign,
            _ => 0,
        };
        for _ in from..to {
            code.wheel(Gesture::Turn(1));
        }
        for _ in to..from {
            code.wheel(Gesture::Turn(-1));
        }
        code.wheel(Gesture::Press);
    }
    code.paired(Err(i18n::tr!("front-error-refused")));
    let regimen: regimen::Regimen = toml::from_str(
        "[[exercise]]\nkind = \"sine\"\nduration_s = 90.0\nrest_s = 60.0\n\
         [[exercise]]\nkind = \"dial\"\nduration_s = 60.0\n",
    )
    .unwrap();
    let mut today = FrontDoor::paired_with(TodayPlan::from_regimen(&regimen));
    today.set_devices(
        vec![StatusLine {
            ok: Some(true),
            text: i18n::tr!("front-device-wheel", name = "Logitech G29"),
        }],
        true,
    );
    today.set_message(Some("Well done this week. Keep going!".into()));
    today.wheel(Gesture::Turn(1));
    // "Ready?" after the rest, as the session's window shows it.
    let view = CourseView::new(&StationConfig::default(), Some(&regimen)).unwrap();
    let mut rec = record::TickRecord::default();
    rec.tick = 90_000;
    rec.score.paused = true;
    rec.score.active_s = 90.0;
    rec.score.exercise_index = 1;
    let ready = view.screen_state(
        &rec,
        &WindowState {
            brk: BreakNow {
                kind: BreakKind::Ready,
                ..BreakNow::default()
            },
            ..WindowState::default()
        },
    );
    vec![
        ("wheel-1-language", welcome(language)),
        ("wheel-2-pairing-card", welcome(with_card)),
        ("wheel-3-pairing-code-refused-kept", welcome(code.page())),
        ("wheel-4-today-choices", welcome(today.page())),
        (
            "wheel-5-paused",
            welcome(wheel_cards::paused_card(crate::session::PauseChoice::Rest)),
        ),
        ("wheel-6-end-now", welcome(wheel_cards::end_now())),
        ("wheel-7-ready-after-rest", ready),
        ("wheel-8-unplugged", welcome(wheel_cards::unplugged(23.4))),
        (
            "wheel-9-arm-sensor-unplugged",
            welcome(wheel_cards::arm_sensor_unplugged(23.4)),
        ),
    ]
}

#[test]
#[ignore = "writes the docs' screenshots; run on purpose"]
fn screenshots_of_the_pages_the_wheel_drives_in_english_the_pseudo_locale_and_german() {
    let out = std::env::var_os("TELEREHAB_SCREENSHOTS").map_or_else(
        || std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/screenshots"),
        std::path::PathBuf::from,
    );
    let (w, h) = (1280, 720);
    let mut renderer = Renderer::new_headless(w, h).expect("an offscreen renderer");
    for lang in ["en", i18n::PSEUDO, "de"] {
        i18n::use_language(lang).unwrap();
        for (name, screen) in pages() {
            let scene = Scene {
                screen,
                ..Scene::default()
            };
            let rgba = renderer.render_to_rgba(&scene).unwrap();
            let suffix = if lang == "en" {
                String::new()
            } else {
                format!("-{lang}")
            };
            save_png(&out.join(format!("{name}{suffix}.png")), &rgba, w, h).unwrap();
        }
    }
    i18n::use_language("en").unwrap();
}
