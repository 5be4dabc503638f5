//! The FHIR export judged by the reference R4 validator, HAPI FHIR's instance validator
//! (scripts/fhir-validator, built by scripts/setup.sh), offline against R4 core: a patient with
//! two ended sessions (measures with every binary digit, as a station computes them), each
//! starting with the standard assessment, both check-ins, a regimen and two clinical scales must
//! give 0 errors and no warning but "this code system is unknown" (LOINC and SNOMED CT: no
//! terminology server offline), in English and in German. One JVM start for every file.

mod common;

use common::api::PASSWORD;
use common::{T0, hello, sqlite_db};

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

use hub::Role;
use hub::db::NewScale;
use hub::fhir::FhirBase;
use netlink::{AssessmentTag, Bye, CheckIn, ExerciseResult};

const REGIMEN: &str = "sessions_per_week = 5\n\n[[exercise]]\nkind = \"sine\"\namplitude_m = 2.0\n\
    wavelength_m = 150.0\nperiods = 2\nlane_width_m = 4.0\nspeed_m_s = 8.0\nduration_s = 30.0\n";

/// The validator's directory (its `target/classpath.txt` and classes come from setup.sh).
fn validator_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scripts/fhir-validator")
}

/// Measures with full binary precision from a fixed-seed generator (xorshift64), as the
/// station's floating-point measures are: the export must round them, not the test.
fn measures(seed: &mut u64) -> BTreeMap<String, f64> {
    let mut next = || {
        *seed ^= *seed << 13;
        *seed ^= *seed >> 7;
        *seed ^= *seed << 17;
        (*seed >> 11) as f64 / (1u64 << 53) as f64
    };
    [
        ("active_s", 600.0),
        ("session_s", 700.0),
        ("sparc_median", -2.0),
        ("movements_per_min", 20.0),
        ("pct_in_lane", 100.0),
        ("rms_lateral_m", 1.5),
        ("wheel_rom_deg", 180.0),
        // A measure the words table lacks: 4 significant digits, its unit from its name.
        ("wheel_speed_deg_s_median", 90.0),
    ]
    .into_iter()
    .map(|(k, scale)| (k.to_owned(), scale * (0.25 + 0.5 * next())))
    .collect()
}

/// The standard assessment's parts as a station reports them (protocol 1, seed `tag_seed`),
/// their scores with every binary digit from `seed`.
fn assessment(tag_seed: u32, seed: &mut u64) -> Vec<ExerciseResult> {
    let mut next = || {
        *seed ^= *seed << 13;
        *seed ^= *seed >> 7;
        *seed ^= *seed << 17;
        (*seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let tag = AssessmentTag {
        protocol: 1,
        seed: tag_seed,
    };
    let tracking = [
        "dial_rms_error_deg",
        "dial_mean_abs_error_deg",
        "trunk_lean_max_deg",
    ];
    let parts: [(&str, &[&str]); 6] = [
        ("range", &["wheel_rom_deg", "trunk_rotation_max_deg"]),
        ("tracking-slow", &tracking),
        ("tracking-medium", &tracking),
        ("tracking-fast", &tracking),
        (
            "steps",
            &[
                "step_responses",
                "reaction_time_s_median",
                "movement_time_s_median",
                "sparc_median",
                "ldlj_median",
                "path_length_ratio_median",
                "initial_direction_error_deg_mean",
            ],
        ),
        (
            "strength",
            &[
                "strength_peak_left_nm",
                "strength_peak_right_nm",
                "strength_left_at_ceiling",
            ],
        ),
    ];
    parts
        .iter()
        .enumerate()
        .map(|(i, (part, names))| ExerciseResult {
            index: i as u32,
            kind: format!("assessment-{part}"),
            name: format!("Assessment {part}"),
            prescribed_s: 30.0,
            active_s: 30.0,
            scores: names
                .iter()
                .map(|n| ((*n).to_owned(), 1.0 + 40.0 * next()))
                .collect(),
            assessment: Some(tag),
        })
        .collect()
}

/// The export, in English and in German, of a patient with two ended sessions each starting
/// with the standard assessment, both check-ins (one question skipped), a regimen, a
/// Fugl-Meyer score and a Box and Block Test.
async fn exported_bundles() -> (String, String) {
    let (db, _dir) = sqlite_db().await;
    let ada = db
        .add_therapist("ada@clinic.example", PASSWORD, Role::Therapist, T0)
        .await
        .unwrap();
    let p = db.add_patient("P-0042", Some(&ada.id), T0).await.unwrap();
    db.add_station("st-1", &p.id, &"a".repeat(64), T0)
        .await
        .unwrap();
    let checkins = [
        CheckIn {
            pain_0_10: Some(2),
            tiredness_0_10: Some(5),
            difficulty: Some("about_right".into()),
        },
        CheckIn {
            pain_0_10: Some(4),
            tiredness_0_10: None,
            difficulty: Some("too_hard".into()),
        },
    ];
    let mut seed = 0x2026_1206_u64;
    for (i, checkin) in checkins.iter().enumerate() {
        let id = format!("s-{i}");
        let start = T0 + i as i64 * 86_400_000;
        let mut h = hello("st-1", &p.id, &id);
        h.started_unix_ms = start as u64;
        db.open_session(&h, start).await.unwrap();
        let bye = Bye {
            session_id: id.clone(),
            reason: "completed".into(),
            final_seq: None,
            measures: BTreeMap::new(),
            hub_unix_ms: None,
            checkin: Some(checkin.clone()),
            difficulty: None,
            exercises: assessment(3_000_000_000 + i as u32, &mut seed),
        };
        db.close_session(&bye, start + 700_000).await.unwrap();
        db.put_metrics(&id, &measures(&mut seed)).await.unwrap();
        db.put_checkin(&id, checkin, start + 701_000).await.unwrap();
    }
    db.put_regimen(&p.id, REGIMEN, Some(5), &ada.id, T0)
        .await
        .unwrap();
    for scale in [
        NewScale {
            scale: "fugl_meyer_ue".into(),
            assessed_on: "2026-11-20".into(),
            score: Some(34.0),
            ..NewScale::default()
        },
        NewScale {
            scale: "box_and_block".into(),
            assessed_on: "2026-11-20".into(),
            affected_blocks_per_min: Some(12.0),
            unaffected_blocks_per_min: Some(48.0),
            ..NewScale::default()
        },
    ] {
        db.add_scale(&p.id, &ada.id, &scale, T0).await.unwrap();
    }
    let base = FhirBase::parse("https://fhir.clinic.example/telerehab", "test").unwrap();
    let now = T0 + 2 * 86_400_000;
    let (en, sessions) = hub::patients::export_fhir(&db, "P-0042", now, &base, None)
        .await
        .unwrap();
    assert_eq!(sessions, 2);
    let (de, _) = hub::patients::export_fhir(&db, "P-0042", now, &base, Some("de"))
        .await
        .unwrap();
    (en, de)
}

/// The validator's reports on `files` (one JVM): each file's messages (severity, message id,
/// location, text) and its summary line.
fn validate(files: &[&Path]) -> Vec<(Vec<Vec<String>>, String)> {
    let dir = validator_dir();
    let classpath = std::fs::read_to_string(dir.join("target/classpath.txt")).unwrap_or_else(|e| {
        panic!(
            "the FHIR validator is not built ({e}): run scripts/setup.sh (it installs Maven and a JDK and builds {})",
            dir.display()
        )
    });
    let run = Command::new("java")
        .arg("-cp")
        .arg(format!(
            "{}:{}",
            dir.join("target/classes").display(),
            classpath.trim()
        ))
        .arg("telerehab.Validate")
        .args(files)
        .output()
        .unwrap_or_else(|e| {
            panic!("cannot run java ({e}): run scripts/setup.sh, which installs a JDK")
        });
    let said = String::from_utf8_lossy(&run.stdout);
    assert!(
        run.status.success(),
        "the validator failed: {}\n{said}",
        String::from_utf8_lossy(&run.stderr)
    );
    println!("{said}");
    // One report a file, each closed by its summary line.
    let mut reports = Vec::new();
    let mut messages = Vec::new();
    for line in said.lines() {
        if line.starts_with("errors=") {
            reports.push((std::mem::take(&mut messages), line.to_owned()));
        } else {
            messages.push(line.splitn(4, '\t').map(str::to_owned).collect());
        }
    }
    assert_eq!(reports.len(), files.len(), "a report a file:\n{said}");
    reports
}

/// Whether message `m` is the validator's "this code system is unknown here" (in either of
/// its two wordings) for LOINC or SNOMED CT, the two terminologies it has no copy of offline;
/// our own code systems it knows (the bundle's).
fn unknown_system(m: &[String]) -> bool {
    let field = |i: usize| m.get(i).map_or("", String::as_str);
    let (id, text) = (field(1), field(3));
    let wording = (id == "Terminology_PassThrough_TX_Message"
        && text.starts_with("CodeSystem is unknown and can't be validated: "))
        || (id == "TERMINOLOGY_TX_SYSTEM_UNSUPPORTED"
            && text.starts_with("The code cannot be checked because codeSystem "));
    let system = ["http://loinc.org", "http://snomed.info/sct"]
        .iter()
        .any(|s| text.contains(&format!(": {s} ")) || text.contains(&format!("'{s}'")));
    wording && system
}

/// The messages of a report that are neither information nor an unknown code system, each
/// joined into one line.
fn beyond_unknown_systems(messages: &[Vec<String>]) -> Vec<String> {
    messages
        .iter()
        .filter(|m| m[0] != "INFORMATION" && !(m[0] == "WARNING" && unknown_system(m)))
        .map(|m| m.join(" | "))
        .collect()
}

/// The resources of `bundle` that are Observations coded `code`.
fn observations<'a>(bundle: &'a serde_json::Value, code: &str) -> Vec<&'a serde_json::Value> {
    bundle["entry"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| &e["resource"])
        .filter(|r| r["resourceType"] == "Observation" && r["code"]["coding"][0]["code"] == code)
        .collect()
}

/// The first resource of `bundle` that `is`.
fn first_mut(
    bundle: &mut serde_json::Value,
    is: impl Fn(&serde_json::Value) -> bool,
) -> &mut serde_json::Value {
    bundle["entry"]
        .as_array_mut()
        .unwrap()
        .iter_mut()
        .map(|e| &mut e["resource"])
        .find(|r| is(r))
        .unwrap()
}

/// Each standard assessment is a panel whose members are its six parts, coded and measured
/// apart from the sessions, named by its protocol; the German bundle's narratives are German.
fn check_assessments_and_language(en: &serde_json::Value, de: &serde_json::Value) {
    let panels = observations(en, "standard-assessment");
    assert_eq!(panels.len(), 2, "one panel an assessment");
    for panel in &panels {
        assert_eq!(panel["method"]["coding"][0]["code"], "protocol-1");
        assert_eq!(panel["category"][0]["coding"][0]["code"], "exam");
        assert_eq!(panel["hasMember"].as_array().unwrap().len(), 6);
    }
    let steps = observations(en, "steps");
    assert_eq!(steps.len(), 2);
    let rt = steps[0]["component"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["code"]["coding"][0]["code"] == "reaction_time_s_median")
        .unwrap();
    // Rounded to the words table's 2 decimals, in UCUM seconds.
    let v = rt["valueQuantity"]["value"].as_f64().unwrap();
    assert_eq!((v * 100.0).round() / 100.0, v, "{v}");
    assert_eq!(rt["valueQuantity"]["code"], "s");
    // No session Observation carries an assessment's measure.
    for s in observations(en, "session") {
        for c in s["component"].as_array().unwrap() {
            assert_ne!(c["code"]["coding"][0]["code"], "step_responses", "{s}");
        }
    }
    let de_steps = observations(de, "steps");
    let div = de_steps[0]["text"]["div"].as_str().unwrap();
    assert!(
        div.contains("lang=\"de\"") && div.contains("Teil des Standardtests"),
        "{div}"
    );
    // The measures' code system is English, each measure's German name a designation.
    let measures = de["entry"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| &e["resource"])
        .find(|r| r["name"] == "TelerehabMeasures")
        .unwrap();
    let rt = measures["concept"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["code"] == "reaction_time_s_median")
        .unwrap();
    assert_eq!(rt["designation"][0]["language"], "de", "{rt}");
    assert_ne!(rt["designation"][0]["value"], rt["display"], "{rt}");
    // The session's exercises in German too (the hub's own name is English).
    let en_session = &observations(en, "session")[0]["code"]["text"];
    let de_session = &observations(de, "session")[0]["code"]["text"];
    assert!(
        de_session
            .as_str()
            .unwrap()
            .starts_with("Telereha-Einheit: ")
            && de_session != en_session,
        "{de_session} / {en_session}"
    );
    for e in de["entry"].as_array().unwrap() {
        let r = &e["resource"];
        let language = if r["resourceType"] == "CodeSystem" {
            "en"
        } else {
            "de"
        };
        assert_eq!(r["language"], language, "{}", r["resourceType"]);
    }
}

#[tokio::test(flavor = "multi_thread")]
async fn the_reference_validator_finds_no_error_and_no_warning_but_unknown_code_systems_in_an_export()
 {
    let (text, german) = exported_bundles().await;
    let out = tempfile::tempdir().unwrap();
    let file = out.path().join("bundle.json");
    std::fs::write(&file, &text).unwrap();
    let german_file = out.path().join("bundle-de.json");
    std::fs::write(&german_file, &german).unwrap();
    // The same bundle with one check-in answered out of range and off the answer list, and an
    // assessment's measure off the measures' code system: the validator must check responses
    // against the questionnaire and the assessment against our code systems.
    let mut broken: serde_json::Value = serde_json::from_str(&text).unwrap();
    let response = first_mut(&mut broken, |r| {
        r["resourceType"] == "QuestionnaireResponse"
    });
    response["item"][0]["answer"][0]["valueInteger"] = 11.into();
    response["item"][2]["answer"][0]["valueCoding"]["code"] = "bogus".into();
    let part = first_mut(&mut broken, |r| r["code"]["coding"][0]["code"] == "steps");
    part["component"][0]["code"]["coding"][0]["code"] = "bogus_measure".into();
    let broken_file = out.path().join("broken.json");
    std::fs::write(&broken_file, broken.to_string()).unwrap();

    let reports = validate(&[&file, &broken_file, &german_file]);
    for (i, language) in [(0, "en"), (2, "de")] {
        let (messages, summary) = &reports[i];
        let wrong = beyond_unknown_systems(messages);
        assert!(
            wrong.is_empty(),
            "{language}: {summary}; beyond unknown code systems:\n{}",
            wrong.join("\n")
        );
        assert!(summary.starts_with("errors=0 "), "{language}: {summary}");
        // It did judge the bundle: the LOINC codes it cannot look up offline were seen.
        assert!(messages.iter().any(|m| unknown_system(m)), "{messages:?}");
    }
    check_assessments_and_language(
        &serde_json::from_str(&text).unwrap(),
        &serde_json::from_str(&german).unwrap(),
    );
    // And it finds what is wrong: the answer over the questionnaire's maximum, the code not
    // in the check-in's code system, the measure not in ours.
    let (broken, summary) = &reports[1];
    let errors: Vec<&Vec<String>> = broken.iter().filter(|m| m[0] == "ERROR").collect();
    let ids: Vec<&str> = errors.iter().map(|m| m[1].as_str()).collect();
    assert!(
        ids.contains(&"QUESTIONNAIRE_QR_ITEM_INTEGER_MAX")
            && ids.contains(&"Questionnaire_QR_Item_NoCoding"),
        "{summary}: {ids:?}"
    );
    assert!(
        errors.iter().any(|m| m.join(" ").contains("bogus_measure")),
        "{summary}: {errors:?}"
    );
}
