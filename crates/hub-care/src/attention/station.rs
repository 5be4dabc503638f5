//! The patient's station: every station of theirs revoked, so they cannot train
//! (`station_revoked`, warning), or a station not heard from for the clinic's number of days
//! (`station_silent`, notice).

use super::{Alert, PatientFacts, Severity, Thresholds, day_of, days_between};

/// The station alerts of `f`.
pub fn check(f: &PatientFacts, t: &Thresholds) -> Vec<Alert> {
    if f.stations.is_empty() {
        return Vec::new();
    }
    let active: Vec<_> = f.stations.iter().filter(|s| !s.is_revoked()).collect();
    if active.is_empty() {
        let revoked = f
            .stations
            .iter()
            .filter_map(|s| s.revoked_at_ms)
            .max()
            .unwrap_or(f.now_ms);
        return vec![
            Alert::new(
                "station_revoked",
                Severity::Warning,
                format!(
                    "station withdrawn on {}: the patient cannot train until a new one is paired",
                    day_of(revoked)
                ),
                revoked.to_string(),
            )
            .at(revoked),
        ];
    }
    let heard = active
        .iter()
        .map(|s| s.last_seen_ms.unwrap_or(s.paired_at_ms))
        .max()
        .unwrap_or(f.now_ms);
    let days = days_between(heard, f.now_ms);
    if days < t.station_silent_days {
        return Vec::new();
    }
    vec![
        Alert::new(
            "station_silent",
            Severity::Notice,
            format!(
                "station not heard from for {days} days (last on {})",
                day_of(heard)
            ),
            heard.to_string(),
        )
        .at(heard)
        .fact("days", days as f64),
    ]
}
