//! The per-session measures as CSV (`GET /api/patients/{id}/measures.csv`, `GET
//! /api/measures.csv` for an admin) and the standard assessments as their own CSV (`GET
//! /api/patients/{id}/assessments.csv`), on SQLite and PostgreSQL.

mod common;

use common::api::{PASSWORD, actions, call, login};
use common::{T0, hello};

use std::collections::BTreeMap;

use axum::Router;
use axum::body::Body;
use axum::http::{HeaderMap, Method, Request, StatusCode, header};
use http_body_util::BodyExt;
use hub::{Db, Role};
use serde_json::json;
use tower::ServiceExt;

/// A GET with the cookie: status, headers and the body as text.
async fn get(app: &Router, uri: &str, cookie: &str) -> (StatusCode, HeaderMap, String) {
    let request = Request::builder()
        .method(Method::GET)
        .uri(uri)
        .header(header::COOKIE, cookie)
        .body(Body::empty())
        .unwrap();
    let response = app.clone().oneshot(request).await.unwrap();
    let (status, headers) = (response.status(), response.headers().clone());
    let bytes = response.into_body().collect().await.unwrap().to_bytes();
    (status, headers, String::from_utf8(bytes.to_vec()).unwrap())
}

/// Patient `pseudonym` of `therapist_id` with a paired station and a session of `measures`
/// for each entry, a minute apart from `T0`; the patient's id.
async fn patient_with_sessions(
    db: &Db,
    pseudonym: &str,
    therapist_id: &str,
    sessions: &[&[(&str, f64)]],
) -> String {
    let p = db
        .add_patient(pseudonym, Some(therapist_id), T0)
        .await
        .unwrap();
    let station = format!("st-{pseudonym}");
    let fingerprint = format!("{:0>64}", pseudonym.len() + sessions.len());
    db.add_station(&station, &p.id, &fingerprint, T0)
        .await
        .unwrap();
    for (i, measures) in sessions.iter().enumerate() {
        let id = format!("s-{pseudonym}-{i}");
        let mut h = hello(&station, &p.id, &id);
        h.started_unix_ms = (T0 + 60_000 * i as i64) as u64;
        db.open_session(&h, T0).await.unwrap();
        let measures: BTreeMap<String, f64> = measures
            .iter()
            .map(|(k, v)| ((*k).to_owned(), *v))
            .collect();
        db.put_metrics(&id, &measures).await.unwrap();
    }
    p.id
}

/// A clinic: admin ana with patient P-0007 (one session), therapist ada with P-0042 (two
/// sessions, the first ended on an unplugged wheel with a check-in); ada's and P-0042's ids.
async fn seeded(db: &Db) -> (hub::Therapist, hub::Therapist, String) {
    let ana = db
        .add_therapist("ana@clinic.example", PASSWORD, Role::Admin, T0)
        .await
        .unwrap();
    let ada = db
        .add_therapist("ada@clinic.example", PASSWORD, Role::Therapist, T0)
        .await
        .unwrap();
    let sparc = -1.612_345_678_901_234_5;
    let p = patient_with_sessions(
        db,
        "P-0042",
        &ada.id,
        &[
            &[
                ("sparc_median", sparc),
                ("active_s", 25.5),
                ("pct_in_lane", 999.999_999_999_999_9),
            ],
            &[
                ("sparc_median", -1.5),
                ("tracking_rms_error_deg", 0.1),
                ("zz_new_measure_s", 0.123_456_7),
            ],
        ],
    )
    .await;
    // The first session ended on an unplugged wheel, with the patient's check-in.
    let bye = netlink::Bye {
        session_id: "s-P-0042-0".to_owned(),
        reason: "wheel unplugged".to_owned(),
        final_seq: None,
        measures: BTreeMap::new(),
        hub_unix_ms: None,
        checkin: None,
        difficulty: None,
        exercises: Vec::new(),
    };
    db.close_session(&bye, T0 + 1000).await.unwrap();
    let checkin = netlink::CheckIn {
        pain_0_10: Some(8),
        tiredness_0_10: Some(6),
        difficulty: Some("too_hard".to_owned()),
    };
    db.put_checkin("s-P-0042-0", &checkin, T0 + 1000)
        .await
        .unwrap();
    patient_with_sessions(db, "P-0007", &ana.id, &[&[("pct_in_lane", 97.25)]]).await;
    (ana, ada, p)
}

async fn a_patients_csv_has_plain_and_technical_headers_rounded_values_local_times_and_check_ins(
    db: Db,
) {
    let (_, _, p) = seeded(&db).await;
    let app = common::api::router_at_t0(&db);
    let cookie = login(&app, "ada@clinic.example").await;
    let (status, headers, csv) = get(
        &app,
        &format!("/api/patients/{p}/measures.csv?tz=Europe/Berlin"),
        &cookie,
    )
    .await;
    assert_eq!(status, StatusCode::OK, "{csv}");
    assert_eq!(headers[header::CONTENT_TYPE], "text/csv; charset=utf-8");
    assert_eq!(
        headers[header::CONTENT_DISPOSITION],
        "attachment; filename=\"measures-P-0042-2026-11-21.csv\""
    );
    let lines: Vec<&str> = csv.split("\r\n").collect();
    // Plain words with units first, the technical names under them; the table's measures in
    // its reading order, any other after them.
    assert_eq!(
        lines[0],
        "Session reference,\"Started (local time, Europe/Berlin)\",Started (UTC),Exercises,How it ended,\
         Ran as prescribed,Pain after (0–10),Effort after (Borg CR10 0–10),How hard it felt,\
         Active time (s),Smoothness (closer to 0 is smoother),Time in lane (%),\
         Distance from the angle asked (°),zz new measure s"
    );
    assert_eq!(
        lines[1],
        "session_id,started_local,started_at_utc,exercise,end_reason,ran_as_prescribed,\
         pain_0_10,tiredness_0_10,difficulty,active_s,sparc_median,pct_in_lane,\
         tracking_rms_error_deg,zz_new_measure_s"
    );
    assert_eq!(
        lines.len(),
        5,
        "two headers, two sessions and the last line's end: {csv:?}"
    );
    let first: Vec<&str> = lines[2].split(',').collect();
    assert_eq!(
        first[..9],
        [
            "s-P-0042-0",
            "2026-11-21 10:30",
            "2026-11-21T09:30:00Z",
            "Sine road",
            "Stopped early: wheel unplugged",
            "no",
            "8",
            "6",
            "too hard"
        ]
    );
    assert_eq!(
        first[9], "26",
        "active time to the second (25.5 rounds to even or up)"
    );
    assert_eq!(first[10], "-1.61", "rounded to the table's decimals");
    assert_eq!(first[11], "1000", "never 999.9999999999999");
    assert_eq!(
        first[12], "",
        "a measure the session lacks is an empty cell"
    );
    let second: Vec<&str> = lines[3].split(',').collect();
    assert_eq!(second[1..3], ["2026-11-21 10:31", "2026-11-21T09:31:00Z"]);
    assert_eq!(second[6..9], ["", "", ""], "no check-in: empty cells");
    assert_eq!(second[12], "0.1");
    assert_eq!(
        second[13], "0.1235",
        "a measure the table lacks: 4 significant digits"
    );
    // An unknown time zone is refused, naming it.
    let (status, _, body) = get(
        &app,
        &format!("/api/patients/{p}/measures.csv?tz=Mars/Olympus"),
        &cookie,
    )
    .await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
    assert!(body.contains("Mars/Olympus"), "{body}");
}

async fn a_german_csv_says_its_words_in_german_and_keeps_the_technical_line_and_numbers(db: Db) {
    let (_, _, p) = seeded(&db).await;
    let app = common::api::router_at_t0(&db);
    let cookie = login(&app, "ada@clinic.example").await;
    let uri = format!("/api/patients/{p}/measures.csv?tz=Europe/Berlin");
    let (_, _, english) = get(&app, &uri, &cookie).await;
    let (status, _, german) = get(&app, &format!("{uri}&lang=de"), &cookie).await;
    assert_eq!(status, StatusCode::OK, "{german}");
    let en: Vec<&str> = english.split("\r\n").collect();
    let de: Vec<&str> = german.split("\r\n").collect();
    assert!(
        de[0].starts_with("Sitzungskennung,\"Beginn (Ortszeit, Europe/Berlin)\""),
        "{}",
        de[0]
    );
    assert!(de[0].contains("Zeit in der Spur (%)"), "{}", de[0]);
    assert_eq!(
        de[1], en[1],
        "the technical names are the same in every language"
    );
    let first: Vec<&str> = de[2].split(',').collect();
    assert_eq!(
        first[3..9],
        [
            "Sinusstraße",
            "Vorzeitig beendet: Lenkrad getrennt",
            "nein",
            "8",
            "6",
            "zu schwer"
        ]
    );
    assert_eq!(
        de[2].split(',').skip(9).collect::<Vec<_>>(),
        en[2].split(',').skip(9).collect::<Vec<_>>(),
        "the numbers are the same"
    );
    // The therapist's console language when the link names none.
    let (status, _, _) = call(
        &app,
        Method::PUT,
        "/api/me/language",
        Some(&cookie),
        Some(json!({"language": "de"})),
    )
    .await;
    assert_eq!(status, StatusCode::OK);
    let (_, _, chosen) = get(&app, &uri, &cookie).await;
    assert_eq!(chosen, german);
}

async fn the_caseload_csv_has_the_same_columns_with_the_patient_first_for_admins_only(db: Db) {
    let (ana, ada, p) = seeded(&db).await;
    let app = common::api::router_at_t0(&db);
    let cookie = login(&app, "ada@clinic.example").await;
    // Another therapist's patient is not found; the caseload is for admins.
    let (status, _, _) = get(&app, &format!("/api/patients/{p}/measures.csv"), &cookie).await;
    assert_eq!(status, StatusCode::OK);
    let (status, _, _) = get(&app, "/api/measures.csv", &cookie).await;
    assert_eq!(status, StatusCode::FORBIDDEN);
    let admin = login(&app, "ana@clinic.example").await;
    let (status, headers, csv) = get(&app, "/api/measures.csv?tz=UTC", &admin).await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(
        headers[header::CONTENT_DISPOSITION],
        "attachment; filename=\"measures-caseload-2026-11-21.csv\""
    );
    let lines: Vec<&str> = csv.split("\r\n").collect();
    assert!(
        lines[0].starts_with("Patient,Session reference,"),
        "{}",
        lines[0]
    );
    assert!(lines[0].contains(",Pain after (0–10),"), "{}", lines[0]);
    assert!(lines[1].starts_with("patient,session_id,"), "{}", lines[1]);
    assert!(lines[1].contains(",pct_in_lane,"), "{}", lines[1]);
    let patients: Vec<&str> = lines[2..5]
        .iter()
        .map(|l| l.split(',').next().unwrap())
        .collect();
    assert_eq!(patients, ["P-0007", "P-0042", "P-0042"], "by pseudonym");
    assert!(
        lines[3].contains(",Stopped early: wheel unplugged,no,8,6,too hard,"),
        "{}",
        lines[3]
    );
    let audit = actions(&db).await;
    assert!(
        audit
            .iter()
            .any(|(a, act, t)| *a == ada.actor() && act == "export_measures_csv" && *t == p)
    );
    assert!(
        audit
            .iter()
            .any(|(a, act, _)| *a == ana.actor() && act == "export_caseload_csv")
    );
}

on_both_backends!(
    a_patients_csv_has_plain_and_technical_headers_rounded_values_local_times_and_check_ins
);
on_both_backends!(the_caseload_csv_has_the_same_columns_with_the_patient_first_for_admins_only);
on_both_backends!(a_german_csv_says_its_words_in_german_and_keeps_the_technical_line_and_numbers);

async fn the_one_table_of_measure_words_is_served_to_the_console(db: Db) {
    db.add_therapist("ada@clinic.example", PASSWORD, Role::Therapist, T0)
        .await
        .unwrap();
    let app = common::api::router_at_t0(&db);
    let (status, _, _) = get(&app, "/api/measures/words", "").await;
    assert_eq!(status, StatusCode::UNAUTHORIZED, "a login first");
    let cookie = login(&app, "ada@clinic.example").await;
    let (status, _, body) = get(&app, "/api/measures/words", &cookie).await;
    assert_eq!(status, StatusCode::OK, "{body}");
    let words: serde_json::Value = serde_json::from_str(&body).unwrap();
    let sparc = words["measures"]
        .as_array()
        .unwrap()
        .iter()
        .find(|m| m["key"] == "sparc_median")
        .unwrap();
    assert_eq!(sparc["name"], "Smoothness (closer to 0 is smoother)");
    assert_eq!(sparc["range"], serde_json::json!([-5.0, 0.0]));
    assert_eq!(sparc["noise"]["kind"], "relative");
    assert_eq!(sparc["better"], "higher");
    assert!(sparc["technical"].as_str().unwrap().contains("SPARC"));
    // Issue 42: its definition (smoothness over discrete movements only), its source and the
    // id of the definition in the console's catalogues.
    assert!(
        sparc["definition"]
            .as_str()
            .unwrap()
            .contains("discrete movements")
    );
    assert!(
        sparc["source"]
            .as_str()
            .unwrap()
            .contains("Balasubramanian")
    );
    assert_eq!(sparc["definition_id"], "words-definition-sparc-median");
    let ends = words["end_reasons"].as_array().unwrap();
    assert!(
        ends.iter()
            .any(|e| e["kind"] == "wheel_unplugged"
                && e["words"] == "Stopped early: wheel unplugged")
    );
}

on_both_backends!(the_one_table_of_measure_words_is_served_to_the_console);

/// A part `kind` of the standard assessment (protocol 1, seed `seed`) at `index` with `scores`.
fn assessment_part(
    index: u32,
    kind: &str,
    seed: u32,
    scores: &[(&str, f64)],
) -> netlink::ExerciseResult {
    netlink::ExerciseResult {
        index,
        kind: kind.into(),
        name: kind.into(),
        prescribed_s: 30.0,
        active_s: 30.0,
        scores: scores.iter().map(|(k, v)| ((*k).to_owned(), *v)).collect(),
        assessment: Some(netlink::AssessmentTag { protocol: 1, seed }),
    }
}

async fn the_assessments_csv_has_a_row_a_measure_marked_by_session_protocol_and_part(db: Db) {
    let (_, _, p) = seeded(&db).await;
    // The first session ran the assessment's range and steps, then a road; the second none.
    let bye = netlink::Bye {
        session_id: "s-P-0042-0".to_owned(),
        reason: "wheel unplugged".to_owned(),
        final_seq: None,
        measures: BTreeMap::new(),
        hub_unix_ms: None,
        checkin: None,
        difficulty: None,
        exercises: vec![
            assessment_part(
                0,
                "assessment-range",
                4_000_000_000,
                &[("wheel_rom_deg", 141.234_567_8)],
            ),
            assessment_part(
                1,
                "assessment-steps",
                4_000_000_000,
                &[
                    ("sparc_median", -1.834_567_8),
                    ("reaction_time_s_median", 0.412_345_6),
                    ("step_responses", 17.0),
                ],
            ),
            netlink::ExerciseResult {
                index: 2,
                kind: "sine-road".into(),
                name: "Sine road".into(),
                prescribed_s: 60.0,
                active_s: 60.0,
                scores: BTreeMap::from([("pct_in_lane".to_owned(), 80.0)]),
                assessment: None,
            },
        ],
    };
    db.close_session(&bye, T0 + 2000).await.unwrap();
    let app = common::api::router_at_t0(&db);
    let cookie = login(&app, "ada@clinic.example").await;
    let uri = format!("/api/patients/{p}/assessments.csv?tz=Europe/Berlin");
    let (status, headers, csv) = get(&app, &uri, &cookie).await;
    assert_eq!(status, StatusCode::OK, "{csv}");
    assert_eq!(
        headers[header::CONTENT_DISPOSITION],
        "attachment; filename=\"assessments-P-0042-2026-11-21.csv\""
    );
    let lines: Vec<&str> = csv.split("\r\n").collect();
    assert_eq!(
        lines[0],
        "Session reference,\"Started (local time, Europe/Berlin)\",Started (UTC),Protocol version,\
         Seed of the target steps,Part (code),Part,Measure (code),Measure,Value,Unit"
    );
    assert_eq!(
        lines[1],
        "session_id,started_local,started_at_utc,assessment_protocol,assessment_seed,\
         assessment_part,part,measure,measure_name,value,unit"
    );
    // One row a measure of a part, in course order, the table's measures in its reading
    // order; the road after the assessment is not in it.
    let rows: Vec<Vec<&str>> = lines[2..lines.len() - 1]
        .iter()
        .map(|l| l.split(',').collect())
        .collect();
    assert_eq!(rows.len(), 4, "{csv}");
    assert_eq!(
        rows[0],
        [
            "s-P-0042-0",
            "2026-11-21 10:30",
            "2026-11-21T09:30:00Z",
            "1",
            "4000000000",
            "range",
            "Active range",
            "wheel_rom_deg",
            "Wheel turning range",
            "141",
            "°"
        ]
    );
    let measures: Vec<(&str, &str, &str)> = rows[1..].iter().map(|r| (r[5], r[7], r[9])).collect();
    assert_eq!(
        measures,
        [
            ("steps", "sparc_median", "-1.83"),
            ("steps", "reaction_time_s_median", "0.41"),
            ("steps", "step_responses", "17"),
        ]
    );
    assert_eq!(rows[2][10], "s");
    assert!(!csv.contains("pct_in_lane"), "{csv}");
    assert!(
        actions(&db)
            .await
            .iter()
            .any(|(_, a, t)| a == "export_assessments_csv" && *t == p)
    );
    // In German: the plain words change, the technical line and the numbers do not.
    let (_, _, de) = get(&app, &format!("{uri}&lang=de"), &cookie).await;
    let de_lines: Vec<&str> = de.split("\r\n").collect();
    assert!(
        de_lines[0].contains("Protokollversion") && de_lines[0].contains("Einheit"),
        "{de}"
    );
    assert_eq!(de_lines[1], lines[1]);
    assert!(
        de_lines[2].contains("Aktiver Bewegungsumfang") && de_lines[2].ends_with(",141,°"),
        "{de}"
    );
}

on_both_backends!(the_assessments_csv_has_a_row_a_measure_marked_by_session_protocol_and_part);
