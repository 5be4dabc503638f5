//! What `telerehab hub patient …` does to the database (`hub::patients`), on SQLite and on
//! PostgreSQL (the latter needs `TELEREHAB_TEST_PG_URL`, see `scripts/with-postgres.sh`).

mod common;

use hub::{Db, HubError, Role, patients};

const T0: i64 = 1_795_253_400_000;
const MEDIUM: &str = include_str!("../../../regimens/medium.toml");

async fn therapist(db: &Db) -> hub::Therapist {
    db.add_therapist(
        "ada@clinic.example",
        "correct horse battery",
        Role::Therapist,
        T0,
    )
    .await
    .unwrap()
}

async fn actions(db: &Db) -> Vec<String> {
    let mut log = db.audit_log(100).await.unwrap();
    log.sort_by_key(|e| e.at_ms);
    log.into_iter().map(|e| e.action).collect()
}

async fn a_patient_added_gets_a_fresh_code_each_time_and_every_step_is_audited(db: Db) {
    let ada = therapist(&db).await;
    let first = patients::add(&db, "P-0042", Some("ada@clinic.example"), T0)
        .await
        .unwrap();
    let again = patients::new_code(&db, "P-0042", T0 + 1).await.unwrap();
    assert_eq!(first.patient_id, again.patient_id);
    assert_ne!(
        first.code, again.code,
        "a new code, not the first one again"
    );
    let report = patients::show(&db, "P-0042", T0 + 2).await.unwrap();
    assert_eq!(report.patient.id, first.patient_id);
    assert_eq!(
        report.patient.therapist_id.as_deref(),
        Some(ada.id.as_str())
    );
    assert!(report.stations.is_empty() && report.sessions.is_empty());
    let log = actions(&db).await;
    for action in ["add_patient", "pairing_code", "show_patient"] {
        assert!(log.iter().any(|a| a == action), "{action} in {log:?}");
    }
    // Unknown names are refused by name, and nothing is added.
    let err = patients::add(&db, "P-0043", Some("bob@clinic.example"), T0)
        .await
        .unwrap_err();
    assert!(
        matches!(&err, HubError::NotFound { what: "therapist", id } if id == "bob@clinic.example"),
        "{err}"
    );
    assert!(db.patient_by_pseudonym("P-0043").await.unwrap().is_none());
    let err = patients::show(&db, "P-9999", T0).await.unwrap_err();
    assert!(err.to_string().contains("P-9999"), "{err}");
}

async fn an_invalid_regimen_is_refused_naming_its_file_and_nothing_is_stored(db: Db) {
    let ada = therapist(&db).await;
    let code = patients::add(&db, "P-0042", None, T0).await.unwrap();
    let bad = "[[exercise]]\nkind = \"straight\"\nduration_s = -5.0\n";
    let err = patients::prescribe(&db, "P-0042", bad, "bad.toml", &ada.email, T0)
        .await
        .unwrap_err();
    assert!(
        matches!(
            err,
            HubError::Invalid {
                field: "regimen",
                ..
            }
        ) && err.to_string().contains("bad.toml"),
        "{err}"
    );
    assert!(db.latest_regimen(&code.patient_id).await.unwrap().is_none());
    assert!(!actions(&db).await.iter().any(|a| a == "put_regimen"));
    let version = patients::prescribe(&db, "P-0042", MEDIUM, "medium.toml", &ada.email, T0)
        .await
        .unwrap();
    assert_eq!(version, 1);
    let stored = db.latest_regimen(&code.patient_id).await.unwrap().unwrap();
    assert_eq!(stored.version, 1);
    let log = db.audit_log(100).await.unwrap();
    assert!(
        log.iter().any(|e| e.action == "put_regimen"
            && e.actor == ada.actor()
            && e.detail == "version 1"),
        "{log:?}"
    );
}

on_both_backends!(
    a_patient_added_gets_a_fresh_code_each_time_and_every_step_is_audited,
    an_invalid_regimen_is_refused_naming_its_file_and_nothing_is_stored,
);
