//! Our own pictures for the patient's pages, drawn with egui shapes (vector: sharp at any
//! size), each with a short caption from the `pictures` catalogue.
//!
//! A picture shows what a sentence says, for a reader who finds words hard (aphasia): the
//! movement of each exercise (every kind of road its own road, the dial's needles, pushing
//! against the wheel), rest, pause, what to do with the wheel's button, the plug, yes and no,
//! the end of a session and today's page. [`Picture`] (plain data, in the scene) is the one
//! picture type of the patient's window: the session's cards and the pages before and after a
//! session all draw from it. [`draw`] paints one into a rectangle; [`draw_with_caption`] adds
//! its caption under it. Moving pictures take an animation clock, s (any clock that moves on).

mod road;
mod symbols;
mod wheel;

use super::scene::{Movement, Picture};
use egui::{Color32, FontId, Painter, Rect, pos2};

/// Dark outlines of the pictures (13:1 on the white card).
pub const INK: Color32 = Color32::from_rgb(0x2A, 0x30, 0x38);

/// Paints `picture` centred in the largest square inside `rect`, `anim_s` moving it.
pub fn draw(p: &Painter, picture: Picture, rect: Rect, anim_s: f64) {
    let side = rect.width().min(rect.height());
    let sq = Rect::from_center_size(rect.center(), egui::vec2(side, side));
    match picture {
        Picture::Exercise(Movement::Dial) => symbols::dial(p, sq, anim_s),
        Picture::Exercise(Movement::Strength) => symbols::strength(p, sq, anim_s),
        Picture::Exercise(m) => road::draw(p, m, sq, anim_s),
        Picture::Rest => symbols::rest(p, sq, anim_s),
        Picture::Pause => symbols::pause(p, sq),
        Picture::Wheel { hold, turn } => wheel::wheel(p, sq, hold, turn),
        Picture::Plug => wheel::plug(p, sq),
        Picture::ArmSensorPlug => wheel::arm_sensor_plug(p, sq),
        Picture::Yes => symbols::yes(p, sq),
        Picture::No => symbols::no(p, sq),
        Picture::Done => symbols::star(p, sq),
        Picture::Today => symbols::calendar(p, sq),
    }
}

/// Caption type size, points at the reference size (see `hud`: 48 px at 1080p).
pub const CAPTION_PT: f32 = 32.0;

/// Paints `picture` in the top of `rect` and its caption, centred and wrapped, under it in
/// `color`; returns the caption's height, points.
pub fn draw_with_caption(
    p: &Painter,
    picture: Picture,
    rect: Rect,
    anim_s: f64,
    color: Color32,
) -> f32 {
    let g = crate::text::layout(
        p,
        &picture.caption(),
        FontId::proportional(CAPTION_PT),
        color,
        rect.width(),
        crate::text::Align::Block,
    );
    let caption_h = g.size().y;
    // The picture at the top, as large as fits, and its caption right under it.
    let side = rect.width().min(rect.height() - caption_h - 8.0).max(0.0);
    let pic = Rect::from_min_size(
        pos2(rect.center().x - side / 2.0, rect.min.y),
        egui::vec2(side, side),
    );
    draw(p, picture, pic, anim_s);
    let x = rect.center().x - g.size().x / 2.0;
    p.galley(pos2(x, pic.max.y + 8.0), g, color);
    caption_h
}

#[cfg(test)]
mod tests {
    use super::*;
    use egui::{Context, Id, LayerId, Order, vec2};
    use std::collections::HashSet;

    /// The shapes `picture` paints into a 300-point square at animation time `t`.
    fn shapes(picture: Picture, t: f64) -> Vec<egui::epaint::ClippedShape> {
        let ctx = Context::default();
        let mut out = ctx.run_pass(egui::RawInput::default(), |ctx| {
            let p = ctx.layer_painter(LayerId::new(Order::Foreground, Id::unique("pic")));
            draw(
                &p,
                picture,
                Rect::from_min_size(pos2(0.0, 0.0), vec2(300.0, 300.0)),
                t,
            );
        });
        out.textures_delta.clear();
        out.shapes
    }

    #[test]
    fn every_picture_draws_inside_its_square() {
        for picture in Picture::all() {
            let s = shapes(picture, 1.3);
            assert!(s.len() >= 3, "{picture:?} draws {} shapes", s.len());
            for c in &s {
                // What shows: the shape within its clip (the roads are clipped to the frame).
                let r = c.shape.visual_bounding_rect().intersect(c.clip_rect);
                if r.is_positive() {
                    assert!(
                        r.min.x >= -12.0
                            && r.min.y >= -12.0
                            && r.max.x <= 312.0
                            && r.max.y <= 312.0,
                        "{picture:?} paints outside its square: {r:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn every_road_exercise_has_its_own_picture() {
        let roads = [
            "straight-road",
            "sine-road",
            "triangle-road",
            "clothoid-road",
            "sharp-turns",
            "s-bend",
            "lane-change",
            "slalom",
        ];
        let movements: HashSet<Movement> = roads.iter().map(|r| Movement::of_exercise(r)).collect();
        assert_eq!(movements.len(), roads.len(), "{movements:?}");
        // And the drawings differ, not only the names: compare the painted shapes.
        let drawn: HashSet<String> = movements
            .iter()
            .map(|m| format!("{:?}", shapes(Picture::Exercise(*m), 0.0)))
            .collect();
        assert_eq!(drawn.len(), roads.len());
    }

    #[test]
    fn every_picture_has_a_short_caption_in_every_language() {
        for lang in i18n::LANGUAGES {
            let cat = i18n::Catalogue::load(lang).unwrap();
            for picture in Picture::all() {
                let id = picture.caption_id();
                assert!(cat.has(id), "{lang}: no caption {id}");
                let text = cat.message(id, None);
                assert!(!text.trim().is_empty(), "{lang}: {id} is empty");
                let words = text.split_whitespace().count();
                assert!(words <= 12, "{lang}: {id} has {words} words");
            }
        }
    }
}
