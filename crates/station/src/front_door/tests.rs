use super::checks::describe;
use super::*;
use crate::render::window::UserRequest::*;

fn type_text(door: &mut FrontDoor, text: &str) {
    for c in text.chars() {
        assert_eq!(door.apply(Typed(c)), Action::None);
    }
}

fn field(door: &FrontDoor) -> (String, String) {
    door.page().field.expect("the pairing page has a field")
}

#[test]
fn typing_the_address_then_the_code_asks_to_pair_with_the_default_port() {
    let mut door = FrontDoor::unpaired(None);
    assert_eq!(field(&door).0, "Clinic address");
    type_text(&mut door, "clinic.example");
    assert_eq!(
        door.apply(Confirm),
        Action::None,
        "Enter moves on to the code"
    );
    assert!(field(&door).0.starts_with("Pairing code"));
    type_text(&mut door, "7KQ2-M9XX");
    assert_eq!(door.apply(Erase), Action::None);
    type_text(&mut door, "D");
    assert_eq!(field(&door).1, "7KQ2-M9XD");
    assert_eq!(
        door.apply(Confirm),
        Action::Pair {
            address: "clinic.example:7878".into(),
            code: "7KQ2-M9XD".into()
        }
    );
    assert_eq!(door.page().title, "Connecting to your clinic…");
    assert_eq!(
        door.apply(Typed('x')),
        Action::None,
        "keys wait while connecting"
    );
}

#[test]
fn an_address_from_the_clinics_installation_starts_on_the_code() {
    let mut door = FrontDoor::unpaired(Some("hub.clinic.org:9000"));
    assert!(field(&door).0.starts_with("Pairing code"));
    assert!(
        door.page()
            .lines
            .iter()
            .any(|l| l.text.contains("hub.clinic.org:9000")),
        "the address is shown"
    );
    assert_eq!(door.apply(NextField), Action::None);
    assert_eq!(
        field(&door),
        ("Clinic address".into(), "hub.clinic.org:9000".into())
    );
}

#[test]
fn a_failed_pairing_returns_to_the_code_with_the_reason_in_red() {
    let mut door = FrontDoor::unpaired(Some("h:1"));
    type_text(&mut door, "ABCD-EFGH");
    assert!(matches!(door.apply(Confirm), Action::Pair { .. }));
    door.paired(Err("The clinic did not accept this code.".into()));
    let page = door.page();
    assert_eq!(
        page.error.as_deref(),
        Some("The clinic did not accept this code.")
    );
    assert_eq!(
        page.field.unwrap().1,
        "",
        "the code is cleared for a new try"
    );
    type_text(&mut door, "A");
    assert_eq!(door.page().error, None, "typing again clears the error");
}

#[test]
fn a_successful_pairing_shows_todays_session() {
    let mut door = FrontDoor::unpaired(Some("h:1"));
    type_text(&mut door, "ABCD-EFGH");
    assert!(matches!(door.apply(Confirm), Action::Pair { .. }));
    door.paired(Ok(TodayPlan::default_drive("sine-road", 120.0)));
    let page = door.page();
    assert_eq!(page.title, "Today's session");
    assert!(
        page.lines[0]
            .text
            .starts_with("1 exercise, about 2 minutes"),
        "{:?}",
        page.lines
    );
    assert!(page.lines[1].text.contains("Sine road"), "{:?}", page.lines);
    assert!(
        page.lines
            .iter()
            .any(|l| l.ok == Some(true) && l.text.contains("connected to your clinic (h:1)")),
        "{:?}",
        page.lines
    );
}

#[test]
fn enter_without_a_code_or_address_asks_for_what_is_missing() {
    let mut door = FrontDoor::unpaired(None);
    assert_eq!(door.apply(Confirm), Action::None);
    assert_eq!(field(&door).0, "Clinic address", "no address: stays on it");
    assert_eq!(door.apply(NextField), Action::None);
    type_text(&mut door, "CODE-1234");
    assert_eq!(door.apply(Confirm), Action::None);
    assert!(door.page().error.unwrap().contains("address"));
}

#[test]
fn space_starts_only_once_a_wheel_is_ready() {
    let mut door = FrontDoor::paired_with(TodayPlan::default_drive("dial-sine", 60.0));
    assert!(
        door.page()
            .lines
            .iter()
            .any(|l| l.text.starts_with("Checking")),
        "before the first check"
    );
    assert_eq!(door.apply(TogglePause), Action::None);
    door.set_devices(vec![], true);
    assert_eq!(door.apply(TogglePause), Action::Done(Outcome::Start));
    assert_eq!(door.apply(Confirm), Action::Done(Outcome::Start));
}

#[test]
fn f2_tries_out_and_esc_closes_on_every_page() {
    for mut door in [
        FrontDoor::unpaired(None),
        FrontDoor::paired_with(TodayPlan::default_drive("sine-road", 60.0)),
    ] {
        assert_eq!(door.apply(TryOut), Action::Done(Outcome::TryOut));
        assert_eq!(door.apply(Quit), Action::Done(Outcome::Quit));
    }
}

#[test]
fn typed_text_is_bounded() {
    let mut door = FrontDoor::unpaired(None);
    for _ in 0..500 {
        door.apply(Typed('a'));
    }
    assert_eq!(field(&door).1.len(), MAX_TYPED);
}

#[test]
fn addresses_keep_their_port_and_bare_hosts_get_the_hubs() {
    assert_eq!(with_default_port("10.0.0.5"), "10.0.0.5:7878");
    assert_eq!(with_default_port("clinic.org:9000"), "clinic.org:9000");
    assert_eq!(with_default_port("clinic.org:"), "clinic.org::7878");
}

#[test]
fn a_regimen_reads_as_named_exercises_with_minutes() {
    let r: regimen::Regimen = toml::from_str(
        "[[exercise]]\nkind = \"sine\"\nduration_s = 90.0\n\
         [[exercise]]\nkind = \"dial\"\nduration_s = 45.0\n",
    )
    .unwrap();
    let plan = TodayPlan::from_regimen(&r);
    let lines: Vec<String> = plan.lines().into_iter().map(|l| l.text).collect();
    assert_eq!(lines[0], "2 exercises, about 3 minutes");
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
fn no_wheel_is_a_red_line_saying_what_to_plug_in_and_blocks_start() {
    let check = describe(&haptic_wheel::DeviceReport::default(), &Ok(vec![]));
    assert!(!check.wheel_ready);
    assert_eq!(check.lines[0].ok, Some(false));
    assert!(
        check.lines[0].text.contains("plug it in"),
        "{:?}",
        check.lines
    );
    assert!(check.lines.last().unwrap().text.contains("No arm sensors"));
}

#[test]
fn pairing_errors_read_as_plain_words() {
    let e = netlink::pairing::PairError::Unreachable {
        addr: "h:1".into(),
        reason: "connection refused".into(),
    };
    let words = pairing_error_words(&e);
    assert!(
        words.starts_with("Cannot reach the clinic at h:1"),
        "{words}"
    );
    let e = netlink::pairing::PairError::Refused("this code was already used".into());
    assert_eq!(pairing_error_words(&e), "This code was already used.");
}

#[test]
fn a_known_wheel_is_a_green_line_with_its_strongest_push_in_newton_metres() {
    let report = crate::commands::doctor::tests::found_wheel(
        "Logitech G29 Driving Force Racing Wheel",
        (0x046d, 0xc24f),
    );
    let ceiling_nm = report.wheels[0].ceiling.as_ref().unwrap().ceiling_nm;
    let check = describe(&report, &Ok(vec![]));
    assert_eq!(check.lines[0].ok, Some(true));
    assert_eq!(
        check.lines[0].text,
        format!(
            "Wheel: Logitech G29 Driving Force Racing Wheel, pushes at most {ceiling_nm:.1} N·m"
        )
    );
    assert_eq!(check.wheel_path.as_deref(), Some("/dev/input/event7"));
}

#[test]
fn an_unknown_wheel_is_named_as_such_with_its_low_assumed_push() {
    let check = describe(
        &crate::commands::doctor::tests::found_wheel("Acme Wheel", (0x1234, 0x5678)),
        &Ok(vec![]),
    );
    assert_eq!(check.lines[0].ok, Some(true));
    assert!(
        check.lines[0]
            .text
            .contains("a model telerehab does not know"),
        "{:?}",
        check.lines
    );
}
