//! The hub's own codes and their units: the session measures (their names as the station
//! reports them, each with a definition and a UCUM unit read from its name), the clinical
//! scales and the check-in's answers, as `CodeSystem` resources at the clinic's canonical
//! address ([`super::FhirBase`]); and the LOINC codes used where one exists.
//!
//! **LOINC searched** (FIELD-NOTES "Codes"; the HL7 Physical Activity IG's value set "PA
//! Observation Activity-related codes"): exercise duration has one, 55411-3 "Exercise
//! duration" (in `min`), exported as an Observation of its own a session ([`EXERCISE_DURATION`]);
//! the pain question of the check-in is the 0–10 numeric rating of LOINC 72514-3
//! ([`PAIN_0_10`]). None was found for the smoothness measures (SPARC, LDLJ), movement counts and
//! rates, lane keeping, tracking error, the wheel's range of motion (LOINC 92850-7 is a
//! joint's upper-extremity range of motion, not a wheel's turn), speed metric, path length
//! ratio, reaction and movement time, assistance, strength on the wheel, the check-in's
//! tiredness (Borg CR10 effort) and "how hard it felt", the Fugl-Meyer upper extremity score,
//! the ARAT or the Box and Block Test: they keep the hub's own codes.

use std::collections::BTreeSet;

use serde_json::{Value, json};

use super::FhirBase;
use super::narrative::Words;

/// LOINC.
pub const LOINC: &str = "http://loinc.org";
/// LOINC 55411-3 "Exercise duration" (HL7 Physical Activity IG's activity codes).
pub const EXERCISE_DURATION: (&str, &str) = ("55411-3", "Exercise duration");
/// LOINC 72514-3 "Pain severity - 0-10 verbal numeric rating \[Score\] - Reported".
pub const PAIN_0_10: (&str, &str) = (
    "72514-3",
    "Pain severity - 0-10 verbal numeric rating [Score] - Reported",
);
/// The UCUM code of a scale's score (points: dimensionless).
pub const SCORE_UNIT: &str = "1";
/// The UCUM code of the Box and Block Test's blocks a minute (a count a minute).
pub const BLOCKS_UNIT: &str = "/min";
/// The name of the measures' code system under the clinic's base.
pub const MEASURES: &str = "measures";
/// The name of the clinical scales' code system.
pub const SCALES: &str = "clinical-scales";
/// The name of the check-in answers' code system.
pub const CHECKIN: &str = "session-checkin";
/// The language of the hub's code systems' displays and definitions.
pub const CODE_LANGUAGE: &str = "en";
/// UCUM.
pub const UCUM: &str = "http://unitsofmeasure.org";

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

/// A measure's value `v` rounded to its resolution: the words table's decimals
/// ([`metrics::words::MeasureWords::round`]), 4 significant digits for a measure the table
/// lacks; `None` for a value that is not a number.
pub fn measure_value(name: &str, v: f64) -> Option<f64> {
    if !v.is_finite() {
        return None;
    }
    let r = metrics::words::measure_words(name)
        .map_or_else(|| metrics::words::round_unknown(v), |m| m.round(v));
    // Never "-0.0".
    Some(if r == 0.0 { 0.0 } else { r })
}

/// A measure's display: the words table's name with its unit, else its name with spaces.
pub fn measure_display(name: &str) -> String {
    metrics::words::measure_words(name).map_or_else(|| name.replace('_', " "), |m| m.header())
}

/// The measures' CodeSystem: every code `names` holds, with its definition and UCUM unit,
/// written in `words` (English); a measure the words table names also carries its name in
/// `asked`'s language as a `designation`, when that is another.
pub fn measures_code_system(
    base: &FhirBase,
    words: &Words,
    asked: &Words,
    names: &BTreeSet<&str>,
) -> Value {
    let mut concepts = vec![
        json!({ "code": "session", "display": "Telerehabilitation session measures",
        "definition": "The measures the station computed of one session, one component each." }),
    ];
    let translated = asked.language() != words.language();
    concepts.extend(names.iter().map(|n| {
        let mut concept = json!({
            "code": n, "display": measure_display(n), "definition": measure_definition(n),
            "property": [{ "code": "unit", "valueCode": ucum_unit(n) }],
        });
        if translated && metrics::words::measure_words(n).is_some() {
            concept["designation"] =
                json!([{ "language": asked.language(), "value": asked.measure(n) }]);
        }
        concept
    }));
    code_system(
        words,
        &base.code_system(MEASURES),
        "TelerehabMeasures",
        "Telerehab session measures",
        concepts,
    )
}

/// The clinical scales' CodeSystem.
pub fn scales_code_system(base: &FhirBase, words: &Words) -> Value {
    let mut concepts: Vec<Value> = hub_store::db::SCALES
        .iter()
        .map(|s| {
            let f = s.fields[0];
            json!({ "code": s.key, "display": s.name,
                "definition": format!("{}: {} from {} to {} {}.", s.name, f.label, f.min, f.max, f.unit),
                "property": [{ "code": "unit", "valueCode": if f.unit == "points" { SCORE_UNIT } else { BLOCKS_UNIT } }] })
        })
        .collect();
    for (code, side) in [
        ("box_and_block_affected", "affected"),
        ("box_and_block_unaffected", "unaffected"),
    ] {
        concepts.push(
            json!({ "code": code, "display": format!("Box and Block Test, {side} side"),
            "definition": format!("Blocks moved in one minute with the {side} hand, 0 to 150."),
            "property": [{ "code": "unit", "valueCode": BLOCKS_UNIT }] }),
        );
    }
    code_system(
        words,
        &base.code_system(SCALES),
        "TelerehabClinicalScales",
        "Clinical scales recorded by the telerehab hub",
        concepts,
    )
}

/// The check-in's answers to "how hard it felt" ([`netlink::frame::CHECKIN_DIFFICULTIES`]),
/// each named as the station asks it.
///
/// Written in `words` (English: a code system's words are its codes' own); each answer also
/// as the patient read it in `asked`'s language, a `designation`, when that is another.
pub fn checkin_code_system(base: &FhirBase, words: &Words, asked: &Words) -> Value {
    let concepts = netlink::frame::CHECKIN_DIFFICULTIES
        .iter()
        .map(|code| {
            let id = difficulty_id(code);
            let display = words.patient(&id);
            let mut concept = json!({ "code": code, "display": display,
                "definition": format!("The patient's answer \"{display}\" to \"{}\" after a session.", words.patient("checkin-difficulty-question")) });
            if asked.language() != words.language() {
                concept["designation"] = json!([{ "language": asked.language(), "value": asked.patient(&id) }]);
            }
            concept
        })
        .collect();
    code_system(
        words,
        &base.code_system(CHECKIN),
        "TelerehabSessionCheckIn",
        "Answers of the telerehab session check-in",
        concepts,
    )
}

/// The station's catalogue id of difficulty answer `code` (`about_right`: "Just right").
pub fn difficulty_id(code: &str) -> String {
    let key = if code == "about_right" {
        "just_right"
    } else {
        code
    };
    format!("checkin-difficulty-{}", key.replace('_', "-"))
}

/// A `CodeSystem` at `url` of `concepts` (each with its `unit` property where it has one).
pub fn code_system(
    words: &Words,
    url: &str,
    name: &str,
    title: &str,
    concepts: Vec<Value>,
) -> Value {
    let count = concepts.len();
    let mut cs = json!({
        "resourceType": "CodeSystem",
        "text": words.sentence(words.say("fhir-code-system", &[("title", title.to_owned()), ("count", count.to_string())])),
        "url": url,
        "name": name,
        "title": title,
        "status": "active",
        "content": "complete",
        "caseSensitive": true,
        "count": count,
        "concept": concepts,
    });
    if cs["concept"]
        .as_array()
        .is_some_and(|c| c.iter().any(|c| c.get("property").is_some()))
    {
        cs["property"] =
            json!([{ "code": "unit", "description": "The value's unit, UCUM", "type": "code" }]);
    }
    cs
}
