//! A card with a picture: the picture and its caption (the card's main sentence, also
//! spoken) on the left, the title and the lines (what to press) on the right; centred, or in
//! the middle of the side the patient attends to.

use super::{CARD, CARD_TEXT, PAD, galley};
use crate::Picture;
use crate::layout;
use crate::palette::CARD_KEYS;
use crate::pictures;
use crate::text;
use egui::{Color32, CornerRadius, Painter, Pos2, Rect, Vec2, pos2, vec2};
use regimen::NeglectedSide;

/// Paints the card over a dimmed screen of `size` points.
pub(super) fn paint(
    p: &Painter,
    size: Vec2,
    picture: Picture,
    title: &str,
    lines: &[String],
    neglected: NeglectedSide,
) {
    p.rect_filled(
        Rect::from_min_size(Pos2::ZERO, size),
        CornerRadius::ZERO,
        Color32::from_black_alpha(110),
    );
    let title_g = galley(p, title, 48.0, CARD_TEXT);
    let line_g: Vec<_> = lines
        .iter()
        .map(|l| galley(p, l.clone(), 32.0, CARD_KEYS))
        .collect();
    let pic = 300.0;
    let words_w = line_g
        .iter()
        .map(|g| g.size().x)
        .fold(title_g.size().x, f32::max);
    let want = vec2(pic + words_w + 7.0 * PAD, pic + 120.0);
    let rect = layout::card_rect(size, want, neglected);
    p.rect_filled(rect, CornerRadius::same(18), CARD);
    let pic_rect = Rect::from_min_size(
        rect.left_top() + vec2(2.0 * PAD, 2.0 * PAD),
        vec2(pic, rect.height() - 4.0 * PAD),
    );
    pictures::draw_with_caption(p, picture, pic_rect, 0.0, CARD_TEXT);
    let left = pic_rect.right() + 3.0 * PAD;
    let width = (rect.right() - 2.0 * PAD - left).max(50.0);
    let wrap = |text: &str, pt: f32, color: Color32| {
        text::layout(
            p,
            text,
            egui::FontId::proportional(pt),
            color,
            width,
            text::Align::Start,
        )
    };
    let mut y = rect.top() + 3.0 * PAD;
    let title_g = wrap(title, 48.0, CARD_TEXT);
    let th = title_g.size().y;
    p.galley(pos2(left, y), title_g, CARD_TEXT);
    y += th + 24.0;
    for line in lines {
        let g = wrap(line, 32.0, CARD_KEYS);
        let gh = g.size().y;
        p.galley(pos2(left, y), g, CARD_KEYS);
        y += gh + 8.0;
    }
}
