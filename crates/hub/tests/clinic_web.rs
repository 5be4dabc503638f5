//! The clinic from the browser: adding patients (with a pairing code), pairing codes, adding
//! therapists (one-time password) and revoking stations through the console API, with who may
//! do what and the audit of each change. The router is called directly.

mod common;

use axum::http::{Method, StatusCode};
use hub::Db;
use serde_json::json;

use common::T0;
use common::api::{PASSWORD, call, login_with as login};
use common::fixture::{Fixture, fixture};

const PAIRING_TTL_MS: i64 = 72 * 3600 * 1000;

async fn audited(db: &Db, action: &str) -> Vec<(String, String, String)> {
    db.audit_log(1000)
        .await
        .unwrap()
        .into_iter()
        .filter(|e| e.action == action)
        .map(|e| (e.actor, e.target, e.detail))
        .collect()
}

#[tokio::test]
async fn a_therapist_adds_a_patient_into_their_own_care_with_a_72_hour_pairing_code() {
    adds_a_patient_with_a_code(&fixture().await).await;
}

async fn adds_a_patient_with_a_code(f: &Fixture) {
    let ada = login(&f.app, "ada@clinic.example", PASSWORD).await;
    let body = json!({"pseudonym": "P-0042"});
    let (status, added, _) = call(
        &f.app,
        Method::POST,
        "/api/patients",
        Some(&ada),
        Some(body),
    )
    .await;
    assert_eq!(status, StatusCode::CREATED, "{added}");
    assert_eq!(added["patient"]["pseudonym"], "P-0042");
    assert_eq!(added["patient"]["therapist_id"], f.ada.id.as_str());
    let code = added["pairing"]["code"].as_str().unwrap();
    assert_eq!((code.len(), &code[4..5]), (9, "-"), "{code}");
    assert_eq!(added["pairing"]["expires_at_ms"], T0 + PAIRING_TTL_MS);
    // The code pairs a station for this patient.
    let id = added["patient"]["id"].as_str().unwrap();
    let ticket = f.db.pairing_ticket(&code[..4], T0 + 1).await.unwrap();
    assert_eq!(ticket.patient_id, id);
    // It is in Ada's caseload now, and both changes are audited as hers.
    let (_, list, _) = call(&f.app, Method::GET, "/api/patients", Some(&ada), None).await;
    assert!(list.as_array().unwrap().iter().any(|p| p["id"] == id));
    let actor = f.ada.actor();
    assert_eq!(
        audited(&f.db, "add_patient").await,
        [(actor.clone(), id.to_owned(), "P-0042".to_owned())]
    );
    assert_eq!(
        audited(&f.db, "pairing_code").await,
        [(actor, id.to_owned(), String::new())]
    );
}

#[tokio::test]
async fn a_therapist_cannot_add_a_patient_for_another_and_a_taken_pseudonym_is_a_409() {
    let f = fixture().await;
    let ada = login(&f.app, "ada@clinic.example", PASSWORD).await;
    let for_bob = json!({"pseudonym": "P-0043", "therapist_email": "bob@clinic.example"});
    let (status, body, _) = call(
        &f.app,
        Method::POST,
        "/api/patients",
        Some(&ada),
        Some(for_bob),
    )
    .await;
    assert_eq!(status, StatusCode::FORBIDDEN, "{body}");
    let taken = json!({"pseudonym": "p-bob-1"});
    let (status, body, _) = call(
        &f.app,
        Method::POST,
        "/api/patients",
        Some(&ada),
        Some(taken),
    )
    .await;
    assert_eq!(status, StatusCode::CONFLICT, "{body}");
    assert!(
        body["error"].as_str().unwrap().contains("p-bob-1"),
        "{body}"
    );
    let a_name = json!({"pseudonym": "Jane Doe"});
    let (status, body, _) = call(
        &f.app,
        Method::POST,
        "/api/patients",
        Some(&ada),
        Some(a_name),
    )
    .await;
    assert_eq!(status, StatusCode::BAD_REQUEST, "{body}");
    assert!(
        body["error"].as_str().unwrap().contains("pseudonym"),
        "{body}"
    );
    assert!(f.db.patient_by_pseudonym("P-0043").await.unwrap().is_none());
}

#[tokio::test]
async fn an_admin_assigns_a_new_patient_to_a_therapist_by_email_or_to_nobody() {
    let f = fixture().await;
    let root = login(&f.app, "root@clinic.example", PASSWORD).await;
    let for_bob = json!({"pseudonym": "P-0050", "therapist_email": "BOB@clinic.example"});
    let (status, added, _) = call(
        &f.app,
        Method::POST,
        "/api/patients",
        Some(&root),
        Some(for_bob),
    )
    .await;
    assert_eq!(status, StatusCode::CREATED, "{added}");
    assert_eq!(added["patient"]["therapist_id"], f.bob.id.as_str());
    let nobody = json!({"pseudonym": "P-0051"});
    let (status, added, _) = call(
        &f.app,
        Method::POST,
        "/api/patients",
        Some(&root),
        Some(nobody),
    )
    .await;
    assert_eq!(status, StatusCode::CREATED, "{added}");
    assert!(added["patient"]["therapist_id"].is_null());
    let unknown = json!({"pseudonym": "P-0052", "therapist_email": "eve@clinic.example"});
    let (status, body, _) = call(
        &f.app,
        Method::POST,
        "/api/patients",
        Some(&root),
        Some(unknown),
    )
    .await;
    assert_eq!(status, StatusCode::BAD_REQUEST, "{body}");
    assert!(body["error"].as_str().unwrap().contains("therapist_email"));
}

#[tokio::test]
async fn a_new_pairing_code_is_for_the_patients_therapist_or_an_admin_only() {
    let f = fixture().await;
    let uri = format!("/api/patients/{}/pairing-code", f.p_bob.id);
    let ada = login(&f.app, "ada@clinic.example", PASSWORD).await;
    let (status, _, _) = call(&f.app, Method::POST, &uri, Some(&ada), Some(json!({}))).await;
    assert_eq!(status, StatusCode::NOT_FOUND, "someone else's patient");
    let (status, _, _) = call(&f.app, Method::POST, &uri, Some(&ada), None).await;
    assert_eq!(
        status,
        StatusCode::UNSUPPORTED_MEDIA_TYPE,
        "a change is JSON"
    );
    let bob = login(&f.app, "bob@clinic.example", PASSWORD).await;
    let (status, code, _) = call(&f.app, Method::POST, &uri, Some(&bob), Some(json!({}))).await;
    assert_eq!(status, StatusCode::OK, "{code}");
    let code = code["code"].as_str().unwrap();
    let ticket = f.db.pairing_ticket(&code[..4], T0).await.unwrap();
    assert_eq!(ticket.patient_id, f.p_bob.id);
}

#[tokio::test]
async fn an_admin_adds_a_therapist_whose_one_time_password_must_be_changed_first() {
    adds_a_therapist(&fixture().await).await;
}

async fn adds_a_therapist(f: &Fixture) {
    let ada = login(&f.app, "ada@clinic.example", PASSWORD).await;
    let new = json!({"email": "cy@clinic.example"});
    let (status, _, _) = call(
        &f.app,
        Method::POST,
        "/api/therapists",
        Some(&ada),
        Some(new.clone()),
    )
    .await;
    assert_eq!(
        status,
        StatusCode::FORBIDDEN,
        "a therapist adds no therapist"
    );
    let (status, _, _) = call(&f.app, Method::GET, "/api/therapists", Some(&ada), None).await;
    assert_eq!(status, StatusCode::FORBIDDEN);
    let root = login(&f.app, "root@clinic.example", PASSWORD).await;
    let (status, added, _) = call(
        &f.app,
        Method::POST,
        "/api/therapists",
        Some(&root),
        Some(new.clone()),
    )
    .await;
    assert_eq!(status, StatusCode::CREATED, "{added}");
    assert_eq!(added["therapist"]["role"], "therapist");
    assert_eq!(added["therapist"]["must_change_password"], true);
    let password = added["one_time_password"].as_str().unwrap();
    assert_eq!(password.len(), 20);
    let (status, _, _) = call(
        &f.app,
        Method::POST,
        "/api/therapists",
        Some(&root),
        Some(new),
    )
    .await;
    assert_eq!(status, StatusCode::CONFLICT, "the e-mail is taken");
    // The new therapist's first login may do nothing but change the password.
    let cy = login(&f.app, "cy@clinic.example", password).await;
    let (status, _, _) = call(&f.app, Method::GET, "/api/patients", Some(&cy), None).await;
    assert_eq!(status, StatusCode::FORBIDDEN);
    let change = json!({"current": password, "new": "a passphrase of my own"});
    let (status, _, _) = call(
        &f.app,
        Method::POST,
        "/api/me/password",
        Some(&cy),
        Some(change),
    )
    .await;
    assert_eq!(status, StatusCode::NO_CONTENT);
    let cy = login(&f.app, "cy@clinic.example", "a passphrase of my own").await;
    let (status, _, _) = call(&f.app, Method::GET, "/api/patients", Some(&cy), None).await;
    assert_eq!(status, StatusCode::OK);
    let (_, list, _) = call(&f.app, Method::GET, "/api/therapists", Some(&root), None).await;
    let emails: Vec<_> = list
        .as_array()
        .unwrap()
        .iter()
        .map(|t| t["email"].clone())
        .collect();
    assert_eq!(emails.len(), 4, "{list}");
    let id = added["therapist"]["id"].as_str().unwrap();
    let who = audited(&f.db, "add_therapist").await;
    assert_eq!(who.len(), 1);
    assert_eq!(who[0].1, format!("therapist:{id}"));
    assert_eq!(who[0].2, "therapist");
}

#[tokio::test]
async fn a_station_is_revoked_by_its_patients_therapist_or_an_admin_not_by_another() {
    revokes_a_station(&fixture().await).await;
}

async fn revokes_a_station(f: &Fixture) {
    f.db.add_station("st-bob-1", &f.p_bob.id, &"ab".repeat(32), T0)
        .await
        .unwrap();
    let ada = login(&f.app, "ada@clinic.example", PASSWORD).await;
    let uri = "/api/stations/st-bob-1/revoke";
    let (status, _, _) = call(&f.app, Method::POST, uri, Some(&ada), Some(json!({}))).await;
    assert_eq!(
        status,
        StatusCode::NOT_FOUND,
        "someone else's patient's station"
    );
    let (status, _, _) = call(
        &f.app,
        Method::POST,
        "/api/stations/st-none/revoke",
        Some(&ada),
        Some(json!({})),
    )
    .await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    assert!(
        !f.db
            .station("st-bob-1")
            .await
            .unwrap()
            .unwrap()
            .is_revoked()
    );
    let bob = login(&f.app, "bob@clinic.example", PASSWORD).await;
    let (status, _, _) = call(&f.app, Method::POST, uri, Some(&bob), None).await;
    assert_eq!(
        status,
        StatusCode::UNSUPPORTED_MEDIA_TYPE,
        "no form can revoke"
    );
    assert!(
        !f.db
            .station("st-bob-1")
            .await
            .unwrap()
            .unwrap()
            .is_revoked()
    );
    let (status, station, _) = call(&f.app, Method::POST, uri, Some(&bob), Some(json!({}))).await;
    assert_eq!(status, StatusCode::OK, "{station}");
    assert_eq!(station["revoked_at_ms"], T0);
    assert!(
        f.db.station("st-bob-1")
            .await
            .unwrap()
            .unwrap()
            .is_revoked()
    );
    assert_eq!(
        audited(&f.db, "revoke_station").await,
        [(f.bob.actor(), "st-bob-1".to_owned(), f.p_bob.id.clone())]
    );
    // An admin may revoke any station (again: the first revocation time stays).
    let root = login(&f.app, "root@clinic.example", PASSWORD).await;
    let (status, station, _) = call(&f.app, Method::POST, uri, Some(&root), Some(json!({}))).await;
    assert_eq!(
        (status, &station["revoked_at_ms"]),
        (StatusCode::OK, &json!(T0))
    );
}

#[tokio::test]
async fn the_clinic_endpoints_behave_the_same_on_postgresql() {
    let Some(pg) = common::PgDb::create().await else {
        return;
    };
    let f = Fixture::on(pg.db.clone(), None, |s| s).await;
    adds_a_patient_with_a_code(&f).await;
    adds_a_therapist(&f).await;
    revokes_a_station(&f).await;
    drop(f);
    pg.drop_db().await;
}
