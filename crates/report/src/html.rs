//! `telerehab report`: one self-contained HTML file (charts as inline SVG, no script, no
//! network) for a clinician: whom it is for (the clinic's pseudonym), each session by date and
//! time with its exercises prescribed against performed, how it ended and its arm set-up, the
//! progress between sessions of the same kind, and the technical details (seeds, files,
//! versions) in an appendix at the end. Structured as the console is: landmarks, headings in
//! order, captioned tables, every chart's numbers also as a table.

mod charts;
mod measures;
mod progress;
mod session;
mod sweep;
mod words;

use charts::{Chart, Line};
use measures::{EXERCISE_MEASURES, MEASURES, unit_suffix};
use session::SessionData;
use std::fmt::Write as _;
use std::path::PathBuf;

pub(crate) use measures::exercise_words;
pub use session::read;

/// Escapes text for HTML.
fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The `id` of session `i`'s section.
fn session_id(i: usize) -> String {
    format!("session-{}", i + 1)
}

/// The whole report for `sessions` (in any order; shown oldest first).
pub fn render(mut sessions: Vec<SessionData>) -> Result<String, String> {
    sessions.sort_by_key(|s| s.start_unix_ns);
    let patients = listed(&distinct(&sessions, words::patient));
    let mut html = HEAD.replace(
        "<title>Rehabilitation report — telerehab</title>",
        &format!(
            "<title>Rehabilitation report: {} — telerehab</title>",
            esc(&patients)
        ),
    );
    front(&mut html, &sessions);
    contents(&mut html, &sessions);
    html.push_str("<main id=\"main\">");
    at_a_glance(&mut html, &sessions);
    if sessions.len() > 1 {
        progress::section(&mut html, &sessions)?;
    }
    for (i, s) in sessions.iter().enumerate() {
        one_session(&mut html, i, s)?;
    }
    html.push_str(DEFINITIONS);
    technical(&mut html, &sessions);
    html.push_str("</main></body></html>\n");
    Ok(html)
}

/// `a`, or `a, b and c`.
fn listed(items: &[String]) -> String {
    match items {
        [] => String::new(),
        [one] => one.clone(),
        [rest @ .., last] => format!("{} and {last}", rest.join(", ")),
    }
}

/// The distinct non-empty values of `f` over the sessions, in order.
fn distinct(sessions: &[SessionData], f: impl Fn(&SessionData) -> String) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for v in sessions.iter().map(f).filter(|v| !v.is_empty()) {
        if !out.contains(&v) {
            out.push(v);
        }
    }
    out
}

/// The header: whom the report is for, clinic and therapist when paired, the sessions' dates.
fn front(html: &mut String, sessions: &[SessionData]) {
    html.push_str("<header><h1>Rehabilitation report</h1><dl class=\"front\">");
    let mut row = |term: &str, value: String| {
        let _ = write!(html, "<dt>{term}</dt><dd>{}</dd>", esc(&value));
    };
    row("Patient", listed(&distinct(sessions, words::patient)));
    let clinic = |s: &SessionData| {
        s.clinic
            .as_ref()
            .map(|c| c.clinic.clone())
            .unwrap_or_default()
    };
    let clinics = distinct(sessions, clinic);
    if !clinics.is_empty() {
        row("Clinic", listed(&clinics));
    }
    let therapist = |s: &SessionData| {
        s.clinic
            .as_ref()
            .map(|c| c.therapist.clone())
            .unwrap_or_default()
    };
    let therapists = distinct(sessions, therapist);
    if !therapists.is_empty() {
        row("Prescribed by", listed(&therapists));
    } else if !clinics.is_empty() {
        row(
            "Prescribed by",
            "not known to the station (see the clinic's console)".to_owned(),
        );
    }
    if let (Some(first), Some(last)) = (sessions.first(), sessions.last()) {
        let (a, b) = (
            words::date(first.start_unix_ns),
            words::date(last.start_unix_ns),
        );
        let range = if a == b { a } else { format!("{a} to {b}") };
        row(
            "Sessions",
            format!("{}, {range}", count(sessions.len(), "session")),
        );
    }
    html.push_str("</dl></header>");
}

/// `n session(s)`.
fn count(n: usize, thing: &str) -> String {
    format!("{n} {thing}{}", if n == 1 { "" } else { "s" })
}

/// The contents: a link to every section.
fn contents(html: &mut String, sessions: &[SessionData]) {
    html.push_str(
        "<nav aria-label=\"Contents\"><h2>Contents</h2><ol><li><a href=\"#glance\">Sessions at a glance</a></li>",
    );
    if sessions.len() > 1 {
        html.push_str("<li><a href=\"#progress\">Progress</a><ol>");
        for (id, title) in progress::kinds(sessions) {
            let _ = write!(html, "<li><a href=\"#{id}\">{}</a></li>", esc(&title));
        }
        html.push_str("</ol></li>");
    }
    for (i, s) in sessions.iter().enumerate() {
        let _ = write!(
            html,
            "<li><a href=\"#{}\">Session {}, {}</a></li>",
            session_id(i),
            i + 1,
            esc(&words::date_time(s.start_unix_ns))
        );
    }
    html.push_str(
        "<li><a href=\"#definitions\">How the measures are made</a></li>\
         <li><a href=\"#technical\">Technical details</a></li></ol></nav>",
    );
}

/// Prescribed and performed time of a session, s (the sum over its exercises), when known.
fn times(s: &SessionData) -> Option<(f64, f64)> {
    (!s.exercises.is_empty()).then(|| {
        (
            s.exercises.iter().map(|e| e.prescribed_s).sum(),
            s.exercises.iter().map(|e| e.active_s).sum(),
        )
    })
}

/// Whether an exercise ran its prescribed time (within a second, or 2 %).
fn completed(e: &record::ExerciseResult) -> bool {
    e.active_s + (0.02 * e.prescribed_s).max(1.0) >= e.prescribed_s
}

/// A row per session: when, its exercises, prescribed against performed, how it ended, and
/// whether it counts in the trends.
fn at_a_glance(html: &mut String, sessions: &[SessionData]) {
    html.push_str(
        "<section id=\"glance\" aria-labelledby=\"glance-h\"><h2 id=\"glance-h\">Sessions at a glance</h2>\
         <table><caption>Each session: its exercises, the time prescribed and the time the \
         patient was active, and how it ended</caption><thead><tr><th scope=\"col\">Session</th>\
         <th scope=\"col\">Exercises</th><th scope=\"col\">Prescribed (min)</th>\
         <th scope=\"col\">Performed, active (min)</th><th scope=\"col\">How it ended</th>\
         <th scope=\"col\">In the trends</th></tr></thead><tbody>",
    );
    for (i, s) in sessions.iter().enumerate() {
        let (prescribed, performed) = match times(s) {
            Some((p, a)) => (format!("{:.1}", p / 60.0), format!("{:.1}", a / 60.0)),
            None => ("–".to_owned(), "–".to_owned()),
        };
        let trended = if words::ran_as_prescribed(s) {
            "yes"
        } else {
            "<strong>no: not as prescribed</strong>"
        };
        let _ = write!(
            html,
            "<tr><th scope=\"row\"><a href=\"#{}\">{}</a></th><td>{}</td><td class=\"num\">{prescribed}</td>\
             <td class=\"num\">{performed}</td><td>{}</td><td>{trended}</td></tr>",
            session_id(i),
            esc(&words::date_time(s.start_unix_ns)),
            esc(&words::exercises_in_words(s)),
            esc(&::session::end_reason::sentence(&s.end_reason)),
        );
    }
    html.push_str("</tbody></table></section>");
}

/// Each exercise as prescribed and as performed: prescribed time, active time, completed.
fn prescribed_performed(html: &mut String, s: &SessionData) {
    if s.exercises.is_empty() {
        html.push_str(
            "<p>This recording does not say each exercise's prescribed and active time (it \
             was made before they were recorded).</p>",
        );
        return;
    }
    html.push_str(
        "<table><caption>Prescribed against performed, per exercise</caption><thead><tr>\
         <th scope=\"col\">Exercise</th><th scope=\"col\">Prescribed (s)</th>\
         <th scope=\"col\">Performed, active (s)</th><th scope=\"col\">Completed</th></tr></thead><tbody>",
    );
    for e in &s.exercises {
        let done = if completed(e) {
            "yes".to_owned()
        } else {
            format!(
                "<strong>no</strong>: {:.0} % of the prescribed time",
                100.0 * e.active_s / e.prescribed_s.max(1e-9)
            )
        };
        let _ = write!(
            html,
            "<tr><th scope=\"row\">{}. {}</th><td class=\"num\">{:.0}</td><td class=\"num\">{:.0}</td><td>{done}</td></tr>",
            e.index + 1,
            esc(&e.name),
            e.prescribed_s,
            e.active_s
        );
    }
    html.push_str("</tbody></table>");
}

/// One session: when and what, prescribed against performed, how it ended, the arm set-up,
/// its measures and its charts.
fn one_session(html: &mut String, i: usize, s: &SessionData) -> Result<(), String> {
    let id = session_id(i);
    let _ = write!(
        html,
        "<section id=\"{id}\" aria-labelledby=\"{id}-h\"><h2 id=\"{id}-h\">Session {}, {}: {}</h2>",
        i + 1,
        esc(&words::date_time(s.start_unix_ns)),
        esc(&words::exercises_in_words(s)),
    );
    let marked = if words::ran_as_prescribed(s) {
        ""
    } else {
        " Not as prescribed: left out of the trends."
    };
    let _ = write!(
        html,
        "<p class=\"ended\">{}.{marked}</p>",
        esc(&::session::end_reason::sentence(&s.end_reason))
    );
    let _ = write!(
        html,
        "<p class=\"arm\">{}</p>",
        esc(&s.arm.as_ref().map_or_else(
            || "Arm calibration: none (no arm sensors in this session).".to_owned(),
            words::arm_line
        ))
    );
    prescribed_performed(html, s);
    if s.measures.is_empty() {
        html.push_str("<p>No measures: the session did not end in order.</p>");
    } else {
        html.push_str(
            "<table><caption>The session's measures</caption><thead><tr><th scope=\"col\">Measure</th>\
             <th scope=\"col\">Value</th><th scope=\"col\">What it measures</th></tr></thead><tbody>",
        );
        for m in &MEASURES {
            if let Some(v) = s.measures.get(m.key) {
                let _ = write!(
                    html,
                    "<tr><th scope=\"row\">{}</th><td class=\"num\">{:.*} {}</td>\
                     <td class=\"definition\">{}</td></tr>",
                    m.label,
                    m.decimals,
                    v,
                    m.unit,
                    esc(m.definition)
                );
            }
        }
        html.push_str("</tbody></table>");
    }
    exercise_table(html, &s.exercises);
    sweep::sweep_figures(html, &s.exercises)?;
    session_charts(html, s)?;
    html.push_str("</section>");
    Ok(())
}

/// The per-exercise table: a column per exercise (its place, the patient's name for it), a
/// row per result any of them has; "–" where one does not apply.
fn exercise_table(html: &mut String, exercises: &[record::ExerciseResult]) {
    if exercises.is_empty() {
        return;
    }
    html.push_str(
        "<h3>Each exercise</h3><table class=\"exercises\"><caption>Each exercise's own results</caption>\
         <thead><tr><th scope=\"col\">Result</th>",
    );
    for e in exercises {
        let _ = write!(
            html,
            "<th scope=\"col\">{}. {}</th>",
            e.index + 1,
            esc(&e.name)
        );
    }
    html.push_str("</tr></thead><tbody>");
    for m in &EXERCISE_MEASURES {
        if exercises.iter().all(|e| !e.scores.contains_key(m.key)) {
            continue;
        }
        let _ = write!(
            html,
            "<tr><th scope=\"row\" title=\"{}\">{}{}</th>",
            esc(m.definition),
            m.label,
            unit_suffix(m.unit)
        );
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
    html.push_str("</tbody></table>");
}

/// A chart over a session's time: title, y axis, lines, shaded spans, decimals of its table.
type SessionChart<'a> = (&'a str, &'a str, Vec<Line<'a>>, Vec<(f64, f64)>, usize);

/// The session's charts over its time, each with its numbers as a table.
fn session_charts(html: &mut String, s: &SessionData) -> Result<(), String> {
    let line = |name, points: &Vec<(f64, f64)>| Line {
        name,
        points: points.clone(),
    };
    let charts: [SessionChart<'_>; 5] = [
        (
            "Tracking: the wheel and the angle aimed for",
            "wheel angle (°)",
            vec![
                line("wheel (°)", &s.wheel_deg),
                line("aimed for (°)", &s.target_deg),
            ],
            vec![],
            1,
        ),
        (
            "Lane keeping: lateral deviation from the lane centre",
            "deviation (m)",
            vec![line("lateral deviation (m)", &s.lateral_m)],
            vec![],
            2,
        ),
        (
            "Torque at the wheel and assistance",
            "torque (N·m)",
            vec![
                line("motor torque (N·m)", &s.torque_nm),
                line("assist torque (N·m)", &s.assist_nm),
            ],
            vec![],
            2,
        ),
        (
            "Joint angles",
            "angle (°)",
            vec![
                line("shoulder elevation (°)", &s.shoulder_deg),
                line("elbow flexion (°)", &s.elbow_deg),
            ],
            vec![],
            0,
        ),
        (
            "Wheel speed, with the movements found shaded",
            "speed (°/s)",
            vec![line("wheel speed (°/s)", &s.speed_deg_s)],
            s.movements.clone(),
            0,
        ),
    ];
    let mut any = false;
    for (title, y_desc, lines, spans, decimals) in charts {
        if lines.iter().all(|l| l.points.is_empty()) {
            continue;
        }
        if !any {
            html.push_str("<h3>Over the session</h3>");
            any = true;
        }
        let chart = Chart {
            title,
            x_desc: "session time (s)",
            y_desc,
            lines,
            spans,
            markers: false,
            x_labels: vec![],
            from_zero: false,
        };
        html.push_str(&charts::figure(&chart, decimals)?);
    }
    Ok(())
}

/// The appendix: what a technician needs and a clinician does not (files, seeds, versions).
fn technical(html: &mut String, sessions: &[SessionData]) {
    let _ = write!(
        html,
        "<section id=\"technical\" aria-labelledby=\"technical-h\"><h2 id=\"technical-h\">Technical details</h2>\
         <p>Made by telerehab {}. A session can be replayed from its file.</p>\
         <table><caption>Each session's recording</caption><thead><tr><th scope=\"col\">Session</th>\
         <th scope=\"col\">File</th><th scope=\"col\">Exercise setting</th><th scope=\"col\">Seed</th>\
         <th scope=\"col\">Recording format</th></tr></thead><tbody>",
        env!("CARGO_PKG_VERSION")
    );
    for s in sessions {
        let _ = write!(
            html,
            "<tr><th scope=\"row\">{}</th><td class=\"path\">{}</td><td>{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td></tr>",
            esc(&words::date_time(s.start_unix_ns)),
            esc(&s.path.display().to_string()),
            esc(&s.exercise),
            s.seed,
            s.format_version
        );
    }
    html.push_str("</tbody></table></section>");
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
section { margin-bottom: 2.5em; } section section { margin-bottom: 1.5em; }
caption { text-align: left; font-weight: 600; padding: 0.3em 0; }
dl.front { display: grid; grid-template-columns: max-content 1fr; gap: 0.2em 1em; margin: 0.5em 0 1em; }
dl.front dt { font-weight: 600; } dl.front dd { margin: 0; }
nav ol { margin: 0.3em 0; } nav a, td a, th a { display: inline-block; min-height: 24px; padding: 2px 0; } #glance th a { white-space: nowrap; } nav h2 { font-size: 1.1em; border: none; }
p.arm { background: #f2f6fa; padding: 0.4em 0.6em; border-left: 4px solid #0072b2; }
details { margin: 0.3em 0 1em; } summary { cursor: pointer; color: #00527f; }
td.path { word-break: break-all; font-family: ui-monospace, monospace; font-size: 0.85em; }
@media print { body { margin: 0; max-width: none; } nav { display: none; } figure.chart, table { break-inside: avoid; } h2, h3 { break-after: avoid; } }
</style></head><body>
"#;

const DEFINITIONS: &str = r#"<section id="definitions" aria-labelledby="definitions-h"><h2 id="definitions-h">How the measures are made</h2>
<details class="definitions"><summary>Details: the technical names and methods</summary><p>The wheel's angle is averaged to 100 Hz, differentiated and low-passed (10 Hz, forward and backward); a movement is where its speed is above 5 % of the session's peak (at least 0.05 rad/s), gaps under 0.1 s joined, movements under 0.2 s left out.
SPARC is the spectral arc length of each movement's speed (Balasubramanian et al. 2015: padding level 4, 10 Hz cut-off, amplitude threshold 0.05); LDLJ the log dimensionless jerk from speed, −ln(T³/v<sub>peak</sub>² ∫ (d²v/dt²)² dt). For both, closer to 0 is smoother.
Ranges of motion are from the arm sensors while the arm is tracked. The patient's share of the work is the positive work of the hand on the wheel over that of the hand and the assist (known in simulated sessions).
Trends are least-squares slopes per session over the sessions of one kind of exercise that ran as prescribed; the baseline is the first of them.</p></details></section>
"#;

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeMap;

    /// 2026-11-27T08:51:25Z.
    const T0_NS: u64 = 1_795_769_485_000_000_000;

    fn result(index: u32, kind: &str, prescribed_s: f64, active_s: f64) -> record::ExerciseResult {
        record::ExerciseResult {
            index,
            kind: kind.into(),
            name: ::session::words::plain_name(kind),
            prescribed_s,
            active_s,
            scores: BTreeMap::from([("rms_lateral_m".to_owned(), 0.1234)]),
        }
    }

    /// A complete session of `kind` `hours` after T0, paired for P-0042.
    fn session(hours: u64, kind: &str, sparc: f64) -> SessionData {
        SessionData {
            path: PathBuf::from(format!("/data/rec/h{hours}.mcap")),
            start_unix_ns: T0_NS + hours * 3_600_000_000_000,
            exercise: kind.into(),
            seed: 4711 + hours,
            patient: "p-a82cb5671882d4c7".into(),
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
            exercises: vec![result(0, kind, 60.0, 60.0)],
            end_reason: "complete".into(),
            clinic: Some(record::ClinicNote {
                patient_pseudonym: "P-0042".into(),
                clinic: "hub.clinic.example".into(),
                therapist: String::new(),
            }),
            arm: None,
            regimen_kinds: vec![],
            format_version: 4,
        }
    }

    /// The text of the report's section `id` (up to the next `<section id=` at its level).
    fn section<'a>(html: &'a str, id: &str) -> &'a str {
        let start = html.find(&format!("<section id=\"{id}\"")).unwrap();
        let rest = &html[start + 1..];
        let end = rest
            .find("<section id=\"session-")
            .map_or(rest.len(), |e| e + 1);
        &html[start..start + end]
    }

    #[test]
    fn sessions_of_one_kind_show_a_trend_over_sessions_labelled_by_date_and_time() {
        let html = render(vec![
            session(3, "sine-road", -1.6),
            session(0, "sine-road", -2.0),
            session(7, "slalom", -1.5),
        ])
        .unwrap();
        let progress = section(&html, "progress");
        assert!(progress.contains("<h3 id=\"progress-road-h\">Road exercises</h3>"));
        // Smoother over the sessions: SPARC rises, which is better; per session, not per day.
        assert!(progress.contains("↑ better"), "{progress}");
        assert!(progress.contains("a session)"), "{progress}");
        // The axis: sessions by date and time, at whole positions only.
        assert!(progress.contains(">27 Nov 08:51<"), "{progress}");
        assert!(progress.contains(">27 Nov 15:51<"), "{progress}");
        for half in [">1.5<", ">2.5<", ">0.5<"] {
            assert!(!progress.contains(half), "no tick between sessions: {half}");
        }
        assert!(!html.contains("all within a day"));
        // Oldest first; nothing to fetch, no script.
        assert!(html.find("h0.mcap").unwrap() < html.find("h7.mcap").unwrap());
        assert!(!html.contains("<script"), "no script");
        assert!(!html.contains("src=\"http") && !html.contains("href=\"http"));
    }

    #[test]
    fn a_session_ended_early_is_listed_marked_and_left_out_of_the_trends() {
        let mut early = session(5, "sine-road", -9.0);
        early.end_reason = ::session::end_reason::ENDED_EARLY.into();
        early.exercises = vec![result(0, "sine-road", 60.0, 21.0)];
        let html = render(vec![
            session(0, "sine-road", -2.0),
            early,
            session(9, "sine-road", -1.8),
        ])
        .unwrap();
        let progress = section(&html, "progress");
        assert!(progress.contains("2 sessions as prescribed; not in the trends: 27 Nov 2026, 13:51 UTC (ended early by the patient"), "{progress}");
        // Its SPARC of −9 is not in the trend's table: −2.00 to −1.80 only.
        assert!(!progress.contains("-9.00"), "{progress}");
        assert!(progress.contains("↑ better"), "{progress}");
        let s2 = section(&html, "session-2");
        assert!(
            s2.contains("Not as prescribed: left out of the trends."),
            "{s2}"
        );
        assert!(
            s2.contains("<strong>no</strong>: 35 % of the prescribed time"),
            "{s2}"
        );
        let glance = section(&html, "glance");
        assert!(
            glance.contains("<strong>no: not as prescribed</strong>"),
            "{glance}"
        );
        assert!(glance.contains("Ended early by the patient"), "{glance}");
    }

    #[test]
    fn sessions_of_different_kinds_are_never_trended_together() {
        let html = render(vec![
            session(0, "sine-road", -2.0),
            session(1, "dial-step", -1.0),
        ])
        .unwrap();
        let progress = section(&html, "progress");
        assert!(progress.contains("Road exercises") && progress.contains("Dial exercises"));
        assert!(
            !progress.contains("↑") && !progress.contains("↓"),
            "{progress}"
        );
        assert_eq!(
            progress.matches("A trend needs two sessions").count(),
            2,
            "{progress}"
        );
    }

    #[test]
    fn seeds_and_file_paths_appear_only_in_the_technical_appendix_at_the_end() {
        let html = render(vec![
            session(0, "sine-road", -2.0),
            session(2, "sine-road", -1.9),
        ])
        .unwrap();
        let appendix = html.find("<section id=\"technical\"").unwrap();
        let (body, tail) = html.split_at(appendix);
        for technical in ["/data/rec/h0.mcap", "4711", "4713", "seed", "format"] {
            assert!(
                !body.to_lowercase().contains(technical),
                "{technical} before the appendix"
            );
            assert!(
                tail.to_lowercase().contains(technical),
                "{technical} in the appendix"
            );
        }
        assert!(tail.contains(env!("CARGO_PKG_VERSION")));
        assert!(!body.contains(env!("CARGO_PKG_VERSION")), "the version too");
        assert!(!body.contains("p-a82cb5671882d4c7") && !tail.contains("p-a82cb5671882d4c7"));
    }

    #[test]
    fn the_front_names_the_patient_clinic_and_dates_and_an_unpaired_one_says_so() {
        let html = render(vec![
            session(0, "sine-road", -2.0),
            session(30, "sine-road", -1.9),
        ])
        .unwrap();
        let header = &html[html.find("<header>").unwrap()..html.find("</header>").unwrap()];
        assert!(
            header.contains("<dt>Patient</dt><dd>P-0042</dd>"),
            "{header}"
        );
        assert!(
            header.contains("<dt>Clinic</dt><dd>hub.clinic.example</dd>"),
            "{header}"
        );
        assert!(
            header.contains("2 sessions, 27 Nov 2026 to 28 Nov 2026"),
            "{header}"
        );
        assert!(html.contains("<title>Rehabilitation report: P-0042 — telerehab</title>"));
        let mut unpaired = session(0, "sine-road", -2.0);
        unpaired.clinic = None;
        unpaired.patient = "patient-0".into();
        let html = render(vec![unpaired]).unwrap();
        assert!(
            html.contains("<dt>Patient</dt><dd>not paired with a clinic</dd>"),
            "{html}"
        );
        assert!(!html.contains("patient-0") && !html.contains("<dt>Clinic"));
    }

    #[test]
    fn a_session_gives_its_exercises_prescribed_against_performed_and_its_arm_line() {
        let mut s = session(0, "sine-road", -1.7);
        s.exercises = vec![
            result(0, "sine-road", 90.0, 90.0),
            result(1, "dial-sine", 60.0, 59.5),
        ];
        s.arm = Some(record::ArmCalibrationSample {
            upper_arm_m: 0.3,
            forearm_m: 0.25,
            rms_residual_m: 0.003,
            condition_number: 20.0,
            samples: 1000.0,
            ..Default::default()
        });
        let html = render(vec![s]).unwrap();
        let one = section(&html, "session-1");
        assert!(
            one.contains("Session 1, 27 Nov 2026, 08:51 UTC: Sine road, then Dial sine"),
            "{one}"
        );
        assert!(one.contains("<th scope=\"row\">1. Sine road</th><td class=\"num\">90</td><td class=\"num\">90</td><td>yes</td>"), "{one}");
        assert!(one.contains("<th scope=\"row\">2. Dial sine</th><td class=\"num\">60</td><td class=\"num\">60</td><td>yes</td>"), "{one}");
        assert!(one.contains("Arm calibration: upper arm 30.0 cm"), "{one}");
        assert!(one.contains("Ended: complete."), "{one}");
        let glance = section(&html, "glance");
        assert!(
            glance.contains("<td class=\"num\">2.5</td>"),
            "2.5 min prescribed: {glance}"
        );
        let mut none = session(0, "sine-road", -1.7);
        none.end_reason = String::new();
        let html = render(vec![none]).unwrap();
        assert!(html.contains("Arm calibration: none (no arm sensors in this session)."));
        assert!(html.contains("How it ended is not recorded"));
    }

    #[test]
    fn reaction_times_and_direction_errors_are_shown_for_each_side() {
        let mut s = session(0, "dial-step", -1.7);
        s.measures.extend([
            ("reaction_time_left_s_median".to_owned(), 1.25),
            ("reaction_time_right_s_median".to_owned(), 0.45),
            ("initial_direction_error_left_deg_mean".to_owned(), 60.0),
            ("initial_direction_error_right_deg_mean".to_owned(), 0.0),
        ]);
        let html = render(vec![s]).unwrap();
        let one = section(&html, "session-1");
        for key in [
            "reaction_time_left_s_median",
            "reaction_time_right_s_median",
            "initial_direction_error_left_deg_mean",
            "initial_direction_error_right_deg_mean",
        ] {
            let m = MEASURES.iter().find(|m| m.key == key).unwrap();
            assert!(one.contains(m.label), "{key}: {one}");
        }
        assert!(
            one.contains(">1.25 s<") && one.contains(">0.45 s<"),
            "{one}"
        );
    }

    /// Issue 42: each measure the report shows carries its definition, and a lane change's
    /// anticipations are shown as such, not as a reaction time.
    #[test]
    fn every_measure_shown_carries_its_definition_and_anticipation_is_its_own_row() {
        let mut s = session(0, "lane-change", -1.7);
        s.measures.insert("anticipation_pct".to_owned(), 67.0);
        let keys: Vec<String> = s.measures.keys().cloned().collect();
        let html = render(vec![s]).unwrap();
        let one = section(&html, "session-1");
        for m in MEASURES.iter().filter(|m| keys.iter().any(|k| k == m.key)) {
            assert!(!m.definition.is_empty(), "{}", m.key);
            assert!(one.contains(&esc(m.definition)), "{}: {one}", m.key);
        }
        let anticipation = MEASURES
            .iter()
            .find(|m| m.key == "anticipation_pct")
            .unwrap();
        assert!(
            one.contains(anticipation.label) && one.contains(">67 %<"),
            "{one}"
        );
        assert!(!one.contains(">Reaction time<"), "{one}");
    }

    #[test]
    fn the_report_has_landmarks_captions_and_every_chart_as_a_table() {
        let html = render(vec![
            session(0, "sine-road", -2.0),
            session(2, "sine-road", -1.9),
        ])
        .unwrap();
        assert!(html.contains("<html lang=\"en\">"));
        for landmark in [
            "<header>",
            "<nav aria-label=\"Contents\">",
            "<main id=\"main\">",
        ] {
            assert_eq!(html.matches(landmark).count(), 1, "{landmark}");
        }
        assert_eq!(html.matches("<h1>").count(), 1);
        assert_eq!(
            html.matches("<table>").count() + html.matches("<table class=").count(),
            html.matches("<caption>").count()
        );
        assert_eq!(
            html.matches("<figure").count(),
            html.matches("<details>").count()
        );
        assert!(
            html.matches("<svg").count() >= 4,
            "session and progress charts"
        );
        // Every link of the contents leads to a section.
        for id in html
            .split("href=\"#")
            .skip(1)
            .map(|r| &r[..r.find('"').unwrap()])
        {
            assert!(html.contains(&format!(" id=\"{id}\"")), "#{id}");
        }
    }

    #[test]
    fn names_from_the_recording_are_escaped() {
        let mut s = session(0, "sine-road", -1.7);
        s.clinic.as_mut().unwrap().patient_pseudonym = "<b>P</b>".into();
        s.exercises[0].name = "Dial <sine>".into();
        let html = render(vec![s]).unwrap();
        assert!(html.contains("&lt;b&gt;P&lt;/b&gt;"));
        assert!(html.contains("1. Dial &lt;sine&gt;"));
        assert!(!html.contains("<b>P"));
    }
}
