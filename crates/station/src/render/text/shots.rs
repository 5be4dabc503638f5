//! The screenshots of docs/screenshots/script-*.png: a therapist's message in Arabic, Hebrew,
//! Russian and Greek on the session's start card (the patient's language English), and an
//! exercise's card in Arabic words as an Arabic catalogue would give them, drawn offscreen by
//! the window's own draw path. Run on purpose:
//! `cargo test -p station --lib render::text::shots -- --ignored --test-threads=1`.

use crate::render::{Movement, NextCard, Renderer, Scene, ScreenState, demo, save_png};
use i18n::tr;

fn shot(renderer: &mut Renderer, scene: &Scene, name: &str) {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/screenshots");
    let rgba = renderer.render_to_rgba(scene).expect("a frame");
    save_png(&dir.join(name), &rgba, 1920, 1080).expect("the PNG");
}

/// The start card of the first exercise with `message` from the therapist.
fn start_card(message: &str) -> ScreenState {
    ScreenState::Next(NextCard {
        heading: tr!("card-get-ready"),
        title: crate::session::words::patient_name("sine-road"),
        what: crate::session::words::patient_instruction("sine-road"),
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
    let mut page = crate::session::wheel_cards::paused_card(crate::session::PauseChoice::Rest);
    page.title = "متوقف مؤقتا".into();
    page.lines[0].text = "أدر المقود للاختيار. ثم اضغط زرا.".into();
    page.choices = vec!["استمر".into(), "استرح".into(), "أنهِ".into()];
    let scene = Scene {
        screen: ScreenState::Welcome(page),
        ..base
    };
    shot(&mut r, &scene, "script-pause-page-ar.png");
}
