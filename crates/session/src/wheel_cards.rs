//! The session's cards the wheel answers, each with a picture: the pause — a choice page like
//! today's, the pause sign beside three choices (go on, rest, end) a turn chooses between and
//! a press does —, "End now?" (press ends, hold goes on), and the unplugged wheel — its own
//! page, not a pause: plug it back in, a picture of the plug, and how long before the session
//! ends.

use super::controls::{BreakKind, BreakNow, PauseChoice};
use i18n::tr;
use render::{Picture, ScreenState, StatusLine, Welcome};

fn plain(text: String) -> StatusLine {
    StatusLine { ok: None, text }
}

/// The card the wheel's state calls for over the exercise, if any: `brk` as the haptic
/// thread tells it, `confirming_end` when Esc was pressed once, `paused` when the exercise is
/// paused by the patient.
pub fn card(brk: &BreakNow, confirming_end: bool, paused: bool) -> Option<ScreenState> {
    if let Some(left_s) = brk.wheel_away_left_s {
        return Some(ScreenState::Welcome(unplugged(left_s)));
    }
    if let Some(left_s) = brk.arm_away_left_s {
        return Some(ScreenState::Welcome(arm_sensor_unplugged(left_s)));
    }
    if confirming_end || brk.end_asked {
        return Some(ScreenState::Welcome(end_now()));
    }
    if paused && brk.kind == BreakKind::None {
        return Some(ScreenState::Welcome(paused_card(brk.pause_choice)));
    }
    None
}

/// The wheel is unplugged: plug it back in; the session ends in `left_s` unless it is.
pub fn unplugged(left_s: f64) -> Welcome {
    let seconds = left_s.max(0.0).ceil() as u64;
    Welcome {
        id: "wheel-unplugged",
        title: tr!("controls-unplugged-title"),
        lines: vec![
            plain(tr!("controls-unplugged-waits")),
            StatusLine {
                ok: Some(false),
                text: tr!("controls-unplugged-left", seconds = seconds),
            },
        ],
        picture: Some(Picture::Plug),
        keys: vec![tr!("controls-unplugged-keys")],
        ..Welcome::default()
    }
}

/// An arm sensor is unplugged mid-session: plug it back in; the exercise waits, and the
/// session ends in `left_s` unless it is.
pub fn arm_sensor_unplugged(left_s: f64) -> Welcome {
    let seconds = left_s.max(0.0).ceil() as u64;
    Welcome {
        id: "arm-sensor-unplugged",
        title: tr!("controls-arm-unplugged-title"),
        lines: vec![
            plain(tr!("controls-unplugged-waits")),
            StatusLine {
                ok: Some(false),
                text: tr!("controls-unplugged-left", seconds = seconds),
            },
        ],
        picture: Some(Picture::ArmSensorPlug),
        keys: vec![tr!("controls-arm-unplugged-keys")],
        ..Welcome::default()
    }
}

/// "End now?": a press ends, a long press goes on.
pub fn end_now() -> Welcome {
    Welcome {
        id: "end-now",
        title: tr!("controls-end-title"),
        lines: vec![
            plain(tr!("controls-end-press")),
            plain(tr!("controls-end-hold")),
        ],
        picture: Some(Picture::Wheel {
            hold: false,
            turn: false,
        }),
        keys: vec![tr!("controls-end-keys")],
        ..Welcome::default()
    }
}

/// Paused: a choice page — go on, rest or end (turn to choose, press to do it), `chosen`
/// framed; the pause sign beside the words (its caption is the sentence spoken).
pub fn paused_card(chosen: PauseChoice) -> Welcome {
    Welcome {
        id: "paused",
        title: tr!("controls-paused-title"),
        lines: vec![plain(tr!("controls-paused-how"))],
        choices: PauseChoice::ALL
            .iter()
            .map(|c| {
                tr!(match c {
                    PauseChoice::GoOn => "controls-paused-go-on",
                    PauseChoice::Rest => "controls-paused-rest",
                    PauseChoice::End => "controls-paused-end",
                })
            })
            .collect(),
        chosen: usize::from(chosen.as_u8()),
        picture: Some(Picture::Pause),
        keys: vec![tr!("controls-paused-keys")],
        ..Welcome::default()
    }
}

/// The practice says so on every screen: over the exercise (before its name), on the cards
/// between exercises and on every page.
pub fn mark_practice(scene: &mut render::Scene) {
    let banner = tr!("front-practice-banner");
    // Over the exercise on a line of its own: the HUD's corner stays narrow in every language.
    scene.hud.exercise = format!("{banner}\n{}", scene.hud.exercise);
    match &mut scene.screen {
        ScreenState::Next(card) => card.heading = format!("{banner} · {}", card.heading),
        ScreenState::Welcome(page) => page.title = format!("{banner} · {}", page.title),
        ScreenState::Instruction { title, .. } => *title = format!("{banner} · {title}"),
        _ => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn id(s: Option<ScreenState>) -> Option<&'static str> {
        match s {
            Some(ScreenState::Welcome(w)) => Some(w.id),
            _ => None,
        }
    }

    #[test]
    fn an_unplugged_wheel_is_its_own_page_over_a_pause_and_says_the_time_left() {
        let brk = BreakNow {
            wheel_away_left_s: Some(12.3),
            ..BreakNow::default()
        };
        assert_eq!(id(card(&brk, false, true)), Some("wheel-unplugged"));
        assert_eq!(id(card(&brk, true, true)), Some("wheel-unplugged"));
        let Some(ScreenState::Welcome(page)) = card(&brk, false, true) else {
            panic!()
        };
        assert_eq!(page.picture, Some(Picture::Plug));
        assert!(page.lines[1].text.contains("13"), "{:?}", page.lines);
        // Plugged back in: the ordinary pause card again.
        assert_eq!(id(card(&BreakNow::default(), false, true)), Some("paused"));
    }

    #[test]
    fn the_pause_is_a_choice_page_of_go_on_rest_and_end_with_the_pause_sign() {
        for chosen in PauseChoice::ALL {
            let brk = BreakNow {
                pause_choice: chosen,
                ..BreakNow::default()
            };
            let Some(ScreenState::Welcome(page)) = card(&brk, false, true) else {
                panic!("no pause page")
            };
            assert_eq!(page.id, "paused");
            assert_eq!(page.picture, Some(Picture::Pause));
            assert_eq!(
                page.choices,
                [
                    tr!("controls-paused-go-on"),
                    tr!("controls-paused-rest"),
                    tr!("controls-paused-end")
                ]
            );
            assert_eq!(page.chosen, usize::from(chosen.as_u8()));
            // The keyboard stays an alternative, said on the page.
            assert_eq!(page.keys, [tr!("controls-paused-keys")]);
        }
    }

    #[test]
    fn an_unplugged_arm_sensor_is_its_own_page_with_its_picture_and_the_time_left() {
        let brk = BreakNow {
            arm_away_left_s: Some(12.3),
            ..BreakNow::default()
        };
        // Over a running exercise and over "End now?" alike: the exercise waits for it.
        assert_eq!(id(card(&brk, false, false)), Some("arm-sensor-unplugged"));
        assert_eq!(id(card(&brk, true, false)), Some("arm-sensor-unplugged"));
        let Some(ScreenState::Welcome(page)) = card(&brk, false, false) else {
            panic!()
        };
        assert_eq!(page.picture, Some(Picture::ArmSensorPlug));
        assert_eq!(page.title, tr!("controls-arm-unplugged-title"));
        assert_eq!(
            page.lines[1].text,
            tr!("controls-unplugged-left", seconds = 13)
        );
        // The wheel unplugged too: the wheel's page first (nothing runs without it).
        let both = BreakNow {
            wheel_away_left_s: Some(5.0),
            ..brk
        };
        assert_eq!(id(card(&both, false, false)), Some("wheel-unplugged"));
        // Plugged back in: no card, the exercise goes on.
        assert_eq!(id(card(&BreakNow::default(), false, false)), None);
    }

    #[test]
    fn end_asked_from_the_wheel_or_the_keys_shows_end_now_and_a_rest_shows_no_card() {
        let asked = BreakNow {
            end_asked: true,
            ..BreakNow::default()
        };
        assert_eq!(id(card(&asked, false, false)), Some("end-now"));
        assert_eq!(id(card(&BreakNow::default(), true, false)), Some("end-now"));
        let resting = BreakNow {
            kind: BreakKind::Asked,
            left_s: 30.0,
            ..BreakNow::default()
        };
        assert_eq!(id(card(&resting, false, true)), None);
        assert_eq!(id(card(&BreakNow::default(), false, false)), None);
    }
}
