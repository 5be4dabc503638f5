//! The database layer on SQLite and PostgreSQL: every test body runs on both backends
//! (`<name>::sqlite`, `<name>::postgres`; the latter needs `TELEREHAB_TEST_PG_URL`, see
//! `scripts/with-postgres.sh`).

mod common;

use common::{T0, hello};

use std::collections::BTreeMap;

use hub::db::{LOCKOUT_MS, Recording};
use hub::{Db, HubError, PairRefusal, Patient, Role, Therapist};
use netlink::store::Appended;
use netlink::{Bye, Summary};

const MIN: i64 = 60_000;
const FP1: &str = "1111111111111111111111111111111111111111111111111111111111111111";
const FP2: &str = "2222222222222222222222222222222222222222222222222222222222222222";

fn summary(session_id: &str, seq: u64) -> Summary {
    Summary {
        extra: BTreeMap::from([("assist_level".to_owned(), 0.25)]),
        ..Summary::example(session_id, seq)
    }
}

/// A therapist, a patient and a paired station `st-1`.
/// The version of the newest file in the store's `migrations/` (`NNNN_name.sql`).
fn latest_migration() -> i64 {
    std::fs::read_dir(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../hub-store/migrations"
    ))
    .unwrap()
    .filter_map(|e| {
        e.ok()?
            .file_name()
            .to_str()?
            .split('_')
            .next()?
            .parse()
            .ok()
    })
    .max()
    .unwrap()
}

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
    let p = db.add_patient("p-0042", Some(&t.id), T0).await.unwrap();
    db.add_station("st-1", &p.id, FP1, T0).await.unwrap();
    (t, p)
}

on_both_backends!(
    dollar_placeholders_work,
    schema_is_migrated,
    therapists_and_lockout,
    a_changed_password_opens_the_account_and_ends_other_logins,
    login_sessions_expire,
    patients_and_caseload,
    hostile_pseudonyms_are_refused,
    pairing_codes_are_single_use,
    attempts_from_one_address_never_make_a_pairing_code_wait_for_another,
    stations_and_revocation,
    summaries_are_stored_exactly_once,
    concurrent_duplicates_are_stored_once,
    a_batch_has_the_outcomes_of_storing_one_by_one,
    a_checkpoint_keeps_every_summary_readable,
    the_databases_size_grows_with_the_summaries_it_stores,
    session_of_another_station_is_refused,
    sessions_close_and_list,
    a_byes_checkin_is_stored_and_high_or_rising_pain_raises_a_caseload_alert,
    a_byes_difficulty_is_stored_once_per_session_newest_first,
    a_byes_exercise_results_are_stored_in_course_order_exactly,
    an_assessment_is_stored_as_its_own_kind_and_kept_out_of_the_exercise_trends,
    metrics_and_recordings,
    regimen_versions_increment,
    audit_log_keeps_entries,
);

async fn dollar_placeholders_work(db: Db) {
    // Out of order and reused: both backends bind `$n` by number.
    let v: i64 = sqlx::query_scalar("SELECT CAST($2 AS BIGINT) * 10 + CAST($1 AS BIGINT)")
        .bind(1_i64)
        .bind(4_i64)
        .fetch_one(db.pool())
        .await
        .unwrap();
    assert_eq!(v, 41);
    let v: i64 = sqlx::query_scalar("SELECT CAST($1 AS BIGINT) + CAST($1 AS BIGINT)")
        .bind(21_i64)
        .fetch_one(db.pool())
        .await
        .unwrap();
    assert_eq!(v, 42);
    let s: String = sqlx::query_scalar("SELECT CAST($1 AS TEXT)")
        .bind("'; DROP TABLE patients; --")
        .fetch_one(db.pool())
        .await
        .unwrap();
    assert_eq!(s, "'; DROP TABLE patients; --");
}

async fn schema_is_migrated(db: Db) {
    assert_eq!(db.schema_version().await.unwrap(), latest_migration());
    let n: i64 = sqlx::query_scalar("SELECT COUNT(*) FROM audit_log")
        .fetch_one(db.pool())
        .await
        .unwrap();
    assert_eq!(n, 0);
}

async fn a_changed_password_opens_the_account_and_ends_other_logins(db: Db) {
    let (t, _) = paired(&db).await;
    let here = db.create_web_session(&t.id, T0, MIN).await.unwrap();
    let other = db.create_web_session(&t.id, T0, MIN).await.unwrap();
    let old = "correct horse battery";
    let rotated = db
        .change_password(&t.email, old, "staple battery horse", T0, MIN)
        .await
        .unwrap();
    // Every old token ends, the changing one too; the new one replaces it.
    assert!(db.web_session(&rotated, T0).await.unwrap().is_some());
    assert!(db.web_session(&here, T0).await.unwrap().is_none());
    assert!(db.web_session(&other, T0).await.unwrap().is_none());
    assert!(
        db.verify_login(&t.email, "staple battery horse", T0)
            .await
            .is_ok()
    );
    assert!(matches!(
        db.verify_login(&t.email, old, T0).await,
        Err(HubError::LoginRefused)
    ));
}

async fn therapists_and_lockout(db: Db) {
    let t = db
        .add_therapist(
            "Ada@Clinic.example",
            "correct horse battery",
            Role::Admin,
            T0,
        )
        .await
        .unwrap();
    assert_eq!(t.email, "ada@clinic.example");
    assert!(t.id.starts_with("t-"));
    assert_eq!(db.therapist(&t.id).await.unwrap(), Some(t.clone()));
    let hash: String = sqlx::query_scalar("SELECT password_hash FROM therapists WHERE id = $1")
        .bind(&t.id)
        .fetch_one(db.pool())
        .await
        .unwrap();
    assert!(hash.starts_with("$argon2id$"), "{hash}");
    let dup = db
        .add_therapist(
            "ada@clinic.example",
            "another long pass",
            Role::Therapist,
            T0,
        )
        .await;
    assert!(
        matches!(dup, Err(HubError::AlreadyExists { .. })),
        "{dup:?}"
    );
    let short = db
        .add_therapist("bob@clinic.example", "short", Role::Therapist, T0)
        .await
        .unwrap_err();
    assert!(short.to_string().contains("password"), "{short}");

    let ok = db
        .verify_login("ada@clinic.example", "correct horse battery", T0)
        .await
        .unwrap();
    assert_eq!(ok.id, t.id);
    let unknown = db
        .verify_login("nobody@clinic.example", "correct horse battery", T0)
        .await
        .unwrap_err();
    let wrong = db
        .verify_login("ada@clinic.example", "wrong", T0)
        .await
        .unwrap_err();
    // Same answer whether or not the email exists.
    assert_eq!(unknown.to_string(), wrong.to_string());
    for _ in 0..4 {
        assert!(matches!(
            db.verify_login("ada@clinic.example", "wrong", T0 + 1).await,
            Err(HubError::LoginRefused)
        ));
    }
    // Five failures: the next attempt waits, even with the right password.
    let locked = db
        .verify_login("ada@clinic.example", "correct horse battery", T0 + 2)
        .await;
    assert!(
        matches!(locked, Err(HubError::Throttled { .. })),
        "{locked:?}"
    );
    let later = db
        .verify_login(
            "ada@clinic.example",
            "correct horse battery",
            T0 + 1 + LOCKOUT_MS,
        )
        .await;
    assert_eq!(later.unwrap().id, t.id);
}

async fn login_sessions_expire(db: Db) {
    let (t, _) = paired(&db).await;
    let token = db.create_web_session(&t.id, T0, 10 * MIN).await.unwrap();
    assert_eq!(token.len(), 64);
    assert_eq!(
        db.web_session(&token, T0 + MIN).await.unwrap(),
        Some(t.clone())
    );
    assert_eq!(db.web_session(&token, T0 + 10 * MIN).await.unwrap(), None);
    assert_eq!(db.web_session("0000", T0).await.unwrap(), None);
    let stored: i64 = sqlx::query_scalar("SELECT COUNT(*) FROM web_sessions WHERE token_hash = $1")
        .bind(&token)
        .fetch_one(db.pool())
        .await
        .unwrap();
    assert_eq!(stored, 0, "the token itself is never stored");
    db.delete_web_session(&token, T0).await.unwrap();
    assert_eq!(db.web_session(&token, T0 + 1).await.unwrap(), None);
}

async fn patients_and_caseload(db: Db) {
    let (t, p) = paired(&db).await;
    let admin = db
        .add_therapist(
            "root@clinic.example",
            "correct horse battery",
            Role::Admin,
            T0,
        )
        .await
        .unwrap();
    let other = db
        .add_therapist(
            "bob@clinic.example",
            "correct horse battery",
            Role::Therapist,
            T0,
        )
        .await
        .unwrap();
    let q = db.add_patient("q-7", Some(&other.id), T0).await.unwrap();
    let dup = db.add_patient("p-0042", None, T0).await;
    assert!(
        matches!(dup, Err(HubError::AlreadyExists { .. })),
        "{dup:?}"
    );
    let ghost = db.add_patient("x", Some("t-nobody"), T0).await;
    assert!(matches!(ghost, Err(HubError::NotFound { .. })), "{ghost:?}");
    assert_eq!(
        db.patient_by_pseudonym("p-0042").await.unwrap(),
        Some(p.clone())
    );
    assert_eq!(db.patient(&p.id).await.unwrap(), Some(p.clone()));
    assert_eq!(db.patient_by_pseudonym("nobody").await.unwrap(), None);

    // Two sessions: one 8 days ago, one 1 day ago (each with a summary: training).
    for (sid, age_days) in [("s-old", 8), ("s-new", 1)] {
        let mut h = hello("st-1", &p.id, sid);
        h.started_unix_ms = (T0 + 10 * 24 * 60 * MIN - age_days * 24 * 60 * MIN) as u64;
        db.open_session(&h, T0).await.unwrap();
        db.store_summary(&Summary::example(sid, 0), T0)
            .await
            .unwrap();
    }
    let now = T0 + 10 * 24 * 60 * MIN;
    let own = db.patients_for(&t, now).await.unwrap();
    assert_eq!(own.len(), 1);
    assert_eq!(own[0].patient, p);
    assert_eq!(own[0].sessions_last_7_days, 1);
    assert_eq!(own[0].last_session_started_ms, Some(now - 24 * 60 * MIN));
    let all = db.patients_for(&admin, now).await.unwrap();
    let ids: Vec<_> = all.iter().map(|o| o.patient.id.clone()).collect();
    assert_eq!(ids, vec![p.id.clone(), q.id.clone()]);
    assert_eq!(all[1].sessions_last_7_days, 0);
    assert_eq!(all[1].last_session_started_ms, None);
    assert_eq!(all[1].alerts, ["no session yet"]);
    assert_eq!(
        own[0].alerts,
        Vec::<String>::new(),
        "a session this week, nothing prescribed"
    );
    // Three a week prescribed, a safety stop and clipping in the last session: all said.
    let three_a_week = "sessions_per_week = 3\n[[exercise]]\nkind = \"sine\"\nduration_s = 60.0\n";
    db.put_regimen(&p.id, three_a_week, Some(3), &t.id, now)
        .await
        .unwrap();
    let faults = [
        ("watchdog_fault_ticks".to_owned(), 40.0),
        ("clipped_pct".to_owned(), 7.5),
        ("arm_sensors_lost".to_owned(), 1.0),
    ];
    db.put_metrics("s-new", &faults.into_iter().collect())
        .await
        .unwrap();
    // Time in lane 90 % then 99 %, wheel range 40° then 30°, SPARC −2.0 twice.
    for (sid, lane, rom) in [("s-old", 90.0, 40.0), ("s-new", 99.0, 30.0)] {
        let m = [
            ("pct_in_lane".to_owned(), lane),
            ("wheel_rom_deg".to_owned(), rom),
            ("sparc_median".to_owned(), -2.0),
        ];
        db.put_metrics(sid, &m.into_iter().collect()).await.unwrap();
        // Trends count only sessions that ran as prescribed.
        let bye = Bye {
            session_id: sid.to_owned(),
            reason: "complete".to_owned(),
            final_seq: None,
            measures: BTreeMap::new(),
            hub_unix_ms: None,
            checkin: None,
            difficulty: None,
            exercises: Vec::new(),
        };
        db.close_session(&bye, now).await.unwrap();
    }
    let own = db.patients_for(&t, now).await.unwrap();
    assert_eq!(own[0].sessions_per_week_prescribed, Some(3));
    let trends: Vec<(&str, &str)> = own[0]
        .trends
        .iter()
        .map(|(k, v)| (k.as_str(), v.as_str()))
        .collect();
    assert_eq!(
        trends,
        [
            ("pct_in_lane", "up"),
            ("sparc_median", "flat"),
            ("wheel_rom_deg", "down")
        ]
    );
    assert_eq!(
        own[0].alerts,
        [
            "1 of 3 sessions this week",
            "safety stop in the last session (torque faded out on a fault)",
            "torque held at the ceiling for 5 % or more of the last session",
            "arm sensors lost in the last session (no joint angles)"
        ]
    );
    adherence_counts_active_minutes(&db, &t, &p, now).await;
    assert!(Db::may_see(&t, &p) && !Db::may_see(&t, &q) && Db::may_see(&admin, &q));
}

/// Adherence in minutes: the caseload row of `p` (whose last session, `s-new`, started within
/// the week before `now`) against a 60 s regimen three times a week, then a 10-minute one once.
async fn adherence_counts_active_minutes(db: &Db, t: &Therapist, p: &Patient, now: i64) {
    let own = db.patients_for(t, now).await.unwrap();
    // Adherence in minutes: three sessions of a 60 s regimen a week is 3 active minutes.
    assert_eq!(own[0].minutes_per_week_prescribed, Some(3.0));
    assert_eq!(own[0].active_minutes_last_7_days, 0.0);
    // One session a week of 10 minutes, done as one short one: the minutes say it.
    let ten_once = "sessions_per_week = 1\n[[exercise]]\nkind = \"dial\"\nduration_s = 600.0\n";
    db.put_regimen(&p.id, ten_once, Some(1), &t.id, now)
        .await
        .unwrap();
    let active = [
        ("active_s".to_owned(), 90.0),
        ("movements".to_owned(), 42.0),
    ];
    db.put_metrics("s-new", &active.into_iter().collect())
        .await
        .unwrap();
    let own = db.patients_for(t, now).await.unwrap();
    assert_eq!(own[0].minutes_per_week_prescribed, Some(10.0));
    assert_eq!(own[0].active_minutes_last_7_days, 1.5);
    // The dose's count beside its time: the week's wheel movements.
    assert_eq!(own[0].repetitions_last_7_days, 42);
    assert!(
        own[0]
            .alerts
            .contains(&"2 of 10 active minutes this week".to_owned()),
        "{:?}",
        own[0].alerts
    );
}

async fn hostile_pseudonyms_are_refused(db: Db) {
    for bad in [
        "'; DROP TABLE patients; --",
        "../../etc",
        "",
        "a b",
        "é",
        &"x".repeat(65),
    ] {
        let err = db.add_patient(bad, None, T0).await.unwrap_err();
        assert!(
            matches!(
                err,
                HubError::Invalid {
                    field: "pseudonym",
                    ..
                }
            ),
            "{bad:?}: {err}"
        );
        assert!(err.to_string().contains("A-Z"), "{err}");
    }
    let n: i64 = sqlx::query_scalar("SELECT COUNT(*) FROM patients")
        .fetch_one(db.pool())
        .await
        .unwrap();
    assert_eq!(n, 0);
    db.add_patient(&"x".repeat(64), None, T0).await.unwrap();
}

async fn pairing_codes_are_single_use(db: Db) {
    let (_, p) = paired(&db).await;
    let code = db.create_pairing_code(&p.id, T0, 15 * MIN).await.unwrap();
    assert_eq!(code.len(), 9);
    let code = netlink::pairing::PairingCode::parse(&code).unwrap();
    let ticket = db.pairing_ticket(code.code_id(), T0 + MIN).await.unwrap();
    assert_eq!(
        (ticket.secret.as_str(), ticket.patient_id.as_str()),
        (code.secret(), p.id.as_str())
    );
    assert_eq!(
        db.pair_station(code.code_id(), "st-a", &"a".repeat(64), T0 + MIN)
            .await
            .unwrap(),
        p.id
    );
    let again = db
        .pair_station(code.code_id(), "st-b", &"b".repeat(64), T0 + MIN)
        .await;
    assert!(
        matches!(again, Err(HubError::Pair(PairRefusal::Used))),
        "{again:?}"
    );
    let again = db.pairing_ticket(code.code_id(), T0 + MIN).await;
    assert!(
        matches!(again, Err(HubError::Pair(PairRefusal::Used))),
        "{again:?}"
    );

    let code2 = db.create_pairing_code(&p.id, T0, 15 * MIN).await.unwrap();
    let code2 = netlink::pairing::PairingCode::parse(&code2).unwrap();
    let late = db
        .pair_station(code2.code_id(), "st-c", &"c".repeat(64), T0 + 15 * MIN)
        .await;
    assert!(
        matches!(late, Err(HubError::Pair(PairRefusal::Expired))),
        "{late:?}"
    );

    // Pairing is one transaction: a station that cannot be added (its certificate is
    // already paired) leaves the code live and no audit entry.
    let code5 = db.create_pairing_code(&p.id, T0, 15 * MIN).await.unwrap();
    let code5 = netlink::pairing::PairingCode::parse(&code5).unwrap();
    let dup = db
        .pair_station(code5.code_id(), "st-dup", FP1, T0 + MIN)
        .await;
    assert!(dup.is_err(), "{dup:?}");
    let fp2 = "ab".repeat(32);
    let paired = db
        .pair_station(code5.code_id(), "st-new", &fp2, T0 + MIN)
        .await;
    assert_eq!(paired.unwrap(), p.id);
    let audited: Vec<String> = db
        .audit_log(100)
        .await
        .unwrap()
        .into_iter()
        .filter(|e| e.action == "station_paired")
        .map(|e| e.target)
        .collect();
    assert!(audited.contains(&"st-new".to_owned()), "{audited:?}");
    assert!(!audited.contains(&"st-dup".to_owned()), "{audited:?}");

    // Parallel attempts at one code from one address: exactly one gets the secret.
    let code4 = db.create_pairing_code(&p.id, T0, 15 * MIN).await.unwrap();
    let code4 = netlink::pairing::PairingCode::parse(&code4).unwrap();
    let mut attempts = tokio::task::JoinSet::new();
    for _ in 0..50 {
        let (db, code_id) = (db.clone(), code4.code_id().to_owned());
        attempts.spawn(async move {
            db.begin_pairing_attempt(&code_id, "192.0.2.1", T0 + MIN)
                .await
        });
    }
    let tickets = attempts.join_all().await;
    assert_eq!(
        tickets.iter().filter(|t| matches!(t, Ok(Some(_)))).count(),
        1
    );

    // Wrong tries never kill a code: each attempt makes it wait, then it takes the next.
    let code3 = db.create_pairing_code(&p.id, T0, 15 * MIN).await.unwrap();
    let code3 = netlink::pairing::PairingCode::parse(&code3).unwrap();
    let mut at = T0;
    for n in 1..=6 {
        let ticket = db
            .begin_pairing_attempt(code3.code_id(), "192.0.2.1", at)
            .await
            .unwrap();
        assert_eq!(ticket.unwrap().secret, code3.secret(), "attempt {n}");
        // Waiting: no ticket (the caller answers as for a wrong code) for that address.
        let early = at + hub::db::attempt_wait_ms(n) - 1;
        assert!(
            db.begin_pairing_attempt(code3.code_id(), "192.0.2.1", early)
                .await
                .unwrap()
                .is_none()
        );
        at += hub::db::attempt_wait_ms(n);
    }
    assert_eq!(
        db.pair_station(code3.code_id(), "st-d", &"d".repeat(64), at)
            .await
            .unwrap(),
        p.id
    );
    assert!(
        db.begin_pairing_attempt(code3.code_id(), "192.0.2.9", at)
            .await
            .unwrap()
            .is_none(),
        "a used code gives no ticket to anyone"
    );

    for unknown in ["ZZZZ", "'; DROP TABLE pairing_codes; --"] {
        let r = db.pairing_ticket(unknown, T0).await;
        assert!(
            matches!(r, Err(HubError::Pair(PairRefusal::Unknown))),
            "{r:?}"
        );
    }
    let ghost = db.create_pairing_code("p-nobody", T0, MIN).await;
    assert!(matches!(ghost, Err(HubError::NotFound { .. })), "{ghost:?}");
}

async fn stations_and_revocation(db: Db) {
    let (_, p) = paired(&db).await;
    let st = db.station("st-1").await.unwrap().unwrap();
    assert_eq!(st.patient_id, p.id);
    assert_eq!(
        db.station_by_fingerprint(FP1).await.unwrap(),
        Some(st.clone())
    );
    assert_eq!(db.station_by_fingerprint(FP2).await.unwrap(), None);
    let dup = db.add_station("st-2", &p.id, FP1, T0).await;
    assert!(
        matches!(dup, Err(HubError::AlreadyExists { .. })),
        "{dup:?}"
    );
    let bad = db.add_station("../x", &p.id, FP2, T0).await;
    assert!(matches!(bad, Err(HubError::Invalid { .. })), "{bad:?}");
    let bad_fp = db.add_station("st-3", &p.id, "ABC", T0).await;
    assert!(
        matches!(bad_fp, Err(HubError::Invalid { .. })),
        "{bad_fp:?}"
    );
    db.touch_station("st-1", T0 + MIN).await.unwrap();
    assert_eq!(
        db.station("st-1").await.unwrap().unwrap().last_seen_ms,
        Some(T0 + MIN)
    );
    assert_eq!(db.stations_of(&p.id).await.unwrap().len(), 1);

    db.open_session(&hello("st-1", &p.id, "s1"), T0)
        .await
        .unwrap();
    db.revoke_station("st-1", T0 + 2 * MIN).await.unwrap();
    db.revoke_station("st-1", T0 + 3 * MIN).await.unwrap();
    let st = db.station("st-1").await.unwrap().unwrap();
    assert!(st.is_revoked());
    assert_eq!(st.revoked_at_ms, Some(T0 + 2 * MIN));
    let refused = db.open_session(&hello("st-1", &p.id, "s1"), T0).await;
    assert!(
        matches!(refused, Err(HubError::StationRevoked(_))),
        "{refused:?}"
    );
    assert!(matches!(
        db.revoke_station("st-nobody", T0).await,
        Err(HubError::NotFound { .. })
    ));
    assert!(matches!(
        db.open_session(&hello("st-nobody", &p.id, "s2"), T0).await,
        Err(HubError::NotFound { .. })
    ));
}

async fn summaries_are_stored_exactly_once(db: Db) {
    let (_, p) = paired(&db).await;
    assert_eq!(
        db.open_session(&hello("st-1", &p.id, "s1"), T0)
            .await
            .unwrap(),
        None
    );
    // In order, a duplicate, a reordered stale one, a gap (the station dropped some).
    let plan = [
        (0, Appended::Stored),
        (1, Appended::Stored),
        (1, Appended::Duplicate),
        (3, Appended::Stored),
        (2, Appended::Duplicate),
        (0, Appended::Duplicate),
        (4, Appended::Stored),
    ];
    for (seq, expected) in plan {
        assert_eq!(
            db.store_summary(&summary("s1", seq), T0).await.unwrap(),
            expected,
            "seq {seq}"
        );
    }
    // A reconnect resumes from the last stored.
    assert_eq!(
        db.open_session(&hello("st-1", &p.id, "s1"), T0 + MIN)
            .await
            .unwrap(),
        Some(4)
    );
    let seqs: Vec<u64> = db
        .summaries_of("s1")
        .await
        .unwrap()
        .iter()
        .map(|s| s.seq)
        .collect();
    assert_eq!(seqs, vec![0, 1, 3, 4]);
    assert_eq!(db.summaries_of("s1").await.unwrap()[0], summary("s1", 0));

    let jump = db
        .store_summary(&summary("s1", 4 + 2 + netlink::frame::MAX_SEQ_STEP), T0)
        .await;
    assert!(matches!(jump, Err(HubError::Conflict(_))), "{jump:?}");
    let ok = db
        .store_summary(&summary("s1", 4 + 1 + netlink::frame::MAX_SEQ_STEP), T0)
        .await;
    assert_eq!(ok.unwrap(), Appended::Stored);
    let huge = db
        .store_summary(&summary("s1", u64::MAX), T0)
        .await
        .unwrap_err();
    assert!(huge.to_string().contains("largest storable"), "{huge}");
    let mut nan = summary("s1", 99_999_999);
    nan.rms_lateral_m = f64::NAN;
    let nan = db.store_summary(&nan, T0).await.unwrap_err();
    assert!(nan.to_string().contains("rms_lateral_m"), "{nan}");
    let unknown = db.store_summary(&summary("s-nobody", 0), T0).await;
    assert!(
        matches!(unknown, Err(HubError::NotFound { .. })),
        "{unknown:?}"
    );
}

/// Outcome of a store as a comparable string (errors by kind).
fn outcome(r: &Result<Appended, HubError>) -> String {
    match r {
        Ok(a) => format!("{a:?}"),
        Err(HubError::Conflict(_)) => "conflict".into(),
        Err(HubError::NotFound { .. }) => "not found".into(),
        Err(HubError::Invalid { .. }) => "invalid".into(),
        Err(e) => format!("other: {e}"),
    }
}

async fn a_batch_has_the_outcomes_of_storing_one_by_one(db: Db) {
    let (_, p) = paired(&db).await;
    for s in ["a1", "a2", "b1", "b2"] {
        db.open_session(&hello("st-1", &p.id, s), T0).await.unwrap();
    }
    let far = 2 + netlink::frame::MAX_SEQ_STEP;
    // Two sessions interleaved: in order, duplicates within the batch, stale reorderings, a
    // gap, a jump too far, an unknown session and an invalid summary.
    let plan: [(usize, u64); 14] = [
        (1, 0),
        (2, 5),
        (1, 1),
        (1, 1),
        (2, 5),
        (0, 0),
        (1, 3),
        (2, far + 5),
        (1, 2),
        (2, 6),
        (1, 0),
        (3, 7),
        (1, 4),
        (2, 4),
    ];
    let make = |prefix: &str, (who, seq): (usize, u64)| {
        let mut s = match who {
            0 => summary("s-nobody", seq),
            1 => summary(&format!("{prefix}1"), seq),
            _ => summary(&format!("{prefix}2"), seq),
        };
        if who == 3 {
            s.rms_lateral_m = f64::NAN;
        }
        s
    };
    let batch: Vec<Summary> = plan.iter().map(|&x| make("a", x)).collect();
    let together: Vec<String> = db
        .store_summaries(&batch, T0)
        .await
        .unwrap()
        .iter()
        .map(outcome)
        .collect();
    let mut one_by_one = Vec::new();
    for &x in &plan {
        one_by_one.push(outcome(&db.store_summary(&make("b", x), T0).await));
    }
    assert_eq!(together, one_by_one);
    assert_eq!(
        together,
        [
            "Stored",
            "Stored",
            "Stored",
            "Duplicate",
            "Duplicate",
            "not found",
            "Stored",
            "conflict",
            "Duplicate",
            "Stored",
            "Duplicate",
            "invalid",
            "Stored",
            "Duplicate"
        ]
    );
    for (a, b) in [("a1", "b1"), ("a2", "b2")] {
        let seqs = |s: Vec<Summary>| s.iter().map(|s| s.seq).collect::<Vec<_>>();
        assert_eq!(
            seqs(db.summaries_of(a).await.unwrap()),
            seqs(db.summaries_of(b).await.unwrap())
        );
    }
    assert_eq!(db.session("a2").await.unwrap().unwrap().last_seq, Some(6));
}

async fn concurrent_duplicates_are_stored_once(db: Db) {
    let (_, p) = paired(&db).await;
    db.open_session(&hello("st-1", &p.id, "s1"), T0)
        .await
        .unwrap();
    // Four writers each deliver the same 0..25, shuffled differently: every seq stored once,
    // and the stored sequence stays increasing.
    let mut tasks = Vec::new();
    for w in 0..4_u64 {
        let db = db.clone();
        tasks.push(tokio::spawn(async move {
            let mut stored = Vec::new();
            for i in 0..25_u64 {
                let seq = if w % 2 == 0 { i } else { (i * 7 + w) % 25 };
                if db.store_summary(&summary("s1", seq), T0).await.unwrap() == Appended::Stored {
                    stored.push(seq);
                }
            }
            stored
        }));
    }
    let mut all = Vec::new();
    for t in tasks {
        all.extend(t.await.unwrap());
    }
    let rows: Vec<u64> = db
        .summaries_of("s1")
        .await
        .unwrap()
        .iter()
        .map(|s| s.seq)
        .collect();
    all.sort_unstable();
    assert_eq!(
        all, rows,
        "each stored summary reported Stored exactly once"
    );
    assert!(rows.windows(2).all(|w| w[0] < w[1]));
    assert_eq!(rows.last(), Some(&24));
}

async fn session_of_another_station_is_refused(db: Db) {
    let (_, p) = paired(&db).await;
    db.add_station("st-2", &p.id, FP2, T0).await.unwrap();
    db.open_session(&hello("st-1", &p.id, "s1"), T0)
        .await
        .unwrap();
    let err = db
        .open_session(&hello("st-2", &p.id, "s1"), T0)
        .await
        .unwrap_err();
    assert!(err.to_string().contains("another station"), "{err}");
    let q = db.add_patient("q-1", None, T0).await.unwrap();
    let err = db
        .open_session(&hello("st-1", &q.id, "s9"), T0)
        .await
        .unwrap_err();
    assert!(err.to_string().contains("paired with patient"), "{err}");
    let err = db
        .open_session(&hello("st-1", &p.id, "../../etc"), T0)
        .await
        .unwrap_err();
    assert!(matches!(err, HubError::Invalid { .. }), "{err}");
}

async fn sessions_close_and_list(db: Db) {
    let (_, p) = paired(&db).await;
    let mut h = hello("st-1", &p.id, "s1");
    db.open_session(&h, T0).await.unwrap();
    h.session_id = "s2".into();
    h.started_unix_ms += 1000;
    db.open_session(&h, T0).await.unwrap();
    for seq in 0..3 {
        db.store_summary(&summary("s1", seq), T0).await.unwrap();
    }
    let bye = Bye {
        session_id: "s1".into(),
        reason: "patient pressed stop".into(),
        final_seq: Some(2),
        measures: BTreeMap::from([
            ("sparc_median".to_owned(), -1.7),
            ("movements".to_owned(), 12.0),
        ]),
        hub_unix_ms: None,
        checkin: None,
        difficulty: None,
        exercises: Vec::new(),
    };
    assert_eq!(db.close_session(&bye, T0 + MIN).await.unwrap(), Some(2));
    assert_eq!(
        db.metrics_of("s1").await.unwrap(),
        bye.measures,
        "the Bye's measures are kept"
    );
    let s1 = db.session("s1").await.unwrap().unwrap();
    assert_eq!(s1.closed_at_ms, Some(T0 + MIN));
    assert_eq!(s1.end_reason.as_deref(), Some("patient pressed stop"));
    assert_eq!((s1.final_seq, s1.last_seq), (Some(2), Some(2)));
    let ids: Vec<_> = db
        .sessions_of(&p.id)
        .await
        .unwrap()
        .into_iter()
        .map(|s| s.session_id)
        .collect();
    assert_eq!(ids, vec!["s2", "s1"]);
    let unknown = Bye {
        session_id: "s-nobody".into(),
        ..bye
    };
    assert!(matches!(
        db.close_session(&unknown, T0).await,
        Err(HubError::NotFound { .. })
    ));
}

/// Closes session `id` (started `minute` minutes after T0) with `pain` answered.
async fn session_with_pain(db: &Db, patient_id: &str, id: &str, minute: i64, pain: u8) {
    let mut h = hello("st-1", patient_id, id);
    h.started_unix_ms = (T0 + minute * MIN) as u64;
    db.open_session(&h, T0).await.unwrap();
    let bye = Bye {
        session_id: id.into(),
        reason: "session complete".into(),
        final_seq: None,
        measures: BTreeMap::new(),
        hub_unix_ms: None,
        checkin: Some(netlink::CheckIn {
            pain_0_10: Some(pain),
            tiredness_0_10: Some(4),
            difficulty: Some("too_hard".into()),
        }),
        difficulty: None,
        exercises: Vec::new(),
    };
    db.close_session(&bye, T0 + minute * MIN).await.unwrap();
    // A repeated Bye (the station missed the reply) stores the same once.
    db.close_session(&bye, T0 + minute * MIN).await.unwrap();
}

async fn a_byes_difficulty_is_stored_once_per_session_newest_first(db: Db) {
    let (_, p) = paired(&db).await;
    for (i, (d, change, reason)) in [
        (0.5, 0.0, "first session: the therapist's start 0.50"),
        (0.4, -0.1, "patient said too hard: \u{2212}0.10"),
    ]
    .into_iter()
    .enumerate()
    {
        let id = format!("s{i}");
        let mut h = hello("st-1", &p.id, &id);
        h.started_unix_ms = (T0 + i as i64 * MIN) as u64;
        db.open_session(&h, T0).await.unwrap();
        let bye = Bye {
            session_id: id,
            reason: "session complete".into(),
            final_seq: None,
            measures: BTreeMap::new(),
            hub_unix_ms: None,
            checkin: None,
            exercises: Vec::new(),
            difficulty: Some(netlink::DifficultyChange {
                difficulty: d,
                change,
                reason: reason.into(),
                success_rate: (i == 1).then_some(0.82),
                // The first session from a station older than the why.
                why: (i == 1).then(|| netlink::DifficultyWhy {
                    code: "felt-too-hard".into(),
                    success_pct: None,
                    target_pct: None,
                    held_at: None,
                }),
            }),
        };
        db.close_session(&bye, T0 + MIN).await.unwrap();
        // A repeated Bye stores the same once.
        db.close_session(&bye, T0 + MIN).await.unwrap();
    }
    let stored = db.difficulty_of(&p.id).await.unwrap();
    assert_eq!(stored.len(), 2, "one row per session: {stored:?}");
    assert_eq!(stored[0].session_id, "s1");
    assert_eq!(
        (
            stored[0].difficulty,
            stored[0].change,
            stored[0].success_rate
        ),
        (0.4, -0.1, Some(0.82))
    );
    assert_eq!(stored[0].reason, "patient said too hard: \u{2212}0.10");
    assert_eq!(stored[1].success_rate, None);
    assert_eq!(
        stored[0].why.as_ref().map(|w| w.code.as_str()),
        Some("felt-too-hard")
    );
    assert_eq!(stored[1].why, None);
    // A value out of range never reaches the table.
    let bad = netlink::DifficultyChange {
        difficulty: 1.5,
        change: 0.0,
        reason: String::new(),
        success_rate: None,
        why: None,
    };
    let err = db.put_difficulty("s1", &bad, T0).await.unwrap_err();
    assert!(err.to_string().contains("difficulty.difficulty"), "{err}");
}

async fn a_byes_checkin_is_stored_and_high_or_rising_pain_raises_a_caseload_alert(db: Db) {
    let (t, p) = paired(&db).await;
    let pain_alerts = |db: Db, t: Therapist| async move {
        let list = db.patients_for(&t, T0).await.unwrap();
        list[0]
            .alerts
            .iter()
            .filter(|a| a.starts_with("pain"))
            .cloned()
            .collect::<Vec<_>>()
    };
    for (i, pain) in [2, 1, 3].into_iter().enumerate() {
        session_with_pain(&db, &p.id, &format!("s{i}"), i as i64, pain).await;
    }
    assert!(
        pain_alerts(db.clone(), t.clone()).await.is_empty(),
        "3 against usual 1.5"
    );
    let stored = db.checkins_of(&p.id).await.unwrap();
    assert_eq!(stored.len(), 3, "one row per session, repeats stored once");
    assert_eq!(stored[0].session_id, "s2");
    assert_eq!(
        (
            stored[0].pain_0_10,
            stored[0].tiredness_0_10,
            stored[0].difficulty.as_deref()
        ),
        (Some(3), Some(4), Some("too_hard"))
    );
    session_with_pain(&db, &p.id, "s3", 3, 4).await;
    assert_eq!(
        pain_alerts(db.clone(), t.clone()).await,
        vec!["pain 4/10 after the last session (usually 2/10)".to_owned()]
    );
    session_with_pain(&db, &p.id, "s4", 4, 7).await;
    assert_eq!(
        pain_alerts(db.clone(), t.clone()).await,
        vec!["pain 7/10 after the last session".to_owned()]
    );
    // An answer out of range never reaches the table.
    let bad = netlink::CheckIn {
        pain_0_10: Some(11),
        ..Default::default()
    };
    let err = db.put_checkin("s4", &bad, T0).await.unwrap_err();
    assert!(err.to_string().contains("pain_0_10"), "{err}");
}

async fn a_checkpoint_keeps_every_summary_readable(db: Db) {
    let (_, p) = paired(&db).await;
    db.open_session(&hello("st-1", &p.id, "s1"), T0)
        .await
        .unwrap();
    let batch: Vec<Summary> = (0..300).map(|seq| summary("s1", seq)).collect();
    db.store_summaries(&batch, T0).await.unwrap();
    // The hub's background checkpoint (SQLite; nothing to do on PostgreSQL) while writing.
    let last = [summary("s1", 300)];
    let (checkpointed, more) = tokio::join!(db.checkpoint(), db.store_summaries(&last, T0));
    checkpointed.unwrap();
    more.unwrap();
    db.checkpoint().await.unwrap();
    assert_eq!(db.summaries_of("s1").await.unwrap().len(), 301);
}

async fn the_databases_size_grows_with_the_summaries_it_stores(db: Db) {
    let (_, p) = paired(&db).await;
    db.open_session(&hello("st-1", &p.id, "s1"), T0)
        .await
        .unwrap();
    db.checkpoint().await.unwrap();
    let before = db.size_bytes().await.unwrap();
    assert!(
        before > 0,
        "an empty migrated database has a size: {before}"
    );
    let batch: Vec<Summary> = (0..2_000).map(|seq| summary("s1", seq)).collect();
    db.store_summaries(&batch, T0).await.unwrap();
    // SQLite's pages count once the write-ahead log is copied into the file.
    db.scrub().await.unwrap();
    let after = db.size_bytes().await.unwrap();
    // Each summary row takes some tens of bytes at least on either engine.
    assert!(
        after - before >= 2_000 * 32,
        "{before} -> {after} bytes for 2 000 summaries"
    );
}

async fn metrics_and_recordings(db: Db) {
    let (_, p) = paired(&db).await;
    db.open_session(&hello("st-1", &p.id, "s1"), T0)
        .await
        .unwrap();
    let mut m = BTreeMap::from([("rom_rad".to_owned(), 1.25), ("jerk".to_owned(), 3.5)]);
    db.put_metrics("s1", &m).await.unwrap();
    m.insert("jerk".to_owned(), 2.0);
    db.put_metrics("s1", &m).await.unwrap();
    assert_eq!(db.metrics_of("s1").await.unwrap(), m);
    let bad = BTreeMap::from([("x".to_owned(), f64::INFINITY)]);
    assert!(matches!(
        db.put_metrics("s1", &bad).await,
        Err(HubError::Invalid { .. })
    ));

    let mut rec = Recording {
        session_id: "s1".into(),
        sha256: FP2.into(),
        size_bytes: 1000,
        received_bytes: 10,
        path: "recordings/s1.mcap".into(),
        complete: false,
        last_part_ms: None,
    };
    db.put_recording(&rec).await.unwrap();
    rec.received_bytes = 1000;
    rec.complete = true;
    db.put_recording(&rec).await.unwrap();
    assert_eq!(db.recording("s1").await.unwrap(), Some(rec));
    assert_eq!(db.recording("s2").await.unwrap(), None);
}

async fn regimen_versions_increment(db: Db) {
    let (t, p) = paired(&db).await;
    assert_eq!(db.latest_regimen(&p.id).await.unwrap(), None);
    assert_eq!(
        db.put_regimen(&p.id, "a = 1", None, &t.id, T0)
            .await
            .unwrap(),
        1
    );
    assert_eq!(
        db.put_regimen(&p.id, "a = 2", None, &t.id, T0 + MIN)
            .await
            .unwrap(),
        2
    );
    let latest = db.latest_regimen(&p.id).await.unwrap().unwrap();
    assert_eq!((latest.version, latest.toml.as_str()), (2, "a = 2"));
    assert_eq!(latest.prescribed_by, t.id);
    assert_eq!(latest.prescribed_at_ms, T0 + MIN);
    let history = db.regimen_history(&p.id).await.unwrap();
    assert_eq!(
        history.iter().map(|r| r.version).collect::<Vec<_>>(),
        vec![1, 2]
    );
    // Another patient starts at 1.
    let q = db.add_patient("q-1", None, T0).await.unwrap();
    assert_eq!(
        db.put_regimen(&q.id, "b = 1", None, &t.id, T0)
            .await
            .unwrap(),
        1
    );
    let ghost = db.put_regimen("p-nobody", "a = 1", None, &t.id, T0).await;
    assert!(matches!(ghost, Err(HubError::NotFound { .. })), "{ghost:?}");
}

async fn audit_log_keeps_entries(db: Db) {
    db.audit("cli", "add_patient", "p-1", "from the command line", T0)
        .await
        .unwrap();
    db.audit("therapist:t-1", "read_patient", "p-1", "", T0 + 1)
        .await
        .unwrap();
    db.audit("station:st-1", "hello", "s1", "line\nbreak", T0 + 2)
        .await
        .unwrap();
    let log = db.audit_log(2).await.unwrap();
    assert_eq!(log.len(), 2);
    assert_eq!(log[0].actor, "station:st-1");
    assert_eq!(log[0].detail, "line break");
    assert_eq!(log[1].action, "read_patient");
    assert_eq!(db.audit_log(100).await.unwrap().len(), 3);
}

#[tokio::test]
async fn sqlite_migrations_are_idempotent_and_files_private() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("new-dir/hub.db");
    let db = Db::open_sqlite(&path).await.unwrap();
    db.add_patient("p-1", None, T0).await.unwrap();
    db.close().await;
    let mode = |p: &std::path::Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
    assert_eq!(mode(&path), 0o600);
    assert_eq!(mode(path.parent().unwrap()), 0o700);
    let again = Db::open(&format!("sqlite://{}?mode=rwc", path.display()))
        .await
        .unwrap();
    assert_eq!(again.schema_version().await.unwrap(), latest_migration());
    assert!(again.patient_by_pseudonym("p-1").await.unwrap().is_some());
    let journal: String = sqlx::query_scalar("PRAGMA journal_mode")
        .fetch_one(again.pool())
        .await
        .unwrap();
    assert_eq!(journal, "wal");
    let fk: i64 = sqlx::query_scalar("PRAGMA foreign_keys")
        .fetch_one(again.pool())
        .await
        .unwrap();
    assert_eq!(fk, 1);
    let bad = Db::open("mysql://x").await.unwrap_err();
    assert!(bad.to_string().contains("sqlite://"), "{bad}");
}

#[tokio::test]
async fn postgres_migrations_are_idempotent() {
    let Some(pg) = common::PgDb::create().await else {
        return;
    };
    pg.db.add_patient("p-1", None, T0).await.unwrap();
    let again = Db::open(&pg.url).await.unwrap();
    assert_eq!(again.backend(), hub::Backend::Postgres);
    assert_eq!(again.schema_version().await.unwrap(), latest_migration());
    assert!(again.patient_by_pseudonym("p-1").await.unwrap().is_some());
    again.close().await;
    pg.drop_db().await;
}

/// Stores a regimen of 4 a week, then empties its `sessions_per_week` as a row stored before
/// migration 0004 has it: the caseload reads the column (4, then none), not the TOML.
async fn a_regimen_as_stored_before_migration_4(db: &Db) -> Therapist {
    let (t, p) = paired(db).await;
    let text = "sessions_per_week = 4\n[[exercise]]\nkind = \"dial\"\n";
    db.put_regimen(&p.id, text, Some(4), &t.id, T0)
        .await
        .unwrap();
    let prescribed =
        async |db: &Db| db.patients_for(&t, T0).await.unwrap()[0].sessions_per_week_prescribed;
    assert_eq!(prescribed(db).await, Some(4));
    sqlx::query("UPDATE regimens SET sessions_per_week = NULL")
        .execute(db.pool())
        .await
        .unwrap();
    assert_eq!(prescribed(db).await, None, "the caseload read the TOML");
    // As a hub stopped before migration 4: its row and its column not there yet.
    for undo in [
        "DELETE FROM _sqlx_migrations WHERE version = 4",
        "ALTER TABLE regimens DROP COLUMN sessions_per_week",
    ] {
        sqlx::query(undo).execute(db.pool()).await.unwrap();
    }
    t
}

/// A regimen of one minute four times a week, stored as a hub before migration 10 kept it
/// (no planned length): the caseload's prescribed minutes are read from the column alone.
async fn a_regimen_as_stored_before_migration_10(db: &Db) -> Therapist {
    let (t, p) = paired(db).await;
    let text = "sessions_per_week = 4\n[[exercise]]\nkind = \"dial\"\nduration_s = 60.0\n";
    db.put_regimen(&p.id, text, Some(4), &t.id, T0)
        .await
        .unwrap();
    let minutes =
        async |db: &Db| db.patients_for(&t, T0).await.unwrap()[0].minutes_per_week_prescribed;
    assert_eq!(minutes(db).await, Some(4.0), "stored when prescribed");
    sqlx::query("UPDATE regimens SET planned_session_s = NULL")
        .execute(db.pool())
        .await
        .unwrap();
    assert_eq!(minutes(db).await, None, "the caseload parses no TOML");
    for undo in [
        "DELETE FROM _sqlx_migrations WHERE version = 10",
        "ALTER TABLE regimens DROP COLUMN planned_session_s",
    ] {
        sqlx::query(undo).execute(db.pool()).await.unwrap();
    }
    t
}

#[tokio::test]
async fn sqlite_fills_the_planned_length_of_older_regimens_on_open() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("hub.db");
    let db = Db::open_sqlite(&path).await.unwrap();
    let t = a_regimen_as_stored_before_migration_10(&db).await;
    db.close().await;
    let again = Db::open_sqlite(&path).await.unwrap();
    let caseload = again.patients_for(&t, T0).await.unwrap();
    assert_eq!(caseload[0].minutes_per_week_prescribed, Some(4.0));
}

#[tokio::test]
async fn sqlite_fills_sessions_per_week_of_older_regimens_on_open() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("hub.db");
    let db = Db::open_sqlite(&path).await.unwrap();
    let t = a_regimen_as_stored_before_migration_4(&db).await;
    db.close().await;
    let again = Db::open_sqlite(&path).await.unwrap();
    let caseload = again.patients_for(&t, T0).await.unwrap();
    assert_eq!(caseload[0].sessions_per_week_prescribed, Some(4));
}

#[tokio::test]
async fn postgres_fills_sessions_per_week_of_older_regimens_on_open() {
    let Some(pg) = common::PgDb::create().await else {
        return;
    };
    let t = a_regimen_as_stored_before_migration_4(&pg.db).await;
    let again = Db::open(&pg.url).await.unwrap();
    let caseload = again.patients_for(&t, T0).await.unwrap();
    assert_eq!(caseload[0].sessions_per_week_prescribed, Some(4));
    again.close().await;
    pg.drop_db().await;
}

/// Two exercises' results, a road and a dial, with values of their own.
fn two_exercise_results() -> Vec<netlink::ExerciseResult> {
    vec![
        netlink::ExerciseResult {
            index: 1,
            kind: "dial-sine".into(),
            name: "Dial sine".into(),
            prescribed_s: 45.0,
            active_s: 44.996,
            scores: BTreeMap::from([
                ("dial_mean_abs_error_deg".to_owned(), 3.125),
                ("dial_rms_error_deg".to_owned(), 4.0000000001),
            ]),
            assessment: None,
        },
        netlink::ExerciseResult {
            index: 0,
            kind: "sine-road".into(),
            name: "Sine road".into(),
            prescribed_s: 90.0,
            active_s: 90.0,
            scores: BTreeMap::from([
                ("rms_lateral_m".to_owned(), 0.1234567890123),
                ("pct_in_lane".to_owned(), 99.5),
            ]),
            assessment: None,
        },
    ]
}

async fn a_byes_exercise_results_are_stored_in_course_order_exactly(db: Db) {
    let (_, p) = paired(&db).await;
    db.open_session(&hello("st-1", &p.id, "s1"), T0)
        .await
        .unwrap();
    db.open_session(&hello("st-1", &p.id, "s-old"), T0)
        .await
        .unwrap();
    let bye = Bye {
        session_id: "s1".into(),
        reason: "complete".into(),
        final_seq: None,
        measures: BTreeMap::new(),
        hub_unix_ms: None,
        checkin: None,
        difficulty: None,
        exercises: two_exercise_results(),
    };
    db.close_session(&bye, T0 + MIN).await.unwrap();
    // A repeated Bye (the station missed the reply) stores the same once.
    db.close_session(&bye, T0 + MIN).await.unwrap();
    let stored = db.exercises_of("s1").await.unwrap();
    assert_eq!(stored.len(), 2);
    for (got, sent) in stored.iter().zip([&bye.exercises[1], &bye.exercises[0]]) {
        assert_eq!(got.index, i64::from(sent.index));
        assert_eq!((&got.kind, &got.name), (&sent.kind, &sent.name));
        assert_eq!(
            (got.prescribed_s, got.active_s),
            (sent.prescribed_s, sent.active_s)
        );
        assert_eq!(got.scores, sent.scores, "every value exactly");
    }
    // A station older than the field: no results, not an error.
    let old = Bye {
        session_id: "s-old".into(),
        exercises: Vec::new(),
        ..bye.clone()
    };
    db.close_session(&old, T0 + MIN).await.unwrap();
    assert!(db.exercises_of("s-old").await.unwrap().is_empty());
    // Out of bounds is refused by name and stores nothing.
    let mut bad = two_exercise_results();
    bad[0].active_s = -1.0;
    let err = db
        .put_exercises("s-old", &bad)
        .await
        .unwrap_err()
        .to_string();
    assert!(err.contains("exercises[1].active_s"), "{err}");
    assert!(db.exercises_of("s-old").await.unwrap().is_empty());
}

/// A session that ran the standard assessment first, then a road: the assessment's parts
/// come back tagged and as the patient's assessment; the session compares with road
/// sessions (its kind `road`, not `assessment+road`); a session without one has none.
async fn an_assessment_is_stored_as_its_own_kind_and_kept_out_of_the_exercise_trends(db: Db) {
    let (_, p) = paired(&db).await;
    let tag = netlink::AssessmentTag {
        protocol: 1,
        seed: 4_000_000_000,
    };
    let part = |index: u32, kind: &str, score: (&str, f64)| netlink::ExerciseResult {
        index,
        kind: kind.into(),
        name: kind.into(),
        prescribed_s: 30.0,
        active_s: 30.0,
        scores: BTreeMap::from([(score.0.to_owned(), score.1)]),
        assessment: Some(tag),
    };
    let mut road = two_exercise_results().remove(1);
    road.index = 2;
    let exercises = vec![
        part(0, "assessment-range", ("wheel_rom_deg", 150.0)),
        part(1, "assessment-steps", ("reaction_time_median_s", 0.41)),
        road,
    ];
    for (id, at) in [("s-old", T0), ("s-new", T0 + 60 * MIN)] {
        db.open_session(&hello("st-1", &p.id, id), at)
            .await
            .unwrap();
        let bye = Bye {
            session_id: id.into(),
            reason: "complete".into(),
            final_seq: None,
            measures: BTreeMap::from([("movements".to_owned(), 12.0)]),
            hub_unix_ms: None,
            checkin: None,
            difficulty: None,
            exercises: if id == "s-new" {
                exercises.clone()
            } else {
                exercises[2..].to_vec()
            },
        };
        db.close_session(&bye, at + MIN).await.unwrap();
    }
    let stored = db.exercises_of("s-new").await.unwrap();
    assert_eq!(stored[0].assessment, Some(tag));
    assert_eq!(stored[2].assessment, None);
    let assessments = db.assessments_of(&p.id).await.unwrap();
    assert_eq!(assessments.len(), 1, "{assessments:?}");
    let a = &assessments[0];
    assert_eq!(
        (a.session_id.as_str(), a.protocol, a.seed),
        ("s-new", 1, tag.seed)
    );
    let kinds: Vec<&str> = a.parts.iter().map(|e| e.kind.as_str()).collect();
    assert_eq!(kinds, ["assessment-range", "assessment-steps"]);
    assert_eq!(a.parts[1].scores["reaction_time_median_s"], 0.41);
    let sessions = db.named_sessions_of(&p.id).await.unwrap();
    assert_eq!(sessions.len(), 2);
    for s in &sessions {
        assert_eq!(s.exercise_kind, "road", "{}", s.row.session_id);
    }
}

async fn attempts_from_one_address_never_make_a_pairing_code_wait_for_another(db: Db) {
    let (_, p) = paired(&db).await;
    let code = db
        .create_pairing_code(&p.id, T0, 60 * 60_000)
        .await
        .unwrap();
    let code = netlink::pairing::PairingCode::parse(&code).unwrap();
    // A guesser who knows the public half keeps beginning attempts (each one that gets
    // through lengthens its own wait) ...
    let mut at = T0;
    for _ in 0..20 {
        let _ = db
            .begin_pairing_attempt(code.code_id(), "198.51.100.7", at)
            .await
            .unwrap();
        at += 1_000;
    }
    assert!(
        db.begin_pairing_attempt(code.code_id(), "198.51.100.7", at)
            .await
            .unwrap()
            .is_none(),
        "the guesser waits"
    );
    // ... and the patient's station, from its own address, gets its real try at once.
    let ticket = db
        .begin_pairing_attempt(code.code_id(), "203.0.113.5", at)
        .await
        .unwrap()
        .expect("the right station is not kept waiting by another address");
    assert_eq!(ticket.secret, code.secret());
    assert_eq!(
        db.pair_station(code.code_id(), "st-pw", &"e".repeat(64), at)
            .await
            .unwrap(),
        p.id
    );
}
