//! Sized for the sofa: the rendered cap height of every text on the session's pages (the
//! cards of the screen and the session's pause page, painted by the HUD) at 1920×1080,
//! against the minimums of [`render::layout`].

use egui::epaint::Shape;
use egui::{Context, Id, LayerId, Order};
use regimen::NeglectedSide;
use render::hud::{input_for, paint, pixels_per_point};
use render::layout::{MAIN_CAP_ARCMIN, MIN_CAP_ARCMIN, px_at_1080p};
use render::{Hud, LiveScore, Movement, NextCard, Picture, Scene, ScreenState};

/// Every text of `scene` painted at 1920×1080: (text, cap height in pixels). The cap height
/// is the median drawn height of its capitals and digits (their glyphs' rasters), so it is
/// measured, not computed from the font size.
fn texts_at_1080p(scene: &Scene) -> Vec<(String, f64)> {
    let ppp = pixels_per_point(1920, 1080);
    let (input, size) = input_for(1920, 1080);
    let ctx = Context::default();
    let mut out = ctx.run_pass(input, |ctx| {
        let p = ctx.layer_painter(LayerId::new(Order::Foreground, Id::unique("sizes")));
        paint(&p, scene, size, NeglectedSide::None);
    });
    out.textures_delta.clear();
    let mut found = Vec::new();
    let mut stack: Vec<Shape> = out.shapes.into_iter().map(|c| c.shape).collect();
    while let Some(shape) = stack.pop() {
        match shape {
            Shape::Vec(v) => stack.extend(v),
            Shape::Text(t) => {
                let mut caps: Vec<f32> = t
                    .galley
                    .rows
                    .iter()
                    .flat_map(|r| r.glyphs.iter())
                    .filter(|g| {
                        (g.chr.is_ascii_uppercase() && !"QJ".contains(g.chr))
                            || g.chr.is_ascii_digit()
                    })
                    .map(|g| g.uv_rect.size.y)
                    .collect();
                if caps.is_empty() {
                    continue;
                }
                caps.sort_by(f32::total_cmp);
                let cap_pt = caps[caps.len() / 2];
                found.push((t.galley.text().to_owned(), f64::from(cap_pt * ppp)));
            }
            _ => {}
        }
    }
    found
}

/// The session's pages: a road exercise running, the card before an exercise, a rest, the
/// pause (the session's choice page, and a recording's in the replay), an instruction and the
/// end.
fn pages() -> Vec<(&'static str, Scene)> {
    let hud = Hud {
        exercise: "Exercise 2 of 4: Slalom".into(),
        time_left_s: 95.0,
        score: LiveScore::Road {
            rms_lateral_m: 0.4,
            in_lane_pct: 92.0,
        },
        speed_m_s: 8.0,
        assist_level: 0.4,
        devices: vec!["Wheel: ready".into()],
        notice: None,
    };
    let next = NextCard {
        heading: "Get ready".into(),
        title: "Exercise 2 of 4: Slalom".into(),
        what: "Steer between the cones".into(),
        movement: Movement::Slalom,
        keys: vec!["Press a wheel button to start".into()],
        message: Some("Good work yesterday. Keep it up!".into()),
        ..NextCard::default()
    };
    let scene = |screen| Scene {
        hud: hud.clone(),
        screen,
        ..Scene::default()
    };
    vec![
        ("running", scene(ScreenState::Running)),
        (
            "running with the cue to sit up",
            Scene {
                hud: Hud {
                    notice: Some("Sit back up straight.".into()),
                    ..hud.clone()
                },
                screen: ScreenState::Running,
                ..Scene::default()
            },
        ),
        ("next card", scene(ScreenState::Next(next.clone()))),
        (
            "rest",
            scene(ScreenState::Next(NextCard {
                heading: "Rest · next".into(),
                countdown_s: Some(42.0),
                message: None,
                ..next
            })),
        ),
        (
            "pause",
            scene(ScreenState::Welcome(session::wheel_cards::paused_card(
                session::PauseChoice::Rest,
            ))),
        ),
        ("replayed pause", scene(ScreenState::Paused)),
        (
            "instruction",
            scene(ScreenState::Instruction {
                title: "Hold the wheel still".into(),
                lines: vec!["Rest both hands on the wheel".into(), "5 s".into()],
            }),
        ),
        (
            "end",
            scene(ScreenState::Summary(vec!["In lane 92 %".into()])),
        ),
    ]
}

#[test]
fn every_text_of_the_session_pages_is_readable_from_the_sofa() {
    let min_px = px_at_1080p(MIN_CAP_ARCMIN);
    for (page, scene) in pages() {
        let texts = texts_at_1080p(&scene);
        assert!(!texts.is_empty(), "{page}: no text measured");
        for (text, cap_px) in texts {
            assert!(
                cap_px >= min_px,
                "{page}: {text:?} is {cap_px:.1} px high at 1080p, the least is {min_px:.1} px"
            );
        }
    }
}

#[test]
fn the_main_sentences_and_captions_are_larger_still() {
    let main_px = px_at_1080p(MAIN_CAP_ARCMIN);
    let main = [
        "Exercise 2 of 4: Slalom",
        "Steer between the cones",
        "Paused",
        "Hold the wheel still",
        "Sit back up straight.",
    ];
    let captions: Vec<String> = [
        Picture::Exercise(Movement::Slalom),
        Picture::Rest,
        Picture::Pause,
    ]
    .iter()
    .map(|p| p.caption())
    .collect();
    let mut seen = 0;
    for (page, scene) in pages() {
        for (text, cap_px) in texts_at_1080p(&scene) {
            let is_main = main.contains(&text.as_str()) && !page.starts_with("running")
                || text == "Sit back up straight.";
            if is_main || captions.contains(&text) {
                seen += 1;
                assert!(
                    cap_px >= main_px,
                    "{page}: {text:?} is {cap_px:.1} px high at 1080p, a main sentence needs {main_px:.1} px"
                );
            }
        }
    }
    assert!(seen >= 8, "only {seen} main sentences measured");
}

#[test]
fn the_rule_in_pixels() {
    // 20′ at 2 m on a 40-inch set is 25 px at 1080p; 25′ is 32 px (docs/DESIGN.md).
    assert!((px_at_1080p(MIN_CAP_ARCMIN) - 25.2).abs() < 0.2);
    assert!((px_at_1080p(MAIN_CAP_ARCMIN) - 31.5).abs() < 0.2);
}
