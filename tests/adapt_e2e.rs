//! End-to-end: difficulty that follows the patient. A regimen with a `[difficulty]` table
//! prescribed at the hub; three simulated sessions in which the station adapts the difficulty
//! within the therapist's bounds and the hub keeps the history; and a "too hard" answer on
//! the end screen (under a display) lowering the next session's difficulty.

use std::path::Path;
use std::time::Duration;
use telerehab_tests::clinic::{Hub, clinic, ok, pair, run_session, show_json};
use telerehab_tests::windowed::{WindowedStation, press};

/// The therapist's bounds: 0.30–0.60, starting at 0.60; one short dial exercise.
const REGIMEN: &str = "[difficulty]\ntarget_success = 0.7\nlowest = 0.3\nhighest = 0.6\n\
    start = 0.6\n\n[[exercise]]\nkind = \"dial\"\nduration_s = 2.0\n";

/// Prescribes [`REGIMEN`] to P-0042 of the clinic at `data`.
fn prescribe(data: &Path, tmp: &Path) {
    let file = tmp.join("adapt.toml");
    std::fs::write(&file, REGIMEN).unwrap();
    let set = ok(
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
    assert!(set.contains("regimen version 1"), "{set}");
}

/// The difficulty a run's report says it ran at, and the line.
fn difficulty_of(report: &str) -> (f64, String) {
    let line = report
        .lines()
        .find(|l| l.starts_with("difficulty "))
        .unwrap_or_else(|| panic!("no difficulty line in {report}"));
    let d = line.split_whitespace().nth(1).unwrap().parse().unwrap();
    (d, line.to_owned())
}

#[test]
fn three_sessions_adapt_the_difficulty_within_the_therapists_bounds_and_the_hub_keeps_it() {
    let tmp = tempfile::tempdir().unwrap();
    let (data, code) = clinic(tmp.path());
    prescribe(&data, tmp.path());
    let hub = Hub::serve(&data, "127.0.0.1:0");
    let home = tmp.path().join("station");
    pair(&hub, &code, &home);
    let mut ran = Vec::new();
    for _ in 0..3 {
        let report = run_session(&home, "4");
        ran.push(difficulty_of(&report));
    }
    let (first, why) = &ran[0];
    assert_eq!(*first, 0.6, "{why}");
    assert!(
        why.contains("first session: the therapist's start"),
        "{why}"
    );
    for (d, why) in &ran {
        assert!((0.3..=0.6).contains(d), "outside the bounds: {why}");
        assert!(
            why.contains("success "),
            "each session tells its success: {why}"
        );
    }
    // The later sessions adapt from the success rate (or say they are held at a bound).
    for (d, why) in &ran[1..] {
        assert!(
            why.contains("% target: ") || why.contains("held at the therapist's"),
            "{d}: {why}"
        );
    }
    // The station keeps its history in its home, one line a session.
    let history = std::fs::read_to_string(home.join("difficulty.jsonl")).unwrap();
    assert_eq!(history.lines().count(), 3, "{history}");
    // Each recording keeps the difficulty it ran at, and the regimen as run at it.
    let mut recordings: Vec<_> = std::fs::read_dir(home.join("recordings"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "mcap"))
        .collect();
    recordings.sort();
    assert_eq!(recordings.len(), 3, "{recordings:?}");
    for (path, (d, why)) in recordings.iter().zip(&ran) {
        let meta = record::Recording::open(path).unwrap().metadata;
        let note = meta
            .difficulty
            .unwrap_or_else(|| panic!("{}", path.display()));
        assert!((note.difficulty - d).abs() < 0.006, "{why}: {note:?}");
        assert!(why.contains(&note.reason), "{why}: {note:?}");
        assert!(meta.regimen_toml.unwrap().contains("[difficulty]"));
    }
    // The hub has the history, newest first, with each session's reason and success.
    let shown = show_json(&data);
    let stored = shown["difficulty"].as_array().unwrap();
    assert_eq!(stored.len(), 3, "{shown}");
    for (s, (d, _)) in stored.iter().rev().zip(&ran) {
        assert!((s["difficulty"].as_f64().unwrap() - d).abs() < 0.006, "{s}");
        assert!(s["success_rate"].as_f64().is_some(), "{s}");
        assert!(!s["reason"].as_str().unwrap().is_empty(), "{s}");
    }
    assert_eq!(
        stored[0]["session_id"], shown["sessions"][0]["session"]["session_id"],
        "{shown}"
    );
}

/// A windowed session from `home` answered "too hard" on the end screen (pain and
/// tiredness skipped); its report.
fn windowed_session_felt_too_hard(home: &Path) -> String {
    let mut station = WindowedStation::start(home, &["--duration", "4"]);
    station.start_the_exercise();
    station.wait_for("end screen: the session's results");
    std::thread::sleep(Duration::from_millis(500));
    // Results → pain: Esc → tiredness: Esc → difficulty: 3 (too hard) → thanks.
    press(&["Return", "Escape", "Escape", "3", "Return", "Return"]);
    let report = station.finish();
    assert!(report.contains("too hard"), "{report}");
    report
}

#[test]
fn a_too_hard_answer_on_the_end_screen_lowers_the_next_sessions_difficulty() {
    if std::env::var_os("DISPLAY").is_none() {
        eprintln!("SKIPPED: no display (run under xvfb-run to test the end screen)");
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let (data, code) = clinic(tmp.path());
    prescribe(&data, tmp.path());
    let hub = Hub::serve(&data, "127.0.0.1:0");
    let home = tmp.path().join("station");
    pair(&hub, &code, &home);
    let (felt, why) = difficulty_of(&windowed_session_felt_too_hard(&home));
    assert_eq!(felt, 0.6, "{why}");
    let (next, why) = difficulty_of(&run_session(&home, "4"));
    assert!((next - 0.5).abs() < 1e-9, "0.60 − 0.10: {why}");
    assert!(why.contains("patient said too hard: \u{2212}0.10"), "{why}");
    let shown = show_json(&data);
    assert_eq!(
        shown["difficulty"][0]["reason"], "patient said too hard: \u{2212}0.10",
        "{shown}"
    );
    assert_eq!(shown["checkins"][0]["difficulty"], "too_hard", "{shown}");
}
