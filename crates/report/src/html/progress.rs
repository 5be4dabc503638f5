//! Progress across sessions, like with like: a section per kind of exercise (road, dial, …)
//! whose trends and charts count only the sessions of that kind that ran as prescribed, over a
//! session axis labelled by date and time. A session that ended early is listed, marked, and
//! left out of the trends.

use super::charts::{self, Chart, Line};
use super::measures::{Better, MEASURES, Measure, PROGRESS, measure, unit_suffix};
use super::session::SessionData;
use super::{esc, words};
use std::fmt::Write as _;

/// The sessions of `kind`, in order: those trended, and those left out (with why).
struct Group<'a> {
    kind: String,
    trended: Vec<&'a SessionData>,
    left_out: Vec<&'a SessionData>,
}

/// Sessions grouped by kind, in the order each kind first appears.
fn groups(sessions: &[SessionData]) -> Vec<Group<'_>> {
    let mut out: Vec<Group<'_>> = Vec::new();
    for s in sessions {
        let kind = words::session_kind(s);
        let i = match out.iter().position(|g| g.kind == kind) {
            Some(i) => i,
            None => {
                out.push(Group {
                    kind,
                    trended: Vec::new(),
                    left_out: Vec::new(),
                });
                out.len() - 1
            }
        };
        if words::ran_as_prescribed(s) {
            out[i].trended.push(s);
        } else {
            out[i].left_out.push(s);
        }
    }
    out
}

/// The `id` of a kind's section (`progress-dial-road`).
pub fn section_id(kind: &str) -> String {
    format!("progress-{}", kind.replace('+', "-"))
}

/// The kinds of `sessions`, each with its heading, for the contents.
pub fn kinds(sessions: &[SessionData]) -> Vec<(String, String)> {
    groups(sessions)
        .iter()
        .map(|g| (section_id(&g.kind), words::kind_title(&g.kind)))
        .collect()
}

/// The progress section: one subsection per kind of exercise.
pub fn section(html: &mut String, sessions: &[SessionData]) -> Result<(), String> {
    html.push_str(
        "<section id=\"progress\" aria-labelledby=\"progress-h\"><h2 id=\"progress-h\">Progress</h2>\
         <p>Sessions are compared only with sessions of the same kind of exercise, and only \
         those that ran as prescribed count in a trend: a session that ended early is listed, \
         marked, and left out.</p>",
    );
    for g in groups(sessions) {
        kind_section(html, &g)?;
    }
    html.push_str("</section>");
    Ok(())
}

/// One kind's table of measures by session, with the baseline (its first session), the
/// latest and the trend, and its charts over the sessions.
fn kind_section(html: &mut String, g: &Group<'_>) -> Result<(), String> {
    let title = words::kind_title(&g.kind);
    let id = section_id(&g.kind);
    let _ = write!(
        html,
        "<section aria-labelledby=\"{id}-h\" id=\"{id}\"><h3 id=\"{id}-h\">{}</h3><p>{} as prescribed",
        esc(&title),
        plural(g.trended.len(), "session")
    );
    if !g.left_out.is_empty() {
        let list: Vec<String> = g
            .left_out
            .iter()
            .map(|s| {
                format!(
                    "{} ({})",
                    words::date_time(s.start_unix_ns),
                    words::continuing(&session::end_reason::sentence(&s.end_reason))
                )
            })
            .collect();
        let _ = write!(html, "; not in the trends: {}", esc(&list.join("; ")));
    }
    html.push_str(".</p>");
    if g.trended.len() < 2 {
        html.push_str(
            "<p>A trend needs two sessions of this kind that ran as prescribed.</p></section>",
        );
        return Ok(());
    }
    table(html, &title, &g.trended);
    charts(html, &title, &g.trended)?;
    html.push_str("</section>");
    Ok(())
}

/// The sessions by date and time, as their columns and axis name them.
fn labels(sessions: &[&SessionData]) -> Vec<String> {
    let starts: Vec<u64> = sessions.iter().map(|s| s.start_unix_ns).collect();
    words::session_labels(&starts)
}

/// `n thing(s)`.
fn plural(n: usize, thing: &str) -> String {
    format!("{n} {thing}{}", if n == 1 { "" } else { "s" })
}

/// The kind's table: a row per measure, a column per session, then baseline, latest, trend.
fn table(html: &mut String, title: &str, sessions: &[&SessionData]) {
    let _ = write!(
        html,
        "<table><caption>{}: each measure by session (oldest first), its baseline (the first \
         session), latest and trend</caption><thead><tr><th scope=\"col\">Measure</th>",
        esc(title)
    );
    for label in labels(sessions) {
        let _ = write!(html, "<th scope=\"col\">{}</th>", esc(&label));
    }
    html.push_str(
        "<th scope=\"col\">Baseline</th><th scope=\"col\">Latest</th><th scope=\"col\">Trend</th></tr></thead><tbody>",
    );
    for m in &MEASURES {
        let values: Vec<Option<f64>> = sessions
            .iter()
            .map(|s| s.measures.get(m.key).copied())
            .collect();
        if values.iter().all(Option::is_none) {
            continue;
        }
        let _ = write!(
            html,
            "<tr><th scope=\"row\">{}{}</th>",
            m.label,
            unit_suffix(m.unit)
        );
        let cell = |v: Option<f64>| match v {
            Some(v) => format!("<td class=\"num\">{:.*}</td>", m.decimals, v),
            None => "<td class=\"num\">–</td>".to_owned(),
        };
        for v in &values {
            html.push_str(&cell(*v));
        }
        html.push_str(&cell(values.iter().flatten().next().copied()));
        html.push_str(&cell(values.last().copied().flatten()));
        let points: Vec<(f64, f64)> = values
            .iter()
            .enumerate()
            .filter_map(|(i, v)| v.map(|v| ((i + 1) as f64, v)))
            .collect();
        let _ = write!(html, "<td>{}</td></tr>", trend(m, &points));
    }
    html.push_str("</tbody></table>");
}

/// The kind's charts over its sessions (1, 2, … labelled by date and time), one unit per
/// axis, each with its numbers as a table.
fn charts(html: &mut String, title: &str, sessions: &[&SessionData]) -> Result<(), String> {
    let labels = labels(sessions);
    for (chart_title, y_desc, keys) in PROGRESS {
        let lines: Vec<Line<'_>> = keys
            .iter()
            .filter_map(|k| measure(k))
            .map(|m| Line {
                name: m.label,
                points: sessions
                    .iter()
                    .enumerate()
                    .filter_map(|(i, s)| s.measures.get(m.key).map(|v| ((i + 1) as f64, *v)))
                    .collect(),
            })
            .filter(|l| !l.points.is_empty())
            .collect();
        // A trend needs two sessions with the measure.
        if lines.iter().all(|l| l.points.len() < 2) {
            continue;
        }
        let decimals = keys
            .iter()
            .filter_map(|k| measure(k))
            .map(|m| m.decimals)
            .max()
            .unwrap_or(2);
        let full_title = format!("{title} — {chart_title}");
        let chart = Chart {
            title: &full_title,
            x_desc: "session (date and time, UTC)",
            y_desc,
            lines,
            spans: vec![],
            markers: true,
            x_labels: labels.clone(),
            from_zero: false,
        };
        html.push_str(&charts::figure(&chart, decimals)?);
    }
    Ok(())
}

/// The least-squares slope of `points` over the sessions (per session), and whether that is
/// better or worse.
fn trend(m: &Measure, points: &[(f64, f64)]) -> String {
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
    let unit = if m.unit.is_empty() {
        String::new()
    } else {
        format!(" {}", m.unit)
    };
    format!(
        "<span class=\"{word}\">{arrow} {word}</span> <span class=\"sub\">({change:+.*}{unit} a session)</span>",
        m.decimals + 1,
    )
}
