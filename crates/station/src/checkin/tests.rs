use super::*;
use UserRequest::*;

fn flow(now: Instant) -> CheckInFlow {
    CheckInFlow::new(
        vec!["You exercised for 5 minutes.".into()],
        Duration::from_secs(60),
        now,
    )
}

#[test]
fn arrows_digits_and_enter_answer_the_three_questions() {
    let t = Instant::now();
    let mut f = flow(t);
    assert_eq!(f.page().title, "Well done — session complete");
    f.apply(Confirm, t);
    assert!(f.page().title.contains("pain"));
    for r in [SeekForward, SeekForward, SeekForward, SeekBack, Confirm] {
        f.apply(r, t);
    }
    assert_eq!(f.answers().pain_0_10, Some(2));
    // Typing 1 then 0 makes 10; arrows stop at the ends.
    for r in [Typed('1'), Typed('0'), SeekForward, Confirm] {
        f.apply(r, t);
    }
    assert_eq!(f.answers().tiredness_0_10, Some(10));
    f.apply(Typed('3'), t);
    f.apply(Confirm, t);
    assert_eq!(f.answers().difficulty.as_deref(), Some("too_hard"));
    assert_eq!(f.page().title, "Thank you");
    f.apply(Confirm, t);
    assert!(f.is_done());
    assert_eq!(
        answers_words(f.answers()).unwrap(),
        "pain 2/10, tiredness 10/10, too hard"
    );
}

#[test]
fn esc_skips_a_question_and_an_unanswered_page_times_out_as_skipped() {
    let t = Instant::now();
    let mut f = flow(t);
    f.apply(Quit, t); // skip the results page
    f.apply(Typed('7'), t);
    f.apply(Quit, t); // pain skipped although a value was chosen
    assert_eq!(f.answers().pain_0_10, None);
    f.apply(Typed('4'), t);
    // Nobody answers: each page gives up after its timeout.
    let mut now = t;
    for _ in 0..3 {
        now += Duration::from_secs(61);
        f.tick(now);
    }
    assert!(f.is_done(), "{:?}", f.page().title);
    assert!(f.answers().is_empty());
    assert_eq!(answers_words(f.answers()), None);
}

#[test]
fn results_say_the_time_active_and_what_improved_against_recent_sessions() {
    let now = EndResults {
        active_s: 270.0,
        pct_in_lane: Some(91.6),
        dial_error_deg: Some(3.2),
    };
    let first = result_lines(&now, &[]);
    assert_eq!(first[0], "You exercised for 4 minutes 30 seconds.");
    assert!(
        first.iter().any(|l| l.contains("in your lane 92 %")),
        "{first:?}"
    );
    assert!(first.last().unwrap().contains("Next time"));
    let before = [
        EndResults {
            active_s: 200.0,
            pct_in_lane: Some(80.0),
            dial_error_deg: Some(3.0),
        },
        EndResults {
            active_s: 220.0,
            pct_in_lane: Some(84.0),
            dial_error_deg: None,
        },
    ];
    let lines = result_lines(&now, &before);
    assert!(
        lines.contains(&"More time in your lane: 92 % (recently 82 %)".to_owned()),
        "{lines:?}"
    );
    assert!(
        lines.iter().any(|l| l.starts_with("Longer exercise")),
        "{lines:?}"
    );
    assert!(
        !lines.iter().any(|l| l.starts_with("Closer on the dial")),
        "the dial got worse"
    );
    let same = result_lines(&before[0], &before[..1]);
    assert!(
        same.last().unwrap().starts_with("About the same"),
        "{same:?}"
    );
}

#[test]
fn the_home_keeps_the_last_five_sessions_results_newest_first() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("results.json");
    assert!(load_results(&path).is_empty());
    for i in 0..7 {
        let before = load_results(&path);
        let r = EndResults {
            active_s: f64::from(i),
            ..Default::default()
        };
        save_results(&path, &r, &before).unwrap();
    }
    let kept: Vec<f64> = load_results(&path).iter().map(|r| r.active_s).collect();
    assert_eq!(kept, [6.0, 5.0, 4.0, 3.0, 2.0]);
}
