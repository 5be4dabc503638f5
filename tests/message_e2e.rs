//! End-to-end: a therapist's message written in the console reaches the paired station, is
//! shown on the start card of its next session under a display, and the hub learns when it
//! was seen (while the session runs), which the station keeps as confirmed.

use std::time::Duration;
use telerehab_tests::clinic::{Hub, NewClinic, pair};
use telerehab_tests::console::Console;
use telerehab_tests::windowed::{WindowedStation, screenshot};

#[test]
fn a_message_from_the_console_shows_on_the_next_start_card_and_the_hub_learns_it_was_seen() {
    if std::env::var_os("DISPLAY").is_none() {
        eprintln!("SKIPPED: no display (run under xvfb-run to test the window)");
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let clinic = NewClinic::make(tmp.path(), None);
    let hub = Hub::serve_console(&clinic.data, "127.0.0.1:0");
    let console = Console::new(&clinic.data, hub.web());
    let cookie = console.login("ana@clinic.example", &clinic.admin_password);
    let patients = console.get("/api/patients", &cookie).json();
    let messages = format!(
        "/api/patients/{}/messages",
        patients[0]["id"].as_str().unwrap()
    );
    let text = "Well done this week, Ana — try to keep the car in the middle today.";
    let body = serde_json::json!({ "text": text }).to_string();
    let posted = console.request("POST", &messages, Some(&cookie), &body);
    assert_eq!(
        posted.status,
        201,
        "{}",
        String::from_utf8_lossy(&posted.body)
    );
    let home = tmp.path().join("station");
    pair(&hub, &clinic.code, &home);

    // A windowed session (no end screen).
    let mut station =
        WindowedStation::start(&home, &["--duration", "2", "--checkin-timeout-s", "0"]);
    station.wait_for("the start card shows the therapist's message");
    station.wait_for("the therapist's message is on the screen");
    std::thread::sleep(Duration::from_millis(500));
    screenshot("message-start-card");
    // Seen while the session runs: the hub has it before the session ends.
    let mut seen = serde_json::Value::Null;
    for _ in 0..100 {
        seen = console.get(&messages, &cookie).json();
        if seen[0]["seen_at_ms"].is_i64() {
            break;
        }
        std::thread::sleep(Duration::from_millis(200));
    }
    assert_eq!(seen[0]["text"], text, "{seen}");
    assert!(seen[0]["seen_at_ms"].is_i64(), "not seen: {seen}");
    assert!(seen[0]["delivered_at_ms"].is_i64(), "{seen}");
    station.start_the_exercise();
    station.finish();
    let kept: serde_json::Value =
        serde_json::from_slice(&std::fs::read(home.join("messages.json")).unwrap()).unwrap();
    assert_eq!(kept[0]["seen_confirmed"], true, "{kept}");
}
