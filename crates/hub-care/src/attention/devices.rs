//! The wheel and the arm sensors: a safety stop in the last session (`safety_stop`,
//! warning); the last session ended on an unplugged wheel (`wheel_unplugged`) or arm sensor
//! (`sensor_unplugged`), the station
//! on for the clinic's number of days without telling its wheel (`wheel_unseen`), the arm
//! sensors lost in the last sessions (`sensors_lost`), torque held at the ceiling
//! (`torque_at_ceiling`), all notices.

use super::{Alert, PatientFacts, Severity, Thresholds, day_of, days_between};

/// The station's end reason of a session stopped by an unplugged wheel
/// (`session::end_reason::WHEEL_UNPLUGGED`).
pub const WHEEL_UNPLUGGED: &str = "wheel unplugged";

/// The station's end reason of a session stopped by an arm sensor unplugged and not back in
/// time (`session::end_reason::ARM_SENSOR_UNPLUGGED`).
pub const ARM_SENSOR_UNPLUGGED: &str = "arm sensor unplugged";

/// Share of a session with torque held at the ceiling that raises `torque_at_ceiling`, %.
pub const CLIPPED_PCT_ALERT: f64 = 5.0;

/// The device alerts of `f`.
pub fn check(f: &PatientFacts, t: &Thresholds) -> Vec<Alert> {
    let mut out = Vec::new();
    let Some(last) = f.sessions.first() else {
        return out;
    };
    let sid = &last.row.session_id;
    let started = last.row.started_unix_ms;
    let measure = |s: &str, name: &str| f.measures.get(s).and_then(|m| m.get(name)).copied();
    if measure(sid, "watchdog_fault_ticks").is_some_and(|v| v > 0.0) {
        out.push(
            Alert::new(
                "safety_stop",
                Severity::Warning,
                format!("safety stop in the session of {}", day_of(started)),
                sid.clone(),
            )
            .at(started),
        );
    }
    if last.row.end_reason.as_deref() == Some(WHEEL_UNPLUGGED) {
        out.push(
            Alert::new(
                "wheel_unplugged",
                Severity::Notice,
                format!(
                    "the session of {} stopped: wheel unplugged",
                    day_of(started)
                ),
                sid.clone(),
            )
            .at(started),
        );
    }
    if last.row.end_reason.as_deref() == Some(ARM_SENSOR_UNPLUGGED) {
        out.push(
            Alert::new(
                "sensor_unplugged",
                Severity::Notice,
                format!(
                    "the session of {} stopped: arm sensor unplugged",
                    day_of(started)
                ),
                sid.clone(),
            )
            .at(started),
        );
    }
    let heard = f
        .stations
        .iter()
        .filter(|s| !s.is_revoked())
        .filter_map(|s| s.last_seen_ms)
        .max();
    if let (Some(heard), Some(wheel)) = (heard, f.wheel_seen_at_ms) {
        let days = days_between(wheel, heard);
        if days >= t.devices_unseen_days {
            out.push(
                Alert::new(
                    "wheel_unseen",
                    Severity::Notice,
                    format!(
                        "wheel not seen for {days} days (last on {}) while the station was on",
                        day_of(wheel)
                    ),
                    wheel.to_string(),
                )
                .at(wheel)
                .fact("days", days as f64),
            );
        }
    }
    let lost: Vec<_> = f
        .sessions
        .iter()
        .take_while(|s| measure(&s.row.session_id, "arm_sensors_lost").is_some_and(|v| v > 0.0))
        .collect();
    if let Some(first) = lost.last() {
        let days = days_between(first.row.started_unix_ms, f.now_ms);
        out.push(
            Alert::new(
                "sensors_lost",
                Severity::Notice,
                format!(
                    "arm sensors lost in the last {} session{} (since {})",
                    lost.len(),
                    if lost.len() == 1 { "" } else { "s" },
                    day_of(first.row.started_unix_ms)
                ),
                sid.clone(),
            )
            .at(first.row.started_unix_ms)
            .fact("sessions", lost.len() as f64)
            .fact("days", days as f64),
        );
    }
    if measure(sid, "clipped_pct").is_some_and(|v| v >= CLIPPED_PCT_ALERT) {
        out.push(
            Alert::new(
                "torque_at_ceiling",
                Severity::Notice,
                format!(
                    "torque held at the ceiling for 5 % or more of the session of {}",
                    day_of(started)
                ),
                sid.clone(),
            )
            .at(started),
        );
    }
    out
}
