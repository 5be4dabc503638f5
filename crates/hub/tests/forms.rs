//! Issue 29's forms at the hub, on SQLite and PostgreSQL: the patient's wheel as their station
//! tells it (`GET /api/patients/{id}`'s `wheel`) bounding every prescribed torque, and the
//! therapist's session notes (`POST`/`GET /api/sessions/{id}/notes`).

mod common;

use common::{T0, hello};

use common::api::{actions, call, clinician, login, router_at_t0};

use axum::http::{Method, StatusCode};
use hub::{Db, Role};
use netlink::WheelInfo;
use serde_json::json;

fn g29() -> WheelInfo {
    WheelInfo {
        model: "Logitech G29".into(),
        rated_torque_nm: 2.2,
        ceiling_nm: 1.87,
        unknown: false,
    }
}

const FINGERPRINT_A: &str = "aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa";
const FINGERPRINT_B: &str = "bbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbb";

async fn a_regimen_above_the_patients_wheel_is_refused_naming_exercise_field_value_and_wheel(
    db: Db,
) {
    let ada = clinician(&db, "ada@clinic.example", Role::Therapist).await;
    let p = db.add_patient("P-0042", Some(&ada.id), T0).await.unwrap();
    db.add_station("st-1", &p.id, FINGERPRINT_A, T0)
        .await
        .unwrap();
    let app = router_at_t0(&db);
    let cookie = login(&app, "ada@clinic.example").await;
    let patient_uri = format!("/api/patients/{}", p.id);
    let regimen_uri = format!("/api/patients/{}/regimen", p.id);
    let five = "[[exercise]]\nkind = \"straight\"\n\n[[exercise]]\nkind = \"sine\"\n\
                [exercise.haptic]\nceiling_nm = 5.0\n";
    // No wheel told yet: the schema's device maximum is the only bound.
    let (_, detail, _) = call(&app, Method::GET, &patient_uri, Some(&cookie), None).await;
    assert!(detail["wheel"].is_null(), "{detail}");
    let (status, v, _) = call(
        &app,
        Method::PUT,
        &regimen_uri,
        Some(&cookie),
        Some(json!({"toml": five})),
    )
    .await;
    assert_eq!(status, StatusCode::OK, "{v}");
    // The station tells its wheel: the patient's own bound from then on.
    db.note_station_wheel("st-1", &g29(), T0 + 1_000)
        .await
        .unwrap();
    let (_, detail, _) = call(&app, Method::GET, &patient_uri, Some(&cookie), None).await;
    let wheel = &detail["wheel"];
    assert_eq!(wheel["model"], "Logitech G29");
    assert_eq!(wheel["rated_torque_nm"], 2.2);
    assert_eq!(wheel["ceiling_nm"], 1.87);
    assert_eq!(wheel["stated_ceiling_nm"], 1.87);
    assert_eq!(wheel["station_id"], "st-1");
    let (status, answer, _) = call(
        &app,
        Method::PUT,
        &regimen_uri,
        Some(&cookie),
        Some(json!({"toml": five})),
    )
    .await;
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY, "{answer}");
    assert_eq!(
        answer["error"],
        "regimen refused: ceiling_nm 5 N·m for exercise 2 (Sine road) is above what P-0042's \
         wheel (Logitech G29) can give: at most 1.87 N·m"
    );
    assert_eq!(
        db.regimen_history(&p.id).await.unwrap().len(),
        1,
        "not stored"
    );
    let refused = actions(&db)
        .await
        .into_iter()
        .filter(|(_, act, _)| act == "regimen_rejected")
        .count();
    assert_eq!(refused, 1, "the refusal is audited");
    let at_most = five.replace("5.0", "1.87");
    let (status, v, _) = call(
        &app,
        Method::PUT,
        &regimen_uri,
        Some(&cookie),
        Some(json!({"toml": at_most})),
    )
    .await;
    assert_eq!(status, StatusCode::OK, "{v}");
    // The newest wheel told counts; a revoked station's no longer does.
    db.add_station("st-2", &p.id, FINGERPRINT_B, T0)
        .await
        .unwrap();
    let weak = WheelInfo {
        model: "unknown wheel (Acme)".into(),
        rated_torque_nm: 5.0,
        ceiling_nm: 0.5,
        unknown: true,
    };
    db.note_station_wheel("st-2", &weak, T0 + 2_000)
        .await
        .unwrap();
    assert_eq!(db.wheel_of(&p.id).await.unwrap().unwrap().ceiling_nm, 0.5);
    db.revoke_station("st-2", T0 + 3_000).await.unwrap();
    assert_eq!(
        db.wheel_of(&p.id).await.unwrap().unwrap().model,
        "Logitech G29"
    );
    // A wheel the protocol refuses is not kept.
    let bad = WheelInfo {
        ceiling_nm: f64::NAN,
        ..g29()
    };
    assert!(db.note_station_wheel("st-1", &bad, T0).await.is_err());
}

async fn a_session_note_is_posted_listed_with_its_therapist_audited_and_hidden_from_others(db: Db) {
    let ada = clinician(&db, "ada@clinic.example", Role::Therapist).await;
    clinician(&db, "bob@clinic.example", Role::Therapist).await;
    let p = db.add_patient("P-0042", Some(&ada.id), T0).await.unwrap();
    db.add_station("st-1", &p.id, FINGERPRINT_A, T0)
        .await
        .unwrap();
    db.open_session(&hello("st-1", &p.id, "s-1"), T0)
        .await
        .unwrap();
    let app = router_at_t0(&db);
    let cookie = login(&app, "ada@clinic.example").await;
    let uri = "/api/sessions/s-1/notes";
    let text = "Tired today; shoulder pain 3/10.\nKeep the ceiling low next week.";
    let (status, note, _) = call(
        &app,
        Method::POST,
        uri,
        Some(&cookie),
        Some(json!({ "text": text })),
    )
    .await;
    assert_eq!(status, StatusCode::CREATED, "{note}");
    assert_eq!(note["text"], text);
    assert_eq!(note["therapist_email"], "ada@clinic.example");
    let (status, list, _) = call(&app, Method::GET, uri, Some(&cookie), None).await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(list.as_array().unwrap().len(), 1);
    assert_eq!(list[0]["therapist_id"], ada.id.as_str());
    assert_eq!(list[0]["created_at_ms"], T0);
    let audit = actions(&db).await;
    for action in ["post_note", "read_notes"] {
        assert!(
            audit
                .iter()
                .any(|(a, act, t)| *a == ada.actor() && act == action && t == "s-1"),
            "{action} not audited: {audit:?}"
        );
    }
    // Another therapist's patient's session is not found, for reading and writing; no login,
    // no notes; an unknown session is not found.
    let bob = login(&app, "bob@clinic.example").await;
    let (status, _, _) = call(&app, Method::GET, uri, Some(&bob), None).await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    let (status, _, _) = call(
        &app,
        Method::POST,
        uri,
        Some(&bob),
        Some(json!({"text": "hi"})),
    )
    .await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    let (status, _, _) = call(&app, Method::GET, uri, None, None).await;
    assert_eq!(status, StatusCode::UNAUTHORIZED);
    let (status, _, _) = call(
        &app,
        Method::GET,
        "/api/sessions/s-none/notes",
        Some(&cookie),
        None,
    )
    .await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    assert_eq!(db.notes_of_session("s-1").await.unwrap().len(), 1);
    // A long record lists its newest notes: the one written after 200 others shows.
    for k in 0..hub::db::MAX_NOTES_LISTED {
        db.add_session_note("s-1", &ada.id, &format!("note {k}"), T0 + 1 + k)
            .await
            .unwrap();
    }
    let listed = db.notes_of_session("s-1").await.unwrap();
    assert_eq!(listed.len() as i64, hub::db::MAX_NOTES_LISTED);
    assert_eq!(listed.last().unwrap().text, "note 199", "the newest, last");
    assert!(
        listed
            .windows(2)
            .all(|w| w[0].created_at_ms <= w[1].created_at_ms)
    );
}

async fn a_note_empty_too_long_or_with_control_characters_is_refused_naming_why(db: Db) {
    let ada = clinician(&db, "ada@clinic.example", Role::Therapist).await;
    let p = db.add_patient("P-0042", Some(&ada.id), T0).await.unwrap();
    db.add_station("st-1", &p.id, FINGERPRINT_A, T0)
        .await
        .unwrap();
    db.open_session(&hello("st-1", &p.id, "s-1"), T0)
        .await
        .unwrap();
    let app = router_at_t0(&db);
    let cookie = login(&app, "ada@clinic.example").await;
    let uri = "/api/sessions/s-1/notes";
    // Counted in characters: 2 000 of 'é' (4 000 bytes) are allowed.
    let (status, v, _) = call(
        &app,
        Method::POST,
        uri,
        Some(&cookie),
        Some(json!({"text": "é".repeat(2_000)})),
    )
    .await;
    assert_eq!(status, StatusCode::CREATED, "{v}");
    for (body, why) in [
        (
            json!({"text": "a".repeat(2_001)}),
            "2001 characters, at most 2000",
        ),
        (json!({"text": "  \n "}), "empty"),
        (json!({"text": "bell\u{7}"}), "control characters"),
        (json!({"text": 5}), "text"),
        (json!({"words": "hi"}), "words"),
    ] {
        let (status, answer, _) = call(&app, Method::POST, uri, Some(&cookie), Some(body)).await;
        assert_eq!(status, StatusCode::BAD_REQUEST, "{answer}");
        let error = answer["error"].as_str().unwrap();
        assert!(error.contains(why), "{error:?} does not say {why:?}");
    }
    assert_eq!(db.notes_of_session("s-1").await.unwrap().len(), 1);
    let refused = actions(&db)
        .await
        .into_iter()
        .filter(|(_, act, _)| act == "note_rejected")
        .count();
    assert_eq!(refused, 3, "each refused text is audited");
}

on_both_backends!(
    a_regimen_above_the_patients_wheel_is_refused_naming_exercise_field_value_and_wheel,
    a_session_note_is_posted_listed_with_its_therapist_audited_and_hidden_from_others,
    a_note_empty_too_long_or_with_control_characters_is_refused_naming_why,
);
