//! The patient's end-of-session check-in ([`netlink::CheckIn`]: pain, tiredness, how hard it
//! felt) as a `QuestionnaireResponse` a check-in, answering the hub's `Questionnaire` (in the
//! bundle, at the clinic's canonical address [`super::FhirBase::questionnaire`]), whose
//! questions are the station's own words.

use serde_json::{Value, json};

use super::FhirBase;
use super::codes::{CHECKIN, LOINC, PAIN_0_10, difficulty_id};
use super::narrative::{Words, when};
use hub_store::db::{SessionCheckIn, iso_utc};

/// The questionnaire's name under the clinic's base.
pub const QUESTIONNAIRE: &str = "session-checkin";
/// Its version (a response names the version it answers).
pub const VERSION: &str = "1";

/// A 0–10 question: link id, the station's question id.
const SCORES: [(&str, &str); 2] = [
    ("pain", "checkin-pain-question"),
    ("tiredness", "checkin-effort-question"),
];
/// The choice question's link id.
const DIFFICULTY: &str = "difficulty";

/// The canonical URL (with its version) a response answers.
pub fn canonical(base: &FhirBase) -> String {
    format!("{}|{VERSION}", base.questionnaire(QUESTIONNAIRE))
}

/// The check-in's `Questionnaire`: two 0–10 integer questions and one choice, each optional
/// (the patient may skip any), in the words the station asks them.
pub fn questionnaire(base: &FhirBase, words: &Words) -> Value {
    let bound = |url: &str, v: u8| json!({ "url": url, "valueInteger": v });
    let mut items: Vec<Value> = SCORES
        .iter()
        .map(|(link, question)| {
            let mut item = json!({
                "linkId": link,
                "text": words.patient(question),
                "type": "integer",
                "required": false,
                "extension": [
                    bound("http://hl7.org/fhir/StructureDefinition/minValue", 0),
                    bound("http://hl7.org/fhir/StructureDefinition/maxValue", netlink::frame::MAX_CHECKIN_SCORE),
                ],
            });
            if *link == "pain" {
                item["code"] = json!([{ "system": LOINC, "code": PAIN_0_10.0, "display": PAIN_0_10.1 }]);
            }
            item
        })
        .collect();
    let system = base.code_system(CHECKIN);
    items.push(json!({
        "linkId": DIFFICULTY,
        "text": words.patient("checkin-difficulty-question"),
        "type": "choice",
        "required": false,
        "answerOption": netlink::frame::CHECKIN_DIFFICULTIES.iter().map(|code| json!({
            "valueCoding": { "system": system, "code": code, "display": words.patient(&difficulty_id(code)) },
        })).collect::<Vec<_>>(),
    }));
    let rows: Vec<(String, String)> = items
        .iter()
        .map(|i| {
            (
                i["linkId"].as_str().unwrap_or_default().to_owned(),
                i["text"].as_str().unwrap_or_default().to_owned(),
            )
        })
        .collect();
    json!({
        "resourceType": "Questionnaire",
        "text": words.narrative(&[words.say("fhir-questionnaire", &[])], None, &rows),
        "url": base.questionnaire(QUESTIONNAIRE),
        "version": VERSION,
        "name": "TelerehabSessionCheckIn",
        "title": "Telerehab session check-in",
        "status": "active",
        "subjectType": ["Patient"],
        "item": items,
    })
}

/// Check-in `c`'s `QuestionnaireResponse` by `subject` (the patient, who answered), part of
/// the session's Observation `session` when the bundle has it.
pub fn response(
    base: &FhirBase,
    words: &Words,
    c: &SessionCheckIn,
    subject: &str,
    session: Option<&str>,
) -> Value {
    let mut items = Vec::new();
    let mut rows = Vec::new();
    let skipped = || words.say("fhir-answer-skipped", &[]);
    for ((link, question), v) in SCORES.iter().zip([c.pain_0_10, c.tiredness_0_10]) {
        let text = words.patient(question);
        match v {
            Some(v) => {
                rows.push((
                    text.clone(),
                    words.say("fhir-answer-score", &[("value", v.to_string())]),
                ));
                items.push(
                    json!({ "linkId": link, "text": text, "answer": [{ "valueInteger": v }] }),
                );
            }
            None => rows.push((text, skipped())),
        }
    }
    let text = words.patient("checkin-difficulty-question");
    match &c.difficulty {
        Some(code) => {
            let display = words.patient(&difficulty_id(code));
            rows.push((text.clone(), display.clone()));
            items.push(
                json!({ "linkId": DIFFICULTY, "text": text, "answer": [{ "valueCoding": {
                "system": base.code_system(CHECKIN), "code": code, "display": display } }] }),
            );
        }
        None => rows.push((text, skipped())),
    }
    let start = when(c.started_unix_ms);
    let mut r = json!({
        "resourceType": "QuestionnaireResponse",
        "text": words.narrative(&[words.say("fhir-checkin", &[("start", start)])], None, &rows),
        "identifier": { "system": base.identifiers("session"), "value": c.session_id },
        "questionnaire": canonical(base),
        "status": "completed",
        "subject": { "reference": subject },
        "authored": iso_utc(c.received_at_ms),
        "author": { "reference": subject },
        "source": { "reference": subject },
    });
    if let Some(session) = session {
        r["partOf"] = json!([{ "reference": session }]);
    }
    if !items.is_empty() {
        r["item"] = json!(items);
    }
    r
}
