//! High reported effort (`effort`, warning): effort (Borg CR10, the check-in's second answer;
//! stored as `tiredness_0_10`, the wire's older name) at or over the clinic's threshold in
//! the latest check-in that answered it, or "too hard" in the last two check-ins that
//! answered how hard it felt.

use super::{Alert, PatientFacts, Severity, Thresholds, day_of};

/// How many "too hard" in a row raise the alert.
pub const TOO_HARD_IN_A_ROW: usize = 2;

/// The effort alert of `f`.
pub fn check(f: &PatientFacts, t: &Thresholds) -> Vec<Alert> {
    if let Some((c, tired)) = f.checkins.iter().find_map(|c| Some((c, c.tiredness_0_10?)))
        && tired >= t.effort_threshold_0_10
    {
        return vec![
            Alert::new(
                "effort",
                Severity::Warning,
                format!(
                    "effort {tired}/10 reported after the session of {}",
                    day_of(c.started_unix_ms)
                ),
                c.session_id.clone(),
            )
            .at(c.started_unix_ms)
            .fact("effort_0_10", tired as f64)
            .fact("tiredness_0_10", tired as f64)
            .fact("threshold_0_10", t.effort_threshold_0_10 as f64),
        ];
    }
    let rated: Vec<_> = f
        .checkins
        .iter()
        .filter(|c| c.difficulty.is_some())
        .take(TOO_HARD_IN_A_ROW)
        .collect();
    if rated.len() == TOO_HARD_IN_A_ROW
        && rated
            .iter()
            .all(|c| c.difficulty.as_deref() == Some("too_hard"))
    {
        let c = rated[0];
        return vec![
            Alert::new(
                "effort",
                Severity::Warning,
                format!("\"too hard\" after the last {TOO_HARD_IN_A_ROW} sessions"),
                c.session_id.clone(),
            )
            .at(c.started_unix_ms)
            .fact("too_hard_sessions", TOO_HARD_IN_A_ROW as f64),
        ];
    }
    Vec::new()
}
