//! The regimen's JSON Schema states exactly the bounds its validator enforces: for every
//! numeric field the schema bounds, a regimen at the bound is accepted and one just beyond it
//! is refused, and every bound in the schema is reached by a sample regimen.

use std::collections::BTreeSet;

use exercises::exercise::ExerciseSpec;
use regimen::{MAX_DEVICE_TORQUE_NM, MAX_EXERCISES, Regimen};
use serde_json::{Value, json};

/// A numeric field met while walking a sample regimen: where it is in the sample, and the
/// schema object holding its bounds.
struct Leaf<'s> {
    path: Vec<PathStep>,
    schema: &'s Value,
}

#[derive(Clone, Debug)]
enum PathStep {
    Key(String),
    Index(usize),
}

/// `schema` with a `$ref` followed (one level; the regimen's schema nests by reference).
fn resolve<'s>(root: &'s Value, schema: &'s Value) -> &'s Value {
    match schema.get("$ref").and_then(Value::as_str) {
        Some(r) => root
            .pointer(r.trim_start_matches('#'))
            .unwrap_or_else(|| panic!("dangling {r}")),
        None => schema,
    }
}

/// Whether `branch` (of a oneOf/anyOf) describes `instance`: its constants match and every key
/// of the instance is one of its properties (or it allows any).
fn branch_fits(root: &Value, branch: &Value, instance: &Value) -> bool {
    let branch = resolve(root, branch);
    match instance {
        Value::Object(map) => {
            let Some(props) = branch.get("properties").and_then(Value::as_object) else {
                return false;
            };
            let consts_match = props.iter().all(|(k, p)| match p.get("const") {
                Some(c) => map.get(k) == Some(c),
                None => true,
            });
            consts_match
                && map.keys().all(|k| {
                    props.contains_key(k)
                        || !branch
                            .get("additionalProperties")
                            .is_some_and(|a| a == false)
                })
        }
        Value::Null => branch.get("type").is_some_and(|t| t == "null"),
        _ => branch.get("type").is_some_and(|t| t != "null"),
    }
}

/// The property schemas that apply to an object `instance` under `schema`: its own and those
/// of the oneOf/anyOf branch it matches and of allOf parts.
fn properties_for<'s>(
    root: &'s Value,
    schema: &'s Value,
    instance: &Value,
    out: &mut Vec<(&'s str, &'s Value)>,
) {
    let schema = resolve(root, schema);
    if let Some(props) = schema.get("properties").and_then(Value::as_object) {
        out.extend(props.iter().map(|(k, v)| (k.as_str(), v)));
    }
    for key in ["oneOf", "anyOf"] {
        if let Some(branches) = schema.get(key).and_then(Value::as_array) {
            let fit: Vec<&Value> = branches
                .iter()
                .filter(|b| branch_fits(root, b, instance))
                .collect();
            assert!(
                !fit.is_empty(),
                "no {key} branch of {schema} fits {instance}"
            );
            properties_for(root, fit[0], instance, out);
        }
    }
    if let Some(parts) = schema.get("allOf").and_then(Value::as_array) {
        for p in parts {
            properties_for(root, p, instance, out);
        }
    }
}

/// Every numeric field of `instance` with its schema, depth first.
fn walk<'s>(
    root: &'s Value,
    schema: &'s Value,
    instance: &Value,
    path: &mut Vec<PathStep>,
    out: &mut Vec<Leaf<'s>>,
) {
    let schema = resolve(root, schema);
    match instance {
        Value::Object(map) => {
            let mut props = Vec::new();
            properties_for(root, schema, instance, &mut props);
            for (k, v) in map {
                let sub = props
                    .iter()
                    .find(|(name, _)| name == k)
                    .unwrap_or_else(|| panic!("{k} of {path:?} is not in the schema"))
                    .1;
                path.push(PathStep::Key(k.clone()));
                walk(root, sub, v, path, out);
                path.pop();
            }
        }
        Value::Array(items) => {
            let item = schema
                .get("items")
                .unwrap_or_else(|| panic!("no items at {path:?}"));
            for (i, v) in items.iter().enumerate() {
                path.push(PathStep::Index(i));
                walk(root, item, v, path, out);
                path.pop();
            }
        }
        Value::Number(_) => {
            // An optional number is `{"type": ["number", "null"]}` with its bounds, or an
            // anyOf of it and null.
            let schema = match schema.get("anyOf").and_then(Value::as_array) {
                Some(b) => resolve(
                    root,
                    b.iter().find(|b| branch_fits(root, b, instance)).unwrap(),
                ),
                None => schema,
            };
            out.push(Leaf {
                path: path.clone(),
                schema,
            });
        }
        _ => {}
    }
}

fn set(instance: &mut Value, path: &[PathStep], value: Value) {
    let mut at = instance;
    for step in path {
        at = match step {
            PathStep::Key(k) => &mut at[k.as_str()],
            PathStep::Index(i) => &mut at[*i],
        };
    }
    *at = value;
}

fn accepted(instance: &Value) -> Result<(), String> {
    let value = toml::Value::try_from(instance).map_err(|e| format!("not TOML: {e}"))?;
    let text = toml::to_string(&value).map_err(|e| format!("not TOML: {e}"))?;
    Regimen::from_toml(&text, "sample")
        .map(|_| ())
        .map_err(|e| e.to_string())
}

fn is_integer(schema: &Value) -> bool {
    match &schema["type"] {
        Value::String(t) => t == "integer",
        Value::Array(ts) => ts.iter().any(|t| t == "integer"),
        _ => false,
    }
}

/// One exercise per sample regimen, so a field at its bound is the only thing that changes
/// (several exercises together could pass the session's planned length).
fn samples() -> Vec<Value> {
    let mut out = Vec::new();
    let with_time_limit = |mut e: Value| {
        if e.get("duration_s").is_some_and(Value::is_null) {
            e["duration_s"] = json!(60.0);
        }
        e
    };
    for name in exercises::exercise::EXERCISE_NAMES {
        let mut e = serde_json::to_value(ExerciseSpec::from_name(name).unwrap()).unwrap();
        if name == "triangle-road" {
            // The largest corner radius depends on amplitude and wavelength: the smallest
            // fits every amplitude and wavelength at their bounds.
            e["corner_radius_m"] = json!(3.0);
        }
        if name == "dial-multi-sine" {
            // The components' amplitudes together stay within the wheel's range: one
            // component can then reach it alone.
            e["reference"]["components"] =
                json!([{ "amplitude_deg": 60.0, "frequency_rad_s": 1.0, "phase_rad": 0.0 }]);
        }
        out.push(json!({ "sessions_per_week": 3, "exercise": [with_time_limit(e)] }));
    }
    // The standard assessment's schedule, and its random steps as a prescribed dial (the
    // holds span the whole range, so each hold reaches its bound with the other in range).
    out.push(json!({
        "assessment": { "every_days": 7 },
        "exercise": [{ "kind": "dial", "duration_s": 60.0,
                       "reference": { "signal": "random-steps", "amplitude_deg": 20.0,
                                      "min_hold_s": 0.5, "max_hold_s": 60.0, "seed": 3 } }]
    }));
    // The trunk cue's threshold.
    out.push(json!({
        "trunk": { "cue_deg": 15.0 },
        "exercise": [{ "kind": "dial", "duration_s": 60.0 }]
    }));
    out.push(json!({
        "patient": { "language": "de", "neglected_side": "left", "speech": true,
                     "speech_volume_pct": 80, "start_after_rest_s": 10.0 },
        "exercise": [{ "kind": "dial", "duration_s": 60.0 }]
    }));
    let effects = json!([
        { "kind": { "condition": { "kind": "spring", "offset": 0.0, "positive_coefficient": 1.0,
            "negative_coefficient": 1.0, "positive_saturation_nm": 1.0, "negative_saturation_nm": 1.0,
            "deadband": 0.1 } } },
        { "kind": { "constant": { "level_nm": 0.2 } }, "start_delay_s": 1.0, "duration_s": 2.0, "gain": 0.5,
          "envelope": { "attack_level_nm": 0.0, "attack_time_s": 0.5, "fade_level_nm": 0.0, "fade_time_s": 0.5 } },
        { "kind": { "ramp": { "start_nm": 0.0, "end_nm": 0.5 } }, "duration_s": 2.0 },
        { "kind": { "periodic": { "waveform": "sine", "magnitude_nm": 0.1, "offset_nm": 0.0,
            "phase_rad": 0.0, "period_s": 0.5 } }, "duration_s": 3.0 },
    ]);
    let model = serde_json::to_value(haptic_wheel::SpringDamper::default()).unwrap();
    // A rest after an exercise.
    out.push(json!({ "exercise": [{ "kind": "dial", "duration_s": 60.0, "rest_s": 30.0 }] }));
    // A dial whose target drifts into the neglected side.
    out.push(json!({ "exercise": [{ "kind": "dial", "duration_s": 60.0, "drift_deg": 30.0 }] }));
    // Difficulty that follows the patient, over the widest bounds.
    // (The start lies between the lowest and the highest: each is pushed to its edges in a
    // sample of its own, the others at their defaults.)
    out.push(
        json!({ "exercise": [{ "kind": "dial", "duration_s": 60.0 }],
        "difficulty": { "target_success": 0.7, "lowest": 0.0, "highest": 1.0 } }),
    );
    out.push(
        json!({ "exercise": [{ "kind": "dial", "duration_s": 60.0 }],
        "difficulty": { "start": 0.5 } }),
    );
    out.push(json!({ "exercise": [{ "kind": "dial", "duration_s": 60.0,
        "haptic": { "effects": effects, "model": model, "ceiling_nm": 5.0 } }] }));
    use assist::spec::*;
    let modes = [
        AssistMode::None {},
        AssistMode::Resist(ResistParams::default()),
        AssistMode::Motion(MotionParams::default()),
        AssistMode::Force(ForceParams::default()),
        AssistMode::Hybrid(HybridParams::default()),
        AssistMode::AssistAsNeeded(AanParams::default()),
    ];
    for mode in modes {
        let assist = serde_json::to_value(AssistSpec {
            model: ModelSpec::default(),
            mode,
        })
        .unwrap();
        out.push(json!({ "exercise": [{ "kind": "dial", "duration_s": 60.0, "assist": assist }] }));
    }
    out
}

/// Bounds that another field of the same sample makes unreachable, with the reason: the
/// schema states the field's own range, the validator also the relation.
const RELATIONAL: [(&str, &str, &str); 2] = [
    (
        "lower_rad",
        "maximum",
        "upper_rad must be above it and is at most π too",
    ),
    (
        "upper_rad",
        "minimum",
        "it must be above lower_rad, which is at least −π",
    ),
];

fn name_of(path: &[PathStep]) -> String {
    path.iter()
        .map(|s| match s {
            PathStep::Key(k) => k.clone(),
            PathStep::Index(i) => i.to_string(),
        })
        .collect::<Vec<_>>()
        .join(".")
}

/// Check one leaf's bounds; returns the schema keywords checked.
fn check_leaf(sample: &Value, leaf: &Leaf<'_>, failures: &mut Vec<String>) {
    let field = match leaf.path.last() {
        Some(PathStep::Key(k)) => k.as_str(),
        _ => "item",
    };
    let int = is_integer(leaf.schema);
    let num = |v: f64| if int { json!(v as i64) } else { json!(v) };
    let beyond = |v: f64, up: bool| match (int, up) {
        (true, true) => v + 1.0,
        (true, false) => v - 1.0,
        (false, true) => v.next_up(),
        (false, false) => v.next_down(),
    };
    let mut probe = |value: Value, want_ok: bool, what: &str| {
        let mut s = sample.clone();
        set(&mut s, &leaf.path, value.clone());
        let got = accepted(&s);
        if got.is_ok() != want_ok {
            failures.push(format!(
                "{} = {value} ({what}): {got:?}",
                name_of(&leaf.path)
            ));
        }
    };
    for (keyword, up) in [("maximum", true), ("minimum", false)] {
        if let Some(b) = leaf.schema.get(keyword).and_then(Value::as_f64) {
            let relational = RELATIONAL
                .iter()
                .any(|(f, k, _)| *f == field && *k == keyword);
            if !relational {
                probe(num(b), true, &format!("at the schema's {keyword}"));
            }
            let out = beyond(b, up);
            // An unsigned field below 0 is refused by the parser: still refused.
            probe(
                if int && out < 0.0 {
                    json!(out as i64)
                } else {
                    num(out)
                },
                false,
                &format!("beyond the schema's {keyword}"),
            );
        }
    }
    if let Some(b) = leaf.schema.get("exclusiveMinimum").and_then(Value::as_f64) {
        probe(num(b), false, "at the schema's exclusiveMinimum");
        probe(
            num(beyond(b, true)),
            true,
            "just above the schema's exclusiveMinimum",
        );
    }
}

/// Every schema object carrying a numeric bound, by JSON pointer.
fn bounded_objects<'s>(v: &'s Value, at: String, out: &mut Vec<(String, &'s Value)>) {
    match v {
        Value::Object(map) => {
            if ["minimum", "maximum", "exclusiveMinimum"]
                .iter()
                .any(|k| map.contains_key(*k))
            {
                out.push((at.clone(), v));
            }
            for (k, sub) in map {
                bounded_objects(sub, format!("{at}/{k}"), out);
            }
        }
        Value::Array(items) => {
            for (i, sub) in items.iter().enumerate() {
                bounded_objects(sub, format!("{at}/{i}"), out);
            }
        }
        _ => {}
    }
}

#[test]
fn every_schema_bound_is_the_validators_edge_accepted_at_it_and_refused_just_beyond() {
    let schema = Regimen::json_schema();
    let mut failures = Vec::new();
    let mut reached = BTreeSet::new();
    for sample in samples() {
        accepted(&sample).unwrap_or_else(|e| panic!("sample {sample} refused: {e}"));
        let mut leaves = Vec::new();
        walk(&schema, &schema, &sample, &mut Vec::new(), &mut leaves);
        for leaf in &leaves {
            reached.insert(std::ptr::from_ref(leaf.schema) as usize);
            check_leaf(&sample, leaf, &mut failures);
        }
    }
    assert!(
        failures.is_empty(),
        "schema and validator disagree:\n{}",
        failures.join("\n")
    );
    let mut all = Vec::new();
    bounded_objects(&schema, String::new(), &mut all);
    let unreached: Vec<&str> = all
        .iter()
        .filter(|(_, v)| !reached.contains(&(std::ptr::from_ref(*v) as usize)))
        .map(|(at, _)| at.as_str())
        .collect();
    assert!(
        unreached.is_empty(),
        "bounds no sample reaches: {unreached:?}"
    );
    assert!(all.len() > 60, "only {} bounded fields", all.len());
}

#[test]
fn the_schema_names_every_exercise_kind_and_the_regimen_wide_limits() {
    let schema = Regimen::json_schema();
    let text = schema.to_string();
    for kind in [
        "straight",
        "sine",
        "triangle",
        "clothoid",
        "sharp-turns",
        "s-bend",
        "lane-change",
        "slalom",
        "dial",
    ] {
        assert!(
            text.contains(&format!("\"const\":\"{kind}\"")),
            "kind {kind} missing"
        );
    }
    assert_eq!(
        schema["properties"]["exercise"]["maxItems"],
        json!(MAX_EXERCISES)
    );
    assert_eq!(schema["properties"]["exercise"]["minItems"], json!(1));
    assert_eq!(
        schema["properties"]["sessions_per_week"]["maximum"],
        json!(28)
    );
    assert_eq!(
        schema["$defs"]["HapticRegimen"]["properties"]["ceiling_nm"]["maximum"],
        json!(MAX_DEVICE_TORQUE_NM)
    );
    assert_eq!(
        schema[regimen::MAX_PLANNED_SESSION_KEYWORD],
        json!(regimen::MAX_PLANNED_SESSION_S)
    );
}
