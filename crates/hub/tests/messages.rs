//! The therapist's messages to a patient through the console API (`POST`/`GET
//! /api/patients/{id}/messages`) and the station's "seen", on SQLite and PostgreSQL.

mod common;

use common::api::{PASSWORD, actions, call, login};

use axum::http::{Method, StatusCode};
use hub::{Db, Role};
use serde_json::json;

const T0: i64 = 1_795_253_400_000;

async fn a_message_is_posted_listed_newest_first_audited_and_seen_once(db: Db) {
    let ada = db
        .add_therapist("ada@clinic.example", PASSWORD, Role::Therapist, T0)
        .await
        .unwrap();
    let bob = db
        .add_therapist("bob@clinic.example", PASSWORD, Role::Therapist, T0)
        .await
        .unwrap();
    let p = db.add_patient("p-ada-1", Some(&ada.id), T0).await.unwrap();
    let p_bob = db.add_patient("p-bob-1", Some(&bob.id), T0).await.unwrap();
    let (now, clock) = common::clock_at(T0);
    let app = common::api::router_with_clock(&db, now);
    let cookie = login(&app, "ada@clinic.example").await;
    let uri = format!("/api/patients/{}/messages", p.id);
    // Counted in characters: 500 characters of 'é' (1 000 bytes) are allowed.
    let long_ok = "é".repeat(500);
    for (i, text) in ["Well done this week — keep going!", long_ok.as_str()]
        .iter()
        .enumerate()
    {
        clock.set_unix_ns(common::ns(T0 + i as i64 * 1_000));
        let (status, m, _) = call(
            &app,
            Method::POST,
            &uri,
            Some(&cookie),
            Some(json!({ "text": text })),
        )
        .await;
        assert_eq!(status, StatusCode::CREATED, "{m}");
        assert_eq!(m["text"], *text);
        assert!(m["seen_at_ms"].is_null());
    }
    let (status, list, _) = call(&app, Method::GET, &uri, Some(&cookie), None).await;
    assert_eq!(status, StatusCode::OK);
    let list = list.as_array().unwrap().clone();
    assert_eq!(list.len(), 2);
    assert_eq!(list[0]["text"], long_ok, "newest first");
    assert_eq!(list[1]["created_at_ms"], T0);
    assert_eq!(list[0]["therapist_id"], ada.id.as_str());
    let audit = actions(&db).await;
    for action in ["post_message", "read_messages"] {
        assert!(
            audit
                .iter()
                .any(|(a, act, t)| *a == ada.actor() && act == action && *t == p.id),
            "{action} not audited: {audit:?}"
        );
    }
    // The station's "seen": once, for its own patient only.
    let oldest = list[1]["id"].as_str().unwrap();
    let unseen = db.unseen_messages(&p.id).await.unwrap();
    assert_eq!(unseen[0].id, oldest, "the station is sent the oldest first");
    assert!(!db.message_seen(&p_bob.id, oldest, 5).await.unwrap());
    assert!(
        db.message_seen(&p.id, oldest, 1_795_253_460_000)
            .await
            .unwrap()
    );
    assert!(
        !db.message_seen(&p.id, oldest, 9).await.unwrap(),
        "seen once"
    );
    assert_eq!(db.unseen_messages(&p.id).await.unwrap().len(), 1);
    let (_, list, _) = call(&app, Method::GET, &uri, Some(&cookie), None).await;
    assert_eq!(list[1]["seen_at_ms"], 1_795_253_460_000_i64);
    // Another therapist's patient is not found, for reading and for writing.
    let other = format!("/api/patients/{}/messages", p_bob.id);
    let (status, _, _) = call(&app, Method::GET, &other, Some(&cookie), None).await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    let body = Some(json!({"text": "hello"}));
    let (status, _, _) = call(&app, Method::POST, &other, Some(&cookie), body).await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    let (status, _, _) = call(&app, Method::GET, &uri, None, None).await;
    assert_eq!(status, StatusCode::UNAUTHORIZED);
}

async fn a_message_too_long_empty_or_with_control_characters_is_refused_naming_why(db: Db) {
    let ada = db
        .add_therapist("ada@clinic.example", PASSWORD, Role::Therapist, T0)
        .await
        .unwrap();
    let p = db.add_patient("p-ada-1", Some(&ada.id), T0).await.unwrap();
    let app = common::api::router_at_t0(&db);
    let cookie = login(&app, "ada@clinic.example").await;
    let uri = format!("/api/patients/{}/messages", p.id);
    let too_long = "a".repeat(501);
    for (body, why) in [
        (
            json!({"text": too_long}),
            "too long: 501 characters, at most 500",
        ),
        (json!({"text": "   "}), "empty"),
        (json!({"text": "line one\nline two"}), "control character"),
        (json!({"text": "bell\u{7}"}), "control character"),
        (json!({"text": 5}), "text"),
        (json!({"words": "hi"}), "words"),
    ] {
        let (status, answer, _) = call(&app, Method::POST, &uri, Some(&cookie), Some(body)).await;
        assert_eq!(status, StatusCode::BAD_REQUEST, "{answer}");
        let error = answer["error"].as_str().unwrap();
        assert!(error.contains(why), "{error:?} does not say {why:?}");
    }
    assert!(db.messages_of(&p.id).await.unwrap().is_empty());
    let refused = actions(&db)
        .await
        .iter()
        .filter(|(_, act, _)| act == "message_rejected")
        .count();
    assert_eq!(refused, 4, "each refused text is audited");
}

on_both_backends!(
    a_message_is_posted_listed_newest_first_audited_and_seen_once,
    a_message_too_long_empty_or_with_control_characters_is_refused_naming_why,
);
