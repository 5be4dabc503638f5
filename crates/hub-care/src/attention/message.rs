//! An alert as a console message (issue 40): the id of its sentence in the console's
//! catalogues (`crates/i18n/console/<lang>/attention.ftl`) and the arguments it is made of, so
//! that the console words it in the therapist's language. The alert's English `text` stays
//! for the API's other users.
//!
//! Arguments are the alert's facts (numbers), `at_ms` (the evidence's time; the console
//! formats the date), and for a decline `measure` and `exercise_kind` (keys the console
//! words from the measure-words table), for an unplugged wheel `end` (the end kind, worded by
//! the one end-reason wording, `metrics::words::EndKind`).

use std::collections::BTreeMap;

use metrics::words::EndKind;
use serde::Serialize;
use serde_json::Value;

use super::Alert;

/// An alert's sentence: a catalogue id and its arguments.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AlertMessage {
    /// `attention-pain-high`, … (every id is in [`MESSAGE_IDS`]).
    pub id: &'static str,
    /// The values the sentence is made of, by the catalogue's variable names.
    pub args: BTreeMap<&'static str, Value>,
}

/// Every id an alert's message can have (each must be in every console catalogue).
pub const MESSAGE_IDS: [&str; 19] = [
    "attention-pain-high",
    "attention-pain-rising",
    "attention-station-revoked",
    "attention-no-session-yet",
    "attention-no-session",
    "attention-decline",
    "attention-safety-stop",
    "attention-ended-early",
    "attention-effort-high",
    "attention-effort-too-hard",
    "attention-low-sessions",
    "attention-low-minutes",
    "attention-low-unprescribed",
    "attention-wheel-unplugged",
    "attention-sensor-unplugged",
    "attention-wheel-unseen",
    "attention-sensors-lost",
    "attention-station-silent",
    "attention-torque-at-ceiling",
];

/// The message of `alert`, from its kind, facts and evidence.
pub fn message_of(alert: &Alert) -> AlertMessage {
    let has = |f: &str| alert.facts.contains_key(f);
    let id = match alert.kind {
        "pain_high" => "attention-pain-high",
        "pain_rising" => "attention-pain-rising",
        "station_revoked" => "attention-station-revoked",
        "no_session" if alert.fingerprint == "none" => "attention-no-session-yet",
        "no_session" => "attention-no-session",
        "decline" => "attention-decline",
        "safety_stop" => "attention-safety-stop",
        "ended_early" => "attention-ended-early",
        "effort" if has("effort_0_10") => "attention-effort-high",
        "effort" => "attention-effort-too-hard",
        "low_activity" if has("sessions_prescribed") => "attention-low-sessions",
        "low_activity" if has("minutes_prescribed") => "attention-low-minutes",
        "low_activity" => "attention-low-unprescribed",
        "wheel_unplugged" => "attention-wheel-unplugged",
        "sensor_unplugged" => "attention-sensor-unplugged",
        "wheel_unseen" => "attention-wheel-unseen",
        "sensors_lost" => "attention-sensors-lost",
        "station_silent" => "attention-station-silent",
        _ => "attention-torque-at-ceiling",
    };
    let mut args: BTreeMap<&'static str, Value> =
        alert.facts.iter().map(|(k, v)| (*k, number(*v))).collect();
    if let Some(at) = alert.at_ms {
        args.insert("at_ms", Value::from(at));
    }
    if let Some(m) = &alert.measure {
        args.insert("measure", Value::from(m.clone()));
    }
    if let Some(k) = &alert.exercise_kind {
        args.insert("exercise_kind", Value::from(k.clone()));
    }
    let end = match alert.kind {
        "wheel_unplugged" => Some(EndKind::WheelUnplugged),
        "sensor_unplugged" => Some(EndKind::ArmSensorUnplugged),
        _ => None,
    };
    if let Some(end) = end {
        args.insert("end", serde_json::to_value(end).unwrap_or(Value::Null));
    }
    if alert.kind == "torque_at_ceiling" {
        args.insert("percent", number(super::devices::CLIPPED_PCT_ALERT));
    }
    AlertMessage { id, args }
}

/// A whole number as an integer (`8`, not `8.0`), else the number.
fn number(v: f64) -> Value {
    if v.fract() == 0.0 && v.abs() < 1e15 {
        Value::from(v as i64)
    } else {
        Value::from(v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::attention::Severity;

    #[test]
    fn every_alert_kind_has_a_message_id_of_the_list() {
        for kind in super::super::KIND_ORDER {
            let a = Alert::new(kind, Severity::Notice, String::new(), "s1".into());
            assert!(MESSAGE_IDS.contains(&message_of(&a).id), "{kind}");
        }
    }

    #[test]
    fn every_message_id_is_in_every_console_language() {
        for tag in i18n::LANGUAGES {
            let text = i18n::console_catalogue(tag).unwrap();
            for id in MESSAGE_IDS {
                let defined = text.lines().any(|l| l.starts_with(&format!("{id} =")));
                assert!(defined, "{tag}: no {id}");
            }
        }
    }

    #[test]
    fn a_pain_alert_carries_its_numbers_and_time() {
        let a = Alert::new("pain_high", Severity::Urgent, String::new(), "s1".into())
            .at(1_700_000_000_000)
            .fact("pain_0_10", 8.0)
            .fact("sessions_since", 0.0);
        let m = message_of(&a);
        assert_eq!(m.id, "attention-pain-high");
        assert_eq!(m.args["pain_0_10"], Value::from(8));
        assert_eq!(m.args["at_ms"], Value::from(1_700_000_000_000_i64));
    }

    #[test]
    fn an_unplugged_wheel_is_worded_by_its_end_kind_never_a_safety_stop() {
        let a = Alert::new(
            "wheel_unplugged",
            Severity::Notice,
            String::new(),
            "s1".into(),
        );
        assert_eq!(message_of(&a).args["end"], Value::from("wheel_unplugged"));
    }
}
