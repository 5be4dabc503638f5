//! End-to-end: the end screen after the last exercise, answered with keys under a display
//! (xdotool), and the answers reaching the clinic's hub in the session's `Bye`.

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use std::sync::mpsc;
use std::time::Duration;
use telerehab_tests::clinic::{Hub, clinic, pair, show_json};
use telerehab_tests::{telerehab_bin, xdotool_in};

/// Press `keys` in the patient window (named "telerehab"), waiting for it to open.
fn press(keys: &[&str]) {
    for key in keys {
        xdotool_in("^telerehab$", &["key", key]);
        std::thread::sleep(Duration::from_millis(300));
    }
}

/// Wait (generously: a loaded machine draws slowly) for a line containing `what`.
fn wait_for(lines: &mpsc::Receiver<String>, what: &str) {
    let mut seen = Vec::new();
    loop {
        match lines.recv_timeout(Duration::from_secs(40)) {
            Ok(line) if line.contains(what) => return,
            Ok(line) => seen.push(line),
            Err(e) => panic!(
                "waited for {what:?}: {e}; the log said:\n{}",
                seen.join("\n")
            ),
        }
    }
}

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
    let mut station = Command::new(telerehab_bin())
        .args(["run", "--sim", "--duration", "2", "--seed", "7"])
        .arg("--home")
        .arg(&home)
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
    let mut stdout = BufReader::new(station.stdout.take().unwrap());
    let mut line = String::new();
    while stdout.read_line(&mut line).unwrap() > 0 && !line.contains("render: adapter") {
        line.clear();
    }
    // Space starts the exercise, once the window has mapped and takes keys (a key sent
    // before is lost: press again until the log says it started).
    let started = (0..30).any(|_| {
        press(&["space"]);
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
    wait_for(&lines, "end screen: the session's results");
    std::thread::sleep(Duration::from_millis(500));
    // Results → pain: type 8 → tiredness: Esc skips (the window stays) → difficulty: 3 → thanks.
    press(&["Return", "8", "Return", "Escape", "3", "Return", "Return"]);
    let mut report = String::new();
    std::io::Read::read_to_string(&mut stdout, &mut report).unwrap();
    assert!(station.wait().unwrap().success(), "{report}");
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
