//! End-to-end: the pause is a choice page the wheel answers. A simulated session with its
//! window on a display the test starts itself (Xvfb), its wheel scripted
//! (`TELEREHAB_WHEEL_SCRIPT`): a press starts the exercise and another pauses it; a turn
//! chooses a rest and a press takes it; a press goes on from the rest; paused again, two turns
//! choose to end, a press asks "End now?" and a last press ends the session — no key pressed.
//! The choices are followed by the log's words for them (`chosen=Rest`), never the page's.

use std::process::{Command, Stdio};
use std::sync::mpsc;
use std::time::Duration;
use telerehab_tests::logged::{self, Xvfb, wheel};
use telerehab_tests::{Reaper, telerehab_bin};

/// Each next log line within 90 s (a loaded machine draws slowly).
fn wait_for(lines: &mpsc::Receiver<String>, what: &[&str]) -> String {
    logged::wait_for(lines, what, Duration::from_secs(90))
}

/// Long enough for the station to take a gesture and draw its page before the next.
fn settle() {
    std::thread::sleep(Duration::from_millis(1500));
}

#[test]
fn paused_the_wheel_chooses_a_rest_then_ending_and_a_press_does_each() {
    let display = Xvfb::start();
    let tmp = tempfile::tempdir().unwrap();
    let home = tmp.path().join("station");
    std::fs::create_dir_all(&home).unwrap();
    let script = tmp.path().join("wheel.script");
    std::fs::write(&script, "").unwrap();
    let mut child = Command::new(telerehab_bin())
        .args(["run", "--sim", "--duration", "120", "--seed", "7", "--home"])
        .arg(&home)
        .env("DISPLAY", &display.display)
        .env("TELEREHAB_WHEEL_SCRIPT", &script)
        .env("TELEREHAB_LANGUAGE", "en")
        .env("RUST_LOG", "info")
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let _reaper = Reaper(child.id());
    let lines = logged::stderr_lines(&mut child);

    // The start card waits for a press; a second press pauses: "Go on" is chosen.
    wait_for(&lines, &["the wheel's buttons are watched"]);
    settle();
    wheel(&script, &["press"]);
    wait_for(&lines, &["the patient paused or went on", "paused=false"]);
    settle();
    wheel(&script, &["press"]);
    wait_for(&lines, &["the patient paused or went on", "paused=true"]);
    settle();
    // A turn to the right chooses a rest; a press takes it.
    wheel(&script, &["turn 1"]);
    wait_for(&lines, &["the pause page's choice", "chosen=Rest"]);
    wheel(&script, &["press"]);
    wait_for(&lines, &["break or card", "brk=Asked"]);
    settle();
    // A press goes on from the rest.
    wheel(&script, &["press"]);
    wait_for(&lines, &["break or card", "brk=None"]);
    settle();
    // Paused again: two turns to the right choose to end; a press asks "End now?".
    wheel(&script, &["press"]);
    wait_for(&lines, &["the patient paused or went on", "paused=true"]);
    settle();
    wheel(&script, &["turn 1", "turn 1"]);
    wait_for(&lines, &["the pause page's choice", "chosen=End"]);
    wheel(&script, &["press"]);
    wait_for(&lines, &["the patient chose to end from the pause page"]);
    wait_for(&lines, &["break or card", "end_asked=true"]);
    settle();
    // A press on "End now?" ends the session.
    wheel(&script, &["press"]);
    wait_for(&lines, &["the patient ended the session from the wheel"]);
    let status = child.wait().unwrap();
    assert!(status.success(), "{status}");
}
