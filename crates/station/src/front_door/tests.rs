//! The first-run pages' state, driven by the wheel and by keys. Pages are told apart by their
//! ids and the words compared with the catalogue in force, never with English literals.

use super::checks::describe;
use super::*;
use Gesture::{Hold, Press, Turn};
use i18n::tr;
use render::window::UserRequest::*;

fn type_text(door: &mut FrontDoor, text: &str) {
    for c in text.chars() {
        assert_eq!(door.apply(Typed(c)), Action::None);
    }
}

fn field(door: &FrontDoor) -> (String, String) {
    door.page().field.expect("a field")
}

fn card(address: &str, code: Option<&str>) -> pairing_file::Found {
    pairing_file::Found::Card(
        "/media/stick/telerehab-pairing.toml".into(),
        pairing_file::PairingCard {
            clinic_address: address.into(),
            code: code.map(Into::into),
        },
    )
}

fn plan() -> TodayPlan {
    TodayPlan::default_drive("sine", 60.0)
}

/// Turns the wheel to `sign` of the code's alphabet from where it points (at the start: the
/// first sign) and presses.
fn choose_sign(door: &mut FrontDoor, from: &mut usize, sign: char) -> Action {
    let to = alphabet()
        .iter()
        .position(|&b| char::from(b) == sign)
        .unwrap();
    for _ in *from..to {
        assert_eq!(door.wheel(Turn(1)), Action::None);
    }
    for _ in to..*from {
        assert_eq!(door.wheel(Turn(-1)), Action::None);
    }
    *from = to;
    door.wheel(Press)
}

#[test]
fn the_first_run_asks_the_language_with_the_wheel_each_in_its_own_name() {
    let mut door =
        FrontDoor::unpaired(&card("hub.example", Some("7KQ2-M9XD")), None).asking_language("en-GB");
    let page = door.page();
    assert_eq!(page.id, "language");
    assert_eq!(page.choices, ["English", "Deutsch", "Español", "中文"]);
    assert_eq!(page.chosen, 0);
    assert_eq!(door.wheel(Turn(1)), Action::None);
    assert_eq!(door.wheel(Turn(1)), Action::None);
    assert_eq!(door.wheel(Turn(-1)), Action::None);
    assert_eq!(door.page().chosen, 1);
    assert_eq!(door.wheel(Press), Action::Language("de".into()));
    assert_eq!(door.page_id(), "pairing-card", "then the pairing page");
    // A language in force that the catalogues have is chosen at first.
    let door = FrontDoor::paired_with(plan()).asking_language("es");
    assert_eq!(door.page().chosen, 2);
    assert!(!door.is_pairing());
}

#[test]
fn the_clinics_pairing_card_pairs_with_one_press_of_a_wheel_button() {
    let mut door = FrontDoor::unpaired(&card("hub.example", Some("7KQ2-M9XD")), None);
    assert_eq!(door.page_id(), "pairing-card");
    assert_eq!(
        door.wheel(Turn(1)),
        Action::None,
        "a turn does nothing here"
    );
    assert_eq!(
        door.wheel(Press),
        Action::Pair {
            address: "hub.example:7878".into(),
            code: "7KQ2-M9XD".into(),
        }
    );
    assert_eq!(door.page_id(), "connecting");
}

#[test]
fn a_card_without_a_code_has_the_code_chosen_sign_by_sign_with_the_wheel() {
    let mut door = FrontDoor::unpaired(&card("hub.example:9000", None), None);
    assert_eq!(door.page_id(), "pairing-code");
    let mut at = 0;
    for sign in "7KQ2M9X".chars() {
        assert_eq!(choose_sign(&mut door, &mut at, sign), Action::None);
    }
    assert_eq!(field(&door).1, format!("7KQ2-M9X  [X]"));
    // A long press takes back the last sign.
    assert_eq!(door.wheel(Hold), Action::None);
    assert_eq!(field(&door).1, format!("7KQ2-M9  [X]"));
    assert_eq!(choose_sign(&mut door, &mut at, 'X'), Action::None);
    // The eighth sign connects.
    assert_eq!(
        choose_sign(&mut door, &mut at, 'D'),
        Action::Pair {
            address: "hub.example:9000".into(),
            code: "7KQ2M9XD".into(),
        }
    );
}

#[test]
fn a_refused_code_stays_on_the_page_with_the_reason_and_a_press_tries_again() {
    let mut door = FrontDoor::unpaired(&card("hub.example", None), None);
    let mut at = 0;
    for sign in "7KQ2M9X".chars() {
        choose_sign(&mut door, &mut at, sign);
    }
    assert!(matches!(
        choose_sign(&mut door, &mut at, 'D'),
        Action::Pair { .. }
    ));
    door.paired(Err(tr!("front-error-refused")));
    let page = door.page();
    assert_eq!(page.id, "pairing-code");
    assert_eq!(page.error, Some(tr!("front-error-refused")));
    assert!(
        page.field.unwrap().1.starts_with("7KQ2-M9XD"),
        "the code is kept so the patient can check it"
    );
    // Take back the last sign, choose the right one: it pairs with the corrected code.
    assert_eq!(door.wheel(Hold), Action::None);
    assert_eq!(
        door.page().error,
        None,
        "changing the code clears the error"
    );
    assert_eq!(
        choose_sign(&mut door, &mut at, 'C'),
        Action::Pair {
            address: "hub.example:7878".into(),
            code: "7KQ2M9XC".into(),
        }
    );
    // The card's code refused: still on the card's page, a press tries again.
    let mut door = FrontDoor::unpaired(&card("hub.example", Some("7KQ2-M9XD")), None);
    door.wheel(Press);
    door.paired(Err(tr!("front-error-unreachable")));
    assert_eq!(door.page_id(), "pairing-card");
    assert!(matches!(door.wheel(Press), Action::Pair { .. }));
}

#[test]
fn without_a_card_or_an_address_the_page_says_to_call_the_clinic_and_the_keyboard_can_type_it() {
    let mut door = FrontDoor::unpaired(&pairing_file::Found::Nothing, None);
    assert_eq!(door.page_id(), "pairing-ask-clinic");
    assert_eq!(door.wheel(Press), Action::None);
    assert_eq!(field(&door).0, tr!("front-pairing-address-label"));
    type_text(&mut door, "10.0.0.5");
    assert_eq!(door.apply(Confirm), Action::None);
    assert_eq!(door.page_id(), "pairing-code");
    type_text(&mut door, "7kq2-m9xd");
    assert_eq!(door.apply(Erase), Action::None);
    type_text(&mut door, "d");
    assert_eq!(
        door.apply(Confirm),
        Action::Pair {
            address: "10.0.0.5:7878".into(),
            code: "7kq2-m9xd".into(),
        }
    );
    // An unreadable card is said in red.
    let door = FrontDoor::unpaired(
        &pairing_file::Found::Unreadable("/x".into(), "bad".into()),
        None,
    );
    assert_eq!(door.page().lines[0].ok, Some(false));
}

#[test]
fn an_address_from_the_clinics_installation_starts_on_the_code() {
    let door = FrontDoor::unpaired(&pairing_file::Found::Nothing, Some("clinic.example.org"));
    assert_eq!(door.page_id(), "pairing-code");
}

#[test]
fn a_successful_pairing_shows_todays_session() {
    let mut door = FrontDoor::unpaired(&card("hub.example", Some("7KQ2-M9XD")), None);
    door.wheel(Press);
    door.paired(Ok(plan()));
    let page = door.page();
    assert_eq!(page.id, "today");
    assert!(page.lines.iter().any(|l| l.text == tr!("front-connected")));
}

#[test]
fn on_todays_page_the_wheel_chooses_start_practice_or_close_and_start_waits_for_a_wheel() {
    let mut door = FrontDoor::paired_with(plan());
    assert_eq!(door.page().chosen, 0);
    assert_eq!(door.wheel(Press), Action::None, "no wheel yet");
    assert_eq!(door.apply(TogglePause), Action::None);
    door.set_devices(vec![], true);
    assert_eq!(door.wheel(Press), Action::Done(Outcome::Start));
    assert_eq!(door.apply(TogglePause), Action::Done(Outcome::Start));
    door.wheel(Turn(1));
    assert_eq!(door.page().chosen, 1);
    assert_eq!(door.wheel(Press), Action::Done(Outcome::TryOut));
    door.wheel(Turn(1));
    assert_eq!(door.wheel(Press), Action::Done(Outcome::Quit));
    door.wheel(Turn(1));
    assert_eq!(door.page().chosen, 0, "round again");
    assert_eq!(door.apply(TryOut), Action::Done(Outcome::TryOut));
    assert_eq!(door.apply(Quit), Action::Done(Outcome::Quit));
}

#[test]
fn todays_page_shows_a_plan_and_a_message_that_arrive_while_it_is_open() {
    let mut door = FrontDoor::paired_with(plan());
    let before = door.page().lines;
    assert!(before.iter().any(|l| l.text == tr!("front-today-no-plan")));
    let r: regimen::Regimen = toml::from_str(
        "[[exercise]]\nkind = \"sine\"\nduration_s = 90.0\nrest_s = 60.0\n\
         [[exercise]]\nkind = \"dial\"\nduration_s = 45.0\n",
    )
    .unwrap();
    door.set_plan(TodayPlan::from_regimen(&r));
    door.set_message(Some("Good work this week.".into()));
    let after = door.page().lines;
    assert!(!after.iter().any(|l| l.text == tr!("front-today-no-plan")));
    assert!(
        after
            .iter()
            .any(|l| l.text.ends_with("Good work this week."))
    );
    assert_eq!(
        after.len(),
        before.len() + 1,
        "one more exercise and the message, no \"no plan\" line"
    );
}

#[test]
fn about_n_minutes_includes_the_rests_between_exercises() {
    let r: regimen::Regimen = toml::from_str(
        "[[exercise]]\nkind = \"sine\"\nduration_s = 90.0\nrest_s = 120.0\n\
         [[exercise]]\nkind = \"dial\"\nduration_s = 45.0\n",
    )
    .unwrap();
    let plan = TodayPlan::from_regimen(&r);
    assert_eq!(plan.total_s(), 90.0 + 120.0 + 45.0);
    let lines: Vec<String> = plan.lines().into_iter().map(|l| l.text).collect();
    // 255 s: about 5 minutes (not 3 without the rest).
    assert_eq!(
        lines[0],
        tr!("front-today-summary", exercises = 2, minutes = 5)
    );
    assert!(
        lines[1].ends_with("1:30") && lines[2].ends_with("0:45"),
        "{lines:?}"
    );
    assert!(
        !lines.iter().any(|l| l.contains('-')),
        "no internal names: {lines:?}"
    );
}

#[test]
fn typed_text_is_bounded() {
    let mut door = FrontDoor::unpaired(&pairing_file::Found::Nothing, None);
    type_text(&mut door, &"x".repeat(MAX_TYPED + 5));
    assert_eq!(field(&door).1.len(), MAX_TYPED);
}

#[test]
fn addresses_keep_their_port_and_bare_hosts_get_the_hubs() {
    assert_eq!(with_default_port("10.0.0.5"), "10.0.0.5:7878");
    assert_eq!(with_default_port("clinic.org:9000"), "clinic.org:9000");
    assert_eq!(with_default_port("clinic.org:"), "clinic.org::7878");
}

#[test]
fn no_wheel_is_a_red_line_and_blocks_start() {
    let check = describe(&wheel_devices::DeviceReport::default(), &Ok(vec![]));
    assert!(!check.wheel_ready);
    assert_eq!(check.lines[0].ok, Some(false));
    assert_eq!(check.lines[0].text, tr!("front-device-no-wheel"));
    assert_eq!(
        check.lines.last().unwrap().text,
        tr!("front-device-no-arm-sensors")
    );
}

#[test]
fn pairing_errors_read_as_the_catalogues_plain_words() {
    let e = netlink::pairing::PairError::Unreachable {
        addr: "h:1".into(),
        reason: "connection refused".into(),
    };
    assert_eq!(pairing_error_words(&e), tr!("front-error-unreachable"));
    let e = netlink::pairing::PairError::Refused("this code was already used".into());
    assert_eq!(pairing_error_words(&e), tr!("front-error-refused"));
}

#[test]
fn a_known_wheel_is_a_green_line_with_its_name() {
    let report = crate::readiness::tests::found_wheel(
        "Logitech G29 Driving Force Racing Wheel",
        (0x046d, 0xc24f),
    );
    let check = describe(&report, &Ok(vec![]));
    assert_eq!(check.lines[0].ok, Some(true));
    assert_eq!(
        check.lines[0].text,
        tr!(
            "front-device-wheel",
            name = "Logitech G29 Driving Force Racing Wheel"
        )
    );
    assert_eq!(check.wheel_path.as_deref(), Some("/dev/input/event7"));
}

#[test]
fn an_unknown_wheel_says_its_force_stays_low() {
    let check = describe(
        &crate::readiness::tests::found_wheel("Acme Wheel", (0x1234, 0x5678)),
        &Ok(vec![]),
    );
    assert_eq!(check.lines[0].ok, Some(true));
    assert_eq!(check.lines[1].text, tr!("front-device-wheel-unknown"));
}
