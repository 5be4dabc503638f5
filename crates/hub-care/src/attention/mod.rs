//! Needs attention today (issue 41): the caseload's alerts, computed on the hub from what it
//! stores, one rule a file, each against the clinic's thresholds ([`hub_store::thresholds`]).
//!
//! | rule | kinds | severity |
//! |---|---|---|
//! | [`pain`] | `pain_high` (latest check-in at or over the threshold), `pain_rising` (three check-ins each higher) | urgent |
//! | [`adherence`] | `no_session` (no session for N days, or none yet), `low_activity` (minutes or sessions under the prescription, or under the clinic's minimum with nothing prescribed) | warning |
//! | [`decline`] | `decline` (a measure worse beyond noise, within one exercise kind; every kind checked) | warning |
//! | [`ended_early`] | `ended_early` (sessions ended early repeatedly) | warning |
//! | [`effort`] | `effort` (high tiredness, or "too hard" twice in a row) | warning |
//! | [`station`] | `station_revoked` (warning: the patient cannot train), `station_silent` (notice) | |
//! | [`devices`] | `safety_stop` (warning), `wheel_unplugged`, `sensor_unplugged`, `wheel_unseen`, `sensors_lost`, `torque_at_ceiling` (notice) | |
//!
//! Each alert has a `fingerprint`, its evidence (the session or day it is about): an
//! acknowledged alert stays quiet while the fingerprint is unchanged, a snoozed one also
//! only until its date ([`hub_store::db::AlertAck`]).

pub mod adherence;
pub mod decline;
pub mod devices;
pub mod effort;
pub mod ended_early;
pub mod message;
pub mod pain;
pub mod station;

use std::collections::BTreeMap;

use serde::Serialize;

use hub_store::HubError;
use hub_store::db::{
    AlertAck, Db, MeasuresBySession, NamedSession, PatientOverview, SessionCheckIn, Station,
};
pub use hub_store::thresholds::Thresholds;

/// The session measures the rules read: [`decline::DECLINE_MEASURES`] and the devices'.
pub const RULE_MEASURES: [&str; 6] = [
    "pct_in_lane",
    "wheel_rom_deg",
    "sparc_median",
    "watchdog_fault_ticks",
    "arm_sensors_lost",
    "clipped_pct",
];

pub use hub_store::db::DAY_MS;

/// How much an alert needs the therapist: urgent first.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Severity {
    /// Act today (red): pain at or over the threshold, rising pain.
    Urgent,
    /// Look today (amber).
    Warning,
    /// Worth knowing (blue).
    Notice,
}

/// One thing the therapist should look at, about one patient.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Alert {
    /// Identifies the alert among the patient's: its kind, and for a decline the exercise
    /// kind and measure (`decline:road:wheel_rom_deg`). Never shown.
    pub key: String,
    /// `pain_high`, `pain_rising`, `no_session`, … (the table in the module's documentation).
    pub kind: &'static str,
    /// How much it needs the therapist.
    pub severity: Severity,
    /// The alert in plain words (English, for the API's other users; the console words it
    /// from [`Alert::message`]).
    pub text: String,
    /// The alert's sentence as a console catalogue id with its arguments
    /// ([`message::message_of`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub message: Option<message::AlertMessage>,
    /// The time the evidence is from (the session's start, the station's last contact), ms
    /// since the Unix epoch.
    pub at_ms: Option<i64>,
    /// The numbers the words are made of (`pain_0_10`, `days`, `latest`, `usual`, …).
    pub facts: BTreeMap<&'static str, f64>,
    /// The exercise kind a decline is in (`road`, `dial`, …).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub exercise_kind: Option<String>,
    /// The measure a decline is of (`wheel_rom_deg`, …).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub measure: Option<String>,
    /// The evidence, e.g. the session it is about: an acknowledgement holds until it changes.
    pub fingerprint: String,
    /// The acknowledgement or snooze keeping it quiet, on a quieted alert.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub quieted: Option<AlertAck>,
}

impl Alert {
    /// A new alert of `kind` with no facts yet.
    pub fn new(kind: &'static str, severity: Severity, text: String, fingerprint: String) -> Self {
        Self {
            key: kind.to_owned(),
            kind,
            severity,
            text,
            message: None,
            at_ms: None,
            facts: BTreeMap::new(),
            exercise_kind: None,
            measure: None,
            fingerprint,
            quieted: None,
        }
    }

    /// The same alert with the fact `name` = `value`.
    pub fn fact(mut self, name: &'static str, value: f64) -> Self {
        self.facts.insert(name, value);
        self
    }

    /// The same alert about evidence from `at_ms`.
    pub fn at(mut self, at_ms: i64) -> Self {
        self.at_ms = Some(at_ms);
        self
    }
}

/// The order of kinds within one severity (the first is the most pressing).
pub const KIND_ORDER: [&str; 15] = [
    "pain_high",
    "pain_rising",
    "station_revoked",
    "no_session",
    "decline",
    "safety_stop",
    "ended_early",
    "effort",
    "low_activity",
    "wheel_unplugged",
    "sensor_unplugged",
    "wheel_unseen",
    "sensors_lost",
    "station_silent",
    "torque_at_ceiling",
];

fn kind_rank(kind: &str) -> usize {
    KIND_ORDER
        .iter()
        .position(|k| *k == kind)
        .unwrap_or(KIND_ORDER.len())
}

/// What the rules read about one patient.
#[derive(Debug, Clone)]
pub struct PatientFacts {
    /// Now, ms since the Unix epoch.
    pub now_ms: i64,
    /// When the patient was added, ms since the Unix epoch.
    pub added_at_ms: i64,
    /// Their training sessions in words, newest first.
    pub sessions: Vec<NamedSession>,
    /// Every measure of those sessions, by session.
    pub measures: MeasuresBySession,
    /// Their check-ins, newest first.
    pub checkins: Vec<SessionCheckIn>,
    /// Their stations.
    pub stations: Vec<Station>,
    /// When a station of theirs last told the hub of its wheel, ms since the Unix epoch.
    pub wheel_seen_at_ms: Option<i64>,
    /// Sessions a week prescribed, if the regimen says.
    pub sessions_per_week_prescribed: Option<i64>,
    /// Training sessions started in the last 7 days.
    pub sessions_last_7_days: i64,
    /// Active minutes in the last 7 days.
    pub active_minutes_last_7_days: f64,
    /// Active minutes a week prescribed, if the regimen says.
    pub minutes_per_week_prescribed: Option<f64>,
}

/// Every rule's alerts for `facts`, most pressing first.
pub fn evaluate(facts: &PatientFacts, t: &Thresholds) -> Vec<Alert> {
    let mut all = Vec::new();
    all.extend(pain::check(facts, t));
    all.extend(adherence::check(facts, t));
    all.extend(decline::check(facts, t));
    all.extend(ended_early::check(facts, t));
    all.extend(effort::check(facts, t));
    all.extend(station::check(facts, t));
    all.extend(devices::check(facts, t));
    for a in &mut all {
        a.message = Some(message::message_of(a));
    }
    sort_alerts(&mut all);
    all
}

/// Most pressing first: by severity, then kind, then key.
pub fn sort_alerts(alerts: &mut [Alert]) {
    alerts.sort_by(|a, b| {
        (a.severity, kind_rank(a.kind), &a.key).cmp(&(b.severity, kind_rank(b.kind), &b.key))
    });
}

/// True while `ack` keeps `alert` quiet at `now_ms`: the same evidence, and a snooze not
/// yet over.
pub fn is_quiet(alert: &Alert, ack: &AlertAck, now_ms: i64) -> bool {
    ack.fingerprint == alert.fingerprint && ack.until_ms.is_none_or(|u| now_ms < u)
}

/// A patient's alerts: those that need the therapist (most pressing first), and those an
/// acknowledgement or snooze keeps quiet (each with it).
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Attention {
    /// The alerts that need the therapist, most pressing first.
    pub attention: Vec<Alert>,
    /// The alerts kept quiet, most pressing first.
    pub quieted: Vec<Alert>,
}

impl Attention {
    /// Splits `alerts` by `acks` at `now_ms`.
    pub fn split(alerts: Vec<Alert>, acks: &BTreeMap<String, AlertAck>, now_ms: i64) -> Self {
        let mut out = Self::default();
        for mut a in alerts {
            match acks.get(&a.key) {
                Some(ack) if is_quiet(&a, ack, now_ms) => {
                    a.quieted = Some(ack.clone());
                    out.quieted.push(a);
                }
                _ => out.attention.push(a),
            }
        }
        out
    }

    /// The sort key of "by need": the most pressing alert's severity (none last), then the
    /// number of alerts of each severity, more first.
    pub fn need_key(&self) -> (u8, i64, i64, i64) {
        let count = |s: Severity| -> i64 {
            self.attention.iter().filter(|a| a.severity == s).count() as i64
        };
        let top = self.attention.first().map_or(3, |a| a.severity as u8);
        (
            top,
            -count(Severity::Urgent),
            -count(Severity::Warning),
            -count(Severity::Notice),
        )
    }
}

/// What the rules read about the patient of caseload row `row` at `now_ms`, from `db`.
pub async fn patient_facts(
    db: &Db,
    row: &PatientOverview,
    now_ms: i64,
) -> Result<PatientFacts, HubError> {
    let id = &row.patient.id;
    Ok(PatientFacts {
        now_ms,
        added_at_ms: row.patient.created_at_ms,
        sessions: db.named_sessions_of(id).await?,
        measures: db.measures_named_of_patient(id, &RULE_MEASURES).await?,
        checkins: db.checkins_of(id).await?,
        stations: db.stations_of(id).await?,
        wheel_seen_at_ms: db.wheel_of(id).await?.map(|w| w.seen_at_ms),
        sessions_per_week_prescribed: row.sessions_per_week_prescribed,
        sessions_last_7_days: row.sessions_last_7_days,
        active_minutes_last_7_days: row.active_minutes_last_7_days,
        minutes_per_week_prescribed: row.minutes_per_week_prescribed,
    })
}

/// The alerts of the patient of caseload row `row` at `now_ms` against `thresholds`, read
/// from `db` and split by their acknowledgements.
pub async fn attention_of(
    db: &Db,
    row: &PatientOverview,
    thresholds: &Thresholds,
    now_ms: i64,
) -> Result<Attention, HubError> {
    let facts = patient_facts(db, row, now_ms).await?;
    let acks = db.alert_acks_of(&row.patient.id).await?;
    Ok(Attention::split(
        evaluate(&facts, thresholds),
        &acks,
        now_ms,
    ))
}

/// Whole days from `from_ms` to `now_ms` (rounded down, never negative).
pub fn days_between(from_ms: i64, now_ms: i64) -> i64 {
    (now_ms - from_ms).max(0) / DAY_MS
}

pub use hub_store::db::day_of;

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// 2026-11-21 09:30 UTC.
    pub(crate) const T0: i64 = 1_795_253_400_000;

    /// A patient added at `T0` with nothing else, seen 10 days later.
    pub(crate) fn facts() -> PatientFacts {
        PatientFacts {
            now_ms: T0 + 10 * DAY_MS,
            added_at_ms: T0,
            sessions: Vec::new(),
            measures: MeasuresBySession::new(),
            checkins: Vec::new(),
            stations: Vec::new(),
            wheel_seen_at_ms: None,
            sessions_per_week_prescribed: None,
            sessions_last_7_days: 0,
            active_minutes_last_7_days: 0.0,
            minutes_per_week_prescribed: None,
        }
    }

    /// The check-in of session `sid` started on day `day` after `T0`.
    pub(crate) fn checkin(sid: &str, day: i64, pain: Option<i64>) -> SessionCheckIn {
        SessionCheckIn {
            session_id: sid.to_owned(),
            started_unix_ms: T0 + day * DAY_MS,
            pain_0_10: pain,
            tiredness_0_10: None,
            difficulty: None,
            received_at_ms: T0 + day * DAY_MS,
        }
    }

    #[test]
    fn acknowledged_alerts_stay_quiet_until_the_evidence_changes_and_snoozes_until_their_day() {
        let alert = Alert::new("pain_high", Severity::Urgent, "pain".into(), "s2".into());
        let ack = AlertAck {
            alert_key: "pain_high".into(),
            fingerprint: "s2".into(),
            until_ms: None,
            note: "called".into(),
            by_email: None,
            at_ms: T0,
        };
        assert!(is_quiet(&alert, &ack, T0 + DAY_MS));
        let newer = Alert {
            fingerprint: "s3".into(),
            ..alert.clone()
        };
        assert!(
            !is_quiet(&newer, &ack, T0 + DAY_MS),
            "new evidence wakes it"
        );
        let snooze = AlertAck {
            until_ms: Some(T0 + DAY_MS),
            ..ack
        };
        assert!(is_quiet(&alert, &snooze, T0 + DAY_MS - 1));
        assert!(
            !is_quiet(&alert, &snooze, T0 + DAY_MS),
            "the snooze is over"
        );
    }

    #[test]
    fn the_rules_read_every_measure_they_check() {
        for (m, _) in decline::DECLINE_MEASURES {
            assert!(RULE_MEASURES.contains(&m), "{m}");
        }
    }

    #[test]
    fn need_puts_urgent_first_then_more_alerts() {
        let a = |k: &'static str, s| Alert::new(k, s, String::new(), String::new());
        let urgent = Attention {
            attention: vec![a("pain_high", Severity::Urgent)],
            quieted: vec![],
        };
        let two = Attention {
            attention: vec![
                a("decline", Severity::Warning),
                a("effort", Severity::Warning),
            ],
            quieted: vec![],
        };
        let none = Attention::default();
        assert!(urgent.need_key() < two.need_key());
        assert!(two.need_key() < none.need_key());
    }
}
