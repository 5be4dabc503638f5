//! End-to-end: the end screen after the last exercise, answered with keys under a display
//! (xdotool), and the answers reaching the clinic's hub in the session's `Bye`.

use std::time::Duration;
use telerehab_tests::clinic::{Hub, clinic, pair, show_json};
use telerehab_tests::windowed::{WindowedStation, press};

#[test]
fn the_end_screen_asks_pain_tiredness_and_difficulty_and_the_answers_reach_the_hub() {
    if std::env::var_os("DISPLAY").is_none() {
        eprintln!("SKIPPED: no display (run under xvfb-run to test the window)");
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let (data, code) = clinic(tmp.path());
    let hub = Hub::serve(&data, "127.0.0.1:0");
    let home = tmp.path().join("station");
    pair(&hub, &code, &home);
    let mut station = WindowedStation::start(&home, &["--duration", "2"]);
    station.start_the_exercise();
    station.wait_for("end screen: the session's results");
    std::thread::sleep(Duration::from_millis(500));
    // Results → pain: type 8 → tiredness: Esc skips (the window stays) → difficulty: 3 → thanks.
    press(&["Return", "8", "Return", "Escape", "3", "Return", "Return"]);
    let report = station.finish();
    assert!(
        report.contains("check-in            pain 8/10, tiredness skipped, too hard"),
        "{report}"
    );
    let shown = show_json(&data);
    let checkin = &shown["checkins"][0];
    assert_eq!(
        checkin["session_id"],
        shown["sessions"][0]["session"]["session_id"]
    );
    assert_eq!(checkin["pain_0_10"], 8, "{shown}");
    assert!(checkin["tiredness_0_10"].is_null(), "{shown}");
    assert_eq!(checkin["difficulty"], "too_hard", "{shown}");
    // The home keeps this session's results for the next end screen.
    assert!(home.join("results.json").exists());
}
