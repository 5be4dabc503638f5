//! The session's results in plain words, against the patient's last sessions the home keeps.

use serde::{Deserialize, Serialize};
use session::SessionReport;
use std::path::Path;

/// Sessions whose results the home keeps to compare the next one with.
pub const KEPT_RESULTS: usize = 5;

/// One session's results, as the end screen compares them (and the home keeps them).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct EndResults {
    /// Time the exercises ran (pauses not counted), s.
    pub active_s: f64,
    /// Time within the lane on the road exercises, %, if the session had any.
    pub pct_in_lane: Option<f64>,
    /// The dial's RMS tracking error, degrees, if the session had the dial.
    pub dial_error_deg: Option<f64>,
}

impl EndResults {
    /// The results of a finished session.
    pub fn of(report: &SessionReport) -> Self {
        let rec = &report.recorder;
        let score = &rec.last.score;
        Self {
            active_s: score.active_s,
            pct_in_lane: (rec.road_ticks > 0).then_some(score.pct_in_lane),
            dial_error_deg: (rec.dial_ticks > 0).then_some(score.dial_rms_error_deg),
        }
    }
}

/// "4 minutes 30 seconds", "45 seconds", in the language in force.
pub fn duration_words(s: f64) -> String {
    let s = s.max(0.0).round() as u64;
    let (m, s) = (s / 60, s % 60);
    let minutes = || i18n::tr!("common-minutes", minutes = m);
    let seconds = || i18n::tr!("checkin-seconds", seconds = s);
    match (m, s) {
        (0, _) => seconds(),
        (_, 0) => minutes(),
        _ => format!("{} {}", minutes(), seconds()),
    }
}

/// The mean of `f` over `before`, where it is known.
fn mean_of(before: &[EndResults], f: impl Fn(&EndResults) -> Option<f64>) -> Option<f64> {
    let v: Vec<f64> = before
        .iter()
        .filter_map(f)
        .filter(|x| x.is_finite())
        .collect();
    (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
}

/// Rounded to whole units for the patient's eyes.
fn whole(x: f64) -> i64 {
    x.round() as i64
}

/// Whether a session that ended on `wheel_fault` ended because the wheel stopped working (not
/// one unplugged: its own page said so all along): its end screen says so, first and in its
/// title ([`crate::checkin::CheckInFlow::stopped_early`]).
pub fn wheel_stopped(wheel_fault: Option<haptic_wheel::WheelFault>) -> bool {
    wheel_fault.is_some_and(|f| f != haptic_wheel::WheelFault::Unplugged)
}

/// The end screen's lines after a session that ended on `wheel_fault`, if one: a wheel that
/// stopped working (not one unplugged: its own page said so all along) is said first, and
/// whom to tell; then [`result_lines`].
pub fn end_lines(
    now: &EndResults,
    before: &[EndResults],
    wheel_fault: Option<haptic_wheel::WheelFault>,
) -> Vec<String> {
    wheel_stopped(wheel_fault)
        .then(|| i18n::tr!("checkin-results-wheel-stopped"))
        .into_iter()
        .chain(result_lines(now, before))
        .collect()
}

/// The end screen's lines: this session's results in plain words, and what improved against
/// the mean of the sessions `before` (newest first; none: this session's only).
pub fn result_lines(now: &EndResults, before: &[EndResults]) -> Vec<String> {
    let mut lines = vec![i18n::tr!(
        "checkin-results-exercised",
        time = duration_words(now.active_s)
    )];
    let mut better = Vec::new();
    if let Some(lane) = now.pct_in_lane.filter(|x| x.is_finite()) {
        lines.push(i18n::tr!("checkin-results-lane", percent = whole(lane)));
        if let Some(was) = mean_of(before, |r| r.pct_in_lane)
            && lane >= was + 1.0
        {
            better.push(i18n::tr!(
                "checkin-results-better-lane",
                percent = whole(lane),
                was = whole(was)
            ));
        }
    }
    if let Some(err) = now.dial_error_deg.filter(|x| x.is_finite()) {
        lines.push(i18n::tr!("checkin-results-dial", degrees = whole(err)));
        if let Some(was) = mean_of(before, |r| r.dial_error_deg)
            && err <= was - 0.5
        {
            better.push(i18n::tr!(
                "checkin-results-better-dial",
                degrees = whole(err),
                was = whole(was)
            ));
        }
    }
    if let Some(was) = mean_of(before, |r| Some(r.active_s))
        && now.active_s >= was + 30.0
    {
        better.push(i18n::tr!(
            "checkin-results-better-time",
            time = duration_words(now.active_s),
            was = duration_words(was)
        ));
    }
    if before.is_empty() {
        lines.push(i18n::tr!("checkin-results-first"));
    } else if better.is_empty() {
        lines.push(i18n::tr!("checkin-results-same"));
    } else {
        lines.push(i18n::tr!("checkin-results-better"));
        lines.extend(better);
    }
    lines
}

/// The results of the patient's last sessions kept in `path` (newest first; none if the file
/// is missing or unreadable).
pub fn load_results(path: &Path) -> Vec<EndResults> {
    std::fs::read(path)
        .ok()
        .and_then(|b| serde_json::from_slice(&b).ok())
        .unwrap_or_default()
}

/// Keeps `now` first in `path` with up to [`KEPT_RESULTS`] − 1 of `before`.
pub fn save_results(path: &Path, now: &EndResults, before: &[EndResults]) -> anyhow::Result<()> {
    let kept: Vec<EndResults> = std::iter::once(*now)
        .chain(before.iter().copied())
        .take(KEPT_RESULTS)
        .collect();
    session::files::write_private(path, &serde_json::to_vec(&kept)?)
}
