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
    assert_eq!(f.page_id(), "results");
    f.apply(Confirm, t);
    assert_eq!(f.page_id(), "pain");
    // The first turn right enters the scale at 0; then one step each: 0, 1, 2, back to 1.
    for r in [SeekForward, SeekForward, SeekForward, SeekBack, Confirm] {
        f.apply(r, t);
    }
    assert_eq!(f.answers().pain_0_10, Some(1));
    assert_eq!(f.page_id(), "effort");
    // Typing 1 then 0 makes 10; arrows stop at the ends.
    for r in [Typed('1'), Typed('0'), SeekForward, Confirm] {
        f.apply(r, t);
    }
    assert_eq!(f.answers().tiredness_0_10, Some(10));
    assert_eq!(f.page_id(), "difficulty");
    f.apply(Typed('3'), t);
    f.apply(Confirm, t);
    assert_eq!(f.answers().difficulty.as_deref(), Some("too_hard"));
    assert_eq!(f.page_id(), "thanks");
    f.apply(Confirm, t);
    assert!(f.is_done());
    assert_eq!(
        answers_words(f.answers()).unwrap(),
        "pain 1/10, effort 10/10, too hard"
    );
}

#[test]
fn nothing_is_recorded_until_the_patient_chooses_a_stray_press_records_no_pain() {
    let t = Instant::now();
    let mut f = flow(t);
    f.apply(Confirm, t);
    assert_eq!(f.page_id(), "pain");
    assert_eq!(f.choice(), None, "no answer preset");
    let scale = f.page().scale.expect("a scale");
    assert_eq!(scale.choice, None, "nothing drawn as chosen");
    // A stray press: nothing recorded, the page stays and says how to choose.
    f.apply(Confirm, t);
    assert_eq!(f.page_id(), "pain");
    assert_eq!(f.answers().pain_0_10, None);
    assert_eq!(
        f.page().scale.unwrap().chosen,
        i18n::tr!("checkin-choose-first")
    );
    // The same on the effort and difficulty pages.
    f.apply(Quit, t);
    assert_eq!((f.page_id(), f.choice()), ("effort", None));
    f.apply(Confirm, t);
    assert_eq!(f.answers().tiredness_0_10, None);
    f.apply(Quit, t);
    assert_eq!((f.page_id(), f.choice()), ("difficulty", None));
    f.apply(Confirm, t);
    assert_eq!(f.answers().difficulty, None);
    assert!(f.answers().is_empty());
}

#[test]
fn a_turn_left_first_enters_the_scale_from_its_top() {
    let t = Instant::now();
    let mut f = flow(t);
    f.apply(Confirm, t);
    f.apply(SeekBack, t);
    assert_eq!(f.choice(), Some(10));
    f.apply(Quit, t);
    f.apply(Quit, t);
    f.apply(SeekBack, t);
    assert_eq!(f.choice(), Some(2), "the thumbs: too hard");
}

#[test]
fn pain_at_or_over_the_threshold_ends_on_the_pain_stop_page_never_the_thanks() {
    let t = Instant::now();
    let mut f = flow(t).with_care(7, Some("+49 30 1234567".into()));
    f.apply(Confirm, t);
    f.apply(Typed('8'), t);
    f.apply(Confirm, t);
    assert_eq!(f.answers().pain_0_10, Some(8));
    assert_eq!(f.page_id(), "pain-stop");
    let page = f.page();
    assert!(page.stop);
    assert!(
        page.lines.iter().any(|l| l.contains("+49 30 1234567")),
        "{:?}",
        page.lines
    );
    assert_eq!(f.spoken().unwrap().0, "checkin-stop-title");
    // The page waits for the patient (longer than a thanks), then closes: no more questions.
    f.tick(t + THANKS_FOR + Duration::from_secs(1));
    assert_eq!(f.page_id(), "pain-stop");
    f.apply(Confirm, t);
    assert!(f.is_done());
    assert_eq!(f.answers().tiredness_0_10, None);
    // Just under the threshold: the ordinary questions and the thanks.
    let mut f = flow(t).with_care(7, None);
    f.apply(Confirm, t);
    f.apply(Typed('6'), t);
    f.apply(Confirm, t);
    assert_eq!(f.page_id(), "effort");
    // The clinic's own threshold counts.
    let mut f = flow(t).with_care(5, None);
    f.apply(Confirm, t);
    f.apply(Typed('5'), t);
    f.apply(Confirm, t);
    assert_eq!(f.page_id(), "pain-stop");
    // Without a phone number the page still says to call the clinic.
    assert_eq!(f.page().lines[2], i18n::tr!("checkin-stop-call-clinic"));
}

#[test]
fn each_page_names_its_sentence_for_speech_and_shows_the_choice_in_words() {
    let t = Instant::now();
    let mut f = flow(t);
    assert_eq!(f.spoken().unwrap().0, "checkin-results-title");
    f.apply(Confirm, t);
    assert_eq!(f.spoken().unwrap().0, "checkin-pain-question");
    assert_eq!(f.page().scale.unwrap().kind, ScaleKind::Faces);
    f.apply(Typed('4'), t);
    let scale = f.page().scale.unwrap();
    assert_eq!(scale.words.len(), 11);
    assert!(scale.chosen.contains('4') && scale.chosen.contains(&pain_words(4)));
    f.apply(Confirm, t);
    assert_eq!(f.spoken().unwrap().0, "checkin-effort-question");
    assert_eq!(f.page().scale.unwrap().kind, ScaleKind::Effort);
    f.apply(Confirm, t); // nothing chosen: stays
    f.apply(Quit, t);
    assert_eq!(f.spoken().unwrap().0, "checkin-difficulty-question");
    let scale = f.page().scale.unwrap();
    assert_eq!(scale.kind, ScaleKind::Thumbs);
    assert_eq!(scale.words.len(), 3);
    // No "[8]" and no typeable box: the chosen words only.
    assert!(!scale.chosen.contains('['));
}

#[test]
fn effort_takes_borgs_cr10_words_and_odd_pains_the_next_face() {
    assert_eq!(effort_words(0), i18n::tr!("checkin-effort-0"));
    assert_eq!(effort_words(6), i18n::tr!("checkin-effort-5"));
    assert_eq!(effort_words(9), i18n::tr!("checkin-effort-7"));
    assert_eq!(effort_words(10), i18n::tr!("checkin-effort-10"));
    assert_eq!(pain_words(1), i18n::tr!("checkin-pain-1"));
    assert_eq!(pain_words(10), i18n::tr!("checkin-pain-5"));
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
    assert!(f.is_done(), "{:?}", f.page_id());
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
    assert_eq!(
        first[0],
        i18n::tr!(
            "checkin-results-exercised",
            time = results::duration_words(270.0)
        )
    );
    assert!(first.iter().any(|l| l.contains("92")), "{first:?}");
    assert_eq!(first.last().unwrap(), &i18n::tr!("checkin-results-first"));
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
        lines.contains(&i18n::tr!(
            "checkin-results-better-lane",
            percent = 92,
            was = 82
        )),
        "{lines:?}"
    );
    assert!(
        lines.contains(&i18n::tr!(
            "checkin-results-better-time",
            time = results::duration_words(270.0),
            was = results::duration_words(210.0)
        )),
        "{lines:?}"
    );
    assert_eq!(
        lines.len(),
        6,
        "no dial line among the better ones: {lines:?}"
    );
    let same = result_lines(&before[0], &before[..1]);
    assert_eq!(same.last().unwrap(), &i18n::tr!("checkin-results-same"));
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

#[test]
fn a_pain_stop_holds_for_the_rest_of_the_day_until_the_therapist_clears_it() {
    let dir = tempfile::tempdir().unwrap();
    let home = crate::home::Home::at(dir.path());
    let now = care::now_unix_ms();
    assert!(care::rest_today(&home, now).is_none(), "no pain, no rest");
    // The hub's settings: threshold 6, a phone number.
    let settings = care::CareSettings {
        pain_threshold_0_10: 6,
        clinic_phone: Some("+49 30 1234567".into()),
        cleared_unix_ms: None,
    };
    settings.save(&home.care_path()).unwrap();
    // Pain 5 changes nothing; pain 6 stops the day.
    let answered = |pain| CheckIn {
        pain_0_10: Some(pain),
        ..Default::default()
    };
    care::note_pain(&home, &answered(5));
    assert!(care::rest_today(&home, now).is_none());
    care::note_pain(&home, &answered(6));
    let page = care::rest_today(&home, care::now_unix_ms()).expect("rest today");
    assert_eq!(page.title, i18n::tr!("checkin-rest-today-title"));
    assert!(page.lines.iter().any(|l| l.text.contains("+49 30 1234567")));
    // Today's page offers no session.
    let mut door = crate::front_door::FrontDoor::paired_with(
        crate::front_door::TodayPlan::default_drive("sine", 60.0),
    );
    door.set_devices(Vec::new(), true);
    door.set_rest_today(Some(page));
    assert!(door.is_resting_today());
    use crate::front_door::{Action, Outcome};
    use session::wheel_gestures::Gesture;
    assert_eq!(door.apply(Confirm), Action::None);
    assert_eq!(door.apply(TogglePause), Action::None);
    // Turning chooses nothing hidden; a press of the wheel closes the page.
    assert_eq!(door.wheel(Gesture::Turn(1)), Action::None);
    assert_eq!(door.wheel(Gesture::Press), Action::Done(Outcome::Quit));
    // Tomorrow it no longer holds.
    let stop = care::PainStop::load(&home.pain_stop_path(), now).unwrap();
    assert!(!stop.holds(&settings, stop.at_unix_ms + 36 * 3_600_000));
    // The therapist clears it (the hub's settings, newer than the pain): training again.
    care::CareSettings {
        cleared_unix_ms: Some(stop.at_unix_ms + 1),
        ..settings
    }
    .save(&home.care_path())
    .unwrap();
    assert!(care::rest_today(&home, care::now_unix_ms()).is_none());
}

#[test]
fn a_wheel_that_stopped_working_is_said_first_with_whom_to_tell_an_unplugged_one_is_not() {
    use haptic_wheel::WheelFault;
    let now = EndResults {
        active_s: 90.0,
        pct_in_lane: Some(80.0),
        dial_error_deg: None,
    };
    let plain = result_lines(&now, &[]);
    assert_eq!(end_lines(&now, &[], None), plain);
    assert_eq!(end_lines(&now, &[], Some(WheelFault::Unplugged)), plain);
    for fault in [
        WheelFault::CommandsRefused,
        WheelFault::Silent,
        WheelFault::OutOfRange,
    ] {
        let lines = end_lines(&now, &[], Some(fault));
        assert_eq!(
            lines[0],
            i18n::tr!("checkin-results-wheel-stopped"),
            "{fault:?}"
        );
        assert_eq!(lines[1..], plain[..], "{fault:?}");
        assert!(wheel_stopped(Some(fault)), "{fault:?}");
    }
    assert!(!wheel_stopped(None) && !wheel_stopped(Some(WheelFault::Unplugged)));
}

/// A session the wheel ended is not "finished": the results page's title, shown and spoken,
/// says it stopped early; the questions after it are as always.
#[test]
fn a_session_stopped_early_is_titled_so_and_not_well_done() {
    let now = Instant::now();
    let lines = vec![i18n::tr!("checkin-results-wheel-stopped")];
    let finished = CheckInFlow::new(lines.clone(), Duration::from_secs(60), now);
    assert_eq!(finished.page().title, i18n::tr!("checkin-results-title"));
    let mut stopped = CheckInFlow::new(lines, Duration::from_secs(60), now).stopped_early(true);
    let page = stopped.page();
    assert_eq!(page.title, i18n::tr!("checkin-results-stopped-title"));
    assert_ne!(page.title, i18n::tr!("checkin-results-title"));
    assert_eq!(stopped.spoken().unwrap().0, "checkin-results-stopped-title");
    stopped.apply(Confirm, now);
    assert_eq!(stopped.page_id(), "pain");
    assert_eq!(stopped.spoken().unwrap().0, "checkin-pain-question");
}
