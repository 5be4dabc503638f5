//! A patient's record as a FHIR R4 Bundle (`GET /api/patients/{id}/fhir`), on SQLite and
//! PostgreSQL. tests/python/test_fhir_export.py validates the same export with an independent
//! FHIR implementation (the Python `fhir.resources` models).

mod common;

use common::api::{PASSWORD, actions, call, login};
use common::{T0, hello};

use std::collections::BTreeMap;
use std::sync::Arc;

use axum::http::{Method, StatusCode};
use hub::db::NewScale;
use hub::web::{self, AppState};
use hub::{Db, Role};
use serde_json::Value;
use tokio::sync::broadcast;

const REGIMEN: &str = "sessions_per_week = 5\n\n[[exercise]]\nkind = \"sine\"\namplitude_m = 2.0\n\
    wavelength_m = 150.0\nperiods = 2\nlane_width_m = 4.0\nspeed_m_s = 8.0\nduration_s = 30.0\n";

fn of_type<'a>(bundle: &'a Value, kind: &str) -> Vec<&'a Value> {
    bundle["entry"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| &e["resource"])
        .filter(|r| r["resourceType"] == kind)
        .collect()
}

async fn a_patients_fhir_bundle_holds_a_pseudonymous_patient_the_regimen_sessions_and_scales(
    db: Db,
) {
    let ada = db
        .add_therapist("ada@clinic.example", PASSWORD, Role::Therapist, T0)
        .await
        .unwrap();
    db.add_therapist("bob@clinic.example", PASSWORD, Role::Therapist, T0)
        .await
        .unwrap();
    let p = db.add_patient("P-0042", Some(&ada.id), T0).await.unwrap();
    db.add_station("st-1", &p.id, &"a".repeat(64), T0)
        .await
        .unwrap();
    for i in 0..3_i64 {
        let id = format!("s-{i}");
        let mut h = hello("st-1", &p.id, &id);
        h.started_unix_ms = (T0 + i * 86_400_000) as u64;
        db.open_session(&h, T0).await.unwrap();
        let measures = BTreeMap::from([
            ("sparc_median".to_owned(), -1.6 + 0.1 * i as f64),
            ("active_s".to_owned(), 25.0),
            ("movements_per_min".to_owned(), 12.5),
        ]);
        db.put_metrics(&id, &measures).await.unwrap();
    }
    db.put_regimen(&p.id, REGIMEN, Some(5), &ada.id, T0)
        .await
        .unwrap();
    let fm = NewScale {
        scale: "fugl_meyer_ue".into(),
        assessed_on: "2026-11-20".into(),
        score: Some(34.0),
        ..NewScale::default()
    };
    db.add_scale(&p.id, &ada.id, &fm, T0).await.unwrap();
    let (live, _) = broadcast::channel(4);
    let app = web::router(AppState::new(db.clone(), live).with_clock(Arc::new(|| T0)));
    let cookie = login(&app, "ada@clinic.example").await;
    let uri = format!("/api/patients/{}/fhir", p.id);
    let (status, bundle, _) = call(&app, Method::GET, &uri, Some(&cookie), None).await;
    assert_eq!(status, StatusCode::OK, "{bundle}");
    assert_eq!(bundle["resourceType"], "Bundle");
    assert_eq!(bundle["type"], "collection");
    // The patient by pseudonym only.
    let patient = of_type(&bundle, "Patient");
    assert_eq!(patient.len(), 1);
    assert_eq!(patient[0]["identifier"][0]["value"], "P-0042");
    for private in ["name", "birthDate", "telecom", "address"] {
        assert!(patient[0].get(private).is_none(), "{private} exported");
    }
    let text = bundle.to_string();
    assert!(
        !text.contains(&p.id),
        "the hub's own patient id stays in the hub"
    );
    // The regimen: a CarePlan whose activity is the SNOMED CT exercise therapy request.
    let request = of_type(&bundle, "ServiceRequest");
    assert_eq!(request[0]["code"]["coding"][0]["code"], "229065009");
    assert_eq!(request[0]["occurrenceTiming"]["repeat"]["frequency"], 5);
    let plan = of_type(&bundle, "CarePlan");
    let subject = format!("urn:uuid:{}", patient[0]["id"].as_str().unwrap());
    assert_eq!(plan[0]["subject"]["reference"], subject.as_str());
    // A session's measures as components with UCUM units; the scale with its day.
    let observations = of_type(&bundle, "Observation");
    assert_eq!(observations.len(), 4, "three sessions and one scale");
    let first = observations[0];
    assert_eq!(first["effectivePeriod"]["start"], "2026-11-21T09:30:00Z");
    let rate = first["component"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["code"]["coding"][0]["code"] == "movements_per_min")
        .unwrap();
    assert_eq!(rate["valueQuantity"]["code"], "/min");
    assert_eq!(rate["valueQuantity"]["value"], 12.5);
    let scale = observations[3];
    assert_eq!(scale["code"]["coding"][0]["code"], "fugl_meyer_ue");
    assert_eq!(scale["effectiveDateTime"], "2026-11-20");
    assert_eq!(scale["valueQuantity"]["value"], 34);
    // Every code used is defined, with a definition and a unit, in the bundle's CodeSystem.
    let systems = of_type(&bundle, "CodeSystem");
    let measures = systems
        .iter()
        .find(|s| s["url"] == hub::fhir::MEASURES_SYSTEM)
        .unwrap();
    for name in ["sparc_median", "active_s", "movements_per_min"] {
        let concept = measures["concept"]
            .as_array()
            .unwrap()
            .iter()
            .find(|c| c["code"] == name)
            .unwrap_or_else(|| panic!("{name} is not in the code system"));
        assert!(concept["definition"].as_str().unwrap().len() > 10);
        assert!(concept["property"][0]["valueCode"].is_string());
    }
    // Audited; another therapist's patient is not found.
    let audit = actions(&db).await;
    assert!(
        audit
            .iter()
            .any(|(a, act, t)| *a == ada.actor() && act == "export_fhir" && *t == p.id)
    );
    let bob = login(&app, "bob@clinic.example").await;
    let (status, _, _) = call(&app, Method::GET, &uri, Some(&bob), None).await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    // The command line's export (`hub export --fhir P-0042`) is the same bundle, audited.
    let (text, sessions) = hub::patients::export_fhir(&db, "P-0042", T0).await.unwrap();
    assert_eq!(sessions, 3);
    assert_eq!(serde_json::from_str::<Value>(&text).unwrap(), bundle);
    let audit = actions(&db).await;
    assert!(
        audit
            .iter()
            .any(|(a, act, _)| a == "cli" && act == "export_fhir")
    );
    let unknown = hub::patients::export_fhir(&db, "P-9999", T0)
        .await
        .unwrap_err();
    assert!(unknown.to_string().contains("P-9999"), "{unknown}");
}

on_both_backends!(
    a_patients_fhir_bundle_holds_a_pseudonymous_patient_the_regimen_sessions_and_scales
);
