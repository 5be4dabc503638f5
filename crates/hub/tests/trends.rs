//! Like with like (issue 29): the caseload's trends compare sessions of one exercise kind that
//! ran as prescribed (in every kind, the one trained last first), and a patient's sessions
//! are named in words. On SQLite and on
//! PostgreSQL (the latter needs `TELEREHAB_TEST_PG_URL`, see `scripts/with-postgres.sh`).

mod common;

use std::collections::BTreeMap;

use hub::{Db, Patient, Role, Therapist};
use netlink::{Bye, ExerciseResult, Hello, PROTOCOL_VERSION};

const T0: i64 = 1_795_253_400_000;
const HOUR_MS: i64 = 3_600_000;
const FP1: &str = "1111111111111111111111111111111111111111111111111111111111111111";

async fn paired(db: &Db) -> (Therapist, Patient) {
    let t = db
        .add_therapist(
            "ada@clinic.example",
            "correct horse battery",
            Role::Therapist,
            T0,
        )
        .await
        .unwrap();
    let p = db.add_patient("P-0042", Some(&t.id), T0).await.unwrap();
    db.add_station("st-1", &p.id, FP1, T0).await.unwrap();
    (t, p)
}

/// Runs session `sid` of `exercise` at hour `hour`, ending for `reason` with `measures` and
/// the per-exercise results `exercises`.
async fn session(
    db: &Db,
    p: &Patient,
    (sid, exercise, hour, reason): (&str, &str, i64, &str),
    measures: &[(&str, f64)],
    exercises: Vec<ExerciseResult>,
) {
    let hello = Hello {
        protocol_version: PROTOCOL_VERSION,
        station_id: "st-1".to_owned(),
        patient_id: p.id.clone(),
        session_id: sid.to_owned(),
        exercise: exercise.to_owned(),
        started_unix_ms: (T0 + hour * HOUR_MS) as u64,
        software_version: "telerehab 0.1.0".to_owned(),
        min_protocol_version: None,
        wheel: None,
    };
    db.open_session(&hello, T0 + hour * HOUR_MS).await.unwrap();
    // A session that ran stored its summaries (a Hello alone is no training session).
    db.store_summary(&netlink::Summary::example(sid, 0), T0 + hour * HOUR_MS)
        .await
        .unwrap();
    let bye = Bye {
        session_id: sid.to_owned(),
        reason: reason.to_owned(),
        final_seq: None,
        measures: measures
            .iter()
            .map(|(k, v)| ((*k).to_owned(), *v))
            .collect(),
        hub_unix_ms: None,
        checkin: None,
        difficulty: None,
        exercises,
    };
    db.close_session(&bye, T0 + hour * HOUR_MS + 600_000)
        .await
        .unwrap();
}

fn result(index: u32, kind: &str, name: &str, prescribed_s: f64) -> ExerciseResult {
    ExerciseResult {
        index,
        kind: kind.to_owned(),
        name: name.to_owned(),
        prescribed_s,
        active_s: prescribed_s,
        scores: BTreeMap::new(),
        assessment: None,
    }
}

/// The caseload row's trends as `(measure, word)` pairs and the kind they compare.
async fn trends(db: &Db, t: &Therapist) -> (Vec<(String, String)>, Option<String>) {
    let row = db.patients_for(t, T0 + 100 * HOUR_MS).await.unwrap();
    (
        row[0].trends.clone().into_iter().collect(),
        row[0].trend_exercise_kind.clone(),
    )
}

fn pairs(list: &[(&str, &str)]) -> Vec<(String, String)> {
    list.iter()
        .map(|(a, b)| ((*a).to_owned(), (*b).to_owned()))
        .collect()
}

async fn trends_compare_the_latest_kind_and_leave_out_sessions_ended_early(db: Db) {
    let (t, p) = paired(&db).await;
    let road = |lane: f64, rom: f64| [("pct_in_lane", lane), ("wheel_rom_deg", rom)];
    session(
        &db,
        &p,
        ("r1", "sine-road", 1, "complete"),
        &road(80.0, 40.0),
        vec![],
    )
    .await;
    session(
        &db,
        &p,
        ("r2", "slalom", 2, "complete"),
        &road(80.0, 40.0),
        vec![],
    )
    .await;
    session(
        &db,
        &p,
        ("r3", "sine-road", 3, "complete"),
        &road(90.0, 40.0),
        vec![],
    )
    .await;
    // Cut short by a fault: far worse, but not how the patient does as prescribed.
    let early = road(10.0, 5.0);
    session(
        &db,
        &p,
        ("r4", "sine-road", 4, "safety fault"),
        &early,
        vec![],
    )
    .await;
    assert_eq!(
        trends(&db, &t).await,
        (
            pairs(&[("pct_in_lane", "up"), ("wheel_rom_deg", "flat")]),
            Some("road".to_owned())
        ),
        "the early session is left out; slalom counts as a road"
    );
    // A dial session: no road to compare it with, and no lane measure at all.
    let dial = [("wheel_rom_deg", 60.0)];
    session(&db, &p, ("d1", "dial-sine", 5, "complete"), &dial, vec![]).await;
    assert_eq!(trends(&db, &t).await, (vec![], Some("dial".to_owned())));
    let dial = [("wheel_rom_deg", 50.0)];
    session(&db, &p, ("d2", "dial-steps", 6, "complete"), &dial, vec![]).await;
    assert_eq!(
        trends(&db, &t).await,
        (pairs(&[("wheel_rom_deg", "down")]), Some("dial".to_owned())),
        "the dial against the dial, not against the roads' 40°"
    );
    // Every kind's trends, the kind trained last first: the road's stay visible.
    let row = db.patients_for(&t, T0 + 100 * HOUR_MS).await.unwrap();
    let by_kind: Vec<(String, Vec<(String, String)>)> = row[0]
        .trends_by_kind
        .iter()
        .map(|k| {
            (
                k.exercise_kind.clone(),
                k.trends.clone().into_iter().collect(),
            )
        })
        .collect();
    assert_eq!(
        by_kind,
        [
            ("dial".to_owned(), pairs(&[("wheel_rom_deg", "down")])),
            (
                "road".to_owned(),
                pairs(&[("pct_in_lane", "up"), ("wheel_rom_deg", "flat")])
            ),
        ]
    );
}

async fn sessions_are_named_by_their_exercises_in_words(db: Db) {
    let (t, p) = paired(&db).await;
    session(&db, &p, ("s1", "sine-road", 1, "complete"), &[], vec![]).await;
    let course = vec![
        result(0, "dial-sine", "Dial sine", 45.0),
        result(1, "sine-road", "Sine road", 60.0),
    ];
    session(&db, &p, ("s2", "regimen:2", 2, "complete"), &[], course).await;
    session(
        &db,
        &p,
        ("s3", "regimen:2", 3, "patient pressed stop"),
        &[],
        vec![],
    )
    .await;
    // A station that reports no exercises: the regimen prescribed before the session names
    // them (not a later version).
    let two = "[[exercise]]\nkind = \"slalom\"\n\n[[exercise]]\nkind = \"dial\"\n";
    db.put_regimen(&p.id, two, None, &t.id, T0 + 3 * HOUR_MS + 1)
        .await
        .unwrap();
    session(&db, &p, ("s4", "regimen:2", 4, "complete"), &[], vec![]).await;
    let one = "[[exercise]]\nkind = \"sine\"\n";
    db.put_regimen(&p.id, one, None, &t.id, T0 + 5 * HOUR_MS)
        .await
        .unwrap();
    let named = db.named_sessions_of(&p.id).await.unwrap();
    let words: Vec<(&str, &str, bool, Option<f64>)> = named
        .iter()
        .map(|s| {
            (
                s.exercise_name.as_str(),
                s.exercise_kind.as_str(),
                s.ran_as_prescribed,
                s.prescribed_s,
            )
        })
        .collect();
    assert_eq!(
        words,
        [
            ("Slalom, then Dial sine", "dial+road", true, None),
            ("A regimen of 2 exercises", "regimen", false, None),
            ("Dial sine, then Sine road", "dial+road", true, Some(105.0)),
            ("Sine road", "road", true, None),
        ]
    );
}

async fn a_session_says_its_recording_arrived_only_once_every_byte_did_how_much_before_and_when_it_stopped(
    db: Db,
) {
    let (_, p) = paired(&db).await;
    for (sid, hour) in [("none", 1), ("half", 2), ("whole", 3)] {
        session(&db, &p, (sid, "sine-road", hour, "complete"), &[], vec![]).await;
    }
    let mut rec = hub::db::Recording {
        session_id: "half".to_owned(),
        sha256: FP1.to_owned(),
        size_bytes: 1000,
        received_bytes: 500,
        path: "/nowhere/half.mcap".to_owned(),
        complete: false,
        last_part_ms: Some(1_000_000),
    };
    db.note_recording_progress(&rec).await.unwrap();
    rec.session_id = "whole".to_owned();
    db.note_recording_progress(&rec).await.unwrap();
    rec.received_bytes = 1000;
    rec.complete = true;
    db.put_recording(&rec).await.unwrap();
    // A late note of progress (a slower hub's) leaves a whole recording whole.
    rec.received_bytes = 500;
    rec.complete = false;
    db.note_recording_progress(&rec).await.unwrap();
    let named = db.named_sessions_of(&p.id).await.unwrap();
    let uploaded: Vec<(&str, bool)> = named
        .iter()
        .map(|s| (s.row.session_id.as_str(), s.recording_uploaded))
        .collect();
    assert_eq!(
        uploaded,
        [("whole", true), ("half", false), ("none", false)]
    );
    // The half-arrived one says how much, the others nothing.
    let arriving: Vec<Option<u8>> = named.iter().map(|s| s.recording_arriving_percent).collect();
    assert_eq!(arriving, [None, Some(50), None]);
    // When its last part was noted says whether it is still arriving or stopped.
    let half = &named[1];
    assert_eq!(half.recording_last_part_ms, Some(1_000_000));
    let stall = hub::db::RECORDING_STALLED_AFTER_MS;
    assert!(!half.recording_stalled(1_000_000 + stall));
    assert!(half.recording_stalled(1_000_001 + stall));
    assert!(
        !named[0].recording_stalled(i64::MAX),
        "a whole recording never stalls"
    );
    assert_eq!(named[0].recording_last_part_ms, None);
    let json = serde_json::to_value(&named[0]).unwrap();
    assert_eq!(json["recording_uploaded"], serde_json::json!(true));
}

on_both_backends!(
    trends_compare_the_latest_kind_and_leave_out_sessions_ended_early,
    sessions_are_named_by_their_exercises_in_words,
    a_session_says_its_recording_arrived_only_once_every_byte_did_how_much_before_and_when_it_stopped,
);
