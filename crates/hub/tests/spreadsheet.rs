//! The per-session measures as CSV (`GET /api/patients/{id}/measures.csv`, `GET
//! /api/measures.csv` for an admin), on SQLite and PostgreSQL.

mod common;

use common::api::{PASSWORD, actions, login};
use common::{T0, hello};

use std::collections::BTreeMap;
use std::sync::Arc;

use axum::Router;
use axum::body::Body;
use axum::http::{HeaderMap, Method, Request, StatusCode, header};
use http_body_util::BodyExt;
use hub::web::{self, AppState};
use hub::{Db, Role};
use tokio::sync::broadcast;
use tower::ServiceExt;

fn app_of(db: &Db) -> Router {
    let (live, _) = broadcast::channel(4);
    web::router(AppState::new(db.clone(), live).with_clock(Arc::new(|| T0)))
}

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

async fn a_patients_measures_download_as_csv_with_units_in_the_headers_and_exact_values(db: Db) {
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
        &db,
        "P-0042",
        &ada.id,
        &[
            &[("sparc_median", sparc), ("active_s", 25.5)],
            &[("sparc_median", -1.5), ("tracking_rms_error_deg", 0.1)],
        ],
    )
    .await;
    patient_with_sessions(&db, "P-0007", &ana.id, &[&[("pct_in_lane", 97.25)]]).await;
    let app = app_of(&db);
    let cookie = login(&app, "ada@clinic.example").await;
    let (status, headers, csv) =
        get(&app, &format!("/api/patients/{p}/measures.csv"), &cookie).await;
    assert_eq!(status, StatusCode::OK, "{csv}");
    assert_eq!(headers[header::CONTENT_TYPE], "text/csv; charset=utf-8");
    assert_eq!(
        headers[header::CONTENT_DISPOSITION],
        "attachment; filename=\"measures-P-0042-2026-11-21.csv\""
    );
    let lines: Vec<&str> = csv.split("\r\n").collect();
    assert_eq!(
        lines[0],
        "session_id,started_at_utc,exercise,ran_as_prescribed,active_s,sparc_median,tracking_rms_error_deg"
    );
    assert_eq!(
        lines.len(),
        4,
        "a header, two sessions and the last line's end: {csv:?}"
    );
    let first: Vec<&str> = lines[1].split(',').collect();
    assert_eq!(
        first[..4],
        ["s-P-0042-0", "2026-11-21T09:30:00Z", "Sine road", "false"]
    );
    assert_eq!(first[4].parse::<f64>().unwrap(), 25.5);
    assert_eq!(first[5].parse::<f64>().unwrap(), sparc, "read back exactly");
    assert_eq!(first[6], "", "a measure the session lacks is an empty cell");
    assert!(lines[2].starts_with("s-P-0042-1,2026-11-21T09:31:00Z,"));
    // Another therapist's patient is not found; the caseload is for admins.
    let (status, _, _) = get(&app, "/api/measures.csv", &cookie).await;
    assert_eq!(status, StatusCode::FORBIDDEN);
    let admin = login(&app, "ana@clinic.example").await;
    let (status, headers, csv) = get(&app, "/api/measures.csv", &admin).await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(
        headers[header::CONTENT_DISPOSITION],
        "attachment; filename=\"measures-caseload-2026-11-21.csv\""
    );
    let lines: Vec<&str> = csv.split("\r\n").collect();
    assert!(lines[0].starts_with("patient,session_id,"), "{}", lines[0]);
    assert!(lines[0].contains(",pct_in_lane,"), "{}", lines[0]);
    let patients: Vec<&str> = lines[1..4]
        .iter()
        .map(|l| l.split(',').next().unwrap())
        .collect();
    assert_eq!(patients, ["P-0007", "P-0042", "P-0042"], "by pseudonym");
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

on_both_backends!(a_patients_measures_download_as_csv_with_units_in_the_headers_and_exact_values);
