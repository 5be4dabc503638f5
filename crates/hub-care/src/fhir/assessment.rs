//! The standard assessment (issue 42, `exercises::assessment`) as its own group of Observations,
//! never mixed with the exercise sessions': one panel Observation an assessment (code
//! `standard-assessment`, `method` the protocol's version), whose `hasMember`s are one
//! Observation a part (active range, tracking slow / medium / fast, steps, strength; code the
//! part, `method` the protocol), each part's measures its `component`s, rounded to their
//! resolution with their UCUM unit as the session's are. Category `exam` (a standardised motor
//! test, as the clinical scales are), performed by the patient on the station's Device;
//! `effectiveDateTime` the session's start (the assessment runs first; the parts' own times are
//! not stored). The codes are the hub's `assessment` code system ([`code_system`]), each
//! protocol and part defined from the protocol's constants.

use std::collections::BTreeSet;

use regimen::assessment::protocol::{self, AssessmentPart};
use serde_json::{Value, json};

use super::codes::{self, MEASURES, UCUM};
use super::narrative::{Words, when};
use super::{Export, FhirBase, entry};
use hub_store::db::{Assessment, iso_utc};

/// The name of the assessment's code system under the clinic's base.
pub const ASSESSMENT: &str = "assessment";
/// The panel's code.
pub const PANEL: &str = "standard-assessment";
/// The panel's English display.
const PANEL_DISPLAY: &str = "Telerehab standard assessment";

/// The code of protocol version `v` (`protocol-1`), the Observations' `method`.
pub fn protocol_code(v: u32) -> String {
    format!("protocol-{v}")
}

/// The English display of protocol version `v`.
fn protocol_display(v: u32) -> String {
    format!("Standard assessment protocol, version {v}")
}

/// What protocol version `v` is, in one paragraph from its constants; a version this hub's
/// software does not know is named, not described.
fn protocol_definition(v: u32) -> String {
    if v != protocol::PROTOCOL_VERSION {
        return format!(
            "Version {v} of the station's standard assessment protocol (crates/exercises/src/assessment.rs of the station software that ran it); its results are not comparable with another version's."
        );
    }
    let f = protocol::TRACKING_FREQUENCIES_RAD_S;
    format!(
        "The same fixed test for every patient and every time, without assistance, the wheel's feel fixed (spring {} N.m/rad, damper {} N.m.s/rad, no added inertia): active range ({} s at each end of the wheel), tracking a {} deg sine at {}, {} and {} rad/s ({} s each), {} deg target steps held {}-{} s at unpredictable times ({} s), strength each side against a {} N.m/rad spring whose limit rises {} N.m/s ({} s a side). Source: crates/exercises/src/assessment.rs, protocol version {v}.",
        protocol::WHEEL_SPRING_NM_PER_RAD,
        protocol::WHEEL_DAMPER_NM_S_PER_RAD,
        protocol::RANGE_HOLD_S,
        protocol::TRACKING_AMPLITUDE_DEG,
        f[0],
        f[1],
        f[2],
        protocol::TRACKING_S,
        protocol::STEP_DEG,
        protocol::STEP_MIN_HOLD_S,
        protocol::STEP_MAX_HOLD_S,
        protocol::STEPS_S,
        protocol::STRENGTH_STIFFNESS_NM_PER_RAD,
        protocol::STRENGTH_RAMP_NM_PER_S,
        protocol::STRENGTH_SIDE_S,
    )
}

/// A part's English display and definition (the code system's).
fn part_words(p: AssessmentPart) -> (&'static str, &'static str) {
    match p {
        AssessmentPart::Range => (
            "Active range each way",
            "The needle stands at the wheel's end on the left, then on the right: the patient turns as far as they can and holds; measured as the wheel's range of motion.",
        ),
        AssessmentPart::TrackingSlow => (
            "Tracking, slow",
            "The patient follows a needle moving as a slow sine (the protocol's first frequency); measured as the angle error.",
        ),
        AssessmentPart::TrackingMedium => (
            "Tracking, medium",
            "The patient follows a needle moving as a sine at the protocol's second frequency; measured as the angle error.",
        ),
        AssessmentPart::TrackingFast => (
            "Tracking, fast",
            "The patient follows a needle moving as a fast sine (the protocol's third frequency); measured as the angle error.",
        ),
        AssessmentPart::Steps => (
            "Target steps",
            "The needle jumps a fixed angle at unpredictable times: each step is one discrete movement, measured by reaction and movement time, smoothness (SPARC, LDLJ), path length ratio and initial direction error.",
        ),
        AssessmentPart::Strength => (
            "Strength each side",
            "The patient turns against a spring whose limit rises: the peak and sustained torque each way.",
        ),
    }
}

/// The part a stored exercise kind names (`assessment-steps`), if it is one.
fn part_of(kind: &str) -> Option<AssessmentPart> {
    kind.strip_prefix("assessment-")
        .and_then(AssessmentPart::from_name)
}

/// The part's name in the export's words (the console's `progress-assessment-part-<part>`).
fn part_said(words: &Words, p: AssessmentPart) -> String {
    words
        .say_if(&format!("progress-assessment-part-{}", p.name()), &[])
        .unwrap_or_else(|| part_words(p).0.to_owned())
}

impl Export<'_> {
    /// The code of `code` in the assessment's code system.
    fn assessment_coding(&self, code: &str, display: &str) -> Value {
        json!({ "system": self.base.code_system(ASSESSMENT), "code": code, "display": display })
    }

    /// The `method` of assessment `a`: its protocol's version (and, in words, its seed).
    fn assessment_method(&self, a: &Assessment) -> Value {
        json!({
            "coding": [self.assessment_coding(&protocol_code(a.protocol), &protocol_display(a.protocol))],
            "text": self.words.say("fhir-assessment-method", &[("protocol", a.protocol.to_string()), ("seed", a.seed.to_string())]),
        })
    }

    /// What every Observation of assessment `a` shares: status, category, subject, time,
    /// performer (the patient), device (the station), method.
    fn assessment_base(&self, a: &Assessment, device: Option<&str>) -> Value {
        let mut o = json!({
            "resourceType": "Observation",
            "status": "final",
            "category": Self::category("exam", "Exam"),
            "subject": { "reference": self.subject },
            "effectiveDateTime": iso_utc(a.started_unix_ms),
            "performer": [{ "reference": self.subject }],
            "method": self.assessment_method(a),
        });
        if let Some(d) = device {
            o["device"] = json!({ "reference": d });
        }
        o
    }

    /// Assessment `a`'s entries, the panel first, then a part each (in course order), on the
    /// station `device`; the measure names its parts use are added to `names`.
    pub(super) fn assessment_entries<'a>(
        &self,
        a: &'a Assessment,
        device: Option<&str>,
        names: &mut BTreeSet<&'a str>,
    ) -> Vec<(String, Value)> {
        let measures_system = self.base.code_system(MEASURES);
        let start = when(a.started_unix_ms);
        let mut parts = Vec::new();
        for e in &a.parts {
            let Some(part) = part_of(&e.kind) else {
                continue;
            };
            let mut rows = Vec::new();
            let components: Vec<Value> = e
                .scores
                .iter()
                .filter_map(|(name, v)| {
                    let value = codes::measure_value(name, *v)?;
                    let unit = codes::ucum_unit(name);
                    let shown = metrics::words::measure_words(name)
                        .map_or_else(|| format!("{value} {unit}"), |m| m.format(value));
                    rows.push((self.words.measure(name), shown));
                    names.insert(name.as_str());
                    Some(json!({
                        "code": { "coding": [{ "system": measures_system, "code": name, "display": codes::measure_display(name) }] },
                        "valueQuantity": { "value": value, "unit": unit, "system": UCUM, "code": unit },
                    }))
                })
                .collect();
            let said = part_said(&self.words, part);
            let line = self.words.say(
                "fhir-assessment-part",
                &[
                    ("part", said.clone()),
                    ("start", start.clone()),
                    ("protocol", a.protocol.to_string()),
                ],
            );
            let head = (
                self.words.say("fhir-measure", &[]),
                self.words.say("fhir-value", &[]),
            );
            let mut o = self.assessment_base(a, device);
            o["text"] = self.words.narrative(&[line], Some(head), &rows);
            o["identifier"] = json!([{ "system": self.base.identifiers(ASSESSMENT), "value": format!("{}/{}", a.session_id, part.name()) }]);
            o["code"] = json!({ "coding": [self.assessment_coding(part.name(), part_words(part).0)], "text": said });
            if !components.is_empty() {
                o["component"] = json!(components);
            }
            parts.push(entry(
                "Observation",
                &format!("assessment/{}/{}", a.session_id, part.name()),
                o,
            ));
        }
        let said: Vec<String> = a
            .parts
            .iter()
            .filter_map(|e| part_of(&e.kind))
            .map(|p| part_said(&self.words, p))
            .collect();
        let line = self.words.say(
            "fhir-assessment",
            &[
                ("start", start),
                ("protocol", a.protocol.to_string()),
                ("seed", a.seed.to_string()),
                (
                    "parts",
                    said.join(&self.words.say("progress-list-separator", &[])),
                ),
            ],
        );
        let mut panel = self.assessment_base(a, device);
        panel["text"] = self.words.sentence(line);
        panel["identifier"] =
            json!([{ "system": self.base.identifiers(ASSESSMENT), "value": a.session_id }]);
        panel["code"] = json!({ "coding": [self.assessment_coding(PANEL, PANEL_DISPLAY)], "text": self.words.say("fhir-assessment-title", &[]) });
        if !parts.is_empty() {
            panel["hasMember"] = json!(
                parts
                    .iter()
                    .map(|(url, _)| json!({ "reference": url }))
                    .collect::<Vec<_>>()
            );
        }
        let mut out = vec![entry(
            "Observation",
            &format!("assessment/{}", a.session_id),
            panel,
        )];
        out.extend(parts);
        out
    }
}

/// The assessment's `CodeSystem`: the panel, each protocol version `protocols` holds, and the
/// parts, each with its definition.
pub fn code_system(base: &FhirBase, words: &Words, protocols: &BTreeSet<u32>) -> Value {
    let mut concepts = vec![json!({
        "code": PANEL, "display": PANEL_DISPLAY,
        "definition": "The station's standard motor assessment on the wheel: one fixed, versioned protocol, the same for every patient, without assistance, kept apart from the exercise sessions; its parts are its members.",
    })];
    concepts.extend(protocols.iter().map(|v| {
        json!({ "code": protocol_code(*v), "display": protocol_display(*v), "definition": protocol_definition(*v) })
    }));
    concepts.extend(AssessmentPart::ALL.iter().map(|p| {
        let (display, definition) = part_words(*p);
        json!({ "code": p.name(), "display": display, "definition": definition })
    }));
    codes::code_system(
        words,
        &base.code_system(ASSESSMENT),
        "TelerehabStandardAssessment",
        "Telerehab standard assessment",
        concepts,
    )
}

#[cfg(test)]
mod tests {
    use super::{AssessmentPart, part_of, protocol_definition};

    #[test]
    fn protocol_one_is_defined_from_its_constants_and_a_part_is_read_from_its_kind() {
        let d = protocol_definition(1);
        assert!(
            d.contains("0.5, 1 and 2 rad/s") && d.contains("20 deg target steps"),
            "{d}"
        );
        assert!(protocol_definition(7).contains("Version 7"));
        assert_eq!(part_of("assessment-steps"), Some(AssessmentPart::Steps));
        assert_eq!(
            part_of("assessment-tracking-fast"),
            Some(AssessmentPart::TrackingFast)
        );
        assert_eq!(part_of("sine-road"), None);
    }
}
