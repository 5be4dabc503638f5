//! A session's haptic sweeps as thesis Appendix E draws them (Fig. E-I to E-IV): the mean
//! absolute tracking error at each level against the level, both axes from 0, a point per
//! level; under each chart its numbers (level, mean absolute and RMS error) and the error's
//! least-squares slope against the level.

use super::charts::{self, Chart, Line};
use super::esc;
use exercises::SweepParameter;
use measures::sweep_points;
use std::fmt::Write as _;

/// The figure of Appendix E this parameter's chart redraws, and its x axis.
fn axis(p: SweepParameter) -> (&'static str, &'static str) {
    match p {
        SweepParameter::Spring => ("Fig. E-I", "spring K (N·m/rad)"),
        SweepParameter::Damper => ("Fig. E-II", "damper B (N·m·s/rad)"),
        SweepParameter::Inertia => ("Fig. E-III", "inertia I (kg·m²)"),
        SweepParameter::Frequency => ("Fig. E-IV", "frequency of the sine (rad/s)"),
    }
}

/// Each haptic sweep of `exercises` as a chart of error against level with its table (none
/// when the session ran no sweep).
pub(super) fn sweep_figures(
    html: &mut String,
    exercises: &[record::ExerciseResult],
) -> Result<(), String> {
    let sweeps = sweep_points(exercises);
    if sweeps.is_empty() {
        return Ok(());
    }
    html.push_str("<h3>Haptic parameter studies</h3>");
    for (p, points) in sweeps {
        let (figure, x_desc) = axis(p);
        let title = format!(
            "Absolute tracking error against the {} (as the thesis's {figure})",
            p.name()
        );
        let chart = Chart {
            title: &title,
            x_desc,
            y_desc: "mean absolute tracking error (°)",
            lines: vec![Line {
                name: "mean absolute error (°)",
                points: points.clone(),
            }],
            spans: vec![],
            markers: true,
            x_labels: vec![],
            from_zero: true,
        };
        let _ = write!(
            html,
            "<figure class=\"chart\">{}{}</figure>",
            charts::svg(&chart)?,
            table(&title, x_desc, p, exercises, &points)
        );
    }
    Ok(())
}

/// The sweep's numbers: a row per level with its mean absolute and RMS error, and the slope.
fn table(
    title: &str,
    x_desc: &str,
    p: SweepParameter,
    exercises: &[record::ExerciseResult],
    points: &[(f64, f64)],
) -> String {
    let mut html = format!(
        "<details open><summary>The numbers of “{t}”</summary><table><caption>{t}: numbers\
         </caption><thead><tr><th scope=\"col\">{}</th><th scope=\"col\">mean absolute \
         error (°)</th><th scope=\"col\">RMS error (°)</th></tr></thead><tbody>",
        esc(x_desc),
        t = esc(title),
    );
    let key = p.level_measure();
    let levels = exercises.iter().filter(|e| {
        e.scores.contains_key(&key) && e.scores.contains_key("dial_mean_abs_error_deg")
    });
    for e in levels {
        let cell = |k: &str| {
            e.scores
                .get(k)
                .map_or_else(|| "–".to_owned(), |v| format!("{v:.2}"))
        };
        let _ = write!(
            html,
            "<tr><th scope=\"row\">{}</th><td class=\"num\">{}</td><td class=\"num\">{}</td></tr>",
            e.scores[&key],
            cell("dial_mean_abs_error_deg"),
            cell("dial_rms_error_deg"),
        );
    }
    html.push_str("</tbody></table>");
    if let Some(slope) = exercises::sweep::error_slope(points) {
        let _ = write!(
            html,
            "<p>Trend: {slope:+.2}° of error per {} (least-squares slope over {} levels).</p>",
            esc(p.unit()),
            points.len()
        );
    }
    html.push_str("</details>");
    html
}

#[cfg(test)]
mod tests {
    use super::*;

    fn level(index: u32, p: SweepParameter, level: f64, error: f64) -> record::ExerciseResult {
        record::ExerciseResult {
            index,
            kind: "haptic-sweep".into(),
            name: "Haptic sweep".into(),
            prescribed_s: 5.0,
            active_s: 5.0,
            scores: [
                (p.level_measure(), level),
                ("dial_mean_abs_error_deg".into(), error),
                ("dial_rms_error_deg".into(), error * 1.1),
            ]
            .into_iter()
            .collect(),
        }
    }

    #[test]
    fn a_sweep_is_charted_against_its_level_from_zero_with_a_row_per_level_and_its_slope() {
        let exercises = vec![
            level(0, SweepParameter::Frequency, 0.5, 3.0),
            level(1, SweepParameter::Frequency, 1.5, 10.0),
            level(2, SweepParameter::Frequency, 2.5, 17.0),
        ];
        let mut html = String::new();
        sweep_figures(&mut html, &exercises).unwrap();
        assert!(html.contains("Fig. E-IV") && html.contains("frequency of the sine (rad/s)"));
        assert!(html.contains("<svg"), "{html}");
        for row in ["<th scope=\"row\">0.5</th>", "<th scope=\"row\">2.5</th>"] {
            assert!(html.contains(row), "{row}");
        }
        assert!(html.contains("17.00") && html.contains("18.70"));
        assert!(html.contains("+7.00° of error per rad/s"), "{html}");
        // No sweep, no section.
        let mut none = String::new();
        sweep_figures(&mut none, &exercises[..0]).unwrap();
        assert!(none.is_empty());
    }
}
