//! Issue 41 at the hub, on SQLite and PostgreSQL: the prescribe form's presets
//! (`GET /api/regimen/presets`, defined in the regimen crate) each accepted as a prescription,
//! and the audit page's filters (`GET /api/audit?actor=…&action=…&target=…`), admins only.

mod common;

use common::T0;

use common::api::{call, clinician, login, router_at_t0};

use axum::http::{Method, StatusCode};
use hub::{Db, Role};
use serde_json::{Value, json};

async fn every_preset_is_served_and_prescribed_in_sets_with_minutes_and_rests(db: Db) {
    let ada = clinician(&db, "ada@clinic.example", Role::Therapist).await;
    let p = db.add_patient("P-0042", Some(&ada.id), T0).await.unwrap();
    let app = router_at_t0(&db);
    let (status, _, _) = call(&app, Method::GET, "/api/regimen/presets", None, None).await;
    assert_eq!(status, StatusCode::UNAUTHORIZED);
    let cookie = login(&app, "ada@clinic.example").await;
    let (status, presets, _) = call(
        &app,
        Method::GET,
        "/api/regimen/presets",
        Some(&cookie),
        None,
    )
    .await;
    assert_eq!(status, StatusCode::OK, "{presets}");
    let presets = presets.as_array().unwrap().clone();
    assert_eq!(presets.len(), 33, "easy, medium and hard of 11 kinds");
    let uri = format!("/api/patients/{}/regimen", p.id);
    for preset in &presets {
        // As the form sends it: the preset's fields, minutes as duration_s, two sets with a
        // rest after each.
        let mut entry = preset["fields"].clone();
        let kind = entry["kind"].as_str().unwrap().to_owned();
        if !["strength", "haptic-sweep"].contains(&kind.as_str()) {
            entry["duration_s"] = json!(150.0);
        }
        entry["rest_s"] = json!(45.0);
        let fields = json!({"exercise": [entry.clone(), entry]});
        let (status, answer, _) = call(
            &app,
            Method::PUT,
            &uri,
            Some(&cookie),
            Some(json!({ "fields": fields })),
        )
        .await;
        assert_eq!(
            status,
            StatusCode::OK,
            "{kind} {}: {answer}",
            preset["level"]
        );
        let (_, view, _) = call(&app, Method::GET, &uri, Some(&cookie), None).await;
        assert_eq!(view["current_fields"], fields, "read back as sent");
    }
}

/// Entries of a page of the audit log as (actor, action, target).
fn triples(page: &Value) -> Vec<(String, String, String)> {
    page["entries"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| {
            let s = |k: &str| e[k].as_str().unwrap().to_owned();
            (s("actor"), s("action"), s("target"))
        })
        .collect()
}

async fn the_audit_log_filters_by_therapist_action_and_patient_and_pages_for_admins_only(db: Db) {
    let admin = clinician(&db, "root@clinic.example", Role::Admin).await;
    let ada = clinician(&db, "ada@clinic.example", Role::Therapist).await;
    let p1 = db.add_patient("P-0001", Some(&ada.id), T0).await.unwrap();
    let p2 = db.add_patient("P-0002", Some(&ada.id), T0).await.unwrap();
    for (i, target) in [&p1.id, &p2.id, &p1.id, &p1.id].into_iter().enumerate() {
        db.audit(&ada.actor(), "read_patient", target, "", T0 + i as i64)
            .await
            .unwrap();
    }
    db.audit(&admin.actor(), "put_regimen", &p1.id, "version 1", T0 + 10)
        .await
        .unwrap();
    let app = router_at_t0(&db);
    let ada_cookie = login(&app, "ada@clinic.example").await;
    let uri = format!("/api/audit?target={}", p1.id);
    let (status, _, _) = call(&app, Method::GET, &uri, Some(&ada_cookie), None).await;
    assert_eq!(status, StatusCode::FORBIDDEN, "the audit log is for admins");
    let cookie = login(&app, "root@clinic.example").await;
    let get = |uri: String| {
        let app = app.clone();
        let cookie = cookie.clone();
        async move {
            let (status, page, _) = call(&app, Method::GET, &uri, Some(&cookie), None).await;
            assert_eq!(status, StatusCode::OK, "{page}");
            page
        }
    };
    // By patient: only entries about P-0001, newest first.
    let page = get(format!("/api/audit?target={}", p1.id)).await;
    let got = triples(&page);
    assert_eq!(got.len(), 4, "{got:?}");
    assert!(got.iter().all(|(_, _, t)| *t == p1.id), "{got:?}");
    assert_eq!(got[0].1, "put_regimen");
    // By therapist and kind together.
    let page = get(format!(
        "/api/audit?actor={}&action=read_patient",
        ada.actor()
    ))
    .await;
    assert_eq!(triples(&page).len(), 4);
    // Paged within the filter: two, then the other two, then nothing more.
    let page = get(format!(
        "/api/audit?actor={}&action=read_patient&limit=2",
        ada.actor()
    ))
    .await;
    let first = triples(&page);
    let next = &page["next"];
    assert_eq!(first.len(), 2);
    let page = get(format!(
        "/api/audit?actor={}&action=read_patient&limit=2&before_ms={}&before_id={}",
        ada.actor(),
        next["before_ms"],
        next["before_id"].as_str().unwrap()
    ))
    .await;
    assert_eq!(triples(&page).len(), 2);
    assert!(page["next"].is_null(), "{page}");
    // An empty filter is no filter.
    let page = get("/api/audit?actor=&action=&target=&limit=1000".to_owned()).await;
    assert!(triples(&page).len() >= 5);
}

on_both_backends!(
    every_preset_is_served_and_prescribed_in_sets_with_minutes_and_rests,
    the_audit_log_filters_by_therapist_action_and_patient_and_pages_for_admins_only,
);
