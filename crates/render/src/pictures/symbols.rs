//! The pictures that are not roads: the dial, pushing the wheel, rest, pause, yes, no, a star
//! for the end and a calendar sheet for today.

use super::INK;
use crate::dial::{needle_direction, paint_dial};
use crate::palette::ACCENT as ACCENT_FILL;
use egui::{Color32, Painter, Pos2, Rect, Shape, Stroke, StrokeKind, pos2, vec2};

const RED: Color32 = Color32::from_rgb(0xC6, 0x28, 0x28);
const TEA: Color32 = Color32::from_rgb(0x8D, 0x5A, 0x3B);
const BLUE: Color32 = Color32::from_rgb(0x2F, 0x6D, 0xB5);

/// The dial with its red target needle swinging and the black one following.
pub(super) fn dial(p: &Painter, sq: Rect, anim_s: f64) {
    let swing = (anim_s * 1.6).sin();
    paint_dial(
        p,
        &crate::Dial {
            desired_rad: swing * 0.9,
            actual_rad: (anim_s * 1.6 - 0.35).sin() * 0.85,
        },
        sq.center(),
        sq.width() * 0.42,
        false,
    );
}

/// A steering wheel of radius `r` at `c`, turned by `turn_rad` (positive anticlockwise).
pub(crate) fn wheel(p: &Painter, c: Pos2, r: f32, turn_rad: f64) {
    p.circle_stroke(c, r, Stroke::new(r * 0.16, INK));
    p.circle_filled(c, r * 0.2, INK);
    for spoke in [90.0_f64, -90.0, 180.0] {
        let d = needle_direction(spoke.to_radians() + turn_rad);
        p.line_segment([c, c + d * r * 0.92], Stroke::new(r * 0.12, INK));
    }
    p.circle_filled(c + needle_direction(turn_rad) * r, r * 0.12, ACCENT_FILL);
}

/// A thick arrow from `from` to `to`.
fn arrow(p: &Painter, from: Pos2, to: Pos2, width: f32, color: Color32) {
    let d = (to - from).normalized();
    let side = vec2(-d.y, d.x);
    let head = width * 1.6;
    p.line_segment([from, to - d * head * 0.8], Stroke::new(width, color));
    p.add(Shape::convex_polygon(
        vec![
            to,
            to - d * head + side * head * 0.8,
            to - d * head - side * head * 0.8,
        ],
        color,
        Stroke::NONE,
    ));
}

/// The wheel held still while an arrow pushes on its rim, left then right.
pub(super) fn strength(p: &Painter, sq: Rect, anim_s: f64) {
    let c = sq.center() + vec2(0.0, sq.height() * 0.05);
    let r = sq.width() * 0.3;
    wheel(p, c, r, 0.0);
    let left = (anim_s * 0.5).fract() < 0.5;
    let s = if left { -1.0 } else { 1.0 };
    // The push: a thick arrow down onto the rim's top, on the side pushed towards.
    let rim = c + vec2(s * r * 0.7, -r * 0.7);
    let w = sq.width() * 0.05;
    arrow(
        p,
        rim + vec2(-s * r * 0.55, -r * 0.55),
        rim + vec2(s * r * 0.05, -r * 0.1),
        w,
        BLUE,
    );
    // A block the wheel pushes against: it does not turn.
    let block = Rect::from_center_size(c + vec2(s * r * 1.35, 0.0), vec2(w * 1.2, r * 1.2));
    p.rect_filled(block, 4.0, INK);
}

/// A cup of tea with steam rising.
pub(super) fn rest(p: &Painter, sq: Rect, anim_s: f64) {
    let w = sq.width();
    let cup = Rect::from_center_size(
        sq.center() + vec2(-w * 0.04, w * 0.12),
        vec2(w * 0.46, w * 0.36),
    );
    p.rect_filled(cup, w * 0.06, TEA);
    p.rect_stroke(
        cup,
        w * 0.06,
        Stroke::new(w * 0.02, INK),
        StrokeKind::Outside,
    );
    p.circle_stroke(
        pos2(cup.right() + w * 0.06, cup.center().y),
        w * 0.08,
        Stroke::new(w * 0.035, INK),
    );
    let saucer = Rect::from_center_size(
        pos2(cup.center().x, cup.bottom() + w * 0.04),
        vec2(w * 0.7, w * 0.05),
    );
    p.rect_filled(saucer, w * 0.025, INK);
    for k in 0..3 {
        let x = cup.left() + cup.width() * (0.25 + 0.25 * k as f32);
        let phase = anim_s as f32 * 2.0 + k as f32;
        let pts: Vec<Pos2> = (0..=12)
            .map(|i| {
                let t = i as f32 / 12.0;
                pos2(
                    x + (t * 6.0 + phase).sin() * w * 0.025,
                    cup.top() - w * 0.04 - t * w * 0.22,
                )
            })
            .collect();
        p.add(Shape::line(
            pts,
            Stroke::new(w * 0.018, Color32::from_gray(110)),
        ));
    }
}

/// Two bars in a circle.
pub(super) fn pause(p: &Painter, sq: Rect) {
    let c = sq.center();
    let r = sq.width() * 0.4;
    p.circle_filled(c, r, BLUE);
    for s in [-1.0, 1.0] {
        p.rect_filled(
            Rect::from_center_size(c + vec2(s * r * 0.28, 0.0), vec2(r * 0.28, r * 1.0)),
            r * 0.05,
            Color32::WHITE,
        );
    }
}

/// A white tick on a green disc.
pub(super) fn yes(p: &Painter, sq: Rect) {
    let c = sq.center();
    let r = sq.width() * 0.4;
    let white = Stroke::new(r * 0.16, Color32::WHITE);
    p.circle_filled(c, r, ACCENT_FILL);
    p.line_segment(
        [c + vec2(-0.5 * r, 0.0), c + vec2(-0.1 * r, 0.4 * r)],
        white,
    );
    p.line_segment(
        [c + vec2(-0.1 * r, 0.4 * r), c + vec2(0.5 * r, -0.4 * r)],
        white,
    );
}

/// A white cross on a red disc.
pub(super) fn no(p: &Painter, sq: Rect) {
    let c = sq.center();
    let r = sq.width() * 0.4;
    let white = Stroke::new(r * 0.16, Color32::WHITE);
    p.circle_filled(c, r, RED);
    p.line_segment(
        [c + vec2(-0.4 * r, -0.4 * r), c + vec2(0.4 * r, 0.4 * r)],
        white,
    );
    p.line_segment(
        [c + vec2(0.4 * r, -0.4 * r), c + vec2(-0.4 * r, 0.4 * r)],
        white,
    );
}

/// A five-pointed gold star (drawn as triangles from its centre: the star is not convex).
pub(super) fn star(p: &Painter, sq: Rect) {
    let c = sq.center();
    let (ro, ri) = (sq.width() * 0.44, sq.width() * 0.18);
    let pt = |k: usize| {
        let r = if k.is_multiple_of(2) { ro } else { ri };
        let a = std::f32::consts::PI * k as f32 / 5.0;
        c + vec2(a.sin(), -a.cos()) * r
    };
    let gold = Color32::from_rgb(0xF2, 0xB7, 0x05);
    for k in 0..10 {
        p.add(Shape::convex_polygon(
            vec![c, pt(k), pt(k + 1)],
            gold,
            Stroke::NONE,
        ));
    }
    let outline: Vec<Pos2> = (0..10).map(pt).collect();
    p.add(Shape::closed_line(
        outline,
        Stroke::new(sq.width() * 0.015, INK),
    ));
}

/// A calendar sheet with a tick for today.
pub(super) fn calendar(p: &Painter, sq: Rect) {
    let w = sq.width();
    let page = Rect::from_center_size(sq.center(), vec2(w * 0.76, w * 0.7));
    p.rect_filled(page, w * 0.05, Color32::WHITE);
    let top = Rect::from_min_size(page.min, vec2(page.width(), page.height() * 0.24));
    p.rect_filled(top, w * 0.05, RED);
    p.rect_stroke(
        page,
        w * 0.05,
        Stroke::new(w * 0.02, INK),
        StrokeKind::Outside,
    );
    for row in 0..3 {
        for col in 0..4 {
            let c = pos2(
                page.left() + page.width() * (0.17 + 0.22 * col as f32),
                page.top() + page.height() * (0.42 + 0.2 * row as f32),
            );
            if (row, col) == (1, 2) {
                yes(p, Rect::from_center_size(c, vec2(w * 0.2, w * 0.2)));
            } else {
                p.circle_filled(c, w * 0.025, Color32::from_gray(150));
            }
        }
    }
}
