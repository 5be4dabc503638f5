//! The screenshots of docs/screenshots/pictures-*.png and script-*.png, drawn offscreen by
//! the window's own draw path (Mesa's software Vulkan here): the session's cards with their
//! pictures, and a left-neglect layout with the anchoring cue; a therapist's message in
//! Arabic, Hebrew, Russian and Greek on the session's start card (the patient's language
//! English), and an exercise's card in Arabic words as an Arabic catalogue would give them.
//! Run on purpose: `cargo test -p station --lib screen::shots -- --ignored --test-threads=1`.

use i18n::tr;
use regimen::NeglectedSide;
use render::{Movement, NextCard, Picture, Renderer, Scene, ScreenState, demo, layout, save_png};

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
        &with(ScreenState::Welcome(session::wheel_cards::paused_card(
            session::PauseChoice::GoOn,
        ))),
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

/// The start card of the first exercise with `message` from the therapist.
fn start_card(message: &str) -> ScreenState {
    ScreenState::Next(NextCard {
        heading: tr!("card-get-ready"),
        title: session::words::patient_name("sine-road"),
        what: session::words::patient_instruction("sine-road"),
        movement: Movement::Steer,
        keys: vec![tr!("controls-start")],
        anim_s: 1.1,
        message: Some(message.to_owned()),
        ..NextCard::default()
    })
}

/// Messages a therapist may write: "Well done yesterday. Today, go slowly and rest when you
/// are tired. See you on Friday!" (Arabic, Hebrew), and shorter ones in Russian and Greek.
const MESSAGES: [(&str, &str); 4] = [
    (
        "ar",
        "أحسنت أمس. اليوم تمرن ببطء واسترح عندما تتعب. نراك يوم الجمعة!",
    ),
    (
        "he",
        "כל הכבוד אתמול. היום תתאמן לאט ותנוח כשאתה עייף. נתראה ביום שישי!",
    ),
    (
        "ru",
        "Вчера было хорошо. Сегодня не спешите и отдыхайте, когда устанете. До пятницы!",
    ),
    (
        "el",
        "Μπράβο χθες. Σήμερα πηγαίνετε αργά και ξεκουραστείτε όταν κουραστείτε. Τα λέμε την Παρασκευή!",
    ),
];

#[test]
#[ignore = "writes docs/screenshots; run on purpose"]
fn screenshots_of_a_message_in_arabic_hebrew_russian_and_greek() {
    let mut r = Renderer::new_headless(1920, 1080).expect("a software adapter");
    let base = demo::sine_road(1.0);
    for (tag, message) in MESSAGES {
        let scene = Scene {
            screen: start_card(message),
            ..base.clone()
        };
        shot(&mut r, &scene, &format!("script-message-{tag}.png"));
    }
    // The pause page with its words in Arabic, as an Arabic catalogue would give them:
    // "Paused", "Turn to choose. Press a button.", "Go on", "Rest", "End".
    let mut page = session::wheel_cards::paused_card(session::PauseChoice::Rest);
    page.title = "متوقف مؤقتا".into();
    page.lines[0].text = "أدر المقود للاختيار. ثم اضغط زرا.".into();
    page.choices = vec!["استمر".into(), "استرح".into(), "أنهِ".into()];
    let scene = Scene {
        screen: ScreenState::Welcome(page),
        ..base
    };
    shot(&mut r, &scene, "script-pause-page-ar.png");
}
