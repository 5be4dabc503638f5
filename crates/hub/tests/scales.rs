//! Clinical scales through the console API (`GET`/`POST /api/patients/{id}/scales`, `DELETE
//! /api/patients/{id}/scales/{scale_id}`), on SQLite and PostgreSQL.

mod common;

use common::T0;
use common::api::{PASSWORD, actions, call, login};

use axum::http::{Method, StatusCode};
use hub::{Db, Role};
use serde_json::json;

async fn three_scales_are_recorded_listed_oldest_first_deleted_and_every_change_audited(db: Db) {
    let ada = db
        .add_therapist("ada@clinic.example", PASSWORD, Role::Therapist, T0)
        .await
        .unwrap();
    db.add_therapist("bob@clinic.example", PASSWORD, Role::Therapist, T0)
        .await
        .unwrap();
    let p = db.add_patient("P-0042", Some(&ada.id), T0).await.unwrap();
    let app = common::api::router_at_t0(&db);
    let cookie = login(&app, "ada@clinic.example").await;
    let uri = format!("/api/patients/{}/scales", p.id);
    // T0 is 2026-11-21 09:30 UTC: the bounds themselves are accepted, and tomorrow (the clinic's
    // day may be ahead of UTC).
    for body in [
        json!({"scale": "fugl_meyer_ue", "assessed_on": "2026-11-10", "score": 66}),
        json!({"scale": "arat", "assessed_on": "2026-11-02", "score": 0}),
        json!({"scale": "box_and_block", "assessed_on": "2026-11-22",
               "affected_blocks_per_min": 12, "unaffected_blocks_per_min": 150}),
    ] {
        let (status, entry, _) =
            call(&app, Method::POST, &uri, Some(&cookie), Some(body.clone())).await;
        assert_eq!(status, StatusCode::CREATED, "{entry}");
        assert_eq!(entry["scale"], body["scale"]);
        assert_eq!(entry["therapist_email"], "ada@clinic.example");
    }
    let (status, list, _) = call(&app, Method::GET, &uri, Some(&cookie), None).await;
    assert_eq!(status, StatusCode::OK);
    let entries = list["entries"].as_array().unwrap();
    let days: Vec<&str> = entries
        .iter()
        .map(|e| e["assessed_on"].as_str().unwrap())
        .collect();
    assert_eq!(
        days,
        ["2026-11-02", "2026-11-10", "2026-11-22"],
        "oldest first"
    );
    assert_eq!(entries[1]["score"], 66);
    assert_eq!(entries[2]["affected_blocks_per_min"], 12);
    assert_eq!(entries[2]["unaffected_blocks_per_min"], 150);
    assert!(entries[2]["score"].is_null());
    assert_eq!(list["scales"][0]["fields"][0]["max"], 66, "{list}");
    // Deleting a mistaken entry: 204, gone, and a second delete is 404.
    let arat = entries[0]["id"].as_str().unwrap().to_owned();
    let one = format!("{uri}/{arat}");
    let (status, _, _) = call(&app, Method::DELETE, &one, Some(&cookie), Some(json!({}))).await;
    assert_eq!(status, StatusCode::NO_CONTENT);
    assert_eq!(db.scales_of(&p.id).await.unwrap().len(), 2);
    let (status, _, _) = call(&app, Method::DELETE, &one, Some(&cookie), Some(json!({}))).await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    let audit = db.audit_log(1000).await.unwrap();
    for action in ["post_scale", "read_scales", "delete_scale"] {
        assert!(
            audit
                .iter()
                .any(|e| e.actor == ada.actor() && e.action == action && e.target == p.id),
            "{action} not audited: {audit:?}"
        );
    }
    let deleted = audit.iter().find(|e| e.action == "delete_scale").unwrap();
    assert!(
        deleted.detail.contains("arat of 2026-11-02: score 0"),
        "the deletion keeps what was deleted: {:?}",
        deleted.detail
    );
    // Another therapist's patient is not found, for reading, writing and deleting.
    let bob = login(&app, "bob@clinic.example").await;
    let (status, _, _) = call(&app, Method::GET, &uri, Some(&bob), None).await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    let body = json!({"scale": "arat", "assessed_on": "2026-11-02", "score": 3});
    let (status, _, _) = call(&app, Method::POST, &uri, Some(&bob), Some(body)).await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    let fm = format!("{uri}/{}", entries[1]["id"].as_str().unwrap());
    let (status, _, _) = call(&app, Method::DELETE, &fm, Some(&bob), Some(json!({}))).await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    assert_eq!(db.scales_of(&p.id).await.unwrap().len(), 2);
}

async fn a_score_outside_its_range_or_a_wrong_date_is_refused_naming_the_field_and_range(db: Db) {
    let ada = db
        .add_therapist("ada@clinic.example", PASSWORD, Role::Therapist, T0)
        .await
        .unwrap();
    let p = db.add_patient("P-0042", Some(&ada.id), T0).await.unwrap();
    let app = common::api::router_at_t0(&db);
    let cookie = login(&app, "ada@clinic.example").await;
    let uri = format!("/api/patients/{}/scales", p.id);
    let day = "2026-11-10";
    let refused = [
        (
            json!({"scale": "fugl_meyer_ue", "assessed_on": day, "score": 67}),
            "score",
            "from 0 to 66 points",
        ),
        (
            json!({"scale": "fugl_meyer_ue", "assessed_on": day, "score": -1}),
            "score",
            "from 0 to 66 points",
        ),
        (
            json!({"scale": "fugl_meyer_ue", "assessed_on": day, "score": 30.5}),
            "score",
            "whole number",
        ),
        (
            json!({"scale": "arat", "assessed_on": day, "score": 58}),
            "score",
            "from 0 to 57 points",
        ),
        (
            json!({"scale": "arat", "assessed_on": day}),
            "score",
            "missing",
        ),
        (
            json!({"scale": "box_and_block", "assessed_on": day, "affected_blocks_per_min": 151,
                "unaffected_blocks_per_min": 40}),
            "affected_blocks_per_min",
            "from 0 to 150 blocks per minute",
        ),
        (
            json!({"scale": "box_and_block", "assessed_on": day, "affected_blocks_per_min": 20}),
            "unaffected_blocks_per_min",
            "missing",
        ),
        (
            json!({"scale": "box_and_block", "assessed_on": day, "score": 20,
                "affected_blocks_per_min": 20, "unaffected_blocks_per_min": 40}),
            "score",
            "not a number of the Box and Block Test",
        ),
        (
            json!({"scale": "barthel", "assessed_on": day, "score": 20}),
            "scale",
            "fugl_meyer_ue, arat, box_and_block",
        ),
        (
            json!({"scale": "arat", "assessed_on": "2026-02-30", "score": 20}),
            "assessed_on",
            "YYYY-MM-DD",
        ),
        (
            json!({"scale": "arat", "assessed_on": "2026-11-23", "score": 20}),
            "assessed_on",
            "in the future",
        ),
        (
            json!({"scale": "arat", "assessed_on": "1989-12-31", "score": 20}),
            "assessed_on",
            "before 1990-01-01",
        ),
    ];
    let tried = refused.len();
    for (body, field, why) in refused {
        let (status, answer, _) = call(&app, Method::POST, &uri, Some(&cookie), Some(body)).await;
        assert_eq!(status, StatusCode::BAD_REQUEST, "{answer}");
        let error = answer["error"].as_str().unwrap();
        assert!(
            error.starts_with(&format!("invalid {field}:")) && error.contains(why),
            "{error:?} does not name {field} and say {why:?}"
        );
    }
    // Not JSON of the right shape: refused by the extractor, naming the unknown field.
    let body = json!({"scale": "arat", "assessed_on": day, "scor": 3});
    let (status, answer, _) = call(&app, Method::POST, &uri, Some(&cookie), Some(body)).await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
    assert!(
        answer["error"].as_str().unwrap().contains("scor"),
        "{answer}"
    );
    assert!(db.scales_of(&p.id).await.unwrap().is_empty());
    let rejected = actions(&db)
        .await
        .iter()
        .filter(|(_, act, _)| act == "scale_rejected")
        .count();
    assert_eq!(rejected, tried, "each refused score is audited");
}

on_both_backends!(
    three_scales_are_recorded_listed_oldest_first_deleted_and_every_change_audited,
    a_score_outside_its_range_or_a_wrong_date_is_refused_naming_the_field_and_range,
);
