//! The roads, seen from above: each kind of road exercise its own shape, a car driving up it.

use super::{INK, Movement};
use crate::palette;
use egui::{Color32, Painter, Pos2, Rect, Shape, Stroke, pos2, vec2};

fn colour(c: [f32; 4]) -> Color32 {
    Color32::from_rgb(
        (c[0] * 255.0) as u8,
        (c[1] * 255.0) as u8,
        (c[2] * 255.0) as u8,
    )
}

/// The road's centre across the picture at height `t` (0 bottom, 1 top), −1…1 of the
/// half-width.
fn centre(m: Movement, t: f32) -> f32 {
    use std::f32::consts::TAU;
    match m {
        Movement::Straight | Movement::Slalom => 0.0,
        Movement::Steer => 0.5 * (TAU * 1.25 * t).sin(),
        Movement::Zigzag => {
            // A triangle wave: straight pieces meeting in points.
            let ph = (t * 2.5).fract();
            0.55 * (1.0 - 4.0 * (ph - 0.5).abs())
                * if (t * 2.5) as i32 % 2 == 0 { 1.0 } else { -1.0 }
        }
        Movement::Tightening => -0.6 + 1.3 * t.powi(3),
        Movement::SharpTurns => {
            // Up, a sharp jog right, up, a sharp jog left, up.
            let jog = |a: f32, b: f32| ((t - a) / (b - a)).clamp(0.0, 1.0);
            -0.45 + 0.9 * jog(0.28, 0.34) - 0.9 * jog(0.64, 0.70)
        }
        Movement::SBend => 0.55 * (TAU * t).sin(),
        Movement::LaneChange | Movement::Dial | Movement::Strength => 0.0,
    }
}

/// Paints the road of `m` in the square `sq`, the car `anim_s` along it.
pub(super) fn draw(p: &Painter, m: Movement, sq: Rect, anim_s: f64) {
    let w = sq.width();
    let half = w * 0.34;
    let at = |t: f32, off: f32| -> Pos2 {
        pos2(
            sq.center().x + centre(m, t) * half + off,
            sq.bottom() - t * sq.height(),
        )
    };
    // Grass behind, so the road reads as a road.
    p.rect_filled(sq.shrink(w * 0.02), w * 0.06, colour(palette::GRASS_A));
    let n = 60;
    let line = |off: f32| -> Vec<Pos2> { (0..=n).map(|i| at(i as f32 / n as f32, off)).collect() };
    let lane_w = if m == Movement::LaneChange {
        w * 0.30
    } else {
        w * 0.2
    };
    let inner = sq.shrink(w * 0.02);
    let clip = p.with_clip_rect(inner);
    clip.add(Shape::line(
        line(0.0),
        Stroke::new(lane_w, colour(palette::ASPHALT)),
    ));
    let edge = Stroke::new(w * 0.012, colour(palette::EDGE_LINE));
    clip.add(Shape::line(line(-lane_w * 0.46), edge));
    clip.add(Shape::line(line(lane_w * 0.46), edge));
    // The centre guide, dashed.
    let dash = Stroke::new(w * 0.014, colour(palette::CENTRE_DASH));
    for i in (0..n).step_by(4) {
        let a = at(i as f32 / n as f32, 0.0);
        let b = at((i + 2) as f32 / n as f32, 0.0);
        clip.line_segment([a, b], dash);
    }
    if m == Movement::Slalom {
        for (k, t) in [0.25_f32, 0.5, 0.75].iter().enumerate() {
            let side = if k % 2 == 0 { -1.0 } else { 1.0 };
            let c = at(*t, side * lane_w * 0.22);
            let r = w * 0.035;
            clip.add(Shape::convex_polygon(
                vec![c + vec2(0.0, -r * 1.6), c + vec2(r, r), c + vec2(-r, r)],
                colour(palette::CONE),
                Stroke::new(w * 0.006, INK),
            ));
        }
    }
    // The car drives up the road again and again; on the slalom it weaves round the cones,
    // on the lane change it keeps to its lane.
    let t = ((anim_s * 0.18).fract() as f32) * 0.8 + 0.1;
    let weave = match m {
        Movement::Slalom => lane_w * 0.2 * (2.0 * std::f32::consts::TAU * (t - 0.25)).cos(),
        Movement::LaneChange => {
            let s = ((t - 0.35) / 0.3).clamp(0.0, 1.0);
            lane_w * 0.22 * (2.0 * s * s * (3.0 - 2.0 * s) - 1.0)
        }
        _ => 0.0,
    };
    let c = at(t, weave);
    let ahead = at((t + 0.02).min(1.0), weave);
    let d = (ahead - c).normalized();
    let side = vec2(-d.y, d.x);
    let (l, hw) = (w * 0.08, w * 0.035);
    clip.add(Shape::convex_polygon(
        vec![
            c + d * l + side * hw,
            c + d * l - side * hw,
            c - d * l - side * hw,
            c - d * l + side * hw,
        ],
        colour(palette::CAR_BODY),
        Stroke::new(w * 0.006, INK),
    ));
    p.rect_stroke(
        inner,
        w * 0.06,
        Stroke::new(w * 0.012, INK),
        egui::StrokeKind::Inside,
    );
}
