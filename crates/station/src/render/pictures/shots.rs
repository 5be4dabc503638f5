//! The screenshots of docs/screenshots/pictures-*.png: the session's cards with their
//! pictures, and a left-neglect layout with the anchoring cue, drawn offscreen by the
//! window's own draw path (Mesa's software Vulkan here). Run on purpose:
//! `cargo test -p station --lib pictures::shots -- --ignored`.

use super::{Movement, Picture};
use crate::render::{NextCard, Renderer, Scene, ScreenState, demo, layout, save_png};
use regimen::NeglectedSide;

fn shot(renderer: &mut Renderer, scene: &Scene, name: &str) {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/screenshots");
    let rgba = renderer.render_to_rgba(scene).expect("a frame");
    save_png(&dir.join(name), &rgba, 1920, 1080).expect("the PNG");
}

fn card(movement: Movement, countdown_s: Option<f64>) -> NextCard {
    NextCard {
        heading: if countdown_s.is_some() {
            "Rest · next"
        } else {
            "Get ready"
        }
        .into(),
        title: "Exercise 2 of 4: Slalom".into(),
        what: "Steer between the cones and keep the car on the road".into(),
        movement,
        countdown_s,
        keys: vec!["Space: start (or a wheel button)".into()],
        anim_s: 1.1,
        message: None,
    }
}

#[test]
#[ignore = "writes docs/screenshots; run on purpose"]
fn screenshots_of_the_pictured_cards_and_the_neglect_layout() {
    let mut r = Renderer::new_headless(1920, 1080).expect("a software adapter");
    let base = demo::slalom(3.0);
    let with = |screen| Scene {
        screen,
        ..base.clone()
    };
    layout::set_neglected_side(NeglectedSide::None);
    shot(
        &mut r,
        &with(ScreenState::Next(card(Movement::Slalom, None))),
        "pictures-1-next-card.png",
    );
    shot(
        &mut r,
        &with(ScreenState::Next(card(Movement::Slalom, Some(42.0)))),
        "pictures-2-rest.png",
    );
    shot(
        &mut r,
        &with(ScreenState::Welcome(
            crate::session::wheel_cards::paused_card(crate::session::PauseChoice::GoOn),
        )),
        "pictures-3-pause.png",
    );
    layout::set_neglected_side(NeglectedSide::Left);
    shot(
        &mut r,
        &with(ScreenState::Next(card(Movement::Slalom, None))),
        "pictures-4-neglect-left-cue.png",
    );
    shot(
        &mut r,
        &with(ScreenState::Running),
        "pictures-5-neglect-left-hud.png",
    );
    layout::set_neglected_side(NeglectedSide::None);
}

/// Every picture on one sheet, with its caption, for the docs.
#[test]
#[ignore = "writes docs/screenshots; run on purpose"]
fn a_sheet_of_every_picture() {
    // Drawn as the pause card's picture, one card per picture, tiled by the test runner's
    // renderer: simplest is one frame per picture into a grid of cards.
    let mut r = Renderer::new_headless(1920, 1080).expect("a software adapter");
    let base = demo::slalom(3.0);
    for (k, picture) in Picture::all().into_iter().enumerate() {
        let scene = Scene {
            screen: ScreenState::Pictured {
                picture,
                title: format!("{picture:?}"),
                lines: vec![],
            },
            ..base.clone()
        };
        let dir = std::env::temp_dir().join("telerehab-pictures");
        std::fs::create_dir_all(&dir).unwrap();
        let rgba = r.render_to_rgba(&scene).unwrap();
        save_png(&dir.join(format!("{k:02}.png")), &rgba, 1920, 1080).unwrap();
    }
}
