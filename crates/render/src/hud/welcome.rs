//! The full-screen pages before a session ([`Welcome`]): pairing, today's session and the
//! device check. Large type for a screen across the room: the title 52 pt, lines 30 pt, the
//! typed code 60 pt at the 1280×720 reference size; dark text on white; what is wrong in red
//! with a cross, what is ready in green with a tick (never colour alone).

use egui::{Align2, Color32, CornerRadius, FontId, Painter, Pos2, Rect, Stroke, Vec2, pos2, vec2};

use super::{CARD, CARD_TEXT, PAD};
use crate::text;
use crate::{StatusLine, Welcome};

/// Behind the page.
const BACKDROP: Color32 = Color32::from_rgb(0x22, 0x3A, 0x4E);
/// What went wrong.
const PROBLEM: Color32 = Color32::from_rgb(0xB7, 0x1C, 0x1C);
/// The chosen choice's fill: dark blue, 8.6:1 under white text.
const CHOSEN: Color32 = Color32::from_rgb(0x0B, 0x3D, 0x91);
/// The keys' line.
const QUIET: Color32 = Color32::from_rgb(0x45, 0x4F, 0x5A);

const TITLE_PT: f32 = 52.0;
const LINE_PT: f32 = 30.0;
const FIELD_PT: f32 = 60.0;

/// Paints `page` over the whole `size` (points).
pub(super) fn paint(p: &Painter, page: &Welcome, size: Vec2) {
    p.rect_filled(
        Rect::from_min_size(Pos2::ZERO, size),
        CornerRadius::ZERO,
        BACKDROP,
    );
    let card = Rect::from_center_size(
        pos2(size.x / 2.0, size.y / 2.0),
        vec2((size.x - 80.0).clamp(300.0, 1100.0), size.y - 60.0),
    );
    p.rect_filled(card, CornerRadius::same(22), CARD);
    let left = card.left() + 3.0 * PAD;
    let mut width = card.width() - 6.0 * PAD;
    let mut picture_bottom = card.top();
    if let Some(picture) = page.picture {
        // The picture at the card's top right, the words beside it.
        let side = (card.height() * 0.42).min(width * 0.32);
        let at = Rect::from_min_size(
            pos2(card.right() - 2.0 * PAD - side, card.top() + 2.0 * PAD),
            vec2(side, side),
        );
        crate::pictures::draw(p, picture, at, 0.0);
        picture_bottom = at.bottom();
        width -= side + PAD;
    }
    let mut y = card.top() + 2.5 * PAD;
    y += text(p, &page.title, TITLE_PT, CARD_TEXT, pos2(left, y), width) + 18.0;
    for line in &page.lines {
        y += status_line(p, line, pos2(left, y), width) + 10.0;
    }
    if let Some((label, typed)) = &page.field {
        y += 8.0;
        y += text(p, label, LINE_PT, CARD_TEXT, pos2(left, y), width) + 8.0;
        y += field(p, typed, pos2(left, y), width) + 10.0;
    }
    if !page.choices.is_empty() {
        y += 10.0;
        y += choices(
            p,
            &page.choices,
            page.chosen,
            pos2(left, y),
            // Beside the picture, never under it; the whole width below it.
            if y < picture_bottom {
                width
            } else {
                card.width() - 6.0 * PAD
            },
        ) + 14.0;
    }
    if let Some(error) = &page.error {
        status_line(
            p,
            &StatusLine {
                ok: Some(false),
                text: error.clone(),
            },
            pos2(left, y),
            width,
        );
    }
    // One line a way of doing it (the wheel's, the keyboard's): never wrapped into each other.
    let keys = page.keys.join("\n");
    if !keys.is_empty() {
        let g = text::layout(
            p,
            &keys,
            FontId::proportional(LINE_PT - 2.0),
            QUIET,
            width,
            text::Align::Start,
        );
        let at = pos2(left, card.bottom() - 2.0 * PAD - g.size().y);
        p.galley(at, g, QUIET);
    }
}

/// Wrapped text at `at`; returns its height.
fn text(p: &Painter, s: &str, pt: f32, color: Color32, at: Pos2, width: f32) -> f32 {
    let g = text::layout(
        p,
        s,
        FontId::proportional(pt),
        color,
        width,
        text::Align::Start,
    );
    let h = g.size().y;
    p.galley(at, g, color);
    h
}

/// A tick, a cross or nothing, then the wrapped line; returns its height.
fn status_line(p: &Painter, line: &StatusLine, at: Pos2, width: f32) -> f32 {
    let mark = 40.0;
    // Only a line with a tick or a cross is indented past it.
    let indent = if line.ok.is_some() { mark + 8.0 } else { 0.0 };
    let color = match line.ok {
        Some(false) => PROBLEM,
        _ => CARD_TEXT,
    };
    let h = text(
        p,
        &line.text,
        LINE_PT,
        color,
        at + vec2(indent, 0.0),
        width - indent,
    );
    let c = at + vec2(mark / 2.0, LINE_PT * 0.62);
    let r = LINE_PT * 0.45;
    let white = Stroke::new(4.0, Color32::WHITE);
    match line.ok {
        Some(true) => super::tick_mark(p, c, r, 4.0),
        Some(false) => {
            p.circle_filled(c, r, PROBLEM);
            let d = 0.4 * r;
            p.line_segment([c + vec2(-d, -d), c + vec2(d, d)], white);
            p.line_segment([c + vec2(-d, d), c + vec2(d, -d)], white);
        }
        None => {}
    }
    h
}

/// The box the code is typed into, with a caret after the text; returns its height.
fn field(p: &Painter, typed: &str, at: Pos2, width: f32) -> f32 {
    let g = p.layout_no_wrap(typed.to_owned(), FontId::monospace(FIELD_PT), CARD_TEXT);
    let h = FIELD_PT * 1.5;
    let rect = Rect::from_min_size(at, vec2(width.min(700.0), h));
    p.rect_filled(rect, CornerRadius::same(10), Color32::WHITE);
    p.rect_stroke(
        rect,
        CornerRadius::same(10),
        Stroke::new(3.0, CARD_TEXT),
        egui::StrokeKind::Inside,
    );
    let text_at =
        Align2::LEFT_CENTER.anchor_size(rect.left_center() + vec2(PAD * 1.5, 0.0), g.size());
    let caret_x = text_at.right() + 4.0;
    p.galley(text_at.min, g, CARD_TEXT);
    p.line_segment(
        [
            pos2(caret_x, rect.top() + 0.2 * h),
            pos2(caret_x, rect.bottom() - 0.2 * h),
        ],
        Stroke::new(3.0, CARD_TEXT),
    );
    h
}

/// Large choices in a row, the chosen one filled and framed (never colour alone: it also has
/// an arrow under it); returns their height.
fn choices(p: &Painter, items: &[String], chosen: usize, at: Pos2, width: f32) -> f32 {
    let gap = 16.0;
    let n = items.len().max(1) as f32;
    let w = ((width - gap * (n - 1.0)) / n).min(360.0);
    let h = LINE_PT * 2.4;
    for (i, item) in items.iter().enumerate() {
        let rect = Rect::from_min_size(at + vec2(i as f32 * (w + gap), 0.0), vec2(w, h));
        let on = i == chosen;
        let (fill, ink) = if on {
            (CHOSEN, Color32::WHITE)
        } else {
            (Color32::WHITE, CARD_TEXT)
        };
        p.rect_filled(rect, CornerRadius::same(12), fill);
        p.rect_stroke(
            rect,
            CornerRadius::same(12),
            Stroke::new(if on { 6.0 } else { 2.0 }, CARD_TEXT),
            egui::StrokeKind::Inside,
        );
        let g = text::layout(
            p,
            item,
            FontId::proportional(LINE_PT),
            ink,
            w - PAD,
            text::Align::Block,
        );
        let text_at = Align2::CENTER_CENTER.anchor_size(rect.center(), g.size());
        p.galley(text_at.min, g, ink);
        if on {
            let tip = pos2(rect.center().x, rect.bottom() + 4.0);
            p.add(egui::Shape::convex_polygon(
                vec![tip, tip + vec2(-14.0, 16.0), tip + vec2(14.0, 16.0)],
                CARD_TEXT,
                Stroke::NONE,
            ));
        }
    }
    h + 20.0
}
