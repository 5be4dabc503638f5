//! The session's screens drawn in the pseudo-locale (accented, 40 % longer) and in German,
//! Spanish and Chinese, offscreen through the window's own drawing code. With
//! `TELEREHAB_SCREENSHOTS=DIR` each is saved as `DIR/words-<language>-<n>-<screen>.png` (the
//! docs' screenshots, looked at for clipped or overlapping text and boxes).

mod common;

use record::TickRecord;
use regimen::Regimen;
use station::config::StationConfig;
use station::render::{Scene, ScreenState};
use station::screen::{CourseView, WindowState, cannot_start_page};
use station::session::{BreakKind, BreakNow};

const W: u32 = 1280;
const H: u32 = 720;

fn tick(tick: u64, index: u32, active_s: f64, paused: bool) -> TickRecord {
    let mut rec = TickRecord {
        tick,
        ..TickRecord::default()
    };
    rec.score.exercise_index = index;
    rec.score.active_s = active_s;
    rec.score.paused = paused;
    rec
}

/// The session's screens in the language in force: (name, scene).
fn screens() -> Vec<(&'static str, Scene)> {
    let text = "[[exercise]]\nkind = \"sine\"\nduration_s = 60.0\nrest_s = 30.0\n\n\
                [[exercise]]\nkind = \"slalom\"\nduration_s = 60.0\npedals = true\n";
    let r = Regimen::from_toml(text, "screens").unwrap();
    let mut view = CourseView::new(&StationConfig::default(), Some(&r)).unwrap();
    view.set_message(Some("今天做得很好。Μπράβο! Gut gemacht.".into()));
    let plain = WindowState::default();
    let rest = WindowState {
        brk: BreakNow {
            kind: BreakKind::Prescribed,
            left_s: 27.0,
            ..BreakNow::default()
        },
        ..plain
    };
    let scene = |rec: &TickRecord, w: &WindowState| {
        let state = view.screen_state(rec, w);
        view.scene(rec, state)
    };
    let confirming = WindowState {
        confirming_end: true,
        ..plain
    };
    let check = station::front_door::checks::check_devices(
        &StationConfig::default().wheel,
        StationConfig::default().haptic.safety.ceiling_nm,
    );
    let mut driving = tick(9000, 0, 8.0, false);
    driving.vehicle = Some(record::VehicleSample {
        ux_m_s: 12.0,
        ..Default::default()
    });
    let no_wheel = Scene {
        screen: ScreenState::Welcome(cannot_start_page(&check.lines)),
        ..Scene::default()
    };
    vec![
        ("next-exercise", scene(&tick(0, 0, 0.0, true), &plain)),
        ("rest-countdown", scene(&tick(40_000, 1, 60.0, true), &rest)),
        ("pause", scene(&tick(9000, 0, 8.0, true), &plain)),
        (
            "end-confirmation",
            scene(&tick(9000, 0, 8.0, false), &confirming),
        ),
        ("running", view.scene(&driving, ScreenState::Running)),
        ("no-wheel", no_wheel),
    ]
}

#[test]
fn every_session_screen_draws_in_the_pseudo_locale_and_each_language() {
    let Some(mut renderer) = common::renderer_or_skip(W, H) else {
        return;
    };
    let out = std::env::var_os("TELEREHAB_SCREENSHOTS").map(std::path::PathBuf::from);
    for language in [i18n::PSEUDO, "de", "es", "zh"] {
        i18n::use_language(language).unwrap();
        for (n, (name, scene)) in screens().into_iter().enumerate() {
            scene.validate().unwrap();
            let rgba = renderer.render_to_rgba(&scene).unwrap();
            assert_eq!(rgba.len(), (W * H * 4) as usize);
            if let Some(dir) = &out {
                let path = dir.join(format!("words-{language}-{}-{name}.png", n + 1));
                station::render::save_png(&path, &rgba, W, H).unwrap();
            }
        }
    }
}
