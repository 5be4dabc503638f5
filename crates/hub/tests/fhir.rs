//! A patient's record as a FHIR R4 Bundle (`GET /api/patients/{id}/fhir`), on SQLite and
//! PostgreSQL. tests/python/test_fhir_export.py validates the same export with an independent
//! FHIR implementation (the Python `fhir.resources` models).

mod common;

use common::api::{PASSWORD, actions, call, login};
use common::{T0, hello};

use std::collections::BTreeMap;

use axum::http::{Method, StatusCode};
use hub::db::NewScale;
use hub::fhir::FhirBase;
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

/// The sessions (performer, device, rounding, exercise duration), the scale (its therapist)
/// and the check-in of the bundle.
fn sessions_scales_and_checkin(bundle: &Value, subject: &str, therapist_id: &str) {
    // A session's measures as components with UCUM units, rounded to their resolution,
    // performed by the patient on the station; the scale with its day, by its therapist.
    let observations = of_type(bundle, "Observation");
    let coded = |code: &str| -> Vec<&Value> {
        observations
            .iter()
            .copied()
            .filter(|o| o["code"]["coding"][0]["code"] == code)
            .collect()
    };
    assert_eq!(
        observations.len(),
        7,
        "three sessions, their durations, one scale"
    );
    let first = coded("session")[0];
    assert_eq!(first["effectivePeriod"]["start"], "2026-11-21T09:30:00Z");
    assert_eq!(first["performer"][0]["reference"], subject);
    let device = of_type(bundle, "Device");
    assert_eq!(device.len(), 1, "one station");
    assert_eq!(device[0]["identifier"][0]["value"], "st-1");
    assert_eq!(
        first["device"]["reference"],
        format!("urn:uuid:{}", device[0]["id"].as_str().unwrap()).as_str()
    );
    let third = coded("session")[2];
    let sparc = third["component"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["code"]["coding"][0]["code"] == "sparc_median")
        .unwrap();
    // -1.6 + 0.2 is -1.4000000000000001 in binary: exported at the measure's resolution.
    assert_eq!(sparc["valueQuantity"]["value"].to_string(), "-1.4");
    // The exercise time as the Physical Activity IG's LOINC 55411-3, in minutes.
    let durations = coded("55411-3");
    assert_eq!(durations.len(), 3);
    assert_eq!(
        durations[0]["code"]["coding"][0]["system"],
        "http://loinc.org"
    );
    assert_eq!(durations[0]["valueQuantity"]["value"].to_string(), "0.42");
    assert_eq!(durations[0]["valueQuantity"]["code"], "min");
    let scale = coded("fugl_meyer_ue")[0];
    let therapist = of_type(bundle, "Practitioner");
    assert_eq!(therapist[0]["identifier"][0]["value"], therapist_id);
    assert_eq!(
        scale["performer"][0]["reference"],
        format!("urn:uuid:{}", therapist[0]["id"].as_str().unwrap()).as_str()
    );
    assert_eq!(scale["code"]["coding"][0]["code"], "fugl_meyer_ue");
    assert_eq!(scale["effectiveDateTime"], "2026-11-20");
    assert_eq!(scale["valueQuantity"]["value"], 34);
    // The check-in as a QuestionnaireResponse to the bundle's Questionnaire, the skipped
    // question left out, part of its session's Observation.
    let responses = of_type(bundle, "QuestionnaireResponse");
    assert_eq!(responses.len(), 1);
    let questionnaire = of_type(bundle, "Questionnaire");
    assert_eq!(
        responses[0]["questionnaire"],
        format!("{}|1", questionnaire[0]["url"].as_str().unwrap()).as_str()
    );
    assert_eq!(
        questionnaire[0]["url"],
        "https://fhir.clinic.example/telerehab/Questionnaire/session-checkin"
    );
    let answers: Vec<(&str, String)> = responses[0]["item"]
        .as_array()
        .unwrap()
        .iter()
        .map(|i| (i["linkId"].as_str().unwrap(), i["answer"][0].to_string()))
        .collect();
    assert_eq!(answers.len(), 2, "{answers:?}");
    assert_eq!(answers[0], ("pain", r#"{"valueInteger":3}"#.to_owned()));
    assert!(answers[1].1.contains("too_hard"), "{answers:?}");
    assert_eq!(
        responses[0]["partOf"][0]["reference"],
        format!("urn:uuid:{}", first["id"].as_str().unwrap()).as_str()
    );
    let rate = first["component"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["code"]["coding"][0]["code"] == "movements_per_min")
        .unwrap();
    assert_eq!(rate["valueQuantity"]["code"], "/min");
    assert_eq!(rate["valueQuantity"]["value"], 12.5);
}

/// Every resource tells itself in words: a generated XHTML narrative of catalogue words.
fn every_resource_has_a_generated_narrative(bundle: &Value) {
    for e in bundle["entry"].as_array().unwrap() {
        let r = &e["resource"];
        assert_eq!(r["text"]["status"], "generated", "{}", r["resourceType"]);
        let div = r["text"]["div"].as_str().unwrap();
        assert!(
            div.starts_with("<div xmlns=\"http://www.w3.org/1999/xhtml\"")
                && !div.contains("[fhir-"),
            "{div}"
        );
    }
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
    // The first session's check-in: pain and how it felt answered, tiredness skipped.
    let checkin = netlink::CheckIn {
        pain_0_10: Some(3),
        tiredness_0_10: None,
        difficulty: Some("too_hard".into()),
    };
    db.put_checkin("s-0", &checkin, T0 + 60_000).await.unwrap();
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
    let base = FhirBase::parse("https://fhir.clinic.example/telerehab/", "test").unwrap();
    let app = web::router(
        AppState::new(db.clone(), live)
            .with_clock(common::clock_at(T0).0)
            .with_fhir_base(base.clone()),
    );
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
    sessions_scales_and_checkin(&bundle, &subject, &ada.id);
    every_resource_has_a_generated_narrative(&bundle);
    // Every code used is defined, with a definition and a unit, in the bundle's CodeSystem
    // at the clinic's address; the placeholder address is gone.
    assert!(!text.contains("telerehab.example"), "a placeholder address");
    let systems = of_type(&bundle, "CodeSystem");
    let measures = systems
        .iter()
        .find(|s| s["url"] == base.code_system("measures").as_str())
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
    the_bundle_speaks_the_language_asked_else_the_therapists(&db, &app, &uri, &cookie, &ada.id)
        .await;
    // The command line's export (`hub export --fhir P-0042`) is the same bundle, audited.
    let (text, sessions) = hub::patients::export_fhir(&db, "P-0042", T0, &base, None)
        .await
        .unwrap();
    assert_eq!(sessions, 3);
    assert_eq!(serde_json::from_str::<Value>(&text).unwrap(), bundle);
    let audit = actions(&db).await;
    assert!(
        audit
            .iter()
            .any(|(a, act, _)| a == "cli" && act == "export_fhir")
    );
    let unknown = hub::patients::export_fhir(&db, "P-9999", T0, &base, None)
        .await
        .unwrap_err();
    assert!(unknown.to_string().contains("P-9999"), "{unknown}");
}

/// The bundle at `uri` in the language asked, else the therapist's console language, else
/// English; a language without words refused, naming it.
async fn the_bundle_speaks_the_language_asked_else_the_therapists(
    db: &Db,
    app: &axum::Router,
    uri: &str,
    cookie: &str,
    therapist: &str,
) {
    let patient_of = |b: &Value| b["entry"][0]["resource"].clone();
    let (_, en, _) = call(app, Method::GET, uri, Some(cookie), None).await;
    assert_eq!(patient_of(&en)["language"], "en");
    let spanish = format!("{uri}?lang=es");
    let (status, es, _) = call(app, Method::GET, &spanish, Some(cookie), None).await;
    assert_eq!(status, StatusCode::OK, "{es}");
    let patient = patient_of(&es);
    assert_eq!(patient["language"], "es");
    let div = patient["text"]["div"].as_str().unwrap();
    assert!(
        div.contains("Paciente P-0042") && div.contains("lang=\"es\""),
        "{div}"
    );
    db.set_therapist_language(therapist, Some("de"))
        .await
        .unwrap();
    let (_, de, _) = call(app, Method::GET, uri, Some(cookie), None).await;
    let patient = patient_of(&de);
    assert_eq!(patient["language"], "de");
    assert!(
        patient["text"]["div"]
            .as_str()
            .unwrap()
            .contains("Pseudonym der Klinik"),
        "{patient}"
    );
    let unknown = format!("{uri}?lang=xx");
    let (status, body, _) = call(app, Method::GET, &unknown, Some(cookie), None).await;
    assert_eq!(status, StatusCode::BAD_REQUEST, "{body}");
    let said = body.to_string();
    assert!(
        said.contains("xx") && said.contains("en, de, es, zh"),
        "{body}"
    );
}

on_both_backends!(
    a_patients_fhir_bundle_holds_a_pseudonymous_patient_the_regimen_sessions_and_scales
);
