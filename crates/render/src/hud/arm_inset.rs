//! The patient's arm, small and calm at the left of the screen: a side view (from the
//! patient's right) of the trunk, the upper arm and forearm, the hand on the wheel's rim,
//! drawn from the live pose with the segment lengths the station uses now. Once the session
//! has measured the patient's own lengths it says so in plain words with a tick.

use egui::{Align2, Color32, CornerRadius, Painter, Pos2, Rect, Stroke, pos2, vec2};

use super::{MARGIN, MIN_TEXT_PT, PAD, PANEL, TEXT, galley};
use crate::ArmInset;

/// The part of the wheel frame shown, m: x (forward) from, to; z (up) from, to. It holds an
/// adult's shoulder, head and trunk at a desk wheel (the default geometry's shoulder is
/// 0.42 m behind and 0.25 m above the wheel centre).
const VIEW_X_M: (f64, f64) = (-0.75, 0.25);
const VIEW_Z_M: (f64, f64) = (-0.30, 0.62);
/// Drawing scale, points per metre (the picture is 150 × 138 points).
const PT_PER_M: f32 = 150.0;

/// Muted colours: the inset must not draw the eye from the road.
const RIM: Color32 = Color32::from_gray(150);
const BODY: Color32 = Color32::from_gray(125);
const ARM: Color32 = Color32::from_rgb(0xB4, 0xC8, 0xDC);

/// What the label says: the tick's words once the lengths are the patient's own.
pub fn label(measured: bool) -> String {
    i18n::tr!(if measured {
        "hud-your-arm-measured"
    } else {
        "hud-your-arm"
    })
}

/// Paints the inset with its left edge at `left_centre` (vertically centred there); returns
/// its rectangle.
pub(super) fn paint(p: &Painter, arm: &ArmInset, left_centre: Pos2) -> Rect {
    let picture = vec2(
        (VIEW_X_M.1 - VIEW_X_M.0) as f32 * PT_PER_M,
        (VIEW_Z_M.1 - VIEW_Z_M.0) as f32 * PT_PER_M,
    );
    let words = galley(p, label(arm.measured), MIN_TEXT_PT, TEXT);
    let mark = if arm.measured { MIN_TEXT_PT + 8.0 } else { 0.0 };
    // As wide before as after the measurement: the panel does not jump when it says so.
    let widest = galley(p, label(true), MIN_TEXT_PT, TEXT).size().x + MIN_TEXT_PT + 8.0;
    let size = vec2(
        picture.x.max(widest) + 2.0 * PAD,
        picture.y + words.size().y + 3.0 * PAD,
    );
    let rect = Align2::LEFT_CENTER.anchor_size(left_centre, size);
    p.rect_filled(rect, CornerRadius::same(12), PANEL);
    let origin = pos2(rect.center().x - picture.x / 2.0, rect.top() + PAD);
    // Side view from the patient's right: forward to the right, up up.
    let at = |x: f64, z: f64| {
        origin
            + vec2(
                ((x - VIEW_X_M.0) as f32) * PT_PER_M,
                ((VIEW_Z_M.1 - z) as f32) * PT_PER_M,
            )
    };
    let side = |v: [f64; 3]| at(v[0], v[2]);
    let clip = p.with_clip_rect(Rect::from_min_size(origin, picture));
    // The wheel seen edge-on (its top tilted toward the patient) and its column.
    let (s, c) = arm.wheel_tilt_rad.sin_cos();
    let r = arm.rim_radius_m;
    clip.line_segment(
        [at(s * r, -c * r), at(-s * r, c * r)],
        Stroke::new(6.0, RIM),
    );
    clip.line_segment(
        [at(0.0, 0.0), at(0.12 * c, 0.12 * s)],
        Stroke::new(4.0, RIM),
    );
    // The trunk below the shoulder and the head above it.
    let shoulder = arm.shoulder_m();
    let [sx, _, sz] = shoulder;
    clip.line_segment(
        [at(sx, sz), at(sx - 0.03, sz - 0.45)],
        Stroke::new(5.0, BODY),
    );
    clip.circle_filled(at(sx + 0.01, sz + 0.2), 0.085 * PT_PER_M, BODY);
    // The arm: shoulder, elbow, hand.
    let (s_pt, e_pt, g_pt) = (side(shoulder), side(arm.elbow_m()), side(arm.grip_m));
    let limb = Stroke::new(6.0, ARM);
    clip.line_segment([s_pt, e_pt], limb);
    clip.line_segment([e_pt, g_pt], limb);
    for (pt, radius) in [(s_pt, 6.0), (e_pt, 5.0), (g_pt, 7.0)] {
        clip.circle_filled(pt, radius, ARM);
    }
    // The words, and a tick once measured.
    let text_at = pos2(rect.left() + PAD, rect.bottom() - PAD - words.size().y);
    let wy = words.size().y;
    p.galley(text_at + vec2(mark, 0.0), words, TEXT);
    if arm.measured {
        super::tick_mark(
            p,
            text_at + vec2(MIN_TEXT_PT * 0.5, wy * 0.5),
            MIN_TEXT_PT * 0.45,
            3.0,
        );
    }
    rect
}

/// Where the inset goes on a screen of `size` points: the left edge, a little below the
/// middle (clear of the exercise's name above and of the speed and help below).
pub(super) fn anchor(size: egui::Vec2) -> Pos2 {
    pos2(MARGIN, size.y * 0.5)
}

/// [`anchor`] for a patient who neglects `side`: with a left neglect the inset's right edge
/// at the right margin instead (its width as [`paint`] sizes it).
pub(super) fn anchor_for(p: &Painter, size: egui::Vec2, side: regimen::NeglectedSide) -> Pos2 {
    if side != regimen::NeglectedSide::Left {
        return anchor(size);
    }
    let picture_w = (VIEW_X_M.1 - VIEW_X_M.0) as f32 * PT_PER_M;
    let widest = galley(p, label(true), MIN_TEXT_PT, TEXT).size().x + MIN_TEXT_PT + 8.0;
    pos2(
        size.x - MARGIN - picture_w.max(widest) - 2.0 * PAD,
        size.y * 0.5,
    )
}
