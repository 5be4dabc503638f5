//! The console API: most tests call the router directly (`tower::ServiceExt::oneshot`), one
//! makes a real HTTPS round trip.

mod common;

use std::sync::Arc;
use std::time::Duration;

use axum::Router;
use axum::http::{Method, Request, StatusCode, header};
use http_body_util::BodyExt;
use hub::Patient;
use hub::db::LOCKOUT_MS;
use hub::web::{self, LiveEvent};
use netlink::{Hello, Summary};
use serde_json::{Value, json};
use tower::ServiceExt;

use common::api::{PASSWORD, actions, exchange as call, login, request};
use common::fixture::fixture;
use common::{T0, hello};

/// A valid one-exercise regimen of `kind`.
fn one_exercise(kind: &str) -> String {
    format!("[[exercise]]\nkind = \"{kind}\"\nduration_s = 30.0\n")
}

fn summary(session_id: &str, seq: u64) -> Summary {
    Summary::example(session_id, seq)
}

#[tokio::test]
async fn login_sets_a_strict_cookie_and_delays_after_failures() {
    let f = fixture().await;
    let (status, headers, body) = call(
        &f.app,
        Method::POST,
        "/api/login",
        None,
        Some(json!({"email": "ada@clinic.example", "password": PASSWORD})),
    )
    .await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(body["email"], "ada@clinic.example");
    assert!(body.get("password_hash").is_none());
    let set = headers[header::SET_COOKIE].to_str().unwrap();
    for attr in ["HttpOnly", "Secure", "SameSite=Strict", "Path=/"] {
        assert!(set.contains(attr), "{set}");
    }
    let cookie = set.split(';').next().unwrap();
    let (status, _, me) = call(&f.app, Method::GET, "/api/me", Some(cookie), None).await;
    assert_eq!(
        (status, me["id"].as_str()),
        (StatusCode::OK, Some(f.ada.id.as_str()))
    );

    let wrong = json!({"email": "ada@clinic.example", "password": "nope nope nope"});
    let unknown = json!({"email": "nobody@clinic.example", "password": PASSWORD});
    let (s1, _, b1) = call(
        &f.app,
        Method::POST,
        "/api/login",
        None,
        Some(wrong.clone()),
    )
    .await;
    let (s2, _, b2) = call(&f.app, Method::POST, "/api/login", None, Some(unknown)).await;
    assert_eq!(
        (s1, s2),
        (StatusCode::UNAUTHORIZED, StatusCode::UNAUTHORIZED)
    );
    assert_eq!(b1, b2, "an unknown email answers like a wrong password");
    for _ in 0..4 {
        call(
            &f.app,
            Method::POST,
            "/api/login",
            None,
            Some(wrong.clone()),
        )
        .await;
    }
    let right = json!({"email": "ada@clinic.example", "password": PASSWORD});
    let (locked, _, _) = call(
        &f.app,
        Method::POST,
        "/api/login",
        None,
        Some(right.clone()),
    )
    .await;
    assert_eq!(locked, StatusCode::TOO_MANY_REQUESTS);
    f.clock.advance(Duration::from_millis(LOCKOUT_MS as u64));
    let (later, _, _) = call(&f.app, Method::POST, "/api/login", None, Some(right)).await;
    assert_eq!(later, StatusCode::OK);
    let log = actions(&f.db).await;
    assert!(
        log.iter()
            .any(|(a, act, t)| a == "web" && act == "login_failed" && t == "nobody@clinic.example")
    );
    assert!(
        log.iter()
            .any(|(a, act, _)| *a == f.ada.actor() && act == "login")
    );
    let (bad, _, _) = call(
        &f.app,
        Method::POST,
        "/api/login",
        None,
        Some(json!({"email": 1})),
    )
    .await;
    assert_eq!(bad, StatusCode::BAD_REQUEST);
}

#[tokio::test]
async fn endpoints_need_a_valid_cookie_and_logout_ends_it() {
    let f = fixture().await;
    let (health, _, body) = call(&f.app, Method::GET, "/api/health", None, None).await;
    assert_eq!((health, body), (StatusCode::OK, json!({"status": "ok"})));
    let forged = format!("{}={}", web::SESSION_COOKIE, "ab".repeat(32));
    for cookie in [
        None,
        Some(forged.as_str()),
        Some("telerehab_session=../../etc"),
    ] {
        for uri in [
            "/api/me",
            "/api/patients",
            &format!("/api/patients/{}", f.p_ada.id),
        ] {
            let (status, _, body) = call(&f.app, Method::GET, uri, cookie, None).await;
            assert_eq!(status, StatusCode::UNAUTHORIZED, "{uri} {cookie:?}");
            assert!(body["error"].as_str().unwrap().contains("log in"), "{body}");
        }
    }
    let cookie = login(&f.app, "ada@clinic.example").await;
    let (ok, headers, _) = call(&f.app, Method::GET, "/api/patients", Some(&cookie), None).await;
    assert_eq!(ok, StatusCode::OK);
    assert_eq!(headers[header::CACHE_CONTROL], "no-store");
    let (out, _, _) = call(
        &f.app,
        Method::POST,
        "/api/logout",
        Some(&cookie),
        Some(json!({})),
    )
    .await;
    assert_eq!(out, StatusCode::NO_CONTENT);
    let (after, _, _) = call(&f.app, Method::GET, "/api/me", Some(&cookie), None).await;
    assert_eq!(after, StatusCode::UNAUTHORIZED);
}

#[tokio::test]
async fn a_password_change_checks_both_passwords_and_ends_the_other_logins() {
    let f = fixture().await;
    let here = login(&f.app, "ada@clinic.example").await;
    let elsewhere = login(&f.app, "ada@clinic.example").await;
    async fn change(app: &Router, cookie: &str, current: &str, new: &str) -> (StatusCode, Value) {
        let body = json!({"current": current, "new": new});
        let (status, headers, body) = call(
            app,
            Method::POST,
            "/api/me/password",
            Some(cookie),
            Some(body),
        )
        .await;
        let set = headers.get(header::SET_COOKIE).map(|v| {
            let v = v.to_str().unwrap();
            v.split(';').next().unwrap().to_owned()
        });
        (status, json!({"body": body, "cookie": set}))
    }
    let (wrong, _) = change(&f.app, &here, "not my password", "a new passphrase").await;
    assert_eq!(wrong, StatusCode::UNAUTHORIZED);
    let (short, body) = change(&f.app, &here, PASSWORD, "short").await;
    assert_eq!(short, StatusCode::BAD_REQUEST);
    assert!(
        body["body"]["error"]
            .as_str()
            .unwrap()
            .contains("at least 10"),
        "{body}"
    );
    let (same, body) = change(&f.app, &here, PASSWORD, PASSWORD).await;
    assert_eq!(same, StatusCode::BAD_REQUEST);
    assert!(
        body["body"]["error"].as_str().unwrap().contains("differ"),
        "{body}"
    );
    let (done, body) = change(&f.app, &here, PASSWORD, "a new passphrase").await;
    assert_eq!(done, StatusCode::NO_CONTENT);
    // Every login ended, this one too; the answer's new cookie replaces it. The old password
    // no longer opens the account.
    let rotated = body["cookie"]
        .as_str()
        .expect("a new session cookie")
        .to_owned();
    for (cookie, want) in [
        (&rotated, StatusCode::OK),
        (&here, StatusCode::UNAUTHORIZED),
        (&elsewhere, StatusCode::UNAUTHORIZED),
    ] {
        let (status, _, _) = call(&f.app, Method::GET, "/api/me", Some(cookie), None).await;
        assert_eq!(status, want);
    }
    for (password, want) in [
        (PASSWORD, StatusCode::UNAUTHORIZED),
        ("a new passphrase", StatusCode::OK),
    ] {
        let body = json!({"email": "ada@clinic.example", "password": password});
        let (status, _, _) = call(&f.app, Method::POST, "/api/login", None, Some(body)).await;
        assert_eq!(status, want, "{password}");
    }
    let audited: Vec<String> = actions(&f.db).await.into_iter().map(|a| a.1).collect();
    assert!(
        audited.iter().any(|a| a == "password_changed"),
        "{audited:?}"
    );
    assert!(
        audited.iter().any(|a| a == "password_change_refused"),
        "{audited:?}"
    );
}

#[tokio::test]
async fn a_therapist_sees_only_their_patients_and_others_are_404() {
    let f = fixture().await;
    f.db.add_station("st-1", &f.p_bob.id, &"ab".repeat(32), T0)
        .await
        .unwrap();
    f.db.open_session(&hello("st-1", &f.p_bob.id, "s-bob"), T0)
        .await
        .unwrap();
    let ada = login(&f.app, "ada@clinic.example").await;
    let (_, _, list) = call(&f.app, Method::GET, "/api/patients", Some(&ada), None).await;
    let ids: Vec<_> = list
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["id"].clone())
        .collect();
    assert_eq!(ids, vec![json!(f.p_ada.id)]);
    assert_eq!(list[0]["sessions_last_7_days"], 0);

    let (s_other, _, b_other) = call(
        &f.app,
        Method::GET,
        &format!("/api/patients/{}", f.p_bob.id),
        Some(&ada),
        None,
    )
    .await;
    let (s_none, _, _) = call(
        &f.app,
        Method::GET,
        "/api/patients/p-nobody",
        Some(&ada),
        None,
    )
    .await;
    assert_eq!(
        (s_other, s_none),
        (StatusCode::NOT_FOUND, StatusCode::NOT_FOUND)
    );
    assert!(b_other["error"].as_str().unwrap().contains("no patient"));
    for uri in [
        format!("/api/patients/{}/sessions", f.p_bob.id),
        format!("/api/patients/{}/regimen", f.p_bob.id),
        format!("/api/patients/{}/live", f.p_bob.id),
        "/api/sessions/s-bob".to_owned(),
        "/api/sessions/s-bob/summaries".to_owned(),
        "/api/sessions/s-bob/metrics".to_owned(),
    ] {
        let (status, _, _) = call(&f.app, Method::GET, &uri, Some(&ada), None).await;
        assert_eq!(status, StatusCode::NOT_FOUND, "{uri}");
    }
    let admin = login(&f.app, "root@clinic.example").await;
    let (_, _, all) = call(&f.app, Method::GET, "/api/patients", Some(&admin), None).await;
    assert_eq!(all.as_array().unwrap().len(), 2);
    let (status, _, detail) = call(
        &f.app,
        Method::GET,
        &format!("/api/patients/{}", f.p_bob.id),
        Some(&admin),
        None,
    )
    .await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(detail["pseudonym"], "p-bob-1");
    assert_eq!(detail["stations"][0]["station_id"], "st-1");
}

#[tokio::test]
async fn sessions_summaries_and_metrics_are_served_and_audited() {
    let f = fixture().await;
    f.db.add_station("st-1", &f.p_ada.id, &"ab".repeat(32), T0)
        .await
        .unwrap();
    f.db.open_session(&hello("st-1", &f.p_ada.id, "s1"), T0)
        .await
        .unwrap();
    for seq in 0..3 {
        f.db.store_summary(&summary("s1", seq), T0).await.unwrap();
    }
    f.db.put_metrics("s1", &[("rom_rad".to_owned(), 1.5)].into())
        .await
        .unwrap();
    let ada = login(&f.app, "ada@clinic.example").await;
    let uri = format!("/api/patients/{}/sessions", f.p_ada.id);
    let (_, _, sessions) = call(&f.app, Method::GET, &uri, Some(&ada), None).await;
    assert_eq!(sessions[0]["session_id"], "s1");
    let (_, _, one) = call(&f.app, Method::GET, "/api/sessions/s1", Some(&ada), None).await;
    assert_eq!(one["last_seq"], 2);
    let (_, _, sums) = call(
        &f.app,
        Method::GET,
        "/api/sessions/s1/summaries",
        Some(&ada),
        None,
    )
    .await;
    assert_eq!(sums.as_array().unwrap().len(), 3);
    assert_eq!(sums[2]["seq"], 2);
    let (_, _, metrics) = call(
        &f.app,
        Method::GET,
        "/api/sessions/s1/metrics",
        Some(&ada),
        None,
    )
    .await;
    assert_eq!(metrics, json!({"rom_rad": 1.5}));
    let log = actions(&f.db).await;
    for action in [
        "read_sessions",
        "read_session",
        "read_summaries",
        "read_metrics",
    ] {
        assert!(
            log.iter()
                .any(|(a, act, _)| *a == f.ada.actor() && act == action),
            "{action} not audited: {log:?}"
        );
    }
}

#[tokio::test]
async fn checkins_are_served_to_the_patients_therapist_only_audited_and_high_pain_alerts() {
    let f = fixture().await;
    f.db.add_station("st-1", &f.p_ada.id, &"ab".repeat(32), T0)
        .await
        .unwrap();
    f.db.open_session(&hello("st-1", &f.p_ada.id, "s1"), T0)
        .await
        .unwrap();
    let bye = netlink::Bye {
        session_id: "s1".into(),
        reason: "session complete".into(),
        final_seq: None,
        measures: Default::default(),
        hub_unix_ms: None,
        checkin: Some(netlink::CheckIn {
            pain_0_10: Some(8),
            tiredness_0_10: None,
            difficulty: Some("about_right".into()),
        }),
        difficulty: None,
        exercises: Vec::new(),
    };
    f.db.close_session(&bye, T0).await.unwrap();
    let ada = login(&f.app, "ada@clinic.example").await;
    let uri = format!("/api/patients/{}/checkins", f.p_ada.id);
    let (status, _, list) = call(&f.app, Method::GET, &uri, Some(&ada), None).await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(list[0]["session_id"], "s1");
    assert_eq!(list[0]["pain_0_10"], 8);
    assert!(list[0]["tiredness_0_10"].is_null());
    assert_eq!(list[0]["difficulty"], "about_right");
    let (_, _, caseload) = call(&f.app, Method::GET, "/api/patients", Some(&ada), None).await;
    let alerts = caseload[0]["alerts"].as_array().unwrap();
    assert!(
        alerts.contains(&json!("pain 8/10 after the last session")),
        "{alerts:?}"
    );
    assert!(
        actions(&f.db)
            .await
            .iter()
            .any(|(a, act, _)| *a == f.ada.actor() && act == "read_checkins")
    );
    let other = format!("/api/patients/{}/checkins", f.p_bob.id);
    let (status, _, _) = call(&f.app, Method::GET, &other, Some(&ada), None).await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    let (status, _, _) = call(&f.app, Method::GET, &uri, None, None).await;
    assert_eq!(status, StatusCode::UNAUTHORIZED);
}

#[tokio::test]
async fn exercise_results_are_served_per_session_to_the_patients_therapist_only_and_audited() {
    let f = fixture().await;
    f.db.add_station("st-1", &f.p_ada.id, &"ab".repeat(32), T0)
        .await
        .unwrap();
    f.db.open_session(&hello("st-1", &f.p_ada.id, "s1"), T0)
        .await
        .unwrap();
    let result = |index: u32, kind: &str, score: (&str, f64)| netlink::ExerciseResult {
        index,
        kind: kind.into(),
        name: format!("Exercise {index}"),
        prescribed_s: 30.0,
        active_s: 29.5,
        scores: [(score.0.to_owned(), score.1)].into(),
        assessment: None,
    };
    let bye = netlink::Bye {
        session_id: "s1".into(),
        reason: "complete".into(),
        final_seq: None,
        measures: Default::default(),
        hub_unix_ms: None,
        checkin: None,
        difficulty: None,
        exercises: vec![
            result(0, "sine-road", ("rms_lateral_m", 0.25)),
            result(1, "dial-sine", ("dial_mean_abs_error_deg", 3.5)),
        ],
    };
    f.db.close_session(&bye, T0).await.unwrap();
    let ada = login(&f.app, "ada@clinic.example").await;
    let uri = "/api/sessions/s1/exercises";
    let (status, _, list) = call(&f.app, Method::GET, uri, Some(&ada), None).await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(list.as_array().unwrap().len(), 2, "{list}");
    assert_eq!(list[0]["index"], 0);
    assert_eq!(list[0]["kind"], "sine-road");
    assert_eq!(list[0]["scores"]["rms_lateral_m"], 0.25);
    assert_eq!(list[1]["name"], "Exercise 1");
    assert_eq!(list[1]["prescribed_s"], 30.0);
    assert_eq!(list[1]["active_s"], 29.5);
    assert_eq!(list[1]["scores"]["dial_mean_abs_error_deg"], 3.5);
    assert!(
        actions(&f.db)
            .await
            .iter()
            .any(|(a, act, d)| *a == f.ada.actor() && act == "read_exercises" && d == "s1"),
        "audited"
    );
    // Another therapist's patient's session is not found; no login is refused.
    f.db.add_station("st-2", &f.p_bob.id, &"cd".repeat(32), T0)
        .await
        .unwrap();
    let bob_hello = Hello {
        station_id: "st-2".into(),
        ..hello("st-1", &f.p_bob.id, "s-bob")
    };
    f.db.open_session(&bob_hello, T0).await.unwrap();
    let (status, _, _) = call(
        &f.app,
        Method::GET,
        "/api/sessions/s-bob/exercises",
        Some(&ada),
        None,
    )
    .await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    let (status, _, _) = call(&f.app, Method::GET, uri, None, None).await;
    assert_eq!(status, StatusCode::UNAUTHORIZED);
    let (status, _, _) = call(
        &f.app,
        Method::GET,
        "/api/sessions/..%2Fx/exercises",
        Some(&ada),
        None,
    )
    .await;
    assert!(status.is_client_error(), "{status}");
}

#[tokio::test]
async fn the_regimen_schema_needs_a_login_and_carries_the_validators_bounds() {
    let f = fixture().await;
    let (status, _, _) = call(&f.app, Method::GET, "/api/regimen/schema", None, None).await;
    assert_eq!(status, StatusCode::UNAUTHORIZED);
    let ada = login(&f.app, "ada@clinic.example").await;
    let (status, _, schema) =
        call(&f.app, Method::GET, "/api/regimen/schema", Some(&ada), None).await;
    assert_eq!(status, StatusCode::OK, "{schema}");
    assert_eq!(schema, regimen::Regimen::json_schema());
    assert_eq!(
        schema["$defs"]["HapticRegimen"]["properties"]["ceiling_nm"]["maximum"],
        json!(regimen::MAX_DEVICE_TORQUE_NM)
    );
    assert_eq!(
        schema["properties"]["sessions_per_week"]["maximum"],
        json!(regimen::MAX_SESSIONS_PER_WEEK)
    );
}

#[tokio::test]
async fn a_regimen_can_be_put_as_fields_and_reads_back_as_fields() {
    let f = fixture().await;
    let ada = login(&f.app, "ada@clinic.example").await;
    let uri = format!("/api/patients/{}/regimen", f.p_ada.id);
    let fields =
        json!({"sessions_per_week": 3, "exercise": [{"kind": "sine", "duration_s": 30.5}]});
    let (status, _, body) = call(
        &f.app,
        Method::PUT,
        &uri,
        Some(&ada),
        Some(json!({ "fields": fields })),
    )
    .await;
    assert_eq!(status, StatusCode::OK, "{body}");
    let text = body["toml"].as_str().unwrap();
    assert!(
        text.contains("sessions_per_week = 3") && text.contains("[[exercise]]"),
        "{text}"
    );
    let (_, _, view) = call(&f.app, Method::GET, &uri, Some(&ada), None).await;
    assert_eq!(view["current_fields"], fields);
    for bad in [json!({}), json!({"toml": "a = 1", "fields": {"a": 1}})] {
        let (status, _, body) = call(&f.app, Method::PUT, &uri, Some(&ada), Some(bad)).await;
        assert_eq!(status, StatusCode::BAD_REQUEST, "{body}");
        assert!(
            body["error"]
                .as_str()
                .unwrap()
                .contains("not both or neither"),
            "{body}"
        );
    }
}

#[tokio::test]
async fn regimen_put_makes_version_2_and_the_validator_can_refuse() {
    let f = fixture().await;
    let ada = login(&f.app, "ada@clinic.example").await;
    let uri = format!("/api/patients/{}/regimen", f.p_ada.id);
    let (_, _, empty) = call(&f.app, Method::GET, &uri, Some(&ada), None).await;
    assert_eq!(empty["current"], Value::Null);
    for (i, text) in [one_exercise("sine"), one_exercise("slalom")]
        .iter()
        .enumerate()
    {
        let (status, _, body) = call(
            &f.app,
            Method::PUT,
            &uri,
            Some(&ada),
            Some(json!({"toml": text})),
        )
        .await;
        assert_eq!(status, StatusCode::OK, "{body}");
        assert_eq!(body["version"], i + 1);
        assert_eq!(body["prescribed_by"], json!(f.ada.id));
    }
    let (status, _, body) = call(
        &f.app,
        Method::PUT,
        &uri,
        Some(&ada),
        Some(json!({"toml": format!("{}[exercise.haptic]\nceiling_nm = 99.0\n", one_exercise("sine"))})),
    )
    .await;
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY);
    assert!(
        body["error"].as_str().unwrap().contains("ceiling"),
        "{body}"
    );
    let (_, _, view) = call(&f.app, Method::GET, &uri, Some(&ada), None).await;
    assert_eq!(view["current"]["version"], 2);
    assert_eq!(view["current"]["toml"], one_exercise("slalom"));
    assert_eq!(view["history"].as_array().unwrap().len(), 2);

    let big = json!({"toml": "x".repeat(web::MAX_BODY_BYTES + 1)});
    let (status, _, _) = call(&f.app, Method::PUT, &uri, Some(&ada), Some(big)).await;
    assert_eq!(status, StatusCode::PAYLOAD_TOO_LARGE);
    let bob_patient = format!("/api/patients/{}/regimen", f.p_bob.id);
    let (status, _, _) = call(
        &f.app,
        Method::PUT,
        &bob_patient,
        Some(&ada),
        Some(json!({"toml": "a = 1"})),
    )
    .await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    assert_eq!(f.db.latest_regimen(&f.p_bob.id).await.unwrap(), None);

    let log = actions(&f.db).await;
    let puts = log
        .iter()
        .filter(|(_, act, _)| act == "put_regimen")
        .count();
    assert_eq!(puts, 2);
    assert_eq!(
        view["current_fields"],
        json!({"exercise": [{"kind": "slalom", "duration_s": 30.0}]})
    );
    assert!(
        log.iter()
            .any(|(_, act, t)| act == "regimen_rejected" && *t == f.p_ada.id)
    );
}

#[tokio::test]
async fn path_like_ids_are_refused_with_400() {
    let f = fixture().await;
    let ada = login(&f.app, "ada@clinic.example").await;
    for uri in [
        "/api/patients/..%2F..%2Fetc",
        "/api/patients/..%2F..%2Fetc/sessions",
        "/api/sessions/..%2F..%2Fetc/summaries",
        "/api/patients/%27%3B%20DROP%20TABLE%20patients/regimen",
    ] {
        let (status, _, body) = call(&f.app, Method::GET, uri, Some(&ada), None).await;
        assert_eq!(status, StatusCode::BAD_REQUEST, "{uri}");
        assert!(body["error"].as_str().unwrap().contains("id"), "{body}");
    }
    let (status, _, _) = call(
        &f.app,
        Method::GET,
        "/api/patients/../../etc",
        Some(&ada),
        None,
    )
    .await;
    assert_eq!(status, StatusCode::NOT_FOUND);
}

#[tokio::test]
async fn the_audit_log_is_for_admins_and_records_reads() {
    let f = fixture().await;
    let ada = login(&f.app, "ada@clinic.example").await;
    call(
        &f.app,
        Method::GET,
        &format!("/api/patients/{}", f.p_ada.id),
        Some(&ada),
        None,
    )
    .await;
    let (status, _, _) = call(&f.app, Method::GET, "/api/audit", Some(&ada), None).await;
    assert_eq!(status, StatusCode::FORBIDDEN);
    let admin = login(&f.app, "root@clinic.example").await;
    let (status, _, log) = call(
        &f.app,
        Method::GET,
        "/api/audit?limit=50",
        Some(&admin),
        None,
    )
    .await;
    assert_eq!(status, StatusCode::OK);
    let entries = log["entries"].as_array().unwrap();
    assert!(entries.iter().any(|e| e["actor"] == json!(f.ada.actor())
        && e["action"] == "read_patient"
        && e["target"] == json!(f.p_ada.id)));
    assert_eq!(entries[0]["actor"], json!(f.admin.actor()));
    assert_eq!(entries[0]["action"], "read_audit");
}

/// The next whole event (up to its blank line) of a live stream's `body`, within 5 s.
async fn next_event(body: &mut axum::body::Body) -> String {
    let mut text = String::new();
    while !text.contains("\n\n") {
        let frame = tokio::time::timeout(Duration::from_secs(5), body.frame())
            .await
            .expect("an event within 5 s")
            .unwrap()
            .unwrap();
        if let Ok(data) = frame.into_data() {
            text.push_str(&String::from_utf8_lossy(&data));
        }
    }
    text
}

#[tokio::test]
async fn live_stream_says_delayed_while_a_running_session_sends_nothing() {
    let f = fixture().await;
    let ada = login(&f.app, "ada@clinic.example").await;
    let uri = format!("/api/patients/{}/live", f.p_ada.id);
    let response = f
        .app
        .clone()
        .oneshot(request(Method::GET, &uri, Some(&ada), None))
        .await
        .unwrap();
    assert_eq!(response.status(), StatusCode::OK);
    f.live
        .send(LiveEvent {
            patient_id: f.p_ada.id.clone(),
            session_id: "s-ada".into(),
            summary: summary("s-ada", 3),
        })
        .unwrap();
    let mut body = response.into_body();
    let first = next_event(&mut body).await;
    assert!(first.starts_with("event: summary\n"), "{first}");
    // A session the hub has no start of: how late is unknown, not zero.
    assert!(first.contains("\"late_ms\":null"), "{first}");
    // Nothing more for longer than the live view's delay: the stream says so at its next check.
    f.clock.advance(Duration::from_millis(
        u64::try_from(web::LIVE_DELAYED_MS).unwrap() + 500,
    ));
    let next = next_event(&mut body).await;
    assert!(next.starts_with("event: delayed\n"), "{next}");
    let data = next
        .lines()
        .find_map(|l| l.strip_prefix("data: "))
        .expect("a data line");
    let got: Value = serde_json::from_str(data).unwrap();
    assert_eq!(got["session_id"], "s-ada");
    assert!(
        got["silent_ms"].as_i64().unwrap() >= web::LIVE_DELAYED_MS,
        "{got}"
    );
}

#[tokio::test]
async fn live_stream_delivers_summaries_of_the_right_patient_only() {
    let f = fixture().await;
    let ada = login(&f.app, "ada@clinic.example").await;
    let uri = format!("/api/patients/{}/live", f.p_ada.id);
    let response = f
        .app
        .clone()
        .oneshot(request(Method::GET, &uri, Some(&ada), None))
        .await
        .unwrap();
    assert_eq!(response.status(), StatusCode::OK);
    assert_eq!(
        response.headers()[header::CONTENT_TYPE],
        "text/event-stream"
    );
    let event = |patient: &Patient, session: &str, seq| LiveEvent {
        patient_id: patient.id.clone(),
        session_id: session.to_owned(),
        summary: summary(session, seq),
    };
    f.live.send(event(&f.p_bob, "s-bob", 7)).unwrap();
    f.live.send(event(&f.p_ada, "s-ada", 3)).unwrap();
    let mut body = response.into_body();
    let mut text = String::new();
    while !text.contains("\n\n") {
        let frame = tokio::time::timeout(Duration::from_secs(5), body.frame())
            .await
            .expect("an event within 5 s")
            .unwrap()
            .unwrap();
        if let Ok(data) = frame.into_data() {
            text.push_str(&String::from_utf8_lossy(&data));
        }
    }
    assert!(text.starts_with("event: summary\n"), "{text}");
    let data = text
        .lines()
        .find_map(|l| l.strip_prefix("data: "))
        .expect("a data line");
    let got: Value = serde_json::from_str(data).unwrap();
    assert_eq!(got["patient_id"], json!(f.p_ada.id));
    assert_eq!(got["summary"]["seq"], 3);
    assert!(!text.contains("s-bob"), "{text}");
    assert!(
        actions(&f.db)
            .await
            .iter()
            .any(|(_, act, t)| act == "watch_live" && *t == f.p_ada.id)
    );
}

#[tokio::test]
async fn https_round_trip_and_plain_http_only_on_loopback() {
    use rustls::pki_types::ServerName;
    let f = fixture().await;
    let dir = tempfile::tempdir().unwrap();
    let cert = rcgen::generate_simple_self_signed(vec!["localhost".to_owned()]).unwrap();
    let (cert_path, key_path) = (dir.path().join("hub.pem"), dir.path().join("hub.key"));
    std::fs::write(&cert_path, cert.cert.pem()).unwrap();
    std::fs::write(&key_path, cert.signing_key.serialize_pem()).unwrap();
    let acceptor = web::acceptor_from_pem(&cert_path, &key_path).unwrap();

    let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
    let addr = listener.local_addr().unwrap();
    let (stop, stopped) = tokio::sync::oneshot::channel::<()>();
    let server = tokio::spawn(web::serve_router(
        listener,
        Some(acceptor),
        f.app.clone(),
        async move {
            stopped.await.ok();
        },
    ));

    let mut roots = rustls::RootCertStore::empty();
    roots.add(cert.cert.der().clone()).unwrap();
    let provider = Arc::new(rustls::crypto::ring::default_provider());
    let config = rustls::ClientConfig::builder_with_provider(provider)
        .with_safe_default_protocol_versions()
        .unwrap()
        .with_root_certificates(roots)
        .with_no_client_auth();
    let connector = tokio_rustls::TlsConnector::from(Arc::new(config));
    let tcp = tokio::net::TcpStream::connect(addr).await.unwrap();
    let tls = connector
        .connect(ServerName::try_from("localhost").unwrap(), tcp)
        .await
        .unwrap();
    let (mut sender, connection) =
        hyper::client::conn::http1::handshake(hyper_util::rt::TokioIo::new(tls))
            .await
            .unwrap();
    tokio::spawn(connection);
    let login = Request::post("/api/login")
        .header(header::HOST, "localhost")
        .header(header::CONTENT_TYPE, "application/json")
        .body(http_body_util::Full::new(bytes_of(&json!({
            "email": "ada@clinic.example", "password": PASSWORD
        }))))
        .unwrap();
    let response = sender.send_request(login).await.unwrap();
    assert_eq!(response.status(), StatusCode::OK);
    let cookie = response.headers()[header::SET_COOKIE]
        .to_str()
        .unwrap()
        .to_owned();
    let cookie = cookie.split(';').next().unwrap().to_owned();
    response.into_body().collect().await.unwrap();
    let me = Request::get("/api/me")
        .header(header::HOST, "localhost")
        .header(header::COOKIE, cookie)
        .body(http_body_util::Full::new(axum::body::Bytes::new()))
        .unwrap();
    let response = sender.send_request(me).await.unwrap();
    assert_eq!(response.status(), StatusCode::OK);
    let body = response.into_body().collect().await.unwrap().to_bytes();
    let me: Value = serde_json::from_slice(&body).unwrap();
    assert_eq!(me["email"], "ada@clinic.example");
    drop(sender);
    stop.send(()).unwrap();
    tokio::time::timeout(Duration::from_secs(10), server)
        .await
        .expect("server stops")
        .unwrap()
        .unwrap();

    let open = tokio::net::TcpListener::bind("0.0.0.0:0").await.unwrap();
    let err = web::serve_router(open, None, f.app.clone(), async {})
        .await
        .unwrap_err();
    assert!(err.to_string().contains("loopback"), "{err}");
}

fn bytes_of(value: &Value) -> axum::body::Bytes {
    axum::body::Bytes::from(value.to_string())
}

#[tokio::test]
async fn the_difficulty_history_is_served_to_the_patients_therapist_only_and_audited() {
    let f = fixture().await;
    f.db.add_station("st-1", &f.p_ada.id, &"ab".repeat(32), T0)
        .await
        .unwrap();
    f.db.open_session(&hello("st-1", &f.p_ada.id, "s1"), T0)
        .await
        .unwrap();
    let bye = netlink::Bye {
        session_id: "s1".into(),
        reason: "session complete".into(),
        final_seq: None,
        measures: Default::default(),
        hub_unix_ms: None,
        checkin: None,
        exercises: Vec::new(),
        difficulty: Some(netlink::DifficultyChange {
            difficulty: 0.45,
            change: -0.1,
            reason: "patient said too hard: \u{2212}0.10".into(),
            success_rate: Some(0.82),
            why: Some(netlink::DifficultyWhy {
                code: "felt-too-hard".into(),
                success_pct: None,
                target_pct: None,
                held_at: None,
            }),
        }),
    };
    f.db.close_session(&bye, T0).await.unwrap();
    let ada = login(&f.app, "ada@clinic.example").await;
    let uri = format!("/api/patients/{}/difficulty", f.p_ada.id);
    let (status, _, list) = call(&f.app, Method::GET, &uri, Some(&ada), None).await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(list[0]["session_id"], "s1");
    assert_eq!(list[0]["difficulty"], 0.45);
    assert_eq!(list[0]["change"], -0.1);
    assert_eq!(list[0]["success_rate"], 0.82);
    assert_eq!(list[0]["reason"], "patient said too hard: \u{2212}0.10");
    assert_eq!(list[0]["why"], json!({"code": "felt-too-hard"}));
    assert!(
        actions(&f.db)
            .await
            .iter()
            .any(|(a, act, _)| *a == f.ada.actor() && act == "read_difficulty")
    );
    let other = format!("/api/patients/{}/difficulty", f.p_bob.id);
    let (status, _, _) = call(&f.app, Method::GET, &other, Some(&ada), None).await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    let (status, _, _) = call(&f.app, Method::GET, &uri, None, None).await;
    assert_eq!(status, StatusCode::UNAUTHORIZED);
}

#[tokio::test]
async fn a_regimen_typo_is_refused_naming_its_line_and_field_and_the_prescriber_reads_as_email() {
    let f = fixture().await;
    let ada = login(&f.app, "ada@clinic.example").await;
    let uri = format!("/api/patients/{}/regimen", f.p_ada.id);
    let typo = "sessions_per_week = 3\n[[exercise]]\nkind = \"sine\"\nduration_s = 30,5\n";
    let wrong_type = "[[exercise]]\nkind = \"sine\"\nduration_s = \"half a minute\"\n";
    for (text, line, field) in [
        (typo, "Line 4", ""),
        (wrong_type, "Line 3", "\"duration_s\""),
    ] {
        let (status, _, body) = call(
            &f.app,
            Method::PUT,
            &uri,
            Some(&ada),
            Some(json!({ "toml": text })),
        )
        .await;
        assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY, "{body}");
        let error = body["error"].as_str().unwrap();
        assert!(error.contains(line) && error.contains(field), "{error}");
        assert!(
            !error.contains("TOML parse error") && !error.contains("f64"),
            "{error}"
        );
    }
    let (status, _, _) = call(
        &f.app,
        Method::PUT,
        &uri,
        Some(&ada),
        Some(json!({ "toml": one_exercise("sine") })),
    )
    .await;
    assert_eq!(status, StatusCode::OK);
    let (_, _, view) = call(&f.app, Method::GET, &uri, Some(&ada), None).await;
    assert_eq!(
        view["current_prescribed_by_email"],
        json!("ada@clinic.example")
    );
}

#[tokio::test]
async fn the_therapists_language_is_kept_checked_and_audited() {
    let f = fixture().await;
    let cookie = login(&f.app, "ada@clinic.example").await;
    let (status, _, body) =
        call(&f.app, Method::GET, "/api/me/language", Some(&cookie), None).await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(body["language"], Value::Null, "never chosen: the browser's");
    assert_eq!(body["languages"], json!(["en", "de", "es", "zh"]));

    let put = |language: Value| {
        call(
            &f.app,
            Method::PUT,
            "/api/me/language",
            Some(&cookie),
            Some(json!({ "language": language })),
        )
    };
    let (status, _, body) = put(json!("de")).await;
    assert_eq!((status, &body["language"]), (StatusCode::OK, &json!("de")));
    let (status, _, body) = put(json!("fr")).await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
    let error = body["error"].as_str().unwrap();
    assert!(
        error.contains("\"fr\"") && error.contains("en, de, es, zh"),
        "{error}"
    );
    assert_eq!(
        f.db.therapist_language(&f.ada.id).await.unwrap().as_deref(),
        Some("de"),
        "a refused choice changes nothing"
    );
    let (status, _, _) = put(json!("en-XA")).await;
    assert_eq!(
        status,
        StatusCode::OK,
        "the pseudo-locale, for layout tests"
    );
    // A new login keeps it; another therapist has their own.
    let again = login(&f.app, "ada@clinic.example").await;
    let (_, _, body) = call(&f.app, Method::GET, "/api/me/language", Some(&again), None).await;
    assert_eq!(body["language"], json!("en-XA"));
    let root = login(&f.app, "root@clinic.example").await;
    let (_, _, body) = call(&f.app, Method::GET, "/api/me/language", Some(&root), None).await;
    assert_eq!(body["language"], Value::Null);
    let (status, _, _) = put(Value::Null).await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(f.db.therapist_language(&f.ada.id).await.unwrap(), None);

    let changes: Vec<_> = actions(&f.db)
        .await
        .into_iter()
        .filter(|(_, action, _)| action == "change_language")
        .collect();
    assert_eq!(changes.len(), 3, "{changes:?}");
    assert!(
        changes
            .iter()
            .all(|(actor, _, target)| actor == &f.ada.actor() && target == &f.ada.id)
    );
    let (status, _, _) = call(&f.app, Method::GET, "/api/me/language", None, None).await;
    assert_eq!(status, StatusCode::UNAUTHORIZED);
}

#[tokio::test]
async fn the_consoles_words_are_served_per_language_and_the_pseudo_locale_is_accented() {
    let f = fixture().await;
    let get = |uri: &'static str| call(&f.app, Method::GET, uri, None, None);
    let (status, headers, de) = get("/console/l10n/de.ftl").await;
    assert_eq!(status, StatusCode::OK);
    assert!(
        headers[header::CONTENT_TYPE]
            .to_str()
            .unwrap()
            .starts_with("text/plain")
    );
    let de = de.as_str().unwrap().to_owned();
    assert!(de.contains("caseload-title = Patienten"), "{}", &de[..200]);
    let (_, _, en) = get("/console/l10n/en.ftl").await;
    let en = en.as_str().unwrap().to_owned();
    assert!(en.contains("caseload-title = Patients"));
    let (_, _, pseudo) = get("/console/l10n/en-XA.ftl").await;
    let pseudo = pseudo.as_str().unwrap().to_owned();
    assert!(
        pseudo.contains("caseload-title = Þåŧîéñŧš~~~~"),
        "accented, 40 % longer"
    );
    assert!(pseudo.contains("{ $count }"), "variables untouched");
    let (status, _, body) = get("/console/l10n/fr.ftl").await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    assert!(body.as_str().unwrap().contains("en, de, es, zh"), "{body}");
    let (status, _, _) = get("/console/l10n/de").await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    let (status, _, _) = get("/console/vendor/fluent-bundle-0.19.1/index.js").await;
    assert_eq!(status, StatusCode::OK);
}
