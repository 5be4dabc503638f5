//! End-to-end: a patient with one hand on the wheel and nothing else. `telerehab` with no
//! arguments on an unpaired simulated station (its wheel scripted: `TELEREHAB_WHEEL_SCRIPT`)
//! under a display (Xvfb), a clinic's hub on loopback and the clinic's pairing card in the
//! station's home: the language, pairing, today's page, the session with a rest after which
//! the next exercise waits for the patient, and the check-in — every step a wheel gesture, no
//! key pressed. The pages and cards are followed by their ids in the log, never by words.

use std::path::Path;
use std::process::{Command, Stdio};
use std::sync::mpsc;
use std::time::Duration;
use telerehab_tests::clinic::{Hub, clinic, ok, show_json};
use telerehab_tests::logged::{self, wheel};
use telerehab_tests::{Reaper, telerehab_bin};

/// Each next log line within 90 s (a loaded machine draws slowly).
fn wait_for(lines: &mpsc::Receiver<String>, what: &[&str]) -> String {
    logged::wait_for(lines, what, Duration::from_secs(90))
}

/// Two short dial exercises with a rest between them, prescribed for P-0042; no
/// `[patient] start_after_rest_s`, so after the rest the next exercise waits for the patient.
fn prescribe_two_with_a_rest(data: &Path, dir: &Path) {
    let file = dir.join("two-with-a-rest.toml");
    std::fs::write(
        &file,
        "[[exercise]]\nkind = \"dial\"\nduration_s = 3.0\nrest_s = 2.0\n\n\
         [[exercise]]\nkind = \"dial\"\nduration_s = 3.0\n",
    )
    .unwrap();
    ok(
        &[
            "hub",
            "patient",
            "regimen",
            "--data",
            data.to_str().unwrap(),
            "P-0042",
            "--file",
            file.to_str().unwrap(),
            "--by",
            "ana@clinic.example",
        ],
        None,
    );
}

#[test]
fn a_patient_goes_from_the_first_run_to_the_end_of_the_check_in_with_the_wheel_alone() {
    if std::env::var_os("DISPLAY").is_none() {
        eprintln!("SKIPPED: no display (run under xvfb-run to test the first-run window)");
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let (data, code) = clinic(tmp.path());
    prescribe_two_with_a_rest(&data, tmp.path());
    let hub = Hub::serve(&data, "127.0.0.1:0");
    let home = tmp.path().join("station");
    std::fs::create_dir_all(&home).unwrap();
    // The clinic's pairing card, as on the USB stick it lends with the station.
    std::fs::write(
        home.join("telerehab-pairing.toml"),
        format!("clinic_address = \"{}\"\ncode = \"{code}\"\n", hub.stations),
    )
    .unwrap();
    let script = tmp.path().join("wheel.script");
    std::fs::write(&script, "").unwrap();
    let mut child = Command::new(telerehab_bin())
        .env("TELEREHAB_HOME", &home)
        .env("TELEREHAB_WHEEL_SCRIPT", &script)
        .env("RUST_LOG", "info")
        .env_remove("TELEREHAB_LANGUAGE")
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let _reaper = Reaper(child.id());
    let lines = logged::stderr_lines(&mut child);

    // The first run: the language, turned to Deutsch and back to English, then pressed.
    wait_for(&lines, &["first-run page shown", "page_id=language"]);
    wheel(&script, &["turn 1", "turn -1", "press"]);
    wait_for(&lines, &["language chosen", "language=\"en\""]);
    let settings = std::fs::read_to_string(home.join("settings.toml")).unwrap();
    assert!(settings.contains("language = \"en\""), "{settings}");
    // The clinic's card: one press pairs.
    wait_for(&lines, &["first-run page shown", "page_id=pairing-card"]);
    assert!(
        !home.join("pairing").exists(),
        "not paired before the press"
    );
    wheel(&script, &["press"]);
    wait_for(&lines, &["first-run page shown", "page_id=today"]);
    let pairing = std::fs::read_to_string(home.join("pairing/hub.toml")).unwrap();
    assert!(pairing.contains(&hub.stations), "{pairing}");
    // Today's page: Start is chosen; a press starts the session.
    wheel(&script, &["press"]);
    // The session's start card waits for the patient: a press starts the exercise.
    wait_for(&lines, &["the wheel's buttons are watched"]);
    wheel(&script, &["press"]);
    // The first exercise, the rest, then "Ready?" waits for the patient.
    wait_for(&lines, &["break or card", "brk=Prescribed"]);
    wait_for(&lines, &["break or card", "brk=Ready", "waits=true"]);
    std::thread::sleep(Duration::from_millis(1500));
    wheel(&script, &["press"]);
    wait_for(&lines, &["break or card", "brk=None"]);
    // The check-in: results → pain (turned to 3) → tiredness (turned to 2) → difficulty
    // (about right) → thanks. Nothing is chosen until the wheel turns: the first turn to the
    // right enters each scale at its lowest, each next one steps up.
    wait_for(&lines, &["end screen: the session's results"]);
    std::thread::sleep(Duration::from_millis(500));
    wheel(&script, &["press"]);
    wait_for(&lines, &["end screen page", "page=\"pain\""]);
    wheel(&script, &["turn 1", "turn 1", "turn 1", "turn 1", "press"]);
    wait_for(&lines, &["end screen page", "page=\"effort\""]);
    wheel(&script, &["turn 1", "turn 1", "turn 1", "press"]);
    wait_for(&lines, &["end screen page", "page=\"difficulty\""]);
    wheel(&script, &["turn 1", "turn 1", "press"]);
    std::thread::sleep(Duration::from_millis(300));
    wheel(&script, &["press"]);
    wait_for(&lines, &["end screen closed"]);
    let status = child.wait().unwrap();
    assert!(status.success(), "{status}");
    let shown = show_json(&data);
    let checkin = &shown["checkins"][0];
    assert_eq!(checkin["pain_0_10"], 3, "{shown}");
    assert_eq!(checkin["tiredness_0_10"], 2, "{shown}");
    assert_eq!(checkin["difficulty"], "about_right", "{shown}");
}
