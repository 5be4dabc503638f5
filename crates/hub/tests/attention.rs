//! Needs attention today (issue 41): each alert rule on seeded patients, their order by need,
//! acknowledging and snoozing (audited), and the clinic's thresholds. On SQLite and on
//! PostgreSQL (the latter needs `TELEREHAB_TEST_PG_URL`, see `scripts/with-postgres.sh`).

mod common;

use axum::http::{Method, StatusCode};
use hub::attention::{Alert, DAY_MS, Severity};
use hub::db::clinic_settings::pain_threshold;
use hub::{Db, Patient, Role, Therapist};
use netlink::{Bye, CheckIn, ExerciseResult, Hello, PROTOCOL_VERSION};
use serde_json::{Value, json};

use common::api::{actions, call, clinician, login};

/// 2026-11-21 09:30 UTC.
const T0: i64 = common::T0;
const FP: [&str; 2] = [
    "1111111111111111111111111111111111111111111111111111111111111111",
    "2222222222222222222222222222222222222222222222222222222222222222",
];

async fn therapist(db: &Db) -> Therapist {
    clinician(db, "ada@clinic.example", Role::Therapist).await
}

/// Patient `pseudonym` of `t`, added at `T0`, with station `st-<pseudonym>`.
async fn patient(db: &Db, t: &Therapist, pseudonym: &str, fp: &str) -> Patient {
    let p = db.add_patient(pseudonym, Some(&t.id), T0).await.unwrap();
    db.add_station(&format!("st-{pseudonym}"), &p.id, fp, T0)
        .await
        .unwrap();
    p
}

/// One session of patient `p`.
struct S<'a> {
    id: &'a str,
    exercise: &'a str,
    day: i64,
    reason: &'a str,
    measures: &'a [(&'a str, f64)],
    checkin: Option<CheckIn>,
}

impl<'a> S<'a> {
    fn new(id: &'a str, exercise: &'a str, day: i64) -> Self {
        Self {
            id,
            exercise,
            day,
            reason: "complete",
            measures: &[],
            checkin: None,
        }
    }
}

async fn run(db: &Db, p: &Patient, s: S<'_>) {
    let start = T0 + s.day * DAY_MS;
    let station = format!("st-{}", p.pseudonym);
    let hello = Hello {
        protocol_version: PROTOCOL_VERSION,
        station_id: station.clone(),
        patient_id: p.id.clone(),
        session_id: s.id.to_owned(),
        exercise: s.exercise.to_owned(),
        started_unix_ms: start as u64,
        software_version: "telerehab 0.1.0".to_owned(),
        min_protocol_version: None,
        wheel: None,
    };
    db.open_session(&hello, start).await.unwrap();
    db.touch_station(&station, start).await.unwrap();
    db.store_summary(&netlink::Summary::example(s.id, 0), start)
        .await
        .unwrap();
    let bye = Bye {
        session_id: s.id.to_owned(),
        reason: s.reason.to_owned(),
        final_seq: None,
        measures: s
            .measures
            .iter()
            .map(|(k, v)| ((*k).to_owned(), *v))
            .collect(),
        hub_unix_ms: None,
        checkin: s.checkin,
        difficulty: None,
        exercises: Vec::<ExerciseResult>::new(),
    };
    db.close_session(&bye, start + 600_000).await.unwrap();
}

fn pain(p: u8) -> Option<CheckIn> {
    Some(CheckIn {
        pain_0_10: Some(p),
        tiredness_0_10: None,
        difficulty: None,
    })
}

/// The alerts of `p` needing attention at `now`.
async fn alerts_of(db: &Db, t: &Therapist, p: &Patient, now: i64) -> Vec<Alert> {
    let row = db
        .patients_for(t, now)
        .await
        .unwrap()
        .into_iter()
        .find(|o| o.patient.id == p.id)
        .unwrap();
    let thresholds = db.thresholds().await.unwrap();
    hub::attention::attention_of(db, &row, &thresholds, now)
        .await
        .unwrap()
        .attention
}

fn kinds(alerts: &[Alert]) -> Vec<&str> {
    alerts.iter().map(|a| a.kind).collect()
}

async fn pain_3_then_8_is_urgent_first_and_names_the_session_it_followed(db: Db) {
    let t = therapist(&db).await;
    let p = patient(&db, &t, "P-pain", FP[0]).await;
    run(
        &db,
        &p,
        S {
            checkin: pain(3),
            ..S::new("a1", "sine-road", 0)
        },
    )
    .await;
    run(
        &db,
        &p,
        S {
            checkin: pain(8),
            ..S::new("a2", "sine-road", 1)
        },
    )
    .await;
    let a = alerts_of(&db, &t, &p, T0 + 2 * DAY_MS).await;
    assert_eq!(a[0].kind, "pain_high", "{a:?}");
    assert_eq!(a[0].severity, Severity::Urgent);
    assert_eq!(a[0].facts["pain_0_10"], 8.0);
    assert_eq!(
        a[0].text,
        "pain 8/10 reported after the session of 2026-11-22"
    );
    // Two later sessions without a check-in: the words still name the session of the pain.
    run(&db, &p, S::new("a3", "sine-road", 2)).await;
    run(&db, &p, S::new("a4", "sine-road", 3)).await;
    let a = alerts_of(&db, &t, &p, T0 + 4 * DAY_MS).await;
    assert_eq!(
        a[0].text,
        "pain 8/10 reported after the session of 2026-11-22 (2 later sessions without a pain \
         answer)"
    );
    assert_eq!(a[0].facts["sessions_since"], 2.0);
    // The older caseload list says so too (it said "after the last session").
    let row = db
        .patients_for(&t, T0 + 4 * DAY_MS)
        .await
        .unwrap()
        .remove(0);
    assert!(
        row.alerts
            .contains(&"pain 8/10 after the session of 2026-11-22".to_owned()),
        "{:?}",
        row.alerts
    );
    // The clinic's own threshold: 9 makes 8 no alert.
    assert_eq!(pain_threshold(&db).await.unwrap(), 7);
    db.put_clinic_setting("pain_threshold_0_10", 9, &t.id, T0)
        .await
        .unwrap();
    assert_eq!(pain_threshold(&db).await.unwrap(), 9);
    let a = alerts_of(&db, &t, &p, T0 + 4 * DAY_MS).await;
    assert!(!kinds(&a).contains(&"pain_high"), "{a:?}");
}

async fn pain_rising_over_three_check_ins_is_urgent(db: Db) {
    let t = therapist(&db).await;
    let p = patient(&db, &t, "P-rise", FP[0]).await;
    for (i, v) in [1u8, 3, 5].into_iter().enumerate() {
        let id = format!("r{i}");
        run(
            &db,
            &p,
            S {
                checkin: pain(v),
                ..S::new(&id, "sine-road", i as i64)
            },
        )
        .await;
    }
    let a = alerts_of(&db, &t, &p, T0 + 3 * DAY_MS).await;
    assert_eq!(a[0].kind, "pain_rising", "{a:?}");
    assert_eq!(a[0].severity, Severity::Urgent);
}

async fn a_decline_in_one_kind_is_not_hidden_by_a_steady_session_of_another_kind(db: Db) {
    let t = therapist(&db).await;
    let p = patient(&db, &t, "P-weak", FP[0]).await;
    for (i, rom) in [40.0, 41.0, 39.0, 28.0].into_iter().enumerate() {
        let id = format!("w{i}");
        let m = [("wheel_rom_deg", rom), ("pct_in_lane", 80.0)];
        run(
            &db,
            &p,
            S {
                measures: &m,
                ..S::new(&id, "sine-road", i as i64)
            },
        )
        .await;
    }
    // Then dial sessions, steady: the caseload's trend now compares dials.
    for i in 4..7 {
        let id = format!("d{i}");
        let m = [("wheel_rom_deg", 90.0)];
        run(
            &db,
            &p,
            S {
                measures: &m,
                ..S::new(&id, "dial-sine", i)
            },
        )
        .await;
    }
    let a = alerts_of(&db, &t, &p, T0 + 7 * DAY_MS).await;
    let decline: Vec<&Alert> = a.iter().filter(|a| a.kind == "decline").collect();
    assert_eq!(decline.len(), 1, "{a:?}");
    assert_eq!(decline[0].key, "decline:road:wheel_rom_deg");
    assert_eq!(decline[0].exercise_kind.as_deref(), Some("road"));
    assert_eq!(decline[0].facts["latest"], 28.0);
    assert_eq!(decline[0].facts["usual"], 40.0);
    assert_eq!(decline[0].severity, Severity::Warning);
    // Within noise (the clinic's 15 %) is no alert: 36 against 40 is 10 % worse.
    let q = patient(&db, &t, "P-noise", FP[1]).await;
    for (i, rom) in [40.0, 40.0, 36.0].into_iter().enumerate() {
        let id = format!("n{i}");
        let m = [("wheel_rom_deg", rom)];
        run(
            &db,
            &q,
            S {
                measures: &m,
                ..S::new(&id, "sine-road", i as i64)
            },
        )
        .await;
    }
    let a = alerts_of(&db, &t, &q, T0 + 3 * DAY_MS).await;
    assert!(!kinds(&a).contains(&"decline"), "{a:?}");
}

async fn one_active_minute_a_week_with_nothing_prescribed_raises_an_alert(db: Db) {
    let t = therapist(&db).await;
    let p = patient(&db, &t, "P-idle", FP[0]).await;
    let m = [("active_s", 60.0)];
    run(
        &db,
        &p,
        S {
            measures: &m,
            reason: "wheel unplugged",
            ..S::new("i1", "sine-road", 5)
        },
    )
    .await;
    let a = alerts_of(&db, &t, &p, T0 + 6 * DAY_MS).await;
    let low = a
        .iter()
        .find(|a| a.kind == "low_activity")
        .expect("low activity");
    assert_eq!(low.facts["active_minutes"], 1.0);
    assert_eq!(low.facts["minimum_minutes"], 30.0);
    assert!(kinds(&a).contains(&"wheel_unplugged"), "{a:?}");
    // Four days later, no session since: against no prescription, the clinic's 3 days.
    let a = alerts_of(&db, &t, &p, T0 + 9 * DAY_MS).await;
    let gap = a
        .iter()
        .find(|a| a.kind == "no_session")
        .expect("no session");
    assert_eq!(gap.facts["days"], 4.0);
    // A patient with no session at all.
    let q = db.add_patient("P-new", Some(&t.id), T0).await.unwrap();
    let a = alerts_of(&db, &t, &q, T0 + DAY_MS).await;
    assert_eq!(kinds(&a), ["no_session"]);
    assert_eq!(
        a[0].text,
        "no session yet (added 2026-11-21; nothing prescribed yet)"
    );
}

async fn a_session_stopped_by_an_unplugged_arm_sensor_says_so_beside_the_wheels(db: Db) {
    let t = therapist(&db).await;
    let p = patient(&db, &t, "P-sensor", FP[0]).await;
    let m = [("active_s", 600.0)];
    run(
        &db,
        &p,
        S {
            measures: &m,
            reason: "arm sensor unplugged",
            ..S::new("a1", "sine-road", 0)
        },
    )
    .await;
    let a = alerts_of(&db, &t, &p, T0 + DAY_MS).await;
    let sensor = a
        .iter()
        .find(|a| a.kind == "sensor_unplugged")
        .expect("the arm sensor's alert");
    assert_eq!(sensor.severity, Severity::Notice);
    assert!(!kinds(&a).contains(&"wheel_unplugged"), "{a:?}");
    let message = hub::attention::message::message_of(sensor);
    assert_eq!(message.id, "attention-sensor-unplugged");
    assert_eq!(message.args["end"], "arm_sensor_unplugged");
}

async fn no_session_is_counted_against_the_prescriptions_own_gap(db: Db) {
    let t = therapist(&db).await;
    let p = patient(&db, &t, "P-once", FP[0]).await;
    let once = "sessions_per_week = 1\n[[exercise]]\nkind = \"dial\"\nduration_s = 60.0\n";
    db.put_regimen(&p.id, once, Some(1), &t.id, T0)
        .await
        .unwrap();
    run(&db, &p, S::new("o1", "dial-sine", 0)).await;
    let a = alerts_of(&db, &t, &p, T0 + 5 * DAY_MS).await;
    assert!(
        !kinds(&a).contains(&"no_session"),
        "once a week: 5 days is on time; {a:?}"
    );
    let a = alerts_of(&db, &t, &p, T0 + 8 * DAY_MS).await;
    assert!(kinds(&a).contains(&"no_session"), "{a:?}");
}

async fn a_revoked_station_says_the_patient_cannot_train(db: Db) {
    let t = therapist(&db).await;
    let p = patient(&db, &t, "P-rev", FP[0]).await;
    run(&db, &p, S::new("v1", "sine-road", 0)).await;
    db.revoke_station("st-P-rev", T0 + DAY_MS).await.unwrap();
    let a = alerts_of(&db, &t, &p, T0 + DAY_MS).await;
    assert_eq!(a[0].kind, "station_revoked", "{a:?}");
    assert!(a[0].text.contains("cannot train"), "{}", a[0].text);
    // A station not heard from for 3 days is a notice.
    let q = patient(&db, &t, "P-quiet", FP[1]).await;
    run(&db, &q, S::new("q1", "sine-road", 0)).await;
    let a = alerts_of(&db, &t, &q, T0 + DAY_MS).await;
    assert!(!kinds(&a).contains(&"station_silent"), "{a:?}");
    let a = alerts_of(&db, &t, &q, T0 + 3 * DAY_MS + 1).await;
    let silent = a
        .iter()
        .find(|a| a.kind == "station_silent")
        .expect("silent");
    assert_eq!(silent.severity, Severity::Notice);
}

async fn sessions_ended_early_repeatedly_and_high_effort_raise_warnings(db: Db) {
    let t = therapist(&db).await;
    let p = patient(&db, &t, "P-early", FP[0]).await;
    run(&db, &p, S::new("e0", "sine-road", 0)).await;
    run(
        &db,
        &p,
        S {
            reason: "paused too long",
            ..S::new("e1", "sine-road", 1)
        },
    )
    .await;
    let a = alerts_of(&db, &t, &p, T0 + 2 * DAY_MS).await;
    assert!(
        !kinds(&a).contains(&"ended_early"),
        "once is not repeatedly: {a:?}"
    );
    let tired = CheckIn {
        pain_0_10: None,
        tiredness_0_10: Some(8),
        difficulty: Some("too_hard".to_owned()),
    };
    run(
        &db,
        &p,
        S {
            reason: "paused too long",
            checkin: Some(tired),
            ..S::new("e2", "sine-road", 2)
        },
    )
    .await;
    let a = alerts_of(&db, &t, &p, T0 + 3 * DAY_MS).await;
    let early = a
        .iter()
        .find(|a| a.kind == "ended_early")
        .expect("ended early");
    assert_eq!(
        (early.facts["ended_early"], early.facts["sessions"]),
        (2.0, 3.0)
    );
    let effort = a.iter().find(|a| a.kind == "effort").expect("effort");
    assert_eq!(effort.facts["tiredness_0_10"], 8.0);
}

async fn the_caseload_sorts_by_need_and_filters_by_alert_kind(db: Db) {
    let t = therapist(&db).await;
    let fine = patient(&db, &t, "A-fine", FP[0]).await;
    let hurt = patient(&db, &t, "Z-hurt", FP[1]).await;
    let once = "sessions_per_week = 1\n[[exercise]]\nkind = \"dial\"\nduration_s = 6.0\n";
    db.put_regimen(&fine.id, once, Some(1), &t.id, T0)
        .await
        .unwrap();
    let m = [("active_s", 600.0)];
    run(
        &db,
        &fine,
        S {
            measures: &m,
            ..S::new("f1", "dial-sine", 1)
        },
    )
    .await;
    run(
        &db,
        &hurt,
        S {
            checkin: pain(9),
            measures: &m,
            ..S::new("h1", "sine-road", 1)
        },
    )
    .await;
    let idle = db.add_patient("M-none", Some(&t.id), T0).await.unwrap();
    let app = common::api::router_with_clock(&db, common::clock_at(T0 + 2 * DAY_MS).0);
    let cookie = login(&app, "ada@clinic.example").await;
    let pseudonyms = |v: &Value| -> Vec<String> {
        v.as_array()
            .unwrap()
            .iter()
            .map(|r| r["pseudonym"].as_str().unwrap().to_owned())
            .collect()
    };
    let (s, v, _) = call(&app, Method::GET, "/api/patients", Some(&cookie), None).await;
    assert_eq!(s, StatusCode::OK);
    assert_eq!(
        pseudonyms(&v),
        ["A-fine", "M-none", "Z-hurt"],
        "the default stays by pseudonym"
    );
    let (_, v, _) = call(
        &app,
        Method::GET,
        "/api/patients?sort=need",
        Some(&cookie),
        None,
    )
    .await;
    assert_eq!(pseudonyms(&v), ["Z-hurt", "M-none", "A-fine"]);
    assert_eq!(v[0]["attention"][0]["kind"], "pain_high");
    assert_eq!(v[0]["attention"][0]["severity"], "urgent");
    assert_eq!(v[2]["attention"], json!([]));
    let (_, v, _) = call(
        &app,
        Method::GET,
        "/api/patients?sort=need&alert=no_session",
        Some(&cookie),
        None,
    )
    .await;
    assert_eq!(pseudonyms(&v), ["M-none"]);
    let (s, v, _) = call(
        &app,
        Method::GET,
        "/api/patients?sort=loudest",
        Some(&cookie),
        None,
    )
    .await;
    assert_eq!(s, StatusCode::BAD_REQUEST);
    assert!(v["error"].as_str().unwrap().contains("need"), "{v}");
    let _ = idle;
    // An admin sees every patient; "mine" leaves only their own.
    let root = clinician(&db, "root@clinic.example", Role::Admin).await;
    db.add_patient("R-own", Some(&root.id), T0).await.unwrap();
    let admin = login(&app, "root@clinic.example").await;
    let (_, v, _) = call(&app, Method::GET, "/api/patients", Some(&admin), None).await;
    assert_eq!(v.as_array().unwrap().len(), 4);
    let (_, v, _) = call(
        &app,
        Method::GET,
        "/api/patients?mine=true",
        Some(&admin),
        None,
    )
    .await;
    assert_eq!(pseudonyms(&v), ["R-own"]);
}

async fn acknowledged_and_snoozed_alerts_are_audited_and_wake_on_something_new(db: Db) {
    let t = therapist(&db).await;
    let p = patient(&db, &t, "P-ack", FP[0]).await;
    run(
        &db,
        &p,
        S {
            checkin: pain(8),
            ..S::new("k1", "sine-road", 0)
        },
    )
    .await;
    // Within one login (8 hours): the clock moves by the hour.
    const HOUR_MS: i64 = DAY_MS / 24;
    let (clock, now) = common::clock_at(T0 + HOUR_MS);
    let app = common::api::router_with_clock(&db, clock);
    let cookie = login(&app, "ada@clinic.example").await;
    let uri = format!("/api/patients/{}/attention", p.id);
    let (_, v, _) = call(&app, Method::GET, &uri, Some(&cookie), None).await;
    let pain_alert = v["attention"][0].clone();
    assert_eq!(pain_alert["kind"], "pain_high");
    let ack_uri = format!("/api/patients/{}/alerts/ack", p.id);
    // A note is required; a changed fingerprint is refused.
    let body =
        |note: &str, fp: &Value| json!({"key": "pain_high", "fingerprint": fp, "note": note});
    let (s, _, _) = call(
        &app,
        Method::POST,
        &ack_uri,
        Some(&cookie),
        Some(body("", &pain_alert["fingerprint"])),
    )
    .await;
    assert_eq!(s, StatusCode::BAD_REQUEST);
    let (s, _, _) = call(
        &app,
        Method::POST,
        &ack_uri,
        Some(&cookie),
        Some(body("called", &json!("k0"))),
    )
    .await;
    assert_eq!(s, StatusCode::CONFLICT);
    let (s, v, _) = call(
        &app,
        Method::POST,
        &ack_uri,
        Some(&cookie),
        Some(body(
            "Called her: resting, no swelling.",
            &pain_alert["fingerprint"],
        )),
    )
    .await;
    assert_eq!(s, StatusCode::OK, "{v}");
    assert!(
        v["attention"]
            .as_array()
            .unwrap()
            .iter()
            .all(|a| a["kind"] != "pain_high")
    );
    assert_eq!(
        v["quieted"][0]["quieted"]["note"],
        "Called her: resting, no swelling."
    );
    assert_eq!(v["quieted"][0]["quieted"]["by_email"], "ada@clinic.example");
    let audit = actions(&db).await;
    assert!(
        audit
            .iter()
            .any(|(_, a, target)| a == "acknowledge_alert" && *target == p.id),
        "{audit:?}"
    );
    // Something new: a higher pain after the next session wakes it.
    run(
        &db,
        &p,
        S {
            checkin: pain(9),
            ..S::new("k2", "sine-road", 1)
        },
    )
    .await;
    now.set_unix_ns(common::ns(T0 + 2 * HOUR_MS));
    let (_, v, _) = call(&app, Method::GET, &uri, Some(&cookie), None).await;
    assert_eq!(v["attention"][0]["kind"], "pain_high", "{v}");
    assert_eq!(v["attention"][0]["facts"]["pain_0_10"], 9.0);
    // Snoozed for a day: quiet, then back.
    let snooze = json!({"key": "pain_high", "fingerprint": v["attention"][0]["fingerprint"],
        "note": "Seeing her tomorrow.", "snooze_until_ms": T0 + 5 * HOUR_MS});
    let (s, v, _) = call(&app, Method::POST, &ack_uri, Some(&cookie), Some(snooze)).await;
    assert_eq!(s, StatusCode::OK, "{v}");
    assert_eq!(v["quieted"][0]["kind"], "pain_high");
    let audit = actions(&db).await;
    assert!(
        audit.iter().any(|(_, a, _)| a == "snooze_alert"),
        "{audit:?}"
    );
    now.set_unix_ns(common::ns(T0 + 4 * HOUR_MS));
    let (_, v, _) = call(&app, Method::GET, &uri, Some(&cookie), None).await;
    assert_ne!(v["attention"][0]["kind"], "pain_high", "snoozed: {v}");
    now.set_unix_ns(common::ns(T0 + 5 * HOUR_MS));
    let (_, v, _) = call(&app, Method::GET, &uri, Some(&cookie), None).await;
    assert_eq!(v["attention"][0]["kind"], "pain_high", "the snooze is over");
}

async fn the_clinics_thresholds_have_explained_defaults_and_only_admins_change_them(db: Db) {
    therapist(&db).await;
    clinician(&db, "root@clinic.example", Role::Admin).await;
    let app = common::api::router_with_clock(&db, common::clock_at(T0).0);
    let ada = login(&app, "ada@clinic.example").await;
    let root = login(&app, "root@clinic.example").await;
    let (s, v, _) = call(&app, Method::GET, "/api/clinic/settings", Some(&ada), None).await;
    assert_eq!(s, StatusCode::OK);
    let pain = v
        .as_array()
        .unwrap()
        .iter()
        .find(|s| s["key"] == "pain_threshold_0_10")
        .unwrap();
    assert_eq!(
        (pain["value"].as_i64(), pain["default"].as_i64()),
        (Some(7), Some(7))
    );
    let (s, _, _) = call(
        &app,
        Method::PUT,
        "/api/clinic/settings",
        Some(&ada),
        Some(json!({"pain_threshold_0_10": 6})),
    )
    .await;
    assert_eq!(s, StatusCode::FORBIDDEN);
    let (s, v, _) = call(
        &app,
        Method::PUT,
        "/api/clinic/settings",
        Some(&root),
        Some(json!({"pain_threshold_0_10": 6, "no_session_days": 0})),
    )
    .await;
    assert_eq!(s, StatusCode::BAD_REQUEST);
    assert!(
        v["error"].as_str().unwrap().contains("no_session_days"),
        "{v}"
    );
    assert_eq!(pain_threshold(&db).await.unwrap(), 7, "nothing changed");
    let (s, v, _) = call(
        &app,
        Method::PUT,
        "/api/clinic/settings",
        Some(&root),
        Some(json!({"pain_threshold_0_10": 6})),
    )
    .await;
    assert_eq!(s, StatusCode::OK, "{v}");
    assert_eq!(v["pain_threshold_0_10"], 6);
    assert_eq!(db.pain_threshold().await.unwrap(), 6);
    let audit = actions(&db).await;
    assert!(
        audit.iter().any(|(_, a, _)| a == "change_setting"),
        "{audit:?}"
    );
}

on_both_backends!(
    pain_3_then_8_is_urgent_first_and_names_the_session_it_followed,
    pain_rising_over_three_check_ins_is_urgent,
    a_decline_in_one_kind_is_not_hidden_by_a_steady_session_of_another_kind,
    one_active_minute_a_week_with_nothing_prescribed_raises_an_alert,
    a_session_stopped_by_an_unplugged_arm_sensor_says_so_beside_the_wheels,
    no_session_is_counted_against_the_prescriptions_own_gap,
    a_revoked_station_says_the_patient_cannot_train,
    sessions_ended_early_repeatedly_and_high_effort_raise_warnings,
    the_caseload_sorts_by_need_and_filters_by_alert_kind,
    acknowledged_and_snoozed_alerts_are_audited_and_wake_on_something_new,
    the_clinics_thresholds_have_explained_defaults_and_only_admins_change_them,
);
