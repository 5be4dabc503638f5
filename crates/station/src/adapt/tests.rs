use super::*;

fn spec(lowest: f64, highest: f64) -> DifficultySpec {
    DifficultySpec {
        lowest,
        highest,
        ..DifficultySpec::default()
    }
}

fn entry(difficulty: f64, success_rate: Option<f64>, felt: Option<&str>) -> Entry {
    Entry {
        unix_ms: 1,
        patient_id: "p1".into(),
        difficulty,
        success_rate,
        felt: felt.map(str::to_owned),
    }
}

#[test]
fn the_first_session_runs_at_the_therapists_start_or_midway() {
    let d = next(&spec(0.2, 0.8), &[]);
    assert_eq!((d.difficulty, d.change), (0.5, 0.0));
    assert!(d.reason.contains("first session"), "{}", d.reason);
    assert_eq!(d.why.code, "first-midway");
    let s = DifficultySpec {
        start: Some(0.3),
        ..spec(0.2, 0.8)
    };
    assert_eq!(next(&s, &[]).difficulty, 0.3);
}

#[test]
fn success_above_the_target_raises_and_below_lowers_saying_by_how_much() {
    let up = next(&spec(0.0, 1.0), &[entry(0.5, Some(0.82), None)]);
    assert!(up.difficulty > 0.5, "{up:?}");
    assert!(
        up.reason
            .starts_with("success 82 % above the 70 % target: +0."),
        "{}",
        up.reason
    );
    let down = next(&spec(0.0, 1.0), &[entry(0.5, Some(0.4), None)]);
    assert!(down.difficulty < 0.5, "{down:?}");
    assert!(
        down.reason.contains("below the 70 % target: \u{2212}0."),
        "{}",
        down.reason
    );
    // The same for words in any language: the side, the success and the target in %.
    assert_eq!(
        (up.why.code.as_str(), up.why.success_pct, up.why.target_pct),
        ("success-above", Some(82.0), Some(70.0))
    );
    assert_eq!(down.why.code, "success-below");
    // One session's step is bounded by the adapter's largest step (0.1).
    assert!((down.change).abs() <= 0.1 + 1e-9, "{down:?}");
}

#[test]
fn too_hard_lowers_by_a_tenth_even_after_a_good_score_and_too_easy_raises() {
    let hard = next(&spec(0.0, 1.0), &[entry(0.5, Some(0.9), Some("too_hard"))]);
    assert!((hard.difficulty - 0.4).abs() < 1e-9, "{hard:?}");
    assert_eq!(hard.reason, "patient said too hard: \u{2212}0.10");
    let easy = next(&spec(0.0, 1.0), &[entry(0.5, Some(0.7), Some("too_easy"))]);
    assert!((easy.difficulty - 0.55).abs() < 1e-9, "{easy:?}");
    assert_eq!(easy.reason, "patient said too easy: +0.05");
    assert_eq!(
        (hard.why.code.as_str(), easy.why.code.as_str()),
        ("felt-too-hard", "felt-too-easy")
    );
    // A larger step from the success rate is kept.
    let lower = next(&spec(0.0, 1.0), &[entry(0.5, Some(0.1), Some("too_hard"))]);
    assert!(lower.difficulty <= 0.4 + 1e-9, "{lower:?}");
}

#[test]
fn the_difficulty_is_held_within_the_therapists_bounds() {
    let s = spec(0.3, 0.6);
    let mut history = vec![entry(0.5, Some(1.0), None)];
    for _ in 0..10 {
        let d = next(&s, &history);
        assert!((0.3..=0.6).contains(&d.difficulty), "{d:?}");
        history.push(entry(d.difficulty, Some(1.0), None));
    }
    let held = next(&s, &history);
    assert_eq!(held.difficulty, 0.6);
    assert!(
        held.reason
            .ends_with("held at the therapist's highest (0.60)"),
        "{}",
        held.reason
    );
    let low = next(&s, &[entry(0.3, Some(0.0), Some("too_hard"))]);
    assert_eq!(low.difficulty, 0.3);
    assert!(low.reason.contains("lowest (0.30)"), "{}", low.reason);
    assert_eq!(held.why.held_at.as_deref(), Some("highest"));
    assert_eq!(low.why.held_at.as_deref(), Some("lowest"));
    // What the hub receives passes the protocol's checks.
    for d in [&held, &low] {
        assert!(d.change_for_hub(Some(1.0)).validate().is_ok(), "{d:?}");
    }
}

#[test]
fn adaptation_off_runs_every_session_at_the_start() {
    let s = DifficultySpec {
        adapt: false,
        start: Some(0.4),
        ..spec(0.0, 1.0)
    };
    let d = next(&s, &[entry(0.4, Some(1.0), Some("too_easy"))]);
    assert_eq!(d.difficulty, 0.4);
    assert!(d.reason.starts_with("adaptation off"), "{}", d.reason);
    assert_eq!(d.why.code, "adapt-off");
}

#[test]
fn the_history_keeps_the_last_fifty_sessions_of_this_patient_only() {
    let dir = tempfile::tempdir().unwrap();
    let path = history_path(dir.path());
    for i in 0..(KEPT_SESSIONS + 5) {
        let mut e = entry(i as f64 / 100.0, Some(0.7), None);
        if i == KEPT_SESSIONS + 4 {
            e.patient_id = "someone-else".into();
        }
        append(&path, &e).unwrap();
    }
    let mut text = std::fs::read_to_string(&path).unwrap();
    text.push_str("not json\n");
    std::fs::write(&path, text).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert_eq!(text.lines().count(), KEPT_SESSIONS + 1);
    let mine = load(&path, "p1");
    assert_eq!(mine.len(), KEPT_SESSIONS - 1);
    assert_eq!(mine.last().unwrap().difficulty, 0.53);
    assert!(load(&dir.path().join("missing.jsonl"), "p1").is_empty());
}

#[test]
fn success_is_time_in_lane_on_roads_and_the_dials_error_against_45_degrees() {
    assert_eq!(success_of(10.0, (100.0, 82.0), (0.0, 0.0)), Some(0.82));
    assert_eq!(success_of(10.0, (0.0, 0.0), (100.0, 9.0)), Some(0.8));
    assert_eq!(success_of(10.0, (0.0, 0.0), (100.0, 90.0)), Some(0.0));
    let mixed = success_of(10.0, (300.0, 100.0), (100.0, 45.0)).unwrap();
    assert!((mixed - 0.75).abs() < 1e-12, "{mixed}");
    assert_eq!(success_of(0.5, (100.0, 82.0), (0.0, 0.0)), None);
    assert_eq!(success_of(f64::NAN, (100.0, 82.0), (0.0, 0.0)), None);
}
