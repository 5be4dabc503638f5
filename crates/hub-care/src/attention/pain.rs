//! Pain: the latest pain answer at or over the clinic's threshold (`pain_high`), or pain
//! rising over the last three answers, each higher than the one before, by at least the
//! clinic's points (`pain_rising`). Both urgent. The words name the session the pain was
//! reported after (later sessions may have had no check-in).

use super::{Alert, PatientFacts, Severity, Thresholds, day_of};
use hub_store::db::SessionCheckIn;

/// The pain alerts of `f`.
pub fn check(f: &PatientFacts, t: &Thresholds) -> Vec<Alert> {
    let answered: Vec<(&SessionCheckIn, i64)> = f
        .checkins
        .iter()
        .filter_map(|c| Some((c, c.pain_0_10?)))
        .collect();
    let Some(&(latest, pain)) = answered.first() else {
        return Vec::new();
    };
    // Training sessions started after the one the pain was reported after.
    let since = f
        .sessions
        .iter()
        .filter(|s| s.row.started_unix_ms > latest.started_unix_ms)
        .count();
    let after = match since {
        0 => format!("after the session of {}", day_of(latest.started_unix_ms)),
        n => format!(
            "after the session of {} ({n} later session{} without a pain answer)",
            day_of(latest.started_unix_ms),
            if n == 1 { "" } else { "s" }
        ),
    };
    let alert = |kind, text: String| {
        Alert::new(kind, Severity::Urgent, text, latest.session_id.clone())
            .at(latest.started_unix_ms)
            .fact("pain_0_10", pain as f64)
            .fact("sessions_since", since as f64)
    };
    if pain >= t.pain_threshold_0_10 {
        return vec![
            alert("pain_high", format!("pain {pain}/10 reported {after}"))
                .fact("threshold_0_10", t.pain_threshold_0_10 as f64),
        ];
    }
    if let [(_, p0), (_, p1), (_, p2), ..] = answered[..]
        && p2 < p1
        && p1 < p0
        && p0 - p2 >= t.pain_rise_points
    {
        return vec![
            alert(
                "pain_rising",
                format!("pain rising: {p2}, then {p1}, then {pain}/10 reported {after}"),
            )
            .fact("first_0_10", p2 as f64)
            .fact("middle_0_10", p1 as f64),
        ];
    }
    Vec::new()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::attention::tests::{checkin, facts};

    #[test]
    fn pain_at_the_threshold_is_urgent_and_names_the_session_it_followed() {
        let mut f = facts();
        f.checkins = vec![checkin("s2", 2, Some(8)), checkin("s1", 1, Some(3))];
        let a = check(&f, &Thresholds::default());
        assert_eq!(a.len(), 1);
        assert_eq!((a[0].kind, a[0].severity), ("pain_high", Severity::Urgent));
        assert_eq!(a[0].fingerprint, "s2");
        assert!(
            a[0].text
                .starts_with("pain 8/10 reported after the session of"),
            "{}",
            a[0].text
        );
        let seven = Thresholds {
            pain_threshold_0_10: 9,
            ..Thresholds::default()
        };
        assert!(
            check(&f, &seven).is_empty(),
            "under the clinic's own threshold"
        );
    }

    #[test]
    fn pain_rising_over_three_answers_is_urgent() {
        let mut f = facts();
        f.checkins = vec![
            checkin("s3", 3, Some(5)),
            checkin("s2", 2, None),
            checkin("s1", 1, Some(4)),
            checkin("s0", 0, Some(2)),
        ];
        let a = check(&f, &Thresholds::default());
        assert_eq!(a[0].kind, "pain_rising");
        assert_eq!(
            a[0].text,
            format!(
                "pain rising: 2, then 4, then 5/10 reported after the session of {}",
                day_of(f.checkins[0].started_unix_ms)
            )
        );
        f.checkins[3].pain_0_10 = Some(4);
        assert!(
            check(&f, &Thresholds::default()).is_empty(),
            "4, 4, 5 is not rising"
        );
    }
}
