//! Training against the prescription: no session for the clinic's number of days (at least
//! the gap the prescription itself leaves: 7 / sessions a week), or none yet (`no_session`);
//! fewer sessions or active minutes this week than prescribed, or — nothing prescribed yet —
//! fewer active minutes than the clinic's weekly minimum (`low_activity`). Both warnings.

use super::{Alert, PatientFacts, Severity, Thresholds, day_of, days_between};

/// Active minutes under this share of the prescribed minutes are too few.
pub const MINUTES_SHARE: f64 = 0.9;

/// The days without a session after which `no_session` is raised: the clinic's
/// `no_session_days`, or the prescription's own gap between sessions if longer.
pub fn allowed_gap_days(t: &Thresholds, sessions_per_week: Option<i64>) -> i64 {
    let own_gap = sessions_per_week
        .filter(|n| *n > 0)
        .map_or(0, |n| (7 + n - 1) / n);
    t.no_session_days.max(own_gap)
}

/// The adherence alerts of `f`.
pub fn check(f: &PatientFacts, t: &Thresholds) -> Vec<Alert> {
    let per_week = f.sessions_per_week_prescribed;
    let prescribed = match per_week {
        Some(n) => format!("; {n} a week prescribed"),
        None => "; nothing prescribed yet".to_owned(),
    };
    let Some(last) = f.sessions.first() else {
        let days = days_between(f.added_at_ms, f.now_ms);
        return vec![
            Alert::new(
                "no_session",
                Severity::Warning,
                format!(
                    "no session yet (added {}{prescribed})",
                    day_of(f.added_at_ms)
                ),
                "none".to_owned(),
            )
            .at(f.added_at_ms)
            .fact("days", days as f64),
        ];
    };
    let mut out = Vec::new();
    let days = days_between(last.row.started_unix_ms, f.now_ms);
    let allowed = allowed_gap_days(t, per_week);
    if days >= allowed {
        out.push(
            Alert::new(
                "no_session",
                Severity::Warning,
                format!(
                    "no session for {days} days (the last on {}{prescribed})",
                    day_of(last.row.started_unix_ms)
                ),
                last.row.session_id.clone(),
            )
            .at(last.row.started_unix_ms)
            .fact("days", days as f64)
            .fact("allowed_days", allowed as f64),
        );
    }
    let minutes = f.active_minutes_last_7_days;
    let low = |text: String| {
        Alert::new(
            "low_activity",
            Severity::Warning,
            text,
            last.row.session_id.clone(),
        )
        .fact("active_minutes", minutes.round())
        .fact("sessions", f.sessions_last_7_days as f64)
    };
    match (per_week, f.minutes_per_week_prescribed) {
        (Some(n), _) if f.sessions_last_7_days < n => out.push(
            low(format!(
                "{} of {n} sessions this week",
                f.sessions_last_7_days
            ))
            .fact("sessions_prescribed", n as f64),
        ),
        (_, Some(m)) if minutes < MINUTES_SHARE * m => out.push(
            low(format!("{minutes:.0} of {m:.0} active minutes this week"))
                .fact("minutes_prescribed", m.round()),
        ),
        (None, None) if minutes < t.min_active_minutes_week as f64 => out.push(
            low(format!(
                "{minutes:.0} active minutes this week (nothing prescribed yet; the clinic \
                 looks for at least {})",
                t.min_active_minutes_week
            ))
            .fact("minimum_minutes", t.min_active_minutes_week as f64),
        ),
        _ => {}
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_gap_allowed_is_the_prescriptions_own_when_longer() {
        let t = Thresholds::default();
        assert_eq!(allowed_gap_days(&t, None), 3);
        assert_eq!(allowed_gap_days(&t, Some(5)), 3);
        assert_eq!(allowed_gap_days(&t, Some(2)), 4);
        assert_eq!(allowed_gap_days(&t, Some(1)), 7);
    }
}
