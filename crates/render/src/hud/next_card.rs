//! The card before an exercise: what comes next in plain words, the movement's picture with
//! its caption (a rest's picture during a rest, the next movement small beside its
//! countdown), kept off the patient's neglected side.

use super::{ACCENT, CARD, CARD_TEXT, MIN_TEXT_PT, PAD, galley};
use crate::Picture;
use crate::layout;
use crate::pictures;
use crate::scene::NextCard;
use crate::text;
use egui::{Color32, CornerRadius, Painter, Pos2, Rect, Vec2, pos2, vec2};
use regimen::NeglectedSide;

/// Paints `next` over a dimmed screen of `size` points, kept off the `neglected` side.
pub(super) fn paint(p: &Painter, size: Vec2, next: &NextCard, neglected: NeglectedSide) {
    p.rect_filled(
        Rect::from_min_size(Pos2::ZERO, size),
        CornerRadius::ZERO,
        Color32::from_black_alpha(150),
    );
    let rect = layout::card_rect(size, vec2(1160.0, 600.0), neglected);
    p.rect_filled(rect, CornerRadius::same(22), CARD);
    // The picture and its caption on the left (a rest's cup of tea during a rest), the
    // words on the right.
    let picture = if next.countdown_s.is_some() {
        Picture::Rest
    } else {
        Picture::Exercise(next.movement)
    };
    let pic_w = (rect.width() * 0.36).min(rect.height() * 0.62);
    let pic_rect = Rect::from_min_size(
        rect.left_top() + vec2(2.0 * PAD, 2.0 * PAD),
        vec2(pic_w, rect.height() - 4.0 * PAD),
    );
    pictures::draw_with_caption(p, picture, pic_rect, next.anim_s, CARD_TEXT);
    let text_left = pic_rect.right() + 3.0 * PAD;
    let width = rect.right() - 3.0 * PAD - text_left;
    let mut y = rect.top() + 3.0 * PAD;
    let line = |text: &str, pt: f32, color: Color32, y: &mut f32| {
        let g = text::layout(
            p,
            text,
            egui::FontId::proportional(pt),
            color,
            width,
            text::Align::Start,
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
        let (gw, gh) = (g.size().x, g.size().y);
        p.galley(pos2(text_left, y + 4.0), g, CARD_TEXT);
        // What comes after the rest, small beside the countdown.
        pictures::draw(
            p,
            Picture::Exercise(next.movement),
            Rect::from_min_size(pos2(text_left + gw + 3.0 * PAD, y + 4.0), vec2(gh, gh)),
            next.anim_s,
        );
    }
    let mut ky = rect.bottom() - 2.0 * PAD;
    for k in next.keys.iter().rev() {
        // Wrapped in the text column: a longer language never runs off the card.
        let g = text::layout(
            p,
            k,
            egui::FontId::proportional(30.0),
            crate::palette::CARD_KEYS,
            width,
            text::Align::Start,
        );
        ky -= g.size().y;
        p.galley(pos2(text_left, ky), g, crate::palette::CARD_KEYS);
    }
}

/// The therapist's message in the card's text column (`left`, `width`) between `top` and
/// `bottom`: "A message from your therapist:" then the text, in the largest type from 34 pt
/// down to [`MIN_TEXT_PT`] that fits (a 500-character message fits at the smallest).
fn paint_message(p: &Painter, message: &str, (left, width): (f32, f32), (top, bottom): (f32, f32)) {
    let heading = text::layout(
        p,
        &i18n::tr!("card-message-from-therapist"),
        egui::FontId::proportional(30.0),
        ACCENT,
        width,
        text::Align::Start,
    );
    let heading_h = heading.size().y;
    p.galley(pos2(left, top), heading, ACCENT);
    let top = top + heading_h + 6.0;
    let text = |pt: f32| {
        text::layout(
            p,
            message,
            egui::FontId::proportional(pt),
            CARD_TEXT,
            width,
            text::Align::Start,
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
