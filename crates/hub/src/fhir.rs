//! A patient's record as a FHIR R4 `Bundle` (type `collection`), for the clinic's electronic
//! health record (`GET /api/patients/{id}/fhir`; docs/FHIR.md describes every resource):
//!
//! - `Patient`: the pseudonym as its only identifier (no name, no birth date);
//! - the current regimen as a `CarePlan` whose activity is a `ServiceRequest` coded SNOMED CT
//!   229065009 "Exercise therapy", its timing the regimen's sessions a week and planned length;
//! - one `Observation` a session, a `component` a measure, coded in the hub's own code system
//!   [`MEASURES_SYSTEM`] with its UCUM unit;
//! - one `Observation` a clinical scale, coded in [`SCALES_SYSTEM`] (no LOINC code is used:
//!   see docs/FHIR.md);
//! - both code systems as `CodeSystem` resources, each code with its definition and unit.
//!
//! Resource ids and `fullUrl`s (`urn:uuid:…`) are derived from the hub's own ids by SHA-256,
//! so the same record exports the same ids every time.

use std::collections::{BTreeMap, BTreeSet};

use serde_json::{Value, json};

use crate::db::{Db, NamedSession, Patient, ScaleEntry, iso_utc};
use crate::error::HubError;

/// The hub's code system of session measures.
pub const MEASURES_SYSTEM: &str = "https://telerehab.example/fhir/CodeSystem/measures";
/// The hub's code system of clinical scales.
pub const SCALES_SYSTEM: &str = "https://telerehab.example/fhir/CodeSystem/clinical-scales";
/// The system of the patient's pseudonym (the clinic's own identifiers).
pub const PSEUDONYM_SYSTEM: &str = "https://telerehab.example/fhir/sid/pseudonym";
/// The system of the hub's session ids.
pub const SESSION_SYSTEM: &str = "https://telerehab.example/fhir/sid/session";
/// UCUM.
const UCUM: &str = "http://unitsofmeasure.org";

/// A statistic a measure's name may end with, and its words.
const STATISTICS: [(&str, &str); 6] = [
    ("_median", "median over the session"),
    ("_mean", "mean over the session"),
    ("_max", "largest in the session"),
    ("_min", "smallest in the session"),
    ("_sd", "standard deviation over the session"),
    ("_p95", "95th percentile over the session"),
];

/// The UCUM unit of a measure, read from the unit its name carries (`_deg`, `_s`, `_nm`,
/// `_pct`, `_per_min`, …, before a statistic such as `_median`); `1` when it has none.
pub fn ucum_unit(name: &str) -> &'static str {
    // A rate ends like the statistic `_min`: read it first.
    if name.contains("_per_min") {
        return "/min";
    }
    let base = STATISTICS
        .iter()
        .find_map(|(s, _)| name.strip_suffix(s))
        .unwrap_or(name);
    let units: &[(&str, &str)] = &[
        ("_deg_s", "deg/s"),
        ("_rad_s", "rad/s"),
        ("_deg", "deg"),
        ("_rad", "rad"),
        ("_ms", "ms"),
        ("_s", "s"),
        ("_nm", "N.m"),
        ("_m", "m"),
        ("_j", "J"),
        ("_pct", "%"),
        ("_hz", "Hz"),
    ];
    if base.starts_with("pct_") {
        return "%";
    }
    units
        .iter()
        .find(|(suffix, _)| base.ends_with(suffix))
        .map_or("1", |(_, unit)| unit)
}

/// A measure's definition: the one words table's (`metrics::words`, with its source) when the
/// table has the measure, else built from its name.
pub fn measure_definition(name: &str) -> String {
    if let Some(m) = metrics::words::measure_words(name) {
        return format!("{} Source: {}.", m.definition, m.source);
    }
    let statistic = STATISTICS.iter().find(|(s, _)| name.ends_with(s));
    let words = name.replace('_', " ");
    match statistic {
        Some((_, w)) => format!("Station measure \"{words}\" ({w}), in {}.", ucum_unit(name)),
        None => format!("Station measure \"{words}\", in {}.", ucum_unit(name)),
    }
}

/// A stable UUID (its text) for `kind`/`id`: the first 16 bytes of their SHA-256, marked as
/// an RFC 9562 version 8 (custom) UUID.
fn uuid_of(kind: &str, id: &str) -> String {
    let h = crate::db::sha256_hex(format!("telerehab:{kind}/{id}").as_bytes());
    let mut hex: Vec<char> = h.chars().take(32).collect();
    hex[12] = '8';
    hex[16] = ['8', '9', 'a', 'b'][usize::from(hex[16].to_digit(16).unwrap_or(0) as u8 & 3)];
    let s: String = hex.into_iter().collect();
    format!(
        "{}-{}-{}-{}-{}",
        &s[..8],
        &s[8..12],
        &s[12..16],
        &s[16..20],
        &s[20..]
    )
}

/// A bundle entry of `resource` (its `resourceType` and the stable id of `kind`/`id`).
fn entry(kind: &str, id: &str, mut resource: Value) -> (String, Value) {
    let uuid = uuid_of(kind, id);
    resource["id"] = json!(uuid);
    let url = format!("urn:uuid:{uuid}");
    (url.clone(), json!({ "fullUrl": url, "resource": resource }))
}

fn patient_resource(p: &Patient) -> Value {
    json!({
        "resourceType": "Patient",
        "identifier": [{ "use": "usual", "system": PSEUDONYM_SYSTEM, "value": p.pseudonym }],
        "active": true,
    })
}

/// The regimen's CarePlan and ServiceRequest (in that order), when the patient has one.
async fn regimen_entries(
    db: &Db,
    p: &Patient,
    subject: &str,
) -> Result<Vec<(String, Value)>, HubError> {
    let Some(rx) = db.latest_regimen(&p.id).await? else {
        return Ok(Vec::new());
    };
    let parsed = regimen::Regimen::from_toml(&rx.toml, "the stored regimen").ok();
    let key = format!("{}/v{}", p.id, rx.version);
    // The regimen by the patient's pseudonym: the hub's own patient id stays in the hub.
    let identifier = format!("{}/v{}", p.pseudonym, rx.version);
    let mut repeat = serde_json::Map::new();
    if let Some(n) = parsed.as_ref().and_then(|r| r.sessions_per_week) {
        repeat.insert("frequency".into(), json!(n));
        repeat.insert("period".into(), json!(1));
        repeat.insert("periodUnit".into(), json!("wk"));
    }
    if let Some(s) = parsed.as_ref().and_then(|r| r.planned_duration_s().ok()) {
        repeat.insert("duration".into(), json!((s / 60.0 * 10.0).round() / 10.0));
        repeat.insert("durationUnit".into(), json!("min"));
    }
    let exercises = parsed.as_ref().map_or(0, |r| r.exercises.len());
    let authored = iso_utc(rx.prescribed_at_ms);
    let title = format!("Home exercise regimen, version {}", rx.version);
    let mut request = json!({
        "resourceType": "ServiceRequest",
        "identifier": [{ "system": "https://telerehab.example/fhir/sid/regimen", "value": identifier }],
        "status": "active",
        "intent": "order",
        "code": { "coding": [{ "system": "http://snomed.info/sct", "code": "229065009", "display": "Exercise therapy" }],
                  "text": format!("{title}: {exercises} exercise(s) on the telerehab station") },
        "subject": { "reference": subject },
        "authoredOn": authored,
    });
    if !repeat.is_empty() {
        request["occurrenceTiming"] = json!({ "repeat": repeat });
    }
    let (request_url, request_entry) = entry("ServiceRequest", &key, request);
    let plan = json!({
        "resourceType": "CarePlan",
        "identifier": [{ "system": "https://telerehab.example/fhir/sid/regimen", "value": identifier }],
        "status": "active",
        "intent": "plan",
        "title": title,
        "subject": { "reference": subject },
        "created": authored,
        "activity": [{ "reference": { "reference": request_url } }],
    });
    Ok(vec![
        entry("CarePlan", &key, plan),
        (request_url, request_entry),
    ])
}

/// A session's Observation: its measures as components.
fn session_observation(
    s: &NamedSession,
    measures: Option<&BTreeMap<String, f64>>,
    subject: &str,
) -> Value {
    let components: Vec<Value> = measures
        .into_iter()
        .flatten()
        .map(|(name, v)| {
            let unit = ucum_unit(name);
            json!({
                "code": { "coding": [{ "system": MEASURES_SYSTEM, "code": name }] },
                "valueQuantity": { "value": v, "unit": unit, "system": UCUM, "code": unit },
            })
        })
        .collect();
    let mut period = json!({ "start": iso_utc(s.row.started_unix_ms) });
    if let Some(end) = s.row.closed_at_ms {
        period["end"] = json!(iso_utc(end.max(s.row.started_unix_ms)));
    }
    let mut o = json!({
        "resourceType": "Observation",
        "identifier": [{ "system": SESSION_SYSTEM, "value": s.row.session_id }],
        "status": if s.row.closed_at_ms.is_some() { "final" } else { "preliminary" },
        "category": [{ "coding": [{ "system": "http://terminology.hl7.org/CodeSystem/observation-category", "code": "activity", "display": "Activity" }] }],
        "code": { "coding": [{ "system": MEASURES_SYSTEM, "code": "session", "display": "Telerehabilitation session measures" }],
                  "text": format!("Telerehabilitation session: {}", s.exercise_name) },
        "subject": { "reference": subject },
        "effectivePeriod": period,
    });
    if !components.is_empty() {
        o["component"] = json!(components);
    }
    o
}

/// A clinical scale's Observation.
fn scale_observation(e: &ScaleEntry, subject: &str) -> Value {
    let quantity =
        |v: i64, unit: &str| json!({ "value": v, "unit": unit, "system": UCUM, "code": unit });
    let mut o = json!({
        "resourceType": "Observation",
        "status": "final",
        "category": [{ "coding": [{ "system": "http://terminology.hl7.org/CodeSystem/observation-category", "code": "exam", "display": "Exam" }] }],
        "code": { "coding": [{ "system": SCALES_SYSTEM, "code": e.scale, "display": e.scale_name }], "text": e.scale_name },
        "subject": { "reference": subject },
        "effectiveDateTime": e.assessed_on,
        "issued": iso_utc(e.created_at_ms),
    });
    if let Some(score) = e.score {
        o["valueQuantity"] = quantity(score, "{score}");
    }
    let sides = [
        (
            "box_and_block_affected",
            "affected side",
            e.affected_blocks_per_min,
        ),
        (
            "box_and_block_unaffected",
            "unaffected side",
            e.unaffected_blocks_per_min,
        ),
    ];
    let components: Vec<Value> = sides
        .iter()
        .filter_map(|(code, words, v)| {
            v.map(|v| json!({
                "code": { "coding": [{ "system": SCALES_SYSTEM, "code": code, "display": format!("Box and Block Test, {words}") }] },
                "valueQuantity": quantity(v, "{blocks}/min"),
            }))
        })
        .collect();
    if !components.is_empty() {
        o["component"] = json!(components);
    }
    o
}

/// The measures' CodeSystem: every code `names` holds, with its definition and UCUM unit.
fn measures_code_system(names: &BTreeSet<&str>) -> Value {
    let mut concepts = vec![
        json!({ "code": "session", "display": "Telerehabilitation session measures",
        "definition": "The measures the station computed of one session, one component each." }),
    ];
    concepts.extend(names.iter().map(|n| {
        json!({
            "code": n, "display": metrics::words::measure_words(n).map_or_else(|| n.replace('_', " "), |m| m.header()), "definition": measure_definition(n),
            "property": [{ "code": "unit", "valueCode": ucum_unit(n) }],
        })
    }));
    code_system(
        MEASURES_SYSTEM,
        "TelerehabMeasures",
        "Telerehab session measures",
        concepts,
    )
}

/// The clinical scales' CodeSystem.
fn scales_code_system() -> Value {
    let mut concepts: Vec<Value> = crate::db::SCALES
        .iter()
        .map(|s| {
            let f = s.fields[0];
            json!({ "code": s.key, "display": s.name,
                "definition": format!("{}: {} from {} to {} {}.", s.name, f.label, f.min, f.max, f.unit),
                "property": [{ "code": "unit", "valueCode": if f.unit == "points" { "{score}" } else { "{blocks}/min" } }] })
        })
        .collect();
    for (code, words) in [
        ("box_and_block_affected", "affected"),
        ("box_and_block_unaffected", "unaffected"),
    ] {
        concepts.push(
            json!({ "code": code, "display": format!("Box and Block Test, {words} side"),
            "definition": format!("Blocks moved in one minute with the {words} hand, 0 to 150."),
            "property": [{ "code": "unit", "valueCode": "{blocks}/min" }] }),
        );
    }
    code_system(
        SCALES_SYSTEM,
        "TelerehabClinicalScales",
        "Clinical scales recorded by the telerehab hub",
        concepts,
    )
}

fn code_system(url: &str, name: &str, title: &str, concepts: Vec<Value>) -> Value {
    json!({
        "resourceType": "CodeSystem",
        "url": url,
        "name": name,
        "title": title,
        "status": "active",
        "content": "complete",
        "caseSensitive": true,
        "property": [{ "code": "unit", "description": "The value's unit, UCUM", "type": "code" }],
        "concept": concepts,
    })
}

/// What the audit log says of an export of a bundle of `sessions` sessions.
pub fn audit_detail(sessions: usize) -> String {
    format!("FHIR R4 bundle of {sessions} sessions")
}

/// Patient `p`'s record as a FHIR R4 `Bundle` of type `collection`, stamped `now_ms`; the
/// bundle and how many sessions it holds.
pub async fn patient_bundle(db: &Db, p: &Patient, now_ms: i64) -> Result<(Value, usize), HubError> {
    let (subject, patient) = entry("Patient", &p.id, patient_resource(p));
    let mut entries = vec![patient];
    entries.extend(
        regimen_entries(db, p, &subject)
            .await?
            .into_iter()
            .map(|(_, e)| e),
    );
    let (sessions, measures) = db.sessions_with_measures(&p.id).await?;
    for s in &sessions {
        let o = session_observation(s, measures.get(&s.row.session_id), &subject);
        entries.push(entry("Observation", &format!("session/{}", s.row.session_id), o).1);
    }
    for e in db.scales_of(&p.id).await? {
        entries.push(
            entry(
                "Observation",
                &format!("scale/{}", e.id),
                scale_observation(&e, &subject),
            )
            .1,
        );
    }
    let names: BTreeSet<&str> = measures
        .values()
        .flat_map(|m| m.keys().map(String::as_str))
        .collect();
    entries.push(entry("CodeSystem", MEASURES_SYSTEM, measures_code_system(&names)).1);
    entries.push(entry("CodeSystem", SCALES_SYSTEM, scales_code_system()).1);
    let bundle = json!({
        "resourceType": "Bundle",
        "id": uuid_of("Bundle", &format!("{}/{now_ms}", p.id)),
        "type": "collection",
        "timestamp": iso_utc(now_ms),
        "entry": entries,
    });
    Ok((bundle, sessions.len()))
}

#[cfg(test)]
mod tests {
    use super::{measure_definition, ucum_unit, uuid_of};

    #[test]
    fn units_are_read_from_the_measures_names_in_ucum() {
        for (name, unit) in [
            ("sparc_median", "1"),
            ("active_s", "s"),
            ("movement_time_s_median", "s"),
            ("initial_direction_error_deg_mean", "deg"),
            ("movement_peak_speed_deg_s_median", "deg/s"),
            ("strength_peak_left_nm", "N.m"),
            ("pct_in_lane", "%"),
            ("active_pct", "%"),
            ("movements_per_min", "/min"),
            ("rms_lateral_m", "m"),
        ] {
            assert_eq!(ucum_unit(name), unit, "{name}");
        }
        assert!(measure_definition("wheel_speed_deg_s").contains("deg/s"));
        // The words table's definition and source, not a second copy.
        let sparc = measure_definition("sparc_median");
        assert!(sparc.contains("discrete movements") && sparc.contains("Balasubramanian"));
        let id = uuid_of("Patient", "p-1");
        assert_eq!(id, uuid_of("Patient", "p-1"), "stable");
        assert_eq!(id.len(), 36);
        assert_eq!(&id[14..15], "8");
    }
}
