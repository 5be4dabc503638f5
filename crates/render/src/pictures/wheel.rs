//! What to do with the wheel: the wheel with its button lit (a ring round it for a long
//! press, arrows for a turn), and the plug going back into the wheel. They stand beside a
//! page's words so a patient who reads little sees what to do.

use egui::{Color32, Painter, Pos2, Rect, Shape, Stroke, pos2, vec2};

/// The wheel's rim and spokes.
const WHEEL: Color32 = Color32::from_rgb(0x26, 0x2B, 0x31);
/// The button to press: a strong orange, 4.6:1 on the card's white.
const BUTTON: Color32 = Color32::from_rgb(0xB3, 0x4A, 0x00);
/// The forearm the sensor is strapped on (a light skin tone, outlined for contrast).
const SKIN: Color32 = Color32::from_rgb(0xE8, 0xB9, 0x96);
/// Arrows and the plug's cable.
const ARROW: Color32 = Color32::from_rgb(0x0B, 0x5C, 0xAD);

/// The wheel with its button lit in `rect`: a ring round the button when `hold`, arrows
/// round the rim when `turn`.
pub(super) fn wheel(p: &Painter, rect: Rect, hold: bool, turn: bool) {
    let c = rect.center();
    let r = rect.width().min(rect.height()) * 0.36;
    let rim = Stroke::new(r * 0.16, WHEEL);
    p.circle_stroke(c, r, rim);
    // Three spokes and the hub.
    for angle in [180.0_f32, 0.0, 90.0] {
        let a = angle.to_radians();
        p.line_segment(
            [c, c + vec2(a.cos(), a.sin()) * r * 0.92],
            Stroke::new(r * 0.12, WHEEL),
        );
    }
    p.circle_filled(c, r * 0.22, WHEEL);
    // The button on the right spoke (where a right hand's thumb rests), lit.
    let b = c + vec2(r * 0.55, -r * 0.02);
    p.circle_filled(b, r * 0.15, BUTTON);
    p.circle_stroke(b, r * 0.22, Stroke::new(r * 0.04, BUTTON));
    if hold {
        // A ring drawn three-quarters round: keep pressing.
        arc(p, b, r * 0.34, -90.0, 180.0, Stroke::new(r * 0.06, BUTTON));
    }
    if turn {
        let s = Stroke::new(r * 0.07, ARROW);
        arc(p, c, r * 1.28, 200.0, 250.0, s);
        arc(p, c, r * 1.28, 290.0, 340.0, s);
        arrow_head(p, c, r * 1.28, 200.0, -1.0, r * 0.18);
        arrow_head(p, c, r * 1.28, 340.0, 1.0, r * 0.18);
    }
}

/// An arc of a circle at `c` of radius `r` from `from_deg` to `to_deg` (clockwise on screen).
fn arc(p: &Painter, c: Pos2, r: f32, from_deg: f32, to_deg: f32, stroke: Stroke) {
    let n = 24;
    let points: Vec<Pos2> = (0..=n)
        .map(|i| {
            let a = (from_deg + (to_deg - from_deg) * i as f32 / n as f32).to_radians();
            c + vec2(a.cos(), a.sin()) * r
        })
        .collect();
    p.add(Shape::line(points, stroke));
}

/// A filled arrow head on the circle at `deg`, pointing along it (`dir` ±1).
fn arrow_head(p: &Painter, c: Pos2, r: f32, deg: f32, dir: f32, size: f32) {
    let a = deg.to_radians();
    let tip = c + vec2(a.cos(), a.sin()) * r;
    let along = vec2(-a.sin(), a.cos()) * dir;
    let out = vec2(a.cos(), a.sin());
    p.add(Shape::convex_polygon(
        vec![
            tip + along * size,
            tip - out * size * 0.7,
            tip + out * size * 0.7,
        ],
        ARROW,
        Stroke::NONE,
    ));
}

/// The plug going into the wheel's socket, an arrow pushing it in.
pub(super) fn plug(p: &Painter, rect: Rect) {
    let s = rect.width().min(rect.height());
    let c = rect.center();
    // The wheel's socket on the right, the plug coming from the left with an arrow.
    let socket = Rect::from_center_size(c + vec2(s * 0.25, 0.0), vec2(s * 0.22, s * 0.34));
    p.rect_filled(socket, 6.0, WHEEL);
    p.rect_filled(
        Rect::from_center_size(socket.center(), vec2(s * 0.1, s * 0.16)),
        3.0,
        Color32::WHITE,
    );
    let body = Rect::from_center_size(c + vec2(-s * 0.08, 0.0), vec2(s * 0.2, s * 0.18));
    p.rect_filled(body, 6.0, ARROW);
    // The pins, into the socket.
    for dy in [-0.04, 0.04] {
        p.line_segment(
            [
                pos2(body.right(), c.y + dy * s),
                pos2(body.right() + s * 0.07, c.y + dy * s),
            ],
            Stroke::new(s * 0.025, WHEEL),
        );
    }
    // The cable.
    p.line_segment(
        [pos2(body.left(), c.y), pos2(rect.left() + s * 0.05, c.y)],
        Stroke::new(s * 0.05, ARROW),
    );
    // The arrow: push it in.
    let y = c.y - s * 0.26;
    let (x0, x1) = (c.x - s * 0.2, c.x + s * 0.1);
    p.line_segment([pos2(x0, y), pos2(x1, y)], Stroke::new(s * 0.04, BUTTON));
    p.add(Shape::convex_polygon(
        vec![
            pos2(x1 + s * 0.08, y),
            pos2(x1, y - s * 0.06),
            pos2(x1, y + s * 0.06),
        ],
        BUTTON,
        Stroke::NONE,
    ));
}

/// The plug going back in (as [`plug`]), its cable coming from the sensor strapped on a
/// forearm at the picture's left.
/// The sensor strapped on the forearm, its cable's plug going back in.
pub(super) fn arm_sensor_plug(p: &Painter, rect: Rect) {
    plug(p, rect);
    let s = rect.width().min(rect.height());
    let c = rect.center();
    let x = rect.left() + s * 0.1;
    // The forearm, upright, outlined so it reads on white.
    let (top, bottom) = (pos2(x, c.y - s * 0.42), pos2(x, c.y + s * 0.42));
    p.line_segment([top, bottom], Stroke::new(s * 0.17, WHEEL));
    p.line_segment([top, bottom], Stroke::new(s * 0.13, SKIN));
    // The strap round it and the sensor on it, where the cable starts.
    p.line_segment(
        [pos2(x - s * 0.09, c.y), pos2(x + s * 0.09, c.y)],
        Stroke::new(s * 0.2, ARROW),
    );
    p.rect_filled(
        Rect::from_center_size(pos2(x, c.y), vec2(s * 0.15, s * 0.12)),
        4.0,
        WHEEL,
    );
}
