//! The end screen's pages ([`CheckInPage`]): the session's results, the three questions on
//! pictured scales, the thanks, and the page that says to stop and call the clinic. Our own
//! drawings, egui shapes only: six faces from green (no pain) to red (the worst pain) over
//! the numbers 0–10; effort as eleven bars growing to the right; a thumb down, flat and up.
//! The choice is the one tile drawn large with a thick dark frame and a pointer above it,
//! and said in large words under the scale; before the patient chooses nothing is framed.
//! Sizes at the 1280×720 reference: title 48 pt, the chosen words 40 pt, lines 30 pt, the
//! smallest text 24 pt ([`super::MIN_TEXT_PT`]).

use egui::epaint::PathShape;
use egui::{Align2, Color32, CornerRadius, FontId, Painter, Pos2, Rect, Stroke, Vec2, pos2, vec2};

use super::{CARD, CARD_TEXT, MIN_TEXT_PT, PAD};
use crate::text;
use crate::{CheckInPage, CheckInScale, ScaleKind};

/// Behind the page (as the pages before a session).
const BACKDROP: Color32 = Color32::from_rgb(0x22, 0x3A, 0x4E);
/// The page that says to stop: its band and frame.
const STOP: Color32 = Color32::from_rgb(0xB7, 0x1C, 0x1C);
/// Quiet words: the keys, the hint to choose (7.9:1 on the card).
const QUIET: Color32 = Color32::from_rgb(0x45, 0x4F, 0x5A);
/// The frame of the chosen tile.
const CHOSEN: Color32 = Color32::from_rgb(0x10, 0x14, 0x1A);

/// The six faces' colours, green to red.
const FACE_COLOURS: [Color32; 6] = [
    Color32::from_rgb(0x2E, 0x7D, 0x32),
    Color32::from_rgb(0x7C, 0xB3, 0x42),
    Color32::from_rgb(0xFB, 0xC0, 0x2D),
    Color32::from_rgb(0xFB, 0x8C, 0x00),
    Color32::from_rgb(0xE6, 0x4A, 0x19),
    Color32::from_rgb(0xC6, 0x28, 0x28),
];

const TITLE_PT: f32 = 48.0;
const CHOSEN_PT: f32 = 40.0;
const LINE_PT: f32 = 30.0;

/// Paints `page` over the whole `size` (points).
pub(super) fn paint(p: &Painter, page: &CheckInPage, size: Vec2) {
    p.rect_filled(
        Rect::from_min_size(Pos2::ZERO, size),
        CornerRadius::ZERO,
        BACKDROP,
    );
    let card = Rect::from_center_size(
        pos2(size.x / 2.0, size.y / 2.0),
        vec2((size.x - 60.0).clamp(300.0, 1200.0), size.y - 40.0),
    );
    p.rect_filled(card, CornerRadius::same(22), CARD);
    let width = card.width() - 4.0 * PAD;
    let mut y = card.top() + 2.0 * PAD;
    if page.stop {
        let band = Rect::from_min_max(card.min, pos2(card.right(), card.top() + 120.0));
        p.rect_filled(band, CornerRadius::same(22), STOP);
        let g = text::layout(
            p,
            &page.title,
            FontId::proportional(TITLE_PT + 4.0),
            Color32::WHITE,
            width,
            text::Align::Block,
        );
        let at = pos2(
            card.center().x - g.size().x / 2.0,
            band.center().y - g.size().y / 2.0,
        );
        p.galley(at, g, Color32::WHITE);
        y = band.bottom() + 2.0 * PAD;
        phone(p, pos2(card.right() - 150.0, y + 120.0), 110.0);
    } else {
        y += centred(
            p,
            &page.title,
            TITLE_PT,
            CARD_TEXT,
            card.center().x,
            y,
            width,
        ) + PAD;
    }
    if let Some(scale) = &page.scale {
        let area = Rect::from_min_size(pos2(card.left() + 2.0 * PAD, y), vec2(width, 300.0));
        match scale.kind {
            ScaleKind::Faces => faces(p, scale, area),
            ScaleKind::Effort => effort(p, scale, area),
            ScaleKind::Thumbs => thumbs(p, scale, area),
        }
        y = area.bottom() + PAD;
        let colour = if scale.choice.is_some() {
            CARD_TEXT
        } else {
            QUIET
        };
        y += centred(
            p,
            &scale.chosen,
            CHOSEN_PT,
            colour,
            card.center().x,
            y,
            width,
        ) + PAD;
    }
    let left = card.left() + 3.0 * PAD;
    let line_width = if page.stop {
        width - 300.0
    } else {
        width - 2.0 * PAD
    };
    for line in &page.lines {
        let g = text::layout(
            p,
            line,
            FontId::proportional(LINE_PT + if page.stop { 4.0 } else { 0.0 }),
            CARD_TEXT,
            line_width,
            text::Align::Start,
        );
        let h = g.size().y;
        p.galley(pos2(left, y), g, CARD_TEXT);
        y += h + 10.0;
    }
    let keys = page.keys.join("     ");
    if !keys.is_empty() {
        let g = text::layout(
            p,
            &keys,
            FontId::proportional(MIN_TEXT_PT + 2.0),
            QUIET,
            width,
            text::Align::Block,
        );
        let at = pos2(
            card.center().x - g.size().x / 2.0,
            card.bottom() - 1.5 * PAD - g.size().y,
        );
        p.galley(at, g, QUIET);
    }
}

/// Text centred on `cx` from `y`, wrapped at `width`; returns its height.
fn centred(p: &Painter, s: &str, pt: f32, colour: Color32, cx: f32, y: f32, width: f32) -> f32 {
    let g = text::layout(
        p,
        s,
        FontId::proportional(pt),
        colour,
        width,
        text::Align::Block,
    );
    let h = g.size().y;
    p.galley(pos2(cx - g.size().x / 2.0, y), g, colour);
    h
}

/// The colour of pain `value` (0–10) between the faces' green and red.
pub fn pain_colour(value: u8) -> Color32 {
    let t = f32::from(value.min(10)) / 2.0;
    let i = (t.floor() as usize).min(4);
    lerp(FACE_COLOURS[i], FACE_COLOURS[i + 1], t - i as f32)
}

fn lerp(a: Color32, b: Color32, t: f32) -> Color32 {
    let m = |x: u8, y: u8| (f32::from(x) + (f32::from(y) - f32::from(x)) * t).round() as u8;
    Color32::from_rgb(m(a.r(), b.r()), m(a.g(), b.g()), m(a.b(), b.b()))
}

/// The face of pain `value`: one of six, at 0, 2, 4, 6, 8 and 10 (odd values the next up).
pub fn face_of(value: u8) -> usize {
    usize::from(value.min(10)).div_ceil(2)
}

/// Eleven numbered tiles across `area`'s bottom, coloured by `colour`, the chosen one large
/// and framed with a pointer above; returns the tiles' centres.
fn tiles(
    p: &Painter,
    area: Rect,
    top: f32,
    choice: Option<u8>,
    colour: impl Fn(u8) -> Color32,
) -> Vec<Pos2> {
    let w = area.width() / 11.0;
    let h = 70.0;
    (0..=10u8)
        .map(|v| {
            let c = pos2(area.left() + (f32::from(v) + 0.5) * w, top + h / 2.0);
            let chosen = choice == Some(v);
            let size = if chosen {
                vec2(w * 0.98, h * 1.25)
            } else {
                vec2(w * 0.84, h)
            };
            let r = Rect::from_center_size(c, size);
            p.rect_filled(r, CornerRadius::same(10), colour(v));
            if chosen {
                p.rect_stroke(
                    r,
                    CornerRadius::same(10),
                    Stroke::new(6.0, CHOSEN),
                    egui::StrokeKind::Outside,
                );
            }
            let text = if text_on_dark(colour(v)) {
                Color32::WHITE
            } else {
                CARD_TEXT
            };
            text::put(
                p,
                c,
                Align2::CENTER_CENTER,
                &v.to_string(),
                FontId::proportional(if chosen { 44.0 } else { 34.0 }),
                text,
            );
            c
        })
        .collect()
}

/// White text reads on this colour (else near-black).
fn text_on_dark(c: Color32) -> bool {
    let l = 0.2126 * f32::from(c.r()) + 0.7152 * f32::from(c.g()) + 0.0722 * f32::from(c.b());
    l < 140.0
}

/// Six faces over the numbers 0–10.
fn faces(p: &Painter, scale: &CheckInScale, area: Rect) {
    let w = area.width() / 11.0;
    let r = (w * 0.95).min(62.0);
    let face_y = area.top() + r + 8.0;
    let chosen_face = scale.choice.map(face_of);
    for (i, colour) in FACE_COLOURS.iter().enumerate() {
        let c = pos2(area.left() + (2.0 * i as f32 + 0.5) * w, face_y);
        face(p, c, r, i, *colour, chosen_face == Some(i));
    }
    let top = face_y + r + 46.0;
    let centres = tiles(p, area, top, scale.choice, pain_colour);
    if let Some(v) = scale.choice {
        pointer(p, centres[usize::from(v)]);
    }
}

/// One face: `i` of six (0 smiling, 5 crying), framed when chosen.
fn face(p: &Painter, c: Pos2, r: f32, i: usize, colour: Color32, chosen: bool) {
    p.circle_filled(c, r, colour);
    let ink = Stroke::new(r * 0.08, CHOSEN);
    p.circle_stroke(c, r, Stroke::new(3.0, CHOSEN));
    if chosen {
        p.circle_stroke(c, r + 7.0, Stroke::new(6.0, CHOSEN));
    }
    let eye_dy = -0.25 * r;
    for side in [-1.0f32, 1.0] {
        let e = c + vec2(side * 0.35 * r, eye_dy);
        p.circle_filled(e, r * 0.09, CHOSEN);
        if i >= 3 {
            // Brows drawn together, higher at the middle: it hurts.
            let lift = 0.06 * (i as f32 - 2.0) * r;
            p.line_segment(
                [
                    e + vec2(-side * 0.05 * r, -0.2 * r - lift),
                    e + vec2(side * 0.22 * r, -0.18 * r + lift * 0.3),
                ],
                ink,
            );
        }
    }
    if i == 5 {
        // A tear.
        p.circle_filled(
            c + vec2(0.45 * r, 0.02 * r),
            r * 0.09,
            Color32::from_rgb(0x90, 0xCA, 0xF9),
        );
    }
    // The mouth: a smile (0) to a deep frown (5).
    let curve = 1.0 - 2.0 * i as f32 / 5.0;
    let mouth: Vec<Pos2> = (0..=12)
        .map(|k| {
            let x = -0.4 + 0.8 * k as f32 / 12.0;
            // Screen y grows downwards: a smile's middle is lower than its ends.
            let y = 0.3 + curve * 0.22 * (1.0 - (x / 0.4).powi(2));
            c + vec2(x * r, (y + 0.05 * (1.0 - curve.abs())) * r - 0.02 * r)
        })
        .collect();
    p.add(PathShape::line(mouth, ink));
}

/// A downward triangle over the chosen tile.
fn pointer(p: &Painter, tile_centre: Pos2) {
    let tip = tile_centre + vec2(0.0, -52.0);
    p.add(PathShape::convex_polygon(
        vec![tip, tip + vec2(-16.0, -20.0), tip + vec2(16.0, -20.0)],
        CHOSEN,
        Stroke::NONE,
    ));
}

/// Effort: eleven bars growing to the right, light to dark blue, over the numbers 0–10, with
/// the words at both ends.
fn effort(p: &Painter, scale: &CheckInScale, area: Rect) {
    let w = area.width() / 11.0;
    let base = area.top() + 150.0;
    let colour = |v: u8| {
        lerp(
            Color32::from_rgb(0xBB, 0xDE, 0xFB),
            Color32::from_rgb(0x0D, 0x47, 0xA1),
            f32::from(v) / 10.0,
        )
    };
    for v in 0..=10u8 {
        let h = 20.0 + 120.0 * f32::from(v) / 10.0;
        let x = area.left() + (f32::from(v) + 0.5) * w;
        let r = Rect::from_min_max(pos2(x - w * 0.3, base - h), pos2(x + w * 0.3, base));
        p.rect_filled(r, CornerRadius::same(6), colour(v));
        if scale.choice == Some(v) {
            p.rect_stroke(
                r,
                CornerRadius::same(6),
                Stroke::new(6.0, CHOSEN),
                egui::StrokeKind::Outside,
            );
        }
    }
    let top = base + 50.0;
    let centres = tiles(p, area, top, scale.choice, colour);
    if let Some(v) = scale.choice {
        pointer(p, centres[usize::from(v)]);
    }
    let ends_y = top + 80.0;
    for (v, align, x) in [
        (0, Align2::LEFT_TOP, area.left()),
        (10, Align2::RIGHT_TOP, area.right()),
    ] {
        if let Some(words) = scale.words.get(v) {
            text::put(
                p,
                pos2(x, ends_y),
                align,
                words,
                FontId::proportional(MIN_TEXT_PT),
                QUIET,
            );
        }
    }
}

/// Three tiles: a thumb down, flat and up, each with its words.
fn thumbs(p: &Painter, scale: &CheckInScale, area: Rect) {
    let gap = 40.0;
    let w = ((area.width() - 2.0 * gap) / 3.0).min(330.0);
    let left = area.center().x - (3.0 * w + 2.0 * gap) / 2.0;
    for i in 0..3u8 {
        let r = Rect::from_min_size(
            pos2(left + f32::from(i) * (w + gap), area.top() + 10.0),
            vec2(w, area.height() - 20.0),
        );
        let chosen = scale.choice == Some(i);
        let fill = if chosen {
            Color32::from_rgb(0xE3, 0xF2, 0xFD)
        } else {
            Color32::from_rgb(0xF0, 0xF0, 0xEC)
        };
        p.rect_filled(r, CornerRadius::same(18), fill);
        p.rect_stroke(
            r,
            CornerRadius::same(18),
            if chosen {
                Stroke::new(7.0, CHOSEN)
            } else {
                Stroke::new(2.0, QUIET)
            },
            egui::StrokeKind::Inside,
        );
        // 0: down, 1: flat (pointing right), 2: up.
        let angle = match i {
            0 => std::f32::consts::PI,
            1 => std::f32::consts::FRAC_PI_2,
            _ => 0.0,
        };
        thumb(p, r.center() - vec2(0.0, 30.0), 70.0, angle);
        if let Some(words) = scale.words.get(usize::from(i)) {
            text::put(
                p,
                pos2(r.center().x, r.bottom() - 22.0),
                Align2::CENTER_BOTTOM,
                words,
                FontId::proportional(LINE_PT + 2.0),
                CARD_TEXT,
            );
        }
    }
}

/// A fist with its thumb out, turned by `angle` (0: thumb up, π/2: right, π: down), about
/// `size` points across.
fn thumb(p: &Painter, c: Pos2, size: f32, angle: f32) {
    let skin = Color32::from_rgb(0xF2, 0xC0, 0x8E);
    let line = Stroke::new(4.0, CHOSEN);
    let turn = |v: Vec2| {
        let (s, co) = angle.sin_cos();
        c + vec2(v.x * co - v.y * s, v.x * s + v.y * co)
    };
    // The fist: a rounded block of four fingers, drawn as a polygon so it turns with the thumb.
    let half = vec2(0.55 * size, 0.45 * size);
    let fist: Vec<Pos2> = [
        vec2(-half.x, -half.y * 0.2),
        vec2(half.x * 0.6, -half.y * 0.2),
        vec2(half.x, half.y * 0.2),
        vec2(half.x, half.y),
        vec2(-half.x, half.y),
    ]
    .into_iter()
    .map(turn)
    .collect();
    p.add(PathShape::convex_polygon(fist, skin, line));
    for k in 1..4 {
        let y = -half.y * 0.2 + (half.y * 1.2) * k as f32 / 4.0;
        p.line_segment(
            [turn(vec2(-half.x, y)), turn(vec2(half.x * 0.2, y))],
            Stroke::new(3.0, CHOSEN),
        );
    }
    // The thumb: up from the fist's top left.
    let thumb: Vec<Pos2> = [
        vec2(-half.x * 0.75, -half.y * 0.2),
        vec2(-half.x * 0.75, -size * 1.05),
        vec2(-half.x * 0.55, -size * 1.15),
        vec2(-half.x * 0.05, -size * 1.05),
        vec2(-half.x * 0.05, -half.y * 0.2),
    ]
    .into_iter()
    .map(turn)
    .collect();
    p.add(PathShape::convex_polygon(thumb, skin, line));
}

/// A telephone: a handset over a desk phone's body, `size` points across, centred at `c`.
fn phone(p: &Painter, c: Pos2, size: f32) {
    let ink = Stroke::new(5.0, CHOSEN);
    let body = Rect::from_center_size(c + vec2(0.0, size * 0.2), vec2(size, size * 0.6));
    p.rect_filled(body, CornerRadius::same(14), STOP);
    p.rect_stroke(body, CornerRadius::same(14), ink, egui::StrokeKind::Outside);
    // The dial's buttons.
    for row in 0..3 {
        for col in 0..3 {
            let b = body.center()
                + vec2(
                    (col as f32 - 1.0) * size * 0.18,
                    (row as f32 - 0.8) * size * 0.12,
                );
            p.circle_filled(b, size * 0.04, Color32::WHITE);
        }
    }
    // The handset resting on top: a bar with an ear and a mouth piece.
    let top = body.top() - size * 0.12;
    let bar = Rect::from_center_size(pos2(c.x, top), vec2(size * 1.1, size * 0.16));
    p.rect_filled(bar, CornerRadius::same(10), STOP);
    p.rect_stroke(bar, CornerRadius::same(10), ink, egui::StrokeKind::Outside);
    for side in [-1.0f32, 1.0] {
        let end = Rect::from_center_size(
            pos2(c.x + side * size * 0.48, top + size * 0.08),
            vec2(size * 0.26, size * 0.2),
        );
        p.rect_filled(end, CornerRadius::same(8), STOP);
        p.rect_stroke(end, CornerRadius::same(8), ink, egui::StrokeKind::Outside);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_faces_go_from_green_to_red_and_odd_values_take_the_next_face() {
        assert_eq!(pain_colour(0), FACE_COLOURS[0]);
        assert_eq!(pain_colour(10), FACE_COLOURS[5]);
        assert!(pain_colour(10).r() > pain_colour(0).r());
        assert!(pain_colour(0).g() > pain_colour(10).g());
        assert_eq!([0, 1, 2, 7, 10].map(face_of), [0, 1, 1, 4, 5]);
    }
}
