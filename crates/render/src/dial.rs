//! The rotary dial of thesis Fig. 3-7(a), painted: face, ticks, the error wedge and the two
//! needles. The HUD's dial task draws it large with its legend; the dial picture
//! (`pictures`) draws it small, its needles swinging.

use egui::{Color32, FontId, Painter, Pos2, Shape, Stroke, Vec2, pos2, vec2};
use i18n::tr;

use super::palette::{CARD, CARD_TEXT};
use super::scene::Dial;
use super::text::line;

/// Colour of the desired-angle needle (thesis Fig. 3-7a: red).
pub const DESIRED_NEEDLE: Color32 = Color32::from_rgb(0xD3, 0x2F, 0x2F);
/// Colour of the actual-angle needle (thesis Fig. 3-7a: black).
pub const ACTUAL_NEEDLE: Color32 = Color32::from_rgb(0x14, 0x14, 0x14);

/// Screen direction (y down) of a needle at wheel angle `rad` (0 up, positive anticlockwise).
pub fn needle_direction(rad: f64) -> Vec2 {
    vec2(-(rad.sin() as f32), -(rad.cos() as f32))
}

/// The rotary dial of thesis Fig. 3-7(a): face, ticks, the error wedge, red desired needle
/// under the black actual needle, and a legend when `legend`.
pub(super) fn paint_dial(p: &Painter, dial: &Dial, c: Pos2, r: f32, legend: bool) {
    p.circle_filled(c + vec2(0.0, 4.0), r + 6.0, Color32::from_black_alpha(40));
    p.circle_filled(c, r, CARD);
    p.circle_stroke(
        c,
        r,
        Stroke::new((r * 0.035).max(2.0), Color32::from_gray(70)),
    );
    for k in 0..36 {
        let major = k % 3 == 0;
        let d = needle_direction((k as f64 * 10.0).to_radians());
        let inner = if major { 0.82 } else { 0.89 };
        let width = if major { r * 0.022 } else { r * 0.012 };
        p.line_segment(
            [c + d * r * inner, c + d * r * 0.95],
            Stroke::new(width.max(1.0), Color32::from_gray(80)),
        );
    }
    // The error wedge between the needles: a light red fan, in chunks of at most 30° so each
    // piece is convex.
    let (a, b) = (dial.actual_rad, dial.desired_rad);
    let span = b - a;
    let chunks = ((span.abs() / 30f64.to_radians()).ceil() as usize).clamp(1, 48);
    if span.abs() > 1e-3 {
        for i in 0..chunks {
            let t0 = a + span * i as f64 / chunks as f64;
            let t1 = a + span * (i + 1) as f64 / chunks as f64;
            let pts = vec![
                c,
                c + needle_direction(t0) * r * 0.8,
                c + needle_direction(t1) * r * 0.8,
            ];
            p.add(Shape::convex_polygon(
                pts,
                Color32::from_rgba_unmultiplied(0xD3, 0x2F, 0x2F, 50),
                Stroke::NONE,
            ));
        }
    }
    needle(p, c, dial.desired_rad, r * 0.86, r * 0.06, DESIRED_NEEDLE);
    needle(p, c, dial.actual_rad, r * 0.74, r * 0.045, ACTUAL_NEEDLE);
    p.circle_filled(c, r * 0.07, Color32::from_gray(40));
    if legend {
        let y = c.y + r + 34.0;
        let fs = 26.0;
        let font = FontId::proportional(fs);
        let target = line(p, &tr!("hud-target"), font.clone(), CARD_TEXT);
        let you = line(p, &tr!("hud-your-wheel"), font, CARD_TEXT);
        let gap = 60.0;
        let total = 28.0 + target.size().x + gap + 28.0 + you.size().x;
        let mut x = c.x - total / 2.0;
        for (g, color) in [(target, DESIRED_NEEDLE), (you, ACTUAL_NEEDLE)] {
            p.line_segment([pos2(x, y), pos2(x + 20.0, y)], Stroke::new(8.0, color));
            x += 28.0;
            let gw = g.size().x;
            p.galley(pos2(x, y - g.size().y / 2.0), g, CARD_TEXT);
            x += gw + gap;
        }
    }
}

/// A tapered needle from a short tail behind the hub to `len` along `rad`.
fn needle(p: &Painter, c: Pos2, rad: f64, len: f32, width: f32, color: Color32) {
    let d = needle_direction(rad);
    let n = vec2(-d.y, d.x);
    let tail = c - d * len * 0.18;
    // A convex pentagon: widest at the tail, tapering to the tip.
    let outline = vec![
        tail + n * width * 0.6,
        c + n * width * 0.5 + d * len * 0.1,
        c + d * len,
        c - n * width * 0.5 + d * len * 0.1,
        tail - n * width * 0.6,
    ];
    p.add(Shape::convex_polygon(outline, color, Stroke::NONE));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn needle_points_up_at_zero_and_left_at_plus_quarter_turn() {
        let up = needle_direction(0.0);
        assert!(up.x.abs() < 1e-6 && (up.y + 1.0).abs() < 1e-6);
        let left = needle_direction(std::f64::consts::FRAC_PI_2);
        assert!((left.x + 1.0).abs() < 1e-6 && left.y.abs() < 1e-6);
    }
}
