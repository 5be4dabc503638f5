//! A patient's rights at the hub: `hub patient export` writes everything held about them into
//! one archive, `hub patient erase` removes it (recordings included) after a confirmation,
//! revokes their stations and leaves one audit entry without the data; another patient's data
//! is untouched. On SQLite and on PostgreSQL.

use std::collections::BTreeMap;
use std::io::Read;
use std::path::{Path, PathBuf};

use telerehab_tests::clinic::{
    Hub, after, clinic_on, fresh_postgres_database, ok, pair, prescribe, run_session, show_json,
    telerehab,
};

/// The finished recordings under `dir` (a clinic's `recordings/` or an export's), by path
/// below it, with their bytes.
fn files_under(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    let mut found = BTreeMap::new();
    for station in std::fs::read_dir(dir).into_iter().flatten().flatten() {
        for file in std::fs::read_dir(station.path()).unwrap().flatten() {
            let rel = file.path().strip_prefix(dir).unwrap().display().to_string();
            found.insert(rel, std::fs::read(file.path()).unwrap());
        }
    }
    found
}

/// Unpack a `.tar.zst` export into `dest`; its `patient.json`.
fn unpack(archive: &Path, dest: &Path) -> serde_json::Value {
    let file = std::fs::File::open(archive).unwrap();
    tar::Archive::new(zstd::Decoder::new(file).unwrap())
        .unpack(dest)
        .unwrap();
    let mut text = String::new();
    std::fs::File::open(dest.join("patient.json"))
        .unwrap()
        .read_to_string(&mut text)
        .unwrap();
    serde_json::from_str(&text).unwrap()
}

/// The audit log of the clinic at `data`, newest first.
fn audit(data: &Path) -> Vec<hub::db::AuditEntry> {
    let rt = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .unwrap();
    rt.block_on(async {
        let db = hub::clinic::Clinic::at(data).open_db(None).await.unwrap();
        let page = db.audit_page(None, 1000).await.unwrap();
        db.close().await;
        page.entries
    })
}

/// A clinic (on `db`, or SQLite) with P-0042 (a regimen, two sessions on one station) and
/// P-0043 (one session), every recording uploaded.
struct TwoPatients {
    tmp: tempfile::TempDir,
    data: PathBuf,
    hub: Hub,
    /// P-0042's station home and station id.
    home: PathBuf,
    station: String,
    /// Summaries stored for P-0042.
    summaries: u64,
}

impl TwoPatients {
    fn make(db: Option<&str>) -> Self {
        let tmp = tempfile::tempdir().unwrap();
        let (data, code) = clinic_on(tmp.path(), db);
        let d = data.to_str().unwrap();
        prescribe(&data, "easy");
        let other = after(
            &ok(
                &[
                    "hub",
                    "patient",
                    "add",
                    "--data",
                    d,
                    "--pseudonym",
                    "P-0043",
                ],
                None,
            ),
            "pairing code: ",
        );
        let hub = Hub::serve(&data, "127.0.0.1:0");
        let (home, home2) = (tmp.path().join("s42"), tmp.path().join("s43"));
        pair(&hub, &code, &home);
        pair(&hub, &other, &home2);
        run_session(&home, "2");
        run_session(&home, "2");
        run_session(&home2, "2");
        let deadline = std::time::Instant::now() + std::time::Duration::from_secs(30);
        while files_under(&data.join("recordings")).len() < 3 {
            assert!(
                std::time::Instant::now() < deadline,
                "recordings not uploaded"
            );
            std::thread::sleep(std::time::Duration::from_millis(100));
        }
        let shown = show_json(&data);
        let station = shown["stations"][0]["station_id"]
            .as_str()
            .unwrap()
            .to_owned();
        let summaries = shown["sessions"]
            .as_array()
            .unwrap()
            .iter()
            .map(|s| s["summaries_stored"].as_u64().unwrap())
            .sum();
        Self {
            tmp,
            data,
            hub,
            home,
            station,
            summaries,
        }
    }

    fn d(&self) -> &str {
        self.data.to_str().unwrap()
    }
}

/// Export P-0042: every row and recording of theirs, none of P-0043's; its `patient.json`.
fn export_has_everything(c: &TwoPatients) -> serde_json::Value {
    let archive = c.tmp.path().join("P-0042.tar.zst");
    let said = ok(
        &[
            "hub",
            "patient",
            "export",
            "--data",
            c.d(),
            "P-0042",
            "--out",
            archive.to_str().unwrap(),
        ],
        None,
    );
    assert!(said.contains("sessions 2, summaries"), "{said}");
    let unpacked = c.tmp.path().join("unpacked");
    let doc = unpack(&archive, &unpacked);
    let tables = &doc["tables"];
    assert_eq!(doc["pseudonym"], "P-0042");
    assert_eq!(tables["sessions"].as_array().unwrap().len(), 2);
    assert_eq!(
        tables["summaries"].as_array().unwrap().len() as u64,
        c.summaries
    );
    assert_eq!(tables["regimens"].as_array().unwrap().len(), 1);
    assert!(
        tables["session_metrics"]
            .as_array()
            .is_some_and(|m| !m.is_empty())
    );
    assert!(
        tables["audit_log"]
            .as_array()
            .is_some_and(|a| !a.is_empty())
    );
    let theirs: BTreeMap<String, Vec<u8>> = files_under(&c.data.join("recordings"))
        .into_iter()
        .filter(|(rel, _)| rel.starts_with(&c.station))
        .collect();
    assert_eq!(theirs.len(), 2);
    assert_eq!(
        files_under(&unpacked.join("recordings")),
        theirs,
        "byte for byte"
    );
    assert!(
        !doc.to_string().contains("P-0043"),
        "another patient's data in the export"
    );
    // The same patient for an electronic health record (validated resource by resource with
    // an independent FHIR implementation in tests/python/test_fhir_export.py).
    let bundle = c.tmp.path().join("bundle.json");
    let said = ok(
        &[
            "hub",
            "export",
            "--data",
            c.d(),
            "--fhir",
            "P-0042",
            "--out",
            bundle.to_str().unwrap(),
        ],
        None,
    );
    assert!(said.contains("(2 sessions)"), "{said}");
    let bundle: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&bundle).unwrap()).unwrap();
    assert_eq!(bundle["resourceType"], "Bundle");
    let observations: Vec<&serde_json::Value> = bundle["entry"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| &e["resource"])
        .filter(|r| r["resourceType"] == "Observation")
        .collect();
    // Each session: its measures as one Observation's components, and its exercise duration
    // (LOINC 55411-3) as one of its own.
    let sessions = observations
        .iter()
        .filter(|o| o["component"].is_array())
        .count();
    assert_eq!(sessions, 2, "an Observation per session");
    let durations = observations
        .iter()
        .filter(|o| o["code"]["coding"][0]["code"] == "55411-3")
        .count();
    assert_eq!(durations, 2, "an exercise duration per session");
    // In the therapist's language: German narratives, each resource saying so; a language
    // without words refused, naming it.
    let german = c.tmp.path().join("bundle-de.json");
    let export_in = |lang: &str, out: &Path| {
        let args = [
            "hub",
            "export",
            "--data",
            c.d(),
            "--fhir",
            "P-0042",
            "--lang",
            lang,
        ];
        telerehab(
            &[&args[..], &["--out", out.to_str().unwrap()]].concat(),
            None,
        )
    };
    assert!(export_in("de", &german).status.success());
    let german: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&german).unwrap()).unwrap();
    let patient = &german["entry"][0]["resource"];
    assert_eq!(patient["language"], "de");
    let div = patient["text"]["div"].as_str().unwrap();
    assert!(div.contains("Pseudonym der Klinik"), "{div}");
    let refused = export_in("xx", &c.tmp.path().join("bundle-xx.json"));
    assert!(!refused.status.success());
    let said = String::from_utf8_lossy(&refused.stderr);
    assert!(
        said.contains("\"xx\"") && said.contains("en, de, es, zh"),
        "{said}"
    );
    doc
}

fn export_then_erase(db: Option<&str>) {
    let c = TwoPatients::make(db);
    let doc = export_has_everything(&c);
    let (d, data) = (c.d(), &c.data);
    // Erase: refused without the right confirmation, then everything goes.
    let refused = telerehab(&["hub", "patient", "erase", "--data", d, "P-0042"], None);
    assert!(!refused.status.success());
    assert!(String::from_utf8_lossy(&refused.stderr).contains("--confirm P-0042"));
    let wrong = telerehab(
        &[
            "hub",
            "patient",
            "erase",
            "--data",
            d,
            "P-0042",
            "--confirm",
            "P-0043",
        ],
        None,
    );
    assert!(!wrong.status.success());
    let said = ok(
        &[
            "hub",
            "patient",
            "erase",
            "--data",
            d,
            "P-0042",
            "--confirm",
            "P-0042",
        ],
        None,
    );
    assert!(said.contains("recording files 2"), "{said}");
    let gone = telerehab(&["hub", "patient", "show", "--data", d, "P-0042"], None);
    assert!(!gone.status.success());
    assert!(String::from_utf8_lossy(&gone.stderr).contains("does not exist"));
    assert!(!data.join("recordings").join(&c.station).exists());
    // Their station is refused from now on: its next session delivers nothing.
    let report = run_session(&c.home, "1");
    assert!(report.contains("unknown station"), "{report}");
    assert!(report.contains(" 0 acknowledged"), "{report}");
    // The other patient keeps everything.
    assert_eq!(files_under(&data.join("recordings")).len(), 1);
    let other_shown = ok(
        &["hub", "patient", "show", "--data", d, "P-0043", "--json"],
        None,
    );
    assert!(other_shown.contains("summaries_stored"), "{other_shown}");
    // One audit entry of the erasure, holding no data; none left about the patient's sessions.
    let log = audit(data);
    let erasures: Vec<_> = log.iter().filter(|e| e.action == "erase_patient").collect();
    assert_eq!(erasures.len(), 1, "{log:?}");
    assert!(!erasures[0].detail.contains("P-0042"), "{:?}", erasures[0]);
    let sessions: Vec<&str> = doc["tables"]["sessions"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["session_id"].as_str().unwrap())
        .collect();
    assert!(
        log.iter().all(|e| !sessions.contains(&e.target.as_str())),
        "audit entries about an erased session remain"
    );
    c.hub.stop();
}

#[test]
fn a_patient_exported_then_erased_on_sqlite_leaves_only_the_erasure_and_others_intact() {
    export_then_erase(None);
}

#[test]
fn a_patient_exported_then_erased_on_postgresql_leaves_only_the_erasure_and_others_intact() {
    let Some(db) = fresh_postgres_database() else {
        return;
    };
    export_then_erase(Some(&db));
}
