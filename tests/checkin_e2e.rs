//! End-to-end: the end screen after the last exercise, answered with keys under a display
//! (xdotool), the answers reaching the clinic's hub in the session's `Bye`, the clinic's pain
//! threshold and phone number reaching the station, and a pain at that threshold ending on the
//! page that says to stop (never the ordinary thanks) and stopping the day.
//!
//! With `TELEREHAB_SCREENSHOTS` set, each page is saved as `checkin-<page>-<language>.png`
//! (the language of `LANG`: run once with `LANG=de_DE.UTF-8` for the German pages).

use std::path::Path;
use std::time::Duration;
use telerehab_tests::clinic::{Hub, clinic, pair, show_json};
use telerehab_tests::windowed::{WindowedStation, press, screenshot};

const PHONE: &str = "+49 30 1234567";

fn no_display() -> bool {
    if std::env::var_os("DISPLAY").is_none() {
        eprintln!("SKIPPED: no display (run under xvfb-run to test the window)");
        return true;
    }
    false
}

/// The language of the screenshots' names: `LANG`'s, e.g. `de` of `de_DE.UTF-8`.
fn language() -> String {
    std::env::var("LANG")
        .ok()
        .and_then(|l| l.get(..2).map(str::to_owned))
        .filter(|l| l.chars().all(|c| c.is_ascii_lowercase()) && l != "C.")
        .unwrap_or_else(|| "en".into())
}

fn shot(page: &str) {
    std::thread::sleep(Duration::from_millis(700));
    screenshot(&format!("checkin-{page}-{}", language()));
}

/// The clinic's pain settings the station keeps, as JSON.
fn kept_care(home: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(home.join("care.json")).expect("care.json in the home");
    serde_json::from_str(&text).unwrap()
}

#[test]
fn the_end_screen_asks_pain_effort_and_difficulty_and_the_answers_and_the_clinics_settings_travel()
{
    if no_display() {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let (data, code) = clinic(tmp.path());
    let hub = Hub::serve_with(
        &data,
        "127.0.0.1:0",
        &["--pain-threshold", "7", "--clinic-phone", PHONE],
    );
    let home = tmp.path().join("station");
    pair(&hub, &code, &home);
    let mut station = WindowedStation::start(&home, &["--duration", "2"]);
    station.start_the_exercise();
    station.wait_for("end screen: the session's results");
    shot("results");
    // The hub's threshold and phone number reached the station during the session.
    let care = kept_care(&home);
    assert_eq!(care["pain_threshold_0_10"], 7, "{care}");
    assert_eq!(care["clinic_phone"], PHONE, "{care}");
    // Results → pain: nothing is chosen yet; a stray press records nothing.
    press(&["Return"]);
    station.wait_for("page=\"pain\"");
    shot("pain-unanswered");
    press(&["Return"]);
    // A digit chooses (the wheel's turns and the arrows step; see the unit tests).
    press(&["4"]);
    shot("pain-chosen");
    press(&["Return"]);
    station.wait_for("page=\"effort\"");
    press(&["6"]);
    shot("effort");
    press(&["Return"]);
    station.wait_for("page=\"difficulty\"");
    press(&["3"]);
    shot("difficulty");
    press(&["Return"]);
    station.wait_for("page=\"thanks\"");
    shot("thanks");
    press(&["Return"]);
    let report = station.finish();
    assert!(
        report.contains("check-in            pain 4/10, effort 6/10, too hard"),
        "{report}"
    );
    let shown = show_json(&data);
    let checkin = &shown["checkins"][0];
    assert_eq!(
        checkin["session_id"],
        shown["sessions"][0]["session"]["session_id"]
    );
    assert_eq!(checkin["pain_0_10"], 4, "{shown}");
    assert_eq!(checkin["tiredness_0_10"], 6, "{shown}");
    assert_eq!(checkin["difficulty"], "too_hard", "{shown}");
    // The home keeps this session's results for the next end screen; no pain stop.
    assert!(home.join("results.json").exists());
    assert!(!home.join("pain-stop.json").exists());
}

#[test]
fn a_pain_at_the_clinics_threshold_ends_on_the_pain_page_and_stops_the_day() {
    if no_display() {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let (data, code) = clinic(tmp.path());
    let hub = Hub::serve_with(
        &data,
        "127.0.0.1:0",
        &["--pain-threshold", "5", "--clinic-phone", PHONE],
    );
    let home = tmp.path().join("station");
    pair(&hub, &code, &home);
    let mut station = WindowedStation::start(&home, &["--duration", "2"]);
    station.start_the_exercise();
    station.wait_for("end screen: the session's results");
    press(&["Return"]);
    station.wait_for("page=\"pain\"");
    press(&["5", "Return"]);
    // The clinic's threshold is 5: the page that says to stop, not the next question.
    station.wait_for("page=\"pain-stop\"");
    shot("pain-stop");
    press(&["Return"]);
    let report = station.finish();
    assert!(
        report.contains("check-in            pain 5/10, effort skipped"),
        "{report}"
    );
    assert_eq!(show_json(&data)["checkins"][0]["pain_0_10"], 5);
    // The day is stopped on this station: today's page offers no session until cleared.
    let stop: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(home.join("pain-stop.json")).unwrap())
            .unwrap();
    assert_eq!(stop["pain_0_10"], 5, "{stop}");
    assert_eq!(kept_care(&home)["pain_threshold_0_10"], 5);
}
