//! `telerehab report`: one self-contained HTML file (charts as inline SVG, no script, no
//! network) with each session's measures and charts and, for several sessions, the progress
//! between them with trends.

mod charts;
mod session;

use charts::{Chart, Line};
use session::SessionData;
use std::fmt::Write as _;
use std::path::PathBuf;

pub use session::read;

/// Which way a measure is better.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Better {
    Higher,
    Lower,
    Neither,
}

/// A measure as a therapist reads it: the recording's name, plain words, unit, decimals.
struct Measure {
    key: &'static str,
    label: &'static str,
    unit: &'static str,
    decimals: usize,
    better: Better,
}

const fn m(
    key: &'static str,
    label: &'static str,
    unit: &'static str,
    decimals: usize,
    better: Better,
) -> Measure {
    Measure {
        key,
        label,
        unit,
        decimals,
        better,
    }
}

/// The measures shown, in order (those a session lacks are left out).
const MEASURES: [Measure; 17] = [
    m("session_s", "Session length", "s", 0, Better::Neither),
    m("paused_s", "Paused", "s", 0, Better::Neither),
    m("movements", "Movements", "", 0, Better::Neither),
    m("active_pct", "Time moving", "%", 0, Better::Higher),
    m(
        "sparc_median",
        "Smoothness, SPARC (median; closer to 0 is smoother)",
        "",
        2,
        Better::Higher,
    ),
    m(
        "ldlj_median",
        "Smoothness, LDLJ (median; closer to 0 is smoother)",
        "",
        2,
        Better::Higher,
    ),
    m(
        "movement_peak_speed_deg_s_median",
        "Peak speed of a movement (median)",
        "°/s",
        0,
        Better::Higher,
    ),
    m(
        "movement_time_s_median",
        "Duration of a movement (median)",
        "s",
        2,
        Better::Neither,
    ),
    m(
        "speed_peaks_median",
        "Speed peaks in a movement (median)",
        "",
        0,
        Better::Lower,
    ),
    m(
        "wheel_rom_deg",
        "Wheel range of motion",
        "°",
        0,
        Better::Higher,
    ),
    m(
        "shoulder_elevation_rom_deg",
        "Shoulder elevation range",
        "°",
        0,
        Better::Higher,
    ),
    m(
        "elbow_flexion_rom_deg",
        "Elbow flexion range",
        "°",
        0,
        Better::Higher,
    ),
    m(
        "rms_lateral_m",
        "Lane keeping: lateral deviation (RMS)",
        "m",
        3,
        Better::Lower,
    ),
    m("pct_in_lane", "Time in lane", "%", 1, Better::Higher),
    m(
        "dial_rms_error_deg",
        "Tracking error (RMS)",
        "°",
        2,
        Better::Lower,
    ),
    m(
        "assist_level_mean",
        "Assist level (mean, 0–1)",
        "",
        2,
        Better::Lower,
    ),
    m(
        "patient_work_pct",
        "Patient's share of the work",
        "%",
        0,
        Better::Higher,
    ),
];

/// An exercise's own results shown in the per-exercise table, in order (rows no exercise has
/// are left out).
const EXERCISE_MEASURES: [Measure; 16] = [
    m(
        "rms_lateral_m",
        "Lane keeping: lateral deviation (RMS)",
        "m",
        3,
        Better::Lower,
    ),
    m("pct_in_lane", "Time in lane", "%", 1, Better::Higher),
    m(
        "heading_rms_error_deg",
        "Heading error (RMS)",
        "°",
        1,
        Better::Lower,
    ),
    m("cone_hits", "Cones hit", "", 0, Better::Lower),
    m(
        "completion_time_s",
        "Completion time",
        "s",
        1,
        Better::Neither,
    ),
    m(
        "tracking_rms_error_deg",
        "Tracking error: wheel to the ideal angle (RMS)",
        "°",
        2,
        Better::Lower,
    ),
    m(
        "dial_mean_abs_error_deg",
        "Dial angle error (mean absolute, as the thesis's Appendix E)",
        "°",
        2,
        Better::Lower,
    ),
    m(
        "dial_rms_error_deg",
        "Dial angle error (RMS)",
        "°",
        2,
        Better::Lower,
    ),
    m("movements", "Movements", "", 0, Better::Neither),
    m("active_pct", "Time moving", "%", 0, Better::Higher),
    m(
        "sparc_median",
        "Smoothness, SPARC (median)",
        "",
        2,
        Better::Higher,
    ),
    m(
        "ldlj_median",
        "Smoothness, LDLJ (median)",
        "",
        2,
        Better::Higher,
    ),
    m(
        "movement_peak_speed_deg_s_median",
        "Peak speed of a movement (median)",
        "°/s",
        0,
        Better::Higher,
    ),
    m(
        "wheel_rom_deg",
        "Wheel range of motion",
        "°",
        0,
        Better::Higher,
    ),
    m(
        "shoulder_elevation_rom_deg",
        "Shoulder elevation range",
        "°",
        0,
        Better::Higher,
    ),
    m(
        "elbow_flexion_rom_deg",
        "Elbow flexion range",
        "°",
        0,
        Better::Higher,
    ),
];

/// An exercise's results in words for the text report, in the table's order: "Lane keeping:
/// lateral deviation (RMS) 0.123 m, Time in lane 99.5 %, …".
pub(crate) fn exercise_words(e: &record::ExerciseResult) -> String {
    EXERCISE_MEASURES
        .iter()
        .filter_map(|m| {
            let v = e.scores.get(m.key)?;
            let unit = if m.unit.is_empty() {
                String::new()
            } else {
                format!(" {}", m.unit)
            };
            Some(format!("{} {:.*}{unit}", m.label, m.decimals, v))
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// The per-exercise table: a column per exercise (its place, the patient's name for it, its
/// kind), a row per result any of them has; "–" where one does not apply.
fn exercise_table(html: &mut String, exercises: &[record::ExerciseResult]) {
    if exercises.is_empty() {
        return;
    }
    html.push_str("<h3>Each exercise</h3><table class=\"exercises\"><tr><th>Result</th>");
    for e in exercises {
        let _ = write!(
            html,
            "<th>{}. {}<br><span class=\"sub\">{}</span></th>",
            e.index + 1,
            esc(&e.name),
            esc(&e.kind)
        );
    }
    html.push_str("</tr><tr><td>Time: active of prescribed (s)</td>");
    for e in exercises {
        let _ = write!(
            html,
            "<td class=\"num\">{:.1} of {:.0}</td>",
            e.active_s, e.prescribed_s
        );
    }
    html.push_str("</tr>");
    for m in &EXERCISE_MEASURES {
        if exercises.iter().all(|e| !e.scores.contains_key(m.key)) {
            continue;
        }
        let _ = write!(html, "<tr><td>{}{}</td>", m.label, unit_suffix(m.unit));
        for e in exercises {
            match e.scores.get(m.key) {
                Some(v) => {
                    let _ = write!(html, "<td class=\"num\">{:.*}</td>", m.decimals, v);
                }
                None => html.push_str("<td class=\"num\">–</td>"),
            }
        }
        html.push_str("</tr>");
    }
    html.push_str("</table>");
}

/// The measures charted across sessions, each chart's lines by key.
const PROGRESS: [(&str, &str, &[&str]); 6] = [
    (
        "Smoothness (SPARC, median; closer to 0 is smoother)",
        "SPARC",
        &["sparc_median"],
    ),
    (
        "Ranges of motion",
        "range (°)",
        &[
            "wheel_rom_deg",
            "shoulder_elevation_rom_deg",
            "elbow_flexion_rom_deg",
        ],
    ),
    (
        "Lane keeping",
        "lateral deviation, RMS (m)",
        &["rms_lateral_m"],
    ),
    ("Tracking error", "RMS error (°)", &["dial_rms_error_deg"]),
    (
        "Time moving and the patient's share of the work",
        "%",
        &["active_pct", "patient_work_pct"],
    ),
    ("Assist level", "level (0–1)", &["assist_level_mean"]),
];

fn measure(key: &str) -> Option<&'static Measure> {
    MEASURES.iter().find(|m| m.key == key)
}

/// Escapes text for HTML.
fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The session's start as `YYYY-MM-DD HH:MM UTC`.
fn when(unix_ns: u64) -> String {
    let t = std::time::UNIX_EPOCH + std::time::Duration::from_nanos(unix_ns);
    let s = humantime::format_rfc3339_seconds(t).to_string();
    format!("{} {} UTC", &s[..10], &s[11..16])
}

/// The whole report for `sessions` (in any order; shown oldest first).
pub fn render(mut sessions: Vec<SessionData>) -> Result<String, String> {
    sessions.sort_by_key(|s| s.start_unix_ns);
    let mut html = String::from(HEAD);
    let patients: Vec<&str> = {
        let mut p: Vec<&str> = sessions.iter().map(|s| s.patient.as_str()).collect();
        p.dedup();
        p
    };
    let _ = write!(
        html,
        "<h1>Rehabilitation report</h1><p class=\"sub\">Patient {} · {} session{} · made by telerehab {}</p>",
        esc(&patients.join(", ")),
        sessions.len(),
        if sessions.len() == 1 { "" } else { "s" },
        env!("CARGO_PKG_VERSION")
    );
    if sessions.len() > 1 {
        progress(&mut html, &sessions)?;
    }
    for s in &sessions {
        one_session(&mut html, s)?;
    }
    html.push_str(DEFINITIONS);
    html.push_str("</body></html>\n");
    Ok(html)
}

/// One session: its measures and charts.
fn one_session(html: &mut String, s: &SessionData) -> Result<(), String> {
    let _ = write!(
        html,
        "<section><h2>{} — {} (seed {})</h2><p class=\"sub\">{}</p>",
        when(s.start_unix_ns),
        esc(&s.exercise),
        s.seed,
        esc(&s.path.display().to_string())
    );
    let _ = write!(
        html,
        "<p class=\"ended\">{}</p>",
        esc(&crate::session::end_reason::sentence(&s.end_reason))
    );
    html.push_str("<table><tr><th>Measure</th><th>Value</th></tr>");
    for m in &MEASURES {
        if let Some(v) = s.measures.get(m.key) {
            let _ = write!(
                html,
                "<tr><td>{}</td><td class=\"num\">{:.*} {}</td></tr>",
                m.label, m.decimals, v, m.unit
            );
        }
    }
    html.push_str("</table>");
    if s.measures.is_empty() {
        html.push_str("<p>No measures: the session did not end in order.</p>");
    }
    exercise_table(html, &s.exercises);
    let mut chart = |title, y_desc, lines: Vec<Line<'_>>, spans: Vec<(f64, f64)>| {
        if lines.iter().all(|l| l.points.is_empty()) {
            return Ok(());
        }
        let svg = charts::svg(&Chart {
            title,
            x_desc: "session time (s)",
            y_desc,
            lines,
            spans,
            markers: false,
        })?;
        let _ = write!(html, "<figure class=\"chart\">{svg}</figure>");
        Ok::<(), String>(())
    };
    let line = |name, points: &Vec<(f64, f64)>| Line {
        name,
        points: points.clone(),
    };
    chart(
        "Tracking: the wheel and the angle aimed for",
        "wheel angle (°)",
        vec![
            line("wheel (°)", &s.wheel_deg),
            line("aimed for (°)", &s.target_deg),
        ],
        vec![],
    )?;
    chart(
        "Lane keeping: lateral deviation from the lane centre",
        "deviation (m)",
        vec![line("lateral deviation (m)", &s.lateral_m)],
        vec![],
    )?;
    chart(
        "Torque at the wheel and assistance",
        "torque (N·m)",
        vec![
            line("motor torque (N·m)", &s.torque_nm),
            line("assist torque (N·m)", &s.assist_nm),
        ],
        vec![],
    )?;
    chart(
        "Joint angles",
        "angle (°)",
        vec![
            line("shoulder elevation (°)", &s.shoulder_deg),
            line("elbow flexion (°)", &s.elbow_deg),
        ],
        vec![],
    )?;
    chart(
        "Wheel speed, with the movements found shaded",
        "speed (°/s)",
        vec![line("wheel speed (°/s)", &s.speed_deg_s)],
        s.movements.clone(),
    )?;
    html.push_str("</section>");
    Ok(())
}

/// Sessions spanning less than this are placed by their number, not their date, days.
const MIN_SPAN_DAYS: f64 = 1.0;

/// Progress across sessions: a table with each measure's trend, and charts over time (over
/// the sessions' numbers when they all fall within a day).
fn progress(html: &mut String, sessions: &[SessionData]) -> Result<(), String> {
    let t0 = sessions[0].start_unix_ns;
    let days = |s: &SessionData| s.start_unix_ns.saturating_sub(t0) as f64 / 86_400e9;
    let by_date = sessions.last().is_some_and(|s| days(s) >= MIN_SPAN_DAYS);
    let xs: Vec<f64> = sessions
        .iter()
        .enumerate()
        .map(|(i, s)| if by_date { days(s) } else { (i + 1) as f64 })
        .collect();
    let (x_desc, per) = if by_date {
        ("days since the first session", " per day")
    } else {
        ("session (all within a day)", " per session")
    };
    html.push_str("<section><h2>Progress</h2><table><tr><th>Measure</th>");
    for s in sessions {
        let _ = write!(html, "<th>{}</th>", &when(s.start_unix_ns)[5..16]);
    }
    html.push_str("<th>Trend</th></tr>");
    for m in &MEASURES {
        let values: Vec<Option<f64>> = sessions
            .iter()
            .map(|s| s.measures.get(m.key).copied())
            .collect();
        if values.iter().all(Option::is_none) {
            continue;
        }
        let _ = write!(html, "<tr><td>{}{}</td>", m.label, unit_suffix(m.unit));
        for v in &values {
            match v {
                Some(v) => {
                    let _ = write!(html, "<td class=\"num\">{:.*}</td>", m.decimals, v);
                }
                None => html.push_str("<td class=\"num\">–</td>"),
            }
        }
        let points: Vec<(f64, f64)> = xs
            .iter()
            .zip(&values)
            .filter_map(|(x, v)| v.map(|v| (*x, v)))
            .collect();
        let _ = write!(html, "<td>{}</td></tr>", trend(m, &points, per));
    }
    html.push_str("</table>");
    for (title, y_desc, keys) in PROGRESS {
        let lines: Vec<Line<'_>> = keys
            .iter()
            .filter_map(|k| measure(k))
            .map(|m| Line {
                name: m.label,
                points: sessions
                    .iter()
                    .zip(&xs)
                    .filter_map(|(s, x)| s.measures.get(m.key).map(|v| (*x, *v)))
                    .collect(),
            })
            .filter(|l| !l.points.is_empty())
            .collect();
        // A trend needs two sessions with the measure.
        if lines.iter().all(|l| l.points.len() < 2) {
            continue;
        }
        let svg = charts::svg(&Chart {
            title,
            x_desc,
            y_desc,
            lines,
            spans: vec![],
            markers: true,
        })?;
        let _ = write!(html, "<figure class=\"chart\">{svg}</figure>");
    }
    html.push_str("</section>");
    Ok(())
}

fn unit_suffix(unit: &str) -> String {
    if unit.is_empty() {
        String::new()
    } else {
        format!(" ({unit})")
    }
}

/// The least-squares slope of `points` (per unit of x, named by `per`), and whether that is
/// better or worse.
fn trend(m: &Measure, points: &[(f64, f64)], per: &str) -> String {
    if points.len() < 2 {
        return "–".into();
    }
    let (change, _) = common::line_fit(points);
    let my = points.iter().map(|p| p.1).sum::<f64>() / points.len() as f64;
    let scale = my.abs().max(1e-9);
    let (arrow, word) = if change.abs() < 0.01 * scale {
        ("→", "steady")
    } else {
        let up = change > 0.0;
        let arrow = if up { "↑" } else { "↓" };
        let word = match (m.better, up) {
            (Better::Higher, true) | (Better::Lower, false) => "better",
            (Better::Higher, false) | (Better::Lower, true) => "worse",
            (Better::Neither, _) => "changing",
        };
        (arrow, word)
    };
    format!(
        "<span class=\"{word}\">{arrow} {word}</span> <span class=\"sub\">({change:+.*}{}{per})</span>",
        m.decimals + 1,
        m.unit
    )
}

/// Summary numbers of a written report, for the command's one line.
pub struct Written {
    /// Sessions in it.
    pub sessions: usize,
    /// Its size, bytes.
    pub bytes: usize,
}

/// Reads `paths` (ticking `progress` per file), renders and writes the report to `out`.
pub fn write(
    paths: &[PathBuf],
    out: &std::path::Path,
    progress: &indicatif::ProgressBar,
) -> anyhow::Result<Written> {
    let mut sessions = Vec::with_capacity(paths.len());
    for p in paths {
        progress.set_message(p.display().to_string());
        sessions.push(read(p)?);
        progress.inc(1);
    }
    let n = sessions.len();
    let html = render(sessions).map_err(anyhow::Error::msg)?;
    std::fs::write(out, &html)
        .map_err(|e| anyhow::anyhow!("cannot write {}: {e}", out.display()))?;
    Ok(Written {
        sessions: n,
        bytes: html.len(),
    })
}

const HEAD: &str = r#"<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<meta http-equiv="Content-Security-Policy" content="default-src 'none'; style-src 'unsafe-inline'; img-src data:">
<title>Rehabilitation report — telerehab</title>
<style>
body { font: 16px/1.45 system-ui, sans-serif; color: #1a1a1a; max-width: 960px; margin: 2em auto; padding: 0 1em; }
h1 { font-size: 1.7em; margin-bottom: 0.1em; } h2 { font-size: 1.3em; border-bottom: 2px solid #0072b2; padding-bottom: 0.2em; }
.sub { color: #555; font-size: 0.9em; }
table { border-collapse: collapse; margin: 0.8em 0; } td, th { padding: 0.25em 0.8em; border-bottom: 1px solid #ddd; text-align: left; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
p.ended { font-weight: 600; }
.better { color: #007a5a; font-weight: 600; } .worse { color: #b34700; font-weight: 600; } .steady, .changing { color: #333; }
figure.chart { margin: 1em 0; } figure.chart svg { max-width: 100%; height: auto; }
section { margin-bottom: 2.5em; }
@media print { body { margin: 0; max-width: none; } section, figure.chart { break-inside: avoid; } }
</style></head><body>
"#;

const DEFINITIONS: &str = r#"<section><h2>How the measures are made</h2>
<p>The wheel's angle is averaged to 100 Hz, differentiated and low-passed (10 Hz, forward and backward); a movement is where its speed is above 5 % of the session's peak (at least 0.05 rad/s), gaps under 0.1 s joined, movements under 0.2 s left out.
SPARC is the spectral arc length of each movement's speed (Balasubramanian et al. 2015: padding level 4, 10 Hz cut-off, amplitude threshold 0.05); LDLJ the log dimensionless jerk from speed, −ln(T³/v<sub>peak</sub>² ∫ (d²v/dt²)² dt). For both, closer to 0 is smoother.
Ranges of motion are from the arm sensors while the arm is tracked. The patient's share of the work is the positive work of the hand on the wheel over that of the hand and the assist (known in simulated sessions).
Trends are least-squares slopes over the sessions' dates.</p></section>
"#;

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeMap;

    fn session(day: u64, sparc: f64) -> SessionData {
        SessionData {
            path: PathBuf::from(format!("day{day}.mcap")),
            start_unix_ns: 1_795_000_000_000_000_000 + day * 86_400_000_000_000,
            exercise: "sine-road".into(),
            seed: day,
            patient: "P-0042".into(),
            wheel_deg: vec![(0.0, 0.0), (1.0, 10.0)],
            target_deg: vec![(0.0, 1.0), (1.0, 9.0)],
            lateral_m: vec![],
            torque_nm: vec![(0.0, 0.1), (1.0, 0.2)],
            assist_nm: vec![],
            shoulder_deg: vec![],
            elbow_deg: vec![],
            speed_deg_s: vec![(0.0, 0.0), (0.5, 20.0), (1.0, 0.0)],
            movements: vec![(0.1, 0.9)],
            measures: BTreeMap::from([
                ("sparc_median".to_owned(), sparc),
                ("movements".to_owned(), 4.0),
            ]),
            exercises: vec![],
            end_reason: String::new(),
        }
    }

    #[test]
    fn several_sessions_show_progress_with_the_trend_judged_by_the_measure() {
        let html = render(vec![session(3, -1.6), session(0, -2.0), session(7, -1.5)]).unwrap();
        assert!(html.contains("Progress"));
        // Smoother over the weeks: SPARC rises, which is better.
        assert!(html.contains("↑ better"), "{html}");
        // Oldest first.
        let (a, b) = (
            html.find("day0.mcap").unwrap(),
            html.find("day7.mcap").unwrap(),
        );
        assert!(a < b);
        assert!(!html.contains("<script"), "no script");
        assert!(
            !html.contains("src=\"http") && !html.contains("href=\"http"),
            "nothing fetched from the network"
        );
    }

    #[test]
    fn one_session_has_its_measures_and_charts_and_no_progress() {
        let html = render(vec![session(0, -1.7)]).unwrap();
        assert!(!html.contains("<h2>Progress"));
        assert!(html.contains("Smoothness, SPARC"));
        assert!(html.contains("-1.70"));
        assert!(
            html.matches("<svg").count() >= 3,
            "tracking, torque and speed charts"
        );
    }

    #[test]
    fn each_exercise_has_its_column_and_the_end_reason_is_said() {
        let mut s = session(0, -1.7);
        let result =
            |index: u32, kind: &str, name: &str, scores: &[(&str, f64)]| record::ExerciseResult {
                index,
                kind: kind.into(),
                name: name.into(),
                prescribed_s: 45.0,
                active_s: 44.95,
                scores: scores.iter().map(|(k, v)| ((*k).to_owned(), *v)).collect(),
            };
        s.exercises = vec![
            result(0, "sine-road", "Sine road", &[("rms_lateral_m", 0.1234)]),
            result(
                1,
                "dial-sine",
                "Dial <sine>",
                &[("dial_mean_abs_error_deg", 3.216)],
            ),
        ];
        s.end_reason = crate::session::end_reason::ENDED_EARLY.into();
        let html = render(vec![s]).unwrap();
        assert!(html.contains("<h3>Each exercise</h3>"), "{html}");
        assert!(html.contains("1. Sine road"));
        assert!(html.contains("2. Dial &lt;sine&gt;"), "escaped");
        assert!(html.contains("44.9 of 45") || html.contains("45.0 of 45"));
        // A row per result, "–" where it does not apply.
        assert!(html.contains(
            "<td>Lane keeping: lateral deviation (RMS) (m)</td><td class=\"num\">0.123</td><td class=\"num\">–</td>"
        ));
        assert!(html.contains(
            "<td>Dial angle error (mean absolute, as the thesis's Appendix E) (°)</td><td class=\"num\">–</td><td class=\"num\">3.22</td>"
        ));
        assert!(html.contains("Ended early by the patient"), "{html}");
        let mut old = session(0, -1.7);
        old.end_reason = String::new();
        let html = render(vec![old]).unwrap();
        assert!(html.contains("How it ended is not recorded"));
        assert!(!html.contains("Each exercise"));
        let mut done = session(0, -1.7);
        done.end_reason = "complete".into();
        assert!(render(vec![done]).unwrap().contains("Ended: complete"));
    }

    #[test]
    fn names_from_the_recording_are_escaped() {
        let mut s = session(0, -1.7);
        s.patient = "<b>P</b>".into();
        let html = render(vec![s]).unwrap();
        assert!(html.contains("&lt;b&gt;P&lt;/b&gt;"));
    }
}
