//! Sessions ended early repeatedly (`ended_early`, warning): at least the clinic's number
//! among the last [`ENDED_EARLY_WINDOW`] finished sessions ended for any reason other than
//! running as prescribed.

use super::{Alert, PatientFacts, Severity, Thresholds};
use hub_store::thresholds::ENDED_EARLY_WINDOW;

/// The ended-early alert of `f`.
pub fn check(f: &PatientFacts, t: &Thresholds) -> Vec<Alert> {
    let finished: Vec<_> = f
        .sessions
        .iter()
        .filter(|s| s.row.end_reason.is_some())
        .take(ENDED_EARLY_WINDOW)
        .collect();
    let early: Vec<_> = finished.iter().filter(|s| !s.ran_as_prescribed).collect();
    let Some(newest) = early.first() else {
        return Vec::new();
    };
    if (early.len() as i64) < t.ended_early_sessions {
        return Vec::new();
    }
    vec![
        Alert::new(
            "ended_early",
            Severity::Warning,
            format!(
                "{} of the last {} sessions ended early",
                early.len(),
                finished.len()
            ),
            newest.row.session_id.clone(),
        )
        .at(newest.row.started_unix_ms)
        .fact("ended_early", early.len() as f64)
        .fact("sessions", finished.len() as f64),
    ]
}
