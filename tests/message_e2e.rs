//! End-to-end: a therapist's message written in the console reaches the paired station, is
//! shown on the start card of its next session under a display, and the hub learns when it
//! was seen (while the session runs), which the station keeps as confirmed.

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::Duration;
use telerehab_tests::clinic::{Hub, NewClinic, pair};
use telerehab_tests::console::Console;
use telerehab_tests::{telerehab_bin, xdotool_in};

/// Where the test saves what the screen showed (`$TELEREHAB_SCREENSHOTS`, for
/// docs/screenshots), or nowhere.
fn screenshot(name: &str) {
    if let Some(dir) = std::env::var_os("TELEREHAB_SCREENSHOTS") {
        let path = std::path::Path::new(&dir).join(format!("{name}.png"));
        let ok = Command::new("import")
            .args(["-window", "root"])
            .arg(&path)
            .status()
            .is_ok_and(|s| s.success());
        assert!(ok, "cannot take the screenshot {}", path.display());
    }
}

/// A windowed simulated session of the station in `home` (no end screen), its log lines.
fn session(home: &std::path::Path) -> (Child, mpsc::Receiver<String>) {
    let mut station = Command::new(telerehab_bin())
        .args(["run", "--sim", "--duration", "2", "--seed", "7"])
        .args(["--checkin-timeout-s", "0", "--home"])
        .arg(home)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let (tx, lines) = mpsc::channel();
    let stderr = BufReader::new(station.stderr.take().unwrap());
    std::thread::spawn(move || {
        for line in stderr.lines().map_while(Result::ok) {
            let _ = tx.send(line);
        }
    });
    (station, lines)
}

/// Waits (generously: a loaded machine draws slowly) for a line containing `what`.
fn wait_for(lines: &mpsc::Receiver<String>, what: &str) -> String {
    let mut seen = Vec::new();
    loop {
        match lines.recv_timeout(Duration::from_secs(60)) {
            Ok(line) if line.contains(what) => return line,
            Ok(line) => seen.push(line),
            Err(e) => panic!(
                "waited for {what:?}: {e}; the log said:\n{}",
                seen.join("\n")
            ),
        }
    }
}

/// Presses Space in the patient window until the exercise starts, then lets the session end.
fn start_and_finish(mut station: Child, lines: &mpsc::Receiver<String>) -> String {
    let started = (0..30).any(|_| {
        xdotool_in("^telerehab$", &["key", "space"]);
        let deadline = std::time::Instant::now() + Duration::from_secs(2);
        while let Some(left) = deadline.checked_duration_since(std::time::Instant::now()) {
            match lines.recv_timeout(left) {
                Ok(l) if l.contains("paused=false") => return true,
                Ok(_) => {}
                Err(_) => break,
            }
        }
        false
    });
    assert!(started, "Space never started the exercise");
    let mut report = String::new();
    std::io::Read::read_to_string(station.stdout.as_mut().unwrap(), &mut report).unwrap();
    assert!(station.wait().unwrap().success(), "{report}");
    report
}

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

    let (station, lines) = session(&home);
    wait_for(&lines, "the start card shows the therapist's message");
    wait_for(&lines, "the therapist's message is on the screen");
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
    start_and_finish(station, &lines);
    let kept: serde_json::Value =
        serde_json::from_slice(&std::fs::read(home.join("messages.json")).unwrap()).unwrap();
    assert_eq!(kept[0]["seen_confirmed"], true, "{kept}");
}
