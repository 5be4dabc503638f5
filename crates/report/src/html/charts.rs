//! The report's charts: plotters drawing SVG text (no fonts needed: the browser sets the
//! text), a colour-blind-safe palette (Okabe & Ito 2008), units on every axis, and long series
//! thinned to what a page can show.

use plotters::prelude::*;
use plotters::style::RGBColor;

/// Okabe–Ito colours, distinguishable with every common colour-vision deficiency.
pub const PALETTE: [RGBColor; 6] = [
    RGBColor(0, 114, 178),   // blue
    RGBColor(213, 94, 0),    // vermillion
    RGBColor(0, 158, 115),   // bluish green
    RGBColor(204, 121, 167), // reddish purple
    RGBColor(230, 159, 0),   // orange
    RGBColor(86, 180, 233),  // sky blue
];

/// Most points drawn of one series: a chart 900 px wide shows no more.
const MAX_POINTS: usize = 1800;

/// Chart size, px.
const SIZE: (u32, u32) = (900, 260);

/// One line of a chart: its name in the legend and its points (x, y).
pub struct Line<'a> {
    /// Legend name, plain words with the unit.
    pub name: &'a str,
    /// Points in x order; a NaN y breaks the line there.
    pub points: Vec<(f64, f64)>,
}

/// A chart: title, axis descriptions with units, lines, shaded x spans (e.g. movements).
pub struct Chart<'a> {
    /// Title above the chart.
    pub title: &'a str,
    /// x axis description, unit included.
    pub x_desc: &'a str,
    /// y axis description, unit included.
    pub y_desc: &'a str,
    /// The lines.
    pub lines: Vec<Line<'a>>,
    /// x spans shaded behind the lines.
    pub spans: Vec<(f64, f64)>,
    /// Draw markers at each point (a few points, e.g. one per session).
    pub markers: bool,
    /// Names of the integer x positions 1, 2, … (sessions by date and time); empty: x is a
    /// number with its unit in `x_desc`.
    pub x_labels: Vec<String>,
    /// Both axes start at 0 (or below, for negative values): the error against a level, as
    /// the thesis's Appendix E draws it.
    pub from_zero: bool,
}

/// Most rows of a chart's numbers table: a time series is sampled at this many instants.
const MAX_TABLE_ROWS: usize = 40;

/// The chart's numbers as an HTML table inside a `<details>` (a chart is a picture: its
/// numbers must be readable as text too): a row per session for a chart over sessions, else
/// the series at up to [`MAX_TABLE_ROWS`] evenly spaced instants (each line's latest value at
/// or before it).
pub fn numbers_table(chart: &Chart<'_>, decimals: usize) -> String {
    use std::fmt::Write as _;
    let esc = super::esc;
    let mut html = format!(
        "<details><summary>The numbers of “{}”</summary><table><caption>{}: numbers</caption>\
         <thead><tr><th scope=\"col\">{}</th>",
        esc(chart.title),
        esc(chart.title),
        esc(if chart.x_labels.is_empty() {
            chart.x_desc
        } else {
            "session"
        })
    );
    for l in &chart.lines {
        let _ = write!(html, "<th scope=\"col\">{}</th>", esc(l.name));
    }
    html.push_str("</tr></thead><tbody>");
    let xs: Vec<(f64, String)> = if chart.x_labels.is_empty() {
        let all = || {
            chart
                .lines
                .iter()
                .flat_map(|l| l.points.iter().map(|p| p.0))
        };
        let (lo, hi) = all().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(x), b.max(x))
        });
        if lo.is_finite() {
            let n = MAX_TABLE_ROWS.min(all().count()).max(1);
            (0..n)
                .map(|i| {
                    let x = lo + (hi - lo) * i as f64 / (n - 1).max(1) as f64;
                    (x, format!("{x:.1}"))
                })
                .collect()
        } else {
            Vec::new()
        }
    } else {
        chart
            .x_labels
            .iter()
            .enumerate()
            .map(|(i, l)| ((i + 1) as f64, l.clone()))
            .collect()
    };
    for (x, label) in xs {
        let _ = write!(html, "<tr><th scope=\"row\">{}</th>", esc(&label));
        for l in &chart.lines {
            let at = if chart.x_labels.is_empty() {
                l.points.iter().take_while(|p| p.0 <= x + 1e-9).last()
            } else {
                l.points.iter().find(|p| (p.0 - x).abs() < 1e-9)
            };
            match at.filter(|p| p.1.is_finite()) {
                Some(p) => {
                    let _ = write!(html, "<td class=\"num\">{:.*}</td>", decimals, p.1);
                }
                None => html.push_str("<td class=\"num\">–</td>"),
            }
        }
        html.push_str("</tr>");
    }
    html.push_str("</tbody></table></details>");
    html
}

/// `points` thinned to at most [`MAX_POINTS`] by keeping each bucket's lowest and highest
/// sample in order (peaks survive, unlike taking every n-th).
pub fn thin(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    if points.len() <= MAX_POINTS {
        return points.to_vec();
    }
    let bucket = points.len().div_ceil(MAX_POINTS / 2);
    points
        .chunks(bucket)
        .flat_map(|c| {
            let lo = c.iter().min_by(|a, b| a.1.total_cmp(&b.1)).copied();
            let hi = c.iter().max_by(|a, b| a.1.total_cmp(&b.1)).copied();
            match (lo, hi) {
                (Some(lo), Some(hi)) if lo.0 <= hi.0 => [lo, hi],
                (Some(lo), Some(hi)) => [hi, lo],
                _ => unreachable!("chunks are never empty"),
            }
        })
        .collect()
}

/// A series thinned as it is taken, in memory bounded whatever its length: the lowest and
/// highest point of each bucket of consecutive points (as [`thin`] keeps them), the buckets
/// doubling in length whenever [`MAX_POINTS`] of them are full.
#[derive(Clone, Debug)]
pub struct Thinner {
    /// Points a full bucket takes.
    per_bucket: usize,
    /// Full buckets.
    buckets: Vec<Bucket>,
    /// The bucket being filled and its points so far.
    open: Option<(Bucket, usize)>,
}

/// The lowest and highest point of a bucket (the first lowest, the last highest, as
/// [`thin`] picks them).
#[derive(Clone, Copy, Debug)]
struct Bucket {
    lo: (f64, f64),
    hi: (f64, f64),
}

impl Bucket {
    /// The bucket of `self`'s points followed by `next`'s.
    fn then(self, next: Bucket) -> Bucket {
        use std::cmp::Ordering::Less;
        Bucket {
            lo: if next.lo.1.total_cmp(&self.lo.1) == Less {
                next.lo
            } else {
                self.lo
            },
            hi: if next.hi.1.total_cmp(&self.hi.1) == Less {
                self.hi
            } else {
                next.hi
            },
        }
    }
}

impl Default for Thinner {
    fn default() -> Self {
        Self {
            per_bucket: 1,
            buckets: Vec::new(),
            open: None,
        }
    }
}

impl Thinner {
    /// Takes the next point (in x order).
    pub fn push(&mut self, point: (f64, f64)) {
        let one = Bucket {
            lo: point,
            hi: point,
        };
        let (bucket, n) = match self.open.take() {
            Some((b, n)) => (b.then(one), n + 1),
            None => (one, 1),
        };
        if n < self.per_bucket {
            self.open = Some((bucket, n));
            return;
        }
        self.buckets.push(bucket);
        if self.buckets.len() >= MAX_POINTS {
            self.buckets = self
                .buckets
                .chunks(2)
                .map(|pair| pair.iter().copied().reduce(Bucket::then).expect("a pair"))
                .collect();
            self.per_bucket *= 2;
        }
    }

    /// The points kept, in x order, at most [`MAX_POINTS`].
    pub fn finish(self) -> Vec<(f64, f64)> {
        let mut points = Vec::with_capacity(2 * (self.buckets.len() + 1));
        for b in self.buckets.into_iter().chain(self.open.map(|(b, _)| b)) {
            let same = b.lo.0.to_bits() == b.hi.0.to_bits() && b.lo.1.to_bits() == b.hi.1.to_bits();
            if same {
                points.push(b.lo);
            } else if b.lo.0 <= b.hi.0 {
                points.extend([b.lo, b.hi]);
            } else {
                points.extend([b.hi, b.lo]);
            }
        }
        thin(&points)
    }
}

/// The range of `values` with a margin, never empty.
fn range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    // A single value (one session, a constant) gets a tenth of itself either side.
    let pad = if hi > lo {
        (hi - lo) * 0.05
    } else {
        (hi.abs() * 0.1).max(1e-6)
    };
    (lo - pad, hi + pad)
}

/// A chart as the report shows it: its SVG and, under it, its numbers as a table (a drawing is
/// not accessible).
pub fn figure(chart: &Chart<'_>, decimals: usize) -> Result<String, String> {
    Ok(format!(
        "<figure class=\"chart\">{}{}</figure>",
        svg(chart)?,
        numbers_table(chart, decimals)
    ))
}

/// The chart as an SVG document.
pub fn svg(chart: &Chart<'_>) -> Result<String, String> {
    let mut out = String::new();
    draw(chart, &mut out).map_err(|e| format!("chart {:?}: {e}", chart.title))?;
    Ok(out)
}

fn draw(chart: &Chart<'_>, out: &mut String) -> Result<(), Box<dyn std::error::Error>> {
    let root = SVGBackend::with_string(out, SIZE).into_drawing_area();
    root.fill(&WHITE)?;
    let all = || chart.lines.iter().flat_map(|l| l.points.iter());
    let (x0, x1) = if chart.x_labels.is_empty() {
        range(all().map(|p| p.0))
    } else {
        // Sessions at 1, 2, …, n with half a step either side.
        (0.5, chart.x_labels.len() as f64 + 0.5)
    };
    let (mut y0, mut y1) = range(all().map(|p| p.1));
    let (mut x0, x1) = (x0, x1);
    if chart.from_zero {
        x0 = x0.min(0.0);
        y0 = y0.min(0.0);
        // Room above the highest point for its marker, however flat the line.
        y1 += 0.08 * (y1 - y0);
    }
    let mut c = ChartBuilder::on(&root)
        .caption(chart.title, ("sans-serif", 18))
        .margin(8)
        .x_label_area_size(36)
        .y_label_area_size(64)
        .build_cartesian_2d(x0..x1, y0..y1)?;
    let n = chart.x_labels.len();
    // A label every `every` sessions, so that dates never overlap (900 px fit about eight).
    let every = n.div_ceil(8).max(1);
    let session_label = |x: &f64| {
        let i = x.round();
        if (x - i).abs() > 1e-6 || i < 1.0 || !(i as usize - 1).is_multiple_of(every) {
            return String::new();
        }
        chart
            .x_labels
            .get(i as usize - 1)
            .cloned()
            .unwrap_or_default()
    };
    let mut mesh = c.configure_mesh();
    mesh.x_desc(chart.x_desc)
        .y_desc(chart.y_desc)
        .label_style(("sans-serif", 13))
        .light_line_style(RGBColor(235, 235, 235));
    if n > 0 {
        // Ticks fine enough to land on every whole session; only those are labelled.
        mesh.x_labels(4 * n + 4)
            .x_label_formatter(&session_label)
            .disable_x_mesh();
    }
    mesh.draw()?;
    c.draw_series(chart.spans.iter().map(|&(a, b)| {
        Rectangle::new([(a, y0), (b, y1)], RGBColor(0, 158, 115).mix(0.12).filled())
    }))?;
    for (i, line) in chart.lines.iter().enumerate() {
        let colour = PALETTE[i % PALETTE.len()];
        let style = colour.stroke_width(2);
        let mut pieces = line
            .points
            .split(|p| !p.1.is_finite())
            .filter(|piece| !piece.is_empty());
        if let Some(first) = pieces.next() {
            c.draw_series(LineSeries::new(thin(first), style))?
                .label(line.name)
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style));
        }
        for piece in pieces {
            c.draw_series(LineSeries::new(thin(piece), style))?;
        }
        if chart.markers {
            c.draw_series(
                line.points
                    .iter()
                    .map(|&p| Circle::new(p, 4, colour.filled())),
            )?;
        }
    }
    if chart.lines.len() > 1 {
        c.configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .label_font(("sans-serif", 13))
            .background_style(WHITE.mix(0.85))
            .border_style(RGBColor(180, 180, 180))
            .draw()?;
    }
    root.present()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_series_thinned_as_it_comes_keeps_its_peaks_in_bounded_points() {
        let wave = |i: usize| ((i as f64) * 0.01).sin() + if i == 123_457 { 5.0 } else { 0.0 };
        let mut short = Thinner::default();
        for i in 0..1000 {
            short.push((i as f64, wave(i)));
        }
        let short = short.finish();
        assert_eq!(short.len(), 1000, "a short series is kept whole");
        assert_eq!(short[17], (17.0, wave(17)));
        let mut long = Thinner::default();
        for i in 0..1_000_000 {
            long.push((i as f64, wave(i)));
            assert!(long.buckets.len() < MAX_POINTS);
        }
        let long = long.finish();
        assert!(
            long.len() <= MAX_POINTS && long.len() > MAX_POINTS / 4,
            "{}",
            long.len()
        );
        assert!(long.windows(2).all(|w| w[0].0 <= w[1].0), "in order");
        assert!(
            long.contains(&(123_457.0, wave(123_457))),
            "the peak survives"
        );
    }

    #[test]
    fn thinning_keeps_the_peaks_and_the_order() {
        let points: Vec<(f64, f64)> = (0..100_000)
            .map(|i| (f64::from(i), if i == 54_321 { 9.0 } else { 0.0 }))
            .collect();
        let thin = thin(&points);
        assert!(thin.len() <= MAX_POINTS, "{}", thin.len());
        assert!(thin.iter().any(|p| p.1 == 9.0), "the peak survives");
        assert!(thin.windows(2).all(|w| w[0].0 <= w[1].0));
    }

    #[test]
    fn a_chart_has_its_title_axes_and_legend_as_text() {
        let chart = Chart {
            title: "Wheel angle",
            x_desc: "time (s)",
            y_desc: "angle (°)",
            lines: vec![
                Line {
                    name: "wheel (°)",
                    points: vec![(0.0, 1.0), (1.0, 2.0)],
                },
                Line {
                    name: "target (°)",
                    points: vec![(0.0, 0.0), (1.0, 3.0)],
                },
            ],
            spans: vec![(0.2, 0.4)],
            markers: false,
            x_labels: vec![],
            from_zero: false,
        };
        let svg = svg(&chart).unwrap();
        for text in [
            "Wheel angle",
            "time (s)",
            "angle (°)",
            "wheel (°)",
            "target (°)",
        ] {
            assert!(svg.contains(text), "{text} missing");
        }
    }
}
