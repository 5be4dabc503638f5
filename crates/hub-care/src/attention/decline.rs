//! A measure worse beyond measurement noise (`decline`, warning), in ANY exercise kind: for
//! each kind on its own, the newest session of that kind that ran as prescribed against the
//! mean of up to [`TREND_BASELINE_SESSIONS`] earlier ones of the same kind that did too
//! (at least [`MIN_BASELINE_SESSIONS`]). A session of another kind never hides a decline: a
//! steady dial does not make a weaker wheel range on the road go away.

use std::collections::BTreeMap;

use super::{Alert, PatientFacts, Severity, Thresholds, day_of};
use hub_store::db::{NamedSession, TREND_BASELINE_SESSIONS};

/// The measures checked, each better when higher (`sparc_median` is negative: nearer zero
/// is smoother), with the words the alert uses.
pub const DECLINE_MEASURES: [(&str, &str); 3] = [
    ("pct_in_lane", "time in lane"),
    ("wheel_rom_deg", "wheel range"),
    ("sparc_median", "smoothness"),
];

/// Earlier sessions a decline needs: one earlier session is no baseline.
pub const MIN_BASELINE_SESSIONS: usize = 2;

/// How much worse `latest` is than the mean of `before`, percent of that mean's size (for a
/// measure better when higher); `None` without enough of `before`.
pub fn worse_percent(latest: f64, before: &[f64]) -> Option<(f64, f64)> {
    if before.len() < MIN_BASELINE_SESSIONS {
        return None;
    }
    let mean = before.iter().sum::<f64>() / before.len() as f64;
    let size = mean.abs().max(1e-9);
    Some(((mean - latest) / size * 100.0, mean))
}

/// The decline alerts of `f`.
pub fn check(f: &PatientFacts, t: &Thresholds) -> Vec<Alert> {
    let mut by_kind: BTreeMap<&str, Vec<&NamedSession>> = BTreeMap::new();
    for s in f.sessions.iter().filter(|s| s.ran_as_prescribed) {
        by_kind.entry(s.exercise_kind.as_str()).or_default().push(s);
    }
    let mut out = Vec::new();
    for (kind, sessions) in by_kind {
        let Some((latest, earlier)) = sessions.split_first() else {
            continue;
        };
        let Some(now) = f.measures.get(&latest.row.session_id) else {
            continue;
        };
        for (measure, words) in DECLINE_MEASURES {
            let Some(&value) = now.get(measure) else {
                continue;
            };
            let before: Vec<f64> = earlier
                .iter()
                .filter_map(|s| f.measures.get(&s.row.session_id)?.get(measure).copied())
                .take(TREND_BASELINE_SESSIONS)
                .collect();
            let Some((worse, usual)) = worse_percent(value, &before) else {
                continue;
            };
            if worse <= t.decline_percent as f64 {
                continue;
            }
            let mut a = Alert::new(
                "decline",
                Severity::Warning,
                format!(
                    "{words} worse in {} sessions: {value:.1} on {} against {usual:.1} before \
                     ({worse:.0} % worse)",
                    kind.replace('+', " and "),
                    day_of(latest.row.started_unix_ms)
                ),
                latest.row.session_id.clone(),
            )
            .at(latest.row.started_unix_ms)
            .fact("latest", value)
            .fact("usual", usual)
            .fact("worse_percent", worse.round())
            .fact("sessions_compared", before.len() as f64);
            a.key = format!("decline:{kind}:{measure}");
            a.exercise_kind = Some(kind.to_owned());
            a.measure = Some(measure.to_owned());
            out.push(a);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn worse_is_against_the_mean_and_needs_two_earlier_sessions() {
        assert_eq!(worse_percent(30.0, &[40.0]), None);
        let (w, mean) = worse_percent(30.0, &[40.0, 40.0]).unwrap();
        assert_eq!((w, mean), (25.0, 40.0));
        // SPARC: −2.5 against −2.0 is 25 % less smooth.
        assert_eq!(worse_percent(-2.5, &[-2.0, -2.0]).unwrap().0, 25.0);
        assert!(worse_percent(45.0, &[40.0, 40.0]).unwrap().0 < 0.0);
    }
}
