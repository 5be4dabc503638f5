//! End-to-end: a therapist's message written in the console reaches the paired station, is
//! shown on the start card of its next session under a display, and the hub learns when it
//! was seen (while the session runs), which the station keeps as confirmed; and a headless
//! station, which never shows it, still uploads every recording (issue 44: the hub's push on
//! the upload's connection once stopped every upload).

use std::time::Duration;
use telerehab_tests::clinic::{Hub, NewClinic, ok, pair, run_session};
use telerehab_tests::console::Console;
use telerehab_tests::windowed::{WindowedStation, screenshot};

/// A clinic whose hub serves the console, a therapist's message `text` written there for its
/// patient, and that patient's station paired in `dir/station`.
struct Written {
    clinic: NewClinic,
    hub: Hub,
    console: Console,
    cookie: String,
    /// The patient's messages, `/api/patients/{id}/messages`.
    messages: String,
    home: std::path::PathBuf,
}

fn a_paired_station_with_a_message(dir: &std::path::Path, text: &str) -> Written {
    let clinic = NewClinic::make(dir, None);
    let hub = Hub::serve_console(&clinic.data, "127.0.0.1:0");
    let console = Console::new(&clinic.data, hub.web());
    let cookie = console.login("ana@clinic.example", &clinic.admin_password);
    let patients = console.get("/api/patients", &cookie).json();
    let messages = format!(
        "/api/patients/{}/messages",
        patients[0]["id"].as_str().unwrap()
    );
    let body = serde_json::json!({ "text": text }).to_string();
    let posted = console.request("POST", &messages, Some(&cookie), &body);
    assert_eq!(
        posted.status,
        201,
        "{}",
        String::from_utf8_lossy(&posted.body)
    );
    let home = dir.join("station");
    pair(&hub, &clinic.code, &home);
    Written {
        clinic,
        hub,
        console,
        cookie,
        messages,
        home,
    }
}

#[test]
fn a_message_from_the_console_shows_on_the_next_start_card_and_the_hub_learns_it_was_seen() {
    if std::env::var_os("DISPLAY").is_none() {
        eprintln!("SKIPPED: no display (run under xvfb-run to test the window)");
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let text = "Well done this week, Ana — try to keep the car in the middle today.";
    // The hub stays up until the test's end.
    let Written {
        hub: _hub,
        console,
        cookie,
        messages,
        home,
        ..
    } = a_paired_station_with_a_message(tmp.path(), text);

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

/// The "recording upload" line of a `run` report, or the "recordings" line of `sync`.
fn upload_line<'a>(said: &'a str, prefix: &str) -> &'a str {
    said.lines()
        .find(|l| l.starts_with(prefix))
        .unwrap_or_else(|| panic!("no {prefix:?} line in {said}"))
}

#[test]
fn a_therapists_message_never_stops_a_headless_stations_uploads_and_waits_unseen_for_it() {
    let tmp = tempfile::tempdir().unwrap();
    let text = "Well done this week - keep going!";
    let Written {
        clinic,
        hub,
        console,
        cookie,
        messages,
        home,
    } = a_paired_station_with_a_message(tmp.path(), text);
    let port = hub.stations_port();

    // The next run (headless: the message is never shown) uploads its recording.
    let report = run_session(&home, "2");
    let line = upload_line(&report, "recording upload");
    assert!(
        line.contains(" 1 uploaded") && line.contains(" 0 still queued"),
        "{report}"
    );
    // The message is kept for the patient, not marked seen, and the hub still waits for it.
    let kept: serde_json::Value =
        serde_json::from_slice(&std::fs::read(home.join("messages.json")).unwrap()).unwrap();
    assert_eq!(kept.as_array().map(Vec::len), Some(1), "{kept}");
    assert_eq!(kept[0]["text"], text, "{kept}");
    assert!(kept[0]["seen_unix_ms"].is_null(), "{kept}");
    let at_hub = console.get(&messages, &cookie).json();
    assert!(at_hub[0]["seen_at_ms"].is_null(), "{at_hub}");
    hub.stop();

    // A run while the hub is down leaves its recording queued; `sync` uploads it once the hub
    // is back (which pushes the unseen message on every connection).
    let report = run_session(&home, "2");
    assert!(
        upload_line(&report, "recording upload").contains(" 1 still queued"),
        "{report}"
    );
    let hub = Hub::serve_with(
        &clinic.data,
        &format!("127.0.0.1:{port}"),
        &["--web", "127.0.0.1:0"],
    );
    let synced = ok(&["sync"], Some(&home));
    let line = upload_line(&synced, "sync: recordings");
    assert!(
        line.contains(" 1 uploaded") && line.contains(" 0 still queued"),
        "{synced}"
    );
    let again = ok(&["sync"], Some(&home));
    assert!(
        upload_line(&again, "sync: recordings").contains("0 uploaded (0.00 MB sent), 0 still"),
        "{again}"
    );
    let stored = std::fs::read_dir(clinic.data.join("recordings"))
        .unwrap()
        .flatten()
        .flat_map(|d| std::fs::read_dir(d.path()).into_iter().flatten().flatten())
        .filter(|f| f.path().extension().is_some_and(|e| e == "mcap"))
        .count();
    assert_eq!(stored, 2, "both recordings at the hub");
    // Still one message, still unseen: the next start card shows it.
    let kept: serde_json::Value =
        serde_json::from_slice(&std::fs::read(home.join("messages.json")).unwrap()).unwrap();
    assert_eq!(kept.as_array().map(Vec::len), Some(1), "{kept}");
    assert!(kept[0]["seen_unix_ms"].is_null(), "{kept}");
    let console = Console::new(&clinic.data, hub.web());
    let cookie = console.login(
        "ana@clinic.example",
        &format!("{} renewed", clinic.admin_password),
    );
    let at_hub = console.get(&messages, &cookie).json();
    assert_eq!(at_hub[0]["text"], text, "{at_hub}");
    assert!(at_hub[0]["seen_at_ms"].is_null(), "{at_hub}");
    hub.stop();
}
