//! The card before an exercise: what comes next in plain words, a small animation of the
//! movement (a wheel turning left and right, or the dial's needles), and a rest's countdown.

use super::{ACCENT, CARD, CARD_TEXT, MIN_TEXT_PT, PAD, galley, needle_direction, paint_dial};
use crate::render::scene::{Dial, Movement, NextCard};
use egui::{Color32, CornerRadius, Painter, Pos2, Rect, Stroke, Vec2, pos2, vec2};

/// Paints `next` over a dimmed screen of `size` points.
pub(super) fn paint(p: &Painter, size: Vec2, next: &NextCard) {
    p.rect_filled(
        Rect::from_min_size(Pos2::ZERO, size),
        CornerRadius::ZERO,
        Color32::from_black_alpha(150),
    );
    let rect = Rect::from_center_size(
        pos2(size.x / 2.0, size.y / 2.0),
        vec2((size.x - 80.0).min(1160.0), (size.y - 60.0).min(600.0)),
    );
    p.rect_filled(rect, CornerRadius::same(22), CARD);
    // The picture on the left, the words on the right.
    let pic_r = (rect.height() * 0.26).min(rect.width() * 0.14);
    let pic_c = pos2(
        rect.left() + 3.0 * PAD + pic_r + 10.0,
        rect.center().y - 20.0,
    );
    let swing = (next.anim_s * 1.6).sin();
    match next.movement {
        Movement::Steer => steering_wheel(p, pic_c, pic_r, swing * 0.9),
        Movement::Dial => paint_dial(
            p,
            &Dial {
                desired_rad: swing * 0.9,
                actual_rad: (next.anim_s * 1.6 - 0.35).sin() * 0.85,
            },
            pic_c,
            pic_r,
            false,
        ),
    }
    let text_left = pic_c.x + pic_r + 4.0 * PAD;
    let width = rect.right() - 3.0 * PAD - text_left;
    let mut y = rect.top() + 3.0 * PAD;
    let line = |text: &str, pt: f32, color: Color32, y: &mut f32| {
        let g = p.layout(
            text.to_owned(),
            egui::FontId::proportional(pt),
            color,
            width,
        );
        let h = g.size().y;
        p.galley(pos2(text_left, *y), g, color);
        *y += h + 10.0;
    };
    line(&next.heading, 32.0, ACCENT, &mut y);
    line(&next.title, 48.0, CARD_TEXT, &mut y);
    line(&next.what, 34.0, CARD_TEXT, &mut y);
    if let Some(message) = &next.message {
        let keys_h = next.keys.len() as f32 * 40.0 + 2.0 * PAD;
        paint_message(
            p,
            message,
            (text_left, width),
            (y + 6.0, rect.bottom() - keys_h),
        );
    }
    if let Some(left) = next.countdown_s {
        let s = left.max(0.0).ceil() as u64;
        let text = format!("{}:{:02}", s / 60, s % 60);
        let g = galley(p, text, 96.0, CARD_TEXT);
        p.galley(pos2(text_left, y + 4.0), g, CARD_TEXT);
    }
    let mut ky = rect.bottom() - 2.0 * PAD;
    for k in next.keys.iter().rev() {
        let g = galley(p, k.clone(), 30.0, Color32::from_gray(70));
        ky -= g.size().y;
        p.galley(pos2(text_left, ky), g, Color32::from_gray(70));
    }
}

/// The therapist's message in the card's text column (`left`, `width`) between `top` and
/// `bottom`: "A message from your therapist:" then the text, in the largest type from 34 pt
/// down to [`MIN_TEXT_PT`] that fits (a 500-character message fits at the smallest).
fn paint_message(p: &Painter, message: &str, (left, width): (f32, f32), (top, bottom): (f32, f32)) {
    let heading = p.layout(
        i18n::tr!("card-message-from-therapist"),
        egui::FontId::proportional(30.0),
        ACCENT,
        width,
    );
    let heading_h = heading.size().y;
    p.galley(pos2(left, top), heading, ACCENT);
    let top = top + heading_h + 6.0;
    let text = |pt: f32| {
        p.layout(
            message.to_owned(),
            egui::FontId::proportional(pt),
            CARD_TEXT,
            width,
        )
    };
    let mut g = text(34.0);
    for pt in [30.0, 27.0, MIN_TEXT_PT] {
        if top + g.size().y <= bottom {
            break;
        }
        g = text(pt);
    }
    p.galley(pos2(left, top), g, CARD_TEXT);
}

/// A steering wheel of radius `r` at `c`, turned by `turn_rad` (positive anticlockwise), with
/// arrows showing the turn left and right.
fn steering_wheel(p: &Painter, c: Pos2, r: f32, turn_rad: f64) {
    let rim = Color32::from_rgb(0x2A, 0x30, 0x38);
    p.circle_stroke(c, r, Stroke::new(r * 0.16, rim));
    p.circle_filled(c, r * 0.2, rim);
    // Three spokes: left, right and down, turned with the wheel.
    for spoke in [90.0_f64, -90.0, 180.0] {
        let d = needle_direction(spoke.to_radians() + turn_rad);
        p.line_segment([c, c + d * r * 0.92], Stroke::new(r * 0.12, rim));
    }
    // A mark at the top of the rim, so the turn is easy to see.
    let top = needle_direction(turn_rad);
    p.circle_filled(c + top * r, r * 0.12, ACCENT);
    // Arrows left and right above the wheel.
    let arrow = |from: f64, to: f64| {
        let n = 12;
        let pts: Vec<Pos2> = (0..=n)
            .map(|i| {
                let a = from + (to - from) * f64::from(i) / f64::from(n);
                c + needle_direction(a.to_radians()) * r * 1.32
            })
            .collect();
        let tip = pts[n as usize];
        let before = pts[n as usize - 1];
        let d = (tip - before).normalized();
        let side = vec2(-d.y, d.x);
        p.add(egui::Shape::line(pts, Stroke::new(r * 0.07, ACCENT)));
        p.add(egui::Shape::convex_polygon(
            vec![
                tip + d * r * 0.14,
                tip + side * r * 0.12,
                tip - side * r * 0.12,
            ],
            ACCENT,
            Stroke::NONE,
        ));
    };
    arrow(15.0, 55.0);
    arrow(-15.0, -55.0);
}
