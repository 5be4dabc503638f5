//! A patient's record as a FHIR R4 `Bundle` (type `collection`), for the clinic's electronic
//! health record (`GET /api/patients/{id}/fhir`, `hub export --fhir`; docs/FHIR.md describes
//! every resource):
//!
//! - `Patient`: the pseudonym as its only identifier (no name, no birth date);
//! - a `Device` a station that recorded a session, a `Practitioner` a therapist who recorded a
//!   scale (by the hub's id only);
//! - the current regimen as a `CarePlan` whose activity is a `ServiceRequest` coded SNOMED CT
//!   229065009 "Exercise therapy", its timing the regimen's sessions a week and planned length;
//! - one `Observation` a session (category `activity`), a `component` a measure rounded to its
//!   resolution with its UCUM unit, performed by the patient on the station's Device; and,
//!   as the HL7 Physical Activity IG models activity, its exercise time as an Observation of
//!   LOINC 55411-3 "Exercise duration" in minutes ([`codes`] lists the LOINC codes searched);
//! - one `Observation` a clinical scale, performed by the therapist who recorded it;
//! - the check-in after a session as a `QuestionnaireResponse` ([`checkin`]) to the hub's
//!   `Questionnaire`;
//! - the hub's code systems as `CodeSystem` resources, each code with its definition and unit,
//!   at the clinic's canonical address ([`FhirBase`]).
//!
//! Every resource has a generated narrative ([`mod@narrative`]). Resource ids and `fullUrl`s
//! (`urn:uuid:…`) are derived from the hub's own ids by SHA-256, so the same record exports
//! the same ids every time.

pub mod assessment;
mod base;
pub mod checkin;
pub mod codes;
pub mod narrative;

use std::collections::{BTreeMap, BTreeSet};

use serde_json::{Value, json};

pub use base::FhirBase;
use codes::{EXERCISE_DURATION, LOINC, MEASURES, SCALES, UCUM};
pub use codes::{measure_definition, ucum_unit};
pub use narrative::Words;
use narrative::when;

use hub_store::HubError;
use hub_store::db::{Db, NamedSession, Patient, ScaleEntry, iso_utc};

/// The observation category of HL7's code system (`activity`, `exam`).
const CATEGORY: &str = "http://terminology.hl7.org/CodeSystem/observation-category";

/// A stable UUID (its text) for `kind`/`id`: the first 16 bytes of their SHA-256, marked as
/// an RFC 9562 version 8 (custom) UUID.
fn uuid_of(kind: &str, id: &str) -> String {
    let h = hub_store::db::sha256_hex(format!("telerehab:{kind}/{id}").as_bytes());
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

/// What one export writes with: the clinic's base, the words, the patient's reference.
struct Export<'a> {
    base: &'a FhirBase,
    words: Words,
    subject: String,
}

impl Export<'_> {
    fn category(code: &str, display: &str) -> Value {
        json!([{ "coding": [{ "system": CATEGORY, "code": code, "display": display }] }])
    }

    fn patient_of(base: &FhirBase, words: &Words, p: &Patient) -> Value {
        json!({
            "resourceType": "Patient",
            "text": words.sentence(words.say("fhir-patient", &[("pseudonym", p.pseudonym.clone())])),
            "identifier": [{ "use": "usual", "system": base.identifiers("pseudonym"), "value": p.pseudonym }],
            "active": true,
        })
    }

    /// The station `station_id` (its software `version`) the patient exercised on.
    fn device(&self, station_id: &str, version: &str) -> Value {
        json!({
            "resourceType": "Device",
            "text": self.words.sentence(self.words.say("fhir-device", &[("station", station_id.to_owned()), ("version", version.to_owned())])),
            "identifier": [{ "system": self.base.identifiers("station"), "value": station_id }],
            "status": "active",
            "deviceName": [{ "name": "telerehab station", "type": "user-friendly-name" }],
            "type": { "text": self.words.say("fhir-device-type", &[]) },
            "version": [{ "value": version }],
            "patient": { "reference": self.subject },
        })
    }

    /// The therapist `id` who recorded a scale (by the hub's id: no name, no mail).
    fn practitioner(&self, id: &str) -> Value {
        json!({
            "resourceType": "Practitioner",
            "text": self.words.sentence(self.words.say("fhir-therapist", &[("id", id.to_owned())])),
            "identifier": [{ "system": self.base.identifiers("therapist"), "value": id }],
        })
    }

    /// The regimen's CarePlan and ServiceRequest (in that order), when the patient has one.
    async fn regimen_entries(
        &self,
        db: &Db,
        p: &Patient,
    ) -> Result<Vec<(String, Value)>, HubError> {
        let Some(rx) = db.latest_regimen(&p.id).await? else {
            return Ok(Vec::new());
        };
        let parsed = regimen::Regimen::from_toml(&rx.toml, "the stored regimen").ok();
        let key = format!("{}/v{}", p.id, rx.version);
        // The regimen by the patient's pseudonym: the hub's own patient id stays in the hub.
        let identifier = json!([{ "system": self.base.identifiers("regimen"), "value": format!("{}/v{}", p.pseudonym, rx.version) }]);
        let mut repeat = serde_json::Map::new();
        let mut lines = Vec::new();
        let exercises = parsed.as_ref().map_or(0, |r| r.exercises.len());
        lines.push(
            self.words
                .say("fhir-request", &[("exercises", exercises.to_string())]),
        );
        let per_week = parsed.as_ref().and_then(|r| r.sessions_per_week);
        let minutes = parsed
            .as_ref()
            .and_then(|r| r.planned_duration_s().ok())
            .map(|s| metrics::words::round_to(s / 60.0, 1));
        if let Some(n) = per_week {
            repeat.insert("frequency".into(), json!(n));
            repeat.insert("period".into(), json!(1));
            repeat.insert("periodUnit".into(), json!("wk"));
        }
        if let Some(m) = minutes {
            repeat.insert("duration".into(), json!(m));
            repeat.insert("durationUnit".into(), json!("min"));
        }
        if let (Some(n), Some(m)) = (per_week, minutes) {
            lines.push(self.words.say(
                "fhir-request-week",
                &[("sessions", n.to_string()), ("minutes", m.to_string())],
            ));
        }
        let authored = iso_utc(rx.prescribed_at_ms);
        let title = self
            .words
            .say("fhir-regimen-title", &[("version", rx.version.to_string())]);
        let mut request = json!({
            "resourceType": "ServiceRequest",
            "text": self.words.narrative(&lines, None, &[]),
            "identifier": identifier,
            "status": "active",
            "intent": "order",
            "code": { "coding": [{ "system": "http://snomed.info/sct", "code": "229065009", "display": "Exercise therapy" }],
                      "text": self.words.say("fhir-request-text", &[("title", title.clone()), ("exercises", exercises.to_string())]) },
            "subject": { "reference": self.subject },
            "authoredOn": authored,
        });
        if !repeat.is_empty() {
            request["occurrenceTiming"] = json!({ "repeat": repeat });
        }
        let (request_url, request_entry) = entry("ServiceRequest", &key, request);
        let day = authored.get(..10).unwrap_or(&authored).to_owned();
        let plan = json!({
            "resourceType": "CarePlan",
            "text": self.words.sentence(self.words.say("fhir-regimen", &[("version", rx.version.to_string()), ("day", day)])),
            "identifier": identifier,
            "status": "active",
            "intent": "plan",
            "title": title,
            "subject": { "reference": self.subject },
            "created": authored,
            "activity": [{ "reference": { "reference": request_url } }],
        });
        Ok(vec![
            entry("CarePlan", &key, plan),
            (request_url, request_entry),
        ])
    }

    /// A session's effective period: the station's start, and when the hub heard the end.
    fn period(s: &NamedSession) -> Value {
        let mut period = json!({ "start": iso_utc(s.row.started_unix_ms) });
        if let Some(end) = s.row.closed_at_ms {
            period["end"] = json!(iso_utc(end.max(s.row.started_unix_ms)));
        }
        period
    }

    fn status(s: &NamedSession) -> &'static str {
        if s.row.closed_at_ms.is_some() {
            "final"
        } else {
            "preliminary"
        }
    }

    /// A session's Observation: its measures as components, rounded to their resolution,
    /// performed by the patient on `device`; `members` its exercise duration's Observation.
    fn session(
        &self,
        s: &NamedSession,
        measures: Option<&BTreeMap<String, f64>>,
        device: &str,
        members: &[String],
    ) -> Value {
        let system = self.base.code_system(MEASURES);
        let mut rows = Vec::new();
        let components: Vec<Value> = measures
            .into_iter()
            .flatten()
            .filter_map(|(name, v)| {
                let value = codes::measure_value(name, *v)?;
                let unit = ucum_unit(name);
                let display = codes::measure_display(name);
                let shown = metrics::words::measure_words(name)
                    .map_or_else(|| format!("{value} {unit}"), |m| m.format(value));
                rows.push((self.words.measure(name), shown));
                Some(json!({
                    "code": { "coding": [{ "system": system, "code": name, "display": display }] },
                    "valueQuantity": { "value": value, "unit": unit, "system": UCUM, "code": unit },
                }))
            })
            .collect();
        let exercises = self.words.exercises(&s.exercise_shorts, &s.exercise_name);
        let mut lines = vec![self.words.say(
            "fhir-session",
            &[
                ("start", when(s.row.started_unix_ms)),
                ("exercise", exercises.clone()),
            ],
        )];
        if s.row.closed_at_ms.is_none() {
            lines.push(self.words.say("fhir-session-open", &[]));
        }
        let head = (
            self.words.say("fhir-measure", &[]),
            self.words.say("fhir-value", &[]),
        );
        let mut o = json!({
            "resourceType": "Observation",
            "text": self.words.narrative(&lines, Some(head), &rows),
            "identifier": [{ "system": self.base.identifiers("session"), "value": s.row.session_id }],
            "status": Self::status(s),
            "category": Self::category("activity", "Activity"),
            "code": { "coding": [{ "system": system, "code": "session", "display": "Telerehabilitation session measures" }],
                      "text": self.words.say("fhir-session-text", &[("exercise", exercises)]) },
            "subject": { "reference": self.subject },
            "effectivePeriod": Self::period(s),
            "performer": [{ "reference": self.subject }],
            "device": { "reference": device },
        });
        if !components.is_empty() {
            o["component"] = json!(components);
        }
        if !members.is_empty() {
            o["hasMember"] = json!(
                members
                    .iter()
                    .map(|m| json!({ "reference": m }))
                    .collect::<Vec<_>>()
            );
        }
        o
    }

    /// A session's exercise time as the HL7 Physical Activity IG's activity measure: LOINC
    /// 55411-3 "Exercise duration", in minutes (to 0.01 min, the resolution of `active_s`'s
    /// whole seconds).
    fn exercise_duration(&self, s: &NamedSession, active_s: f64, device: &str) -> Option<Value> {
        let seconds = codes::measure_value("active_s", active_s)?;
        let minutes = metrics::words::round_to(seconds / 60.0, 2);
        Some(json!({
            "resourceType": "Observation",
            "text": self.words.sentence(self.words.say("fhir-duration", &[("start", when(s.row.started_unix_ms)), ("minutes", minutes.to_string())])),
            "status": Self::status(s),
            "category": Self::category("activity", "Activity"),
            "code": { "coding": [{ "system": LOINC, "code": EXERCISE_DURATION.0, "display": EXERCISE_DURATION.1 }] },
            "subject": { "reference": self.subject },
            "effectivePeriod": Self::period(s),
            "performer": [{ "reference": self.subject }],
            "device": { "reference": device },
            "valueQuantity": { "value": minutes, "unit": "min", "system": UCUM, "code": "min" },
        }))
    }

    /// A clinical scale's Observation, performed by the therapist `performer`.
    fn scale(&self, e: &ScaleEntry, performer: &str) -> Value {
        // UCUM without annotations (`{score}` is ignored when units are compared: the
        // validator advises against it): a score is dimensionless, blocks are counted.
        let quantity = |v: i64, unit: &str, code: &str| json!({ "value": v, "unit": unit, "system": UCUM, "code": code });
        let system = self.base.code_system(SCALES);
        let value = match (
            e.score,
            e.affected_blocks_per_min,
            e.unaffected_blocks_per_min,
        ) {
            (Some(score), _, _) => self
                .words
                .say("scales-points", &[("score", score.to_string())]),
            (None, a, u) => self.words.say(
                "scales-blocks",
                &[
                    ("affected", a.map_or_else(String::new, |v| v.to_string())),
                    ("unaffected", u.map_or_else(String::new, |v| v.to_string())),
                ],
            ),
        };
        let line = self.words.say(
            "fhir-scale",
            &[
                ("scale", e.scale_name.clone()),
                ("day", e.assessed_on.clone()),
                ("value", value),
            ],
        );
        let mut o = json!({
            "resourceType": "Observation",
            "text": self.words.sentence(line),
            "status": "final",
            "category": Self::category("exam", "Exam"),
            "code": { "coding": [{ "system": system, "code": e.scale, "display": e.scale_name }], "text": e.scale_name },
            "subject": { "reference": self.subject },
            "effectiveDateTime": e.assessed_on,
            "issued": iso_utc(e.created_at_ms),
            "performer": [{ "reference": performer }],
        });
        if let Some(score) = e.score {
            o["valueQuantity"] = quantity(score, "points", codes::SCORE_UNIT);
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
            .filter_map(|(code, side, v)| {
                v.map(|v| json!({
                    "code": { "coding": [{ "system": system, "code": code, "display": format!("Box and Block Test, {side}") }] },
                    "valueQuantity": quantity(v, "blocks/min", codes::BLOCKS_UNIT),
                }))
            })
            .collect();
        if !components.is_empty() {
            o["component"] = json!(components);
        }
        o
    }
}

impl Export<'_> {
    /// The hub's own resources the bundle's codes and answers need: the check-in's
    /// Questionnaire and the code systems (the measures `names`, the assessment's when
    /// `protocols` holds one), as entries.
    ///
    /// The code systems are written in English, whatever the export's language: a code system
    /// defines its codes once for every reader, its displays are what every `Coding` names
    /// (the measures' names and the check-in's answers also carry their words in the
    /// export's language as `designation`s).
    fn own_resources(&self, names: &BTreeSet<&str>, protocols: &BTreeSet<u32>) -> Vec<Value> {
        let base = self.base;
        let words = &Words::english();
        let mut own = vec![
            (
                base.questionnaire(checkin::QUESTIONNAIRE),
                checkin::questionnaire(base, &self.words),
            ),
            (
                base.code_system(MEASURES),
                codes::measures_code_system(base, words, &self.words, names),
            ),
            (
                base.code_system(SCALES),
                codes::scales_code_system(base, words),
            ),
            (
                base.code_system(codes::CHECKIN),
                codes::checkin_code_system(base, words, &self.words),
            ),
        ];
        if !protocols.is_empty() {
            own.push((
                base.code_system(assessment::ASSESSMENT),
                assessment::code_system(base, words, protocols),
            ));
        }
        own.into_iter()
            .map(|(url, resource)| {
                let kind = resource["resourceType"]
                    .as_str()
                    .unwrap_or_default()
                    .to_owned();
                entry(&kind, &url, resource).1
            })
            .collect()
    }

    /// Sets `resource`'s `language`: the export's, but a code system's, written in English
    /// ([`Self::own_resources`]).
    fn stamp_language(&self, resource: &mut Value) {
        let language = if resource["resourceType"] == "CodeSystem" {
            codes::CODE_LANGUAGE
        } else {
            self.words.language()
        };
        resource["language"] = json!(language);
    }
}

/// What the audit log says of an export of a bundle of `sessions` sessions.
pub fn audit_detail(sessions: usize) -> String {
    format!("FHIR R4 bundle of {sessions} sessions")
}

/// Patient `p`'s record as a FHIR R4 `Bundle` of type `collection`, stamped `now_ms`, its own
/// codes at the clinic's `base`, its narratives in `words` (each resource's `language`); the
/// bundle and how many sessions it holds.
pub async fn patient_bundle(
    db: &Db,
    p: &Patient,
    now_ms: i64,
    base: &FhirBase,
    words: Words,
) -> Result<(Value, usize), HubError> {
    let (subject, patient_entry) = entry("Patient", &p.id, Export::patient_of(base, &words, p));
    let x = Export {
        base,
        words,
        subject,
    };
    let mut entries = vec![patient_entry];
    let (sessions, measures) = db.sessions_with_measures(&p.id).await?;
    // One Device a station, in the order the sessions name them.
    let mut devices: BTreeMap<&str, String> = BTreeMap::new();
    for s in &sessions {
        if !devices.contains_key(s.row.station_id.as_str()) {
            let (url, e) = entry(
                "Device",
                &s.row.station_id,
                x.device(&s.row.station_id, &s.row.software_version),
            );
            devices.insert(&s.row.station_id, url);
            entries.push(e);
        }
    }
    let scales = db.scales_of(&p.id).await?;
    let mut therapists: BTreeMap<&str, String> = BTreeMap::new();
    for e in &scales {
        if !therapists.contains_key(e.therapist_id.as_str()) {
            let (url, en) = entry(
                "Practitioner",
                &e.therapist_id,
                x.practitioner(&e.therapist_id),
            );
            therapists.insert(&e.therapist_id, url);
            entries.push(en);
        }
    }
    entries.extend(x.regimen_entries(db, p).await?.into_iter().map(|(_, e)| e));
    let mut session_urls: BTreeMap<&str, String> = BTreeMap::new();
    for s in &sessions {
        let m = measures.get(&s.row.session_id);
        let device = &devices[s.row.station_id.as_str()];
        let duration = m
            .and_then(|m| m.get("active_s"))
            .and_then(|v| x.exercise_duration(s, *v, device))
            .map(|o| entry("Observation", &format!("duration/{}", s.row.session_id), o));
        let members: Vec<String> = duration.iter().map(|(url, _)| url.clone()).collect();
        let (url, e) = entry(
            "Observation",
            &format!("session/{}", s.row.session_id),
            x.session(s, m, device, &members),
        );
        session_urls.insert(&s.row.session_id, url);
        entries.push(e);
        entries.extend(duration.map(|(_, e)| e));
    }
    // The standard assessments, each its own group, apart from the sessions' Observations.
    let assessments = db.assessments_of(&p.id).await?;
    let mut names: BTreeSet<&str> = measures
        .values()
        .flat_map(|m| m.keys().map(String::as_str))
        .collect();
    let station_of: std::collections::HashMap<&str, &str> = sessions
        .iter()
        .map(|s| (s.row.session_id.as_str(), s.row.station_id.as_str()))
        .collect();
    for a in assessments.iter().rev() {
        let device = station_of
            .get(a.session_id.as_str())
            .map(|station| devices[*station].as_str());
        entries.extend(
            x.assessment_entries(a, device, &mut names)
                .into_iter()
                .map(|(_, e)| e),
        );
    }
    for e in &scales {
        let performer = &therapists[e.therapist_id.as_str()];
        entries.push(
            entry(
                "Observation",
                &format!("scale/{}", e.id),
                x.scale(e, performer),
            )
            .1,
        );
    }
    let checkins = db.checkins_of(&p.id).await?;
    for c in checkins.iter().rev() {
        let session = session_urls.get(c.session_id.as_str()).map(String::as_str);
        let r = checkin::response(base, &x.words, c, &x.subject, session);
        entries.push(
            entry(
                "QuestionnaireResponse",
                &format!("checkin/{}", c.session_id),
                r,
            )
            .1,
        );
    }
    let protocols: BTreeSet<u32> = assessments.iter().map(|a| a.protocol).collect();
    entries.extend(x.own_resources(&names, &protocols));
    for e in &mut entries {
        x.stamp_language(&mut e["resource"]);
    }
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
