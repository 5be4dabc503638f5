//! Where the essential things of the patient's screen go when the patient neglects one side
//! of space (after a stroke, often the left): everything that matters away from that side,
//! and an anchoring cue on it before each exercise to draw the eyes over.
//!
//! The side is process-wide ([`set_neglected_side`]): the station shows one patient's
//! screens, and the prescription's `[patient] neglected_side` sets it. The drawing functions
//! take the side as an argument, so tests need not touch the process-wide value.

use egui::{Align2, Color32, CornerRadius, Painter, Pos2, Rect, Vec2, pos2, vec2};
use regimen::NeglectedSide;
use std::sync::atomic::{AtomicU8, Ordering};

static SIDE: AtomicU8 = AtomicU8::new(0);

/// Lays out every later frame for a patient who neglects `side`.
pub fn set_neglected_side(side: NeglectedSide) {
    let v = match side {
        NeglectedSide::None => 0,
        NeglectedSide::Left => 1,
        NeglectedSide::Right => 2,
    };
    SIDE.store(v, Ordering::Relaxed);
}

/// The side set by [`set_neglected_side`] (none at first).
pub fn neglected_side() -> NeglectedSide {
    match SIDE.load(Ordering::Relaxed) {
        1 => NeglectedSide::Left,
        2 => NeglectedSide::Right,
        _ => NeglectedSide::None,
    }
}

/// The share of the screen's width, from the neglected edge, that holds nothing essential.
pub const NEGLECTED_SHARE: f32 = 0.28;

/// A card of at most `max` points on a screen of `size`: centred without neglect; with it,
/// narrowed to the attended `1 − NEGLECTED_SHARE` of the screen (less a margin) and centred
/// there.
pub fn card_rect(size: Vec2, max: Vec2, side: NeglectedSide) -> Rect {
    let margin = 40.0;
    let (lo, hi) = attended_span(size.x, side);
    let w = max.x.min(hi - lo - 2.0 * margin).max(100.0);
    let h = max.y.min(size.y - 60.0).max(100.0);
    Rect::from_center_size(pos2((lo + hi) / 2.0, size.y / 2.0), vec2(w, h))
}

/// The span of x (points) that holds the essential things on a screen `width` wide.
pub fn attended_span(width: f32, side: NeglectedSide) -> (f32, f32) {
    match side {
        NeglectedSide::None => (0.0, width),
        NeglectedSide::Left => (width * NEGLECTED_SHARE, width),
        NeglectedSide::Right => (0.0, width * (1.0 - NEGLECTED_SHARE)),
    }
}

/// `align` for a HUD panel: with a left neglect, what sits on the left edge moves to the
/// right edge and the right to the left (a mirror), so the exercise's name, the help meter
/// and the speed stay in view; a right neglect keeps them on the left already.
pub fn hud_align(align: Align2, side: NeglectedSide) -> Align2 {
    if side != NeglectedSide::Left {
        return align;
    }
    let x = match align.x() {
        egui::Align::Min => egui::Align::Max,
        egui::Align::Max => egui::Align::Min,
        c => c,
    };
    Align2([x, align.y()])
}

/// The x of a HUD anchor at `x` on a screen `width` wide, mirrored like [`hud_align`]; the
/// middle (the time left) moves into the attended span's middle.
pub fn hud_x(x: f32, width: f32, side: NeglectedSide) -> f32 {
    let mid = (width / 2.0 - x).abs() < 1.0;
    match side {
        NeglectedSide::None => x,
        _ if mid => {
            let (lo, hi) = attended_span(width, side);
            (lo + hi) / 2.0
        }
        NeglectedSide::Left => width - x,
        NeglectedSide::Right => x,
    }
}

/// The anchoring cue's colour: a warm orange no screen element uses.
pub const CUE: Color32 = Color32::from_rgb(0xF5, 0x7C, 0x00);

/// Width of the anchoring bar, points at the reference size (5 % of the width).
pub const CUE_WIDTH_PT: f32 = 64.0;

/// The anchoring cue: a bright bar along the neglected edge, pulsing with `anim_s`, with an
/// arrow pointing into it. Nothing without neglect. Returns the bar's rectangle.
pub fn paint_cue(p: &Painter, size: Vec2, side: NeglectedSide, anim_s: f64) -> Option<Rect> {
    let left = match side {
        NeglectedSide::None => return None,
        NeglectedSide::Left => true,
        NeglectedSide::Right => false,
    };
    let bar = if left {
        Rect::from_min_size(Pos2::ZERO, vec2(CUE_WIDTH_PT, size.y))
    } else {
        Rect::from_min_size(pos2(size.x - CUE_WIDTH_PT, 0.0), vec2(CUE_WIDTH_PT, size.y))
    };
    let pulse = 0.75 + 0.25 * (anim_s * 4.0).sin() as f32;
    p.rect_filled(bar, CornerRadius::ZERO, CUE.gamma_multiply(pulse));
    // Chevrons down the bar pointing outwards: "look this way".
    let s = if left { -1.0 } else { 1.0 };
    for k in 0..4 {
        let c = pos2(bar.center().x, size.y * (0.2 + 0.2 * k as f32));
        let h = CUE_WIDTH_PT * 0.35;
        p.line_segment(
            [c + vec2(-s * h * 0.5, -h), c + vec2(s * h * 0.5, 0.0)],
            egui::Stroke::new(8.0, Color32::WHITE),
        );
        p.line_segment(
            [c + vec2(s * h * 0.5, 0.0), c + vec2(-s * h * 0.5, h)],
            egui::Stroke::new(8.0, Color32::WHITE),
        );
    }
    Some(bar)
}

// Sized for the sofa: the patient reads a television across the room.

/// The reading distance the screens are sized for, m (a sofa to a television).
pub const VIEWING_DISTANCE_M: f64 = 2.0;

/// The picture height of the smallest television the screens are sized for, m (a 40-inch
/// 16:9 set: 0.498 m).
pub const SCREEN_HEIGHT_M: f64 = 0.498;

/// The smallest cap height of any text on a session's pages, arc minutes at
/// [`VIEWING_DISTANCE_M`]: the preferred character height for reading of HFES 100 (20–22′).
pub const MIN_CAP_ARCMIN: f64 = 20.0;

/// The cap height of a page's main sentence (the cards' titles, instructions and picture
/// captions), arc minutes: half as large again, for eyes over 65 and after a stroke.
pub const MAIN_CAP_ARCMIN: f64 = 25.0;

/// Pixels at 1080 lines that subtend `arcmin` at the viewing distance on the reference set.
pub fn px_at_1080p(arcmin: f64) -> f64 {
    let m = 2.0 * VIEWING_DISTANCE_M * (arcmin / 60.0 / 2.0).to_radians().tan();
    m / (SCREEN_HEIGHT_M / 1080.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    const SIZE: Vec2 = vec2(1280.0, 720.0);

    #[test]
    fn without_neglect_a_card_is_centred() {
        let r = card_rect(SIZE, vec2(1160.0, 600.0), NeglectedSide::None);
        assert!((r.center().x - 640.0).abs() < 0.5);
    }

    #[test]
    fn with_a_neglected_side_the_card_keeps_off_that_side() {
        let left = card_rect(SIZE, vec2(1160.0, 600.0), NeglectedSide::Left);
        assert!(left.left() >= SIZE.x * NEGLECTED_SHARE, "{left:?}");
        assert!(left.right() <= SIZE.x);
        let right = card_rect(SIZE, vec2(1160.0, 600.0), NeglectedSide::Right);
        assert!(
            right.right() <= SIZE.x * (1.0 - NEGLECTED_SHARE),
            "{right:?}"
        );
    }

    #[test]
    fn with_left_neglect_the_left_edge_hud_moves_right_and_the_time_into_the_attended_middle() {
        let a = hud_align(Align2::LEFT_TOP, NeglectedSide::Left);
        assert_eq!(a, Align2::RIGHT_TOP);
        assert_eq!(hud_x(16.0, 1280.0, NeglectedSide::Left), 1264.0);
        let mid = hud_x(640.0, 1280.0, NeglectedSide::Left);
        assert!(mid > 1280.0 * NEGLECTED_SHARE + 200.0, "{mid}");
        assert_eq!(
            hud_align(Align2::LEFT_TOP, NeglectedSide::Right),
            Align2::LEFT_TOP
        );
    }
}
