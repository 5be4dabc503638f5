//! Heads-up display, dial task and start/pause/summary cards, laid out with egui.
//!
//! Layout is in egui points on a 1280×720 reference screen; `pixels_per_point` scales it to
//! the real size, so text keeps the same share of the screen in a small window and in
//! full-screen. Sizes are chosen for older patients reading a TV from 2 m
//! ([`super::layout::MIN_CAP_ARCMIN`]): the smallest text of a session's screen is
//! [`MIN_TEXT_PT`] = 25 pt at the reference size, **37.5 px at 1080p** (capitals 26 px: 20
//! arc minutes at 2 m on a 40-inch TV), white on a dark panel or near-black on white; the
//! cards' lines are 32 pt (48 px at 1080p) and their titles 48–52 pt.

use egui::epaint::ClippedPrimitive;
use egui::{
    Align2, Color32, Context, CornerRadius, FontId, Galley, Id, LayerId, Order, Painter, Pos2,
    Rect, Stroke, TexturesDelta, Vec2, ViewportId, pos2, vec2,
};
use std::sync::Arc;

use super::dial::paint_dial;
use super::layout;
use super::scene::{LiveScore, Scene, ScreenState};
use i18n::tr;
use regimen::NeglectedSide;

pub mod arm_inset;
mod checkin;
mod next_card;
mod picture_card;
mod welcome;

/// The smallest text of a session's screen, points at the reference size (37.5 px at
/// 1080p: capitals 26 px high, over the 20′ at 2 m of `layout::MIN_CAP_ARCMIN`).
pub const MIN_TEXT_PT: f32 = 25.0;

/// Reference layout size, points.
pub const REFERENCE_SIZE: [f32; 2] = [1280.0, 720.0];

// The colours of text and panels are in `palette`, where a test checks their contrast.
const PANEL: Color32 = super::palette::PANEL;
const TEXT: Color32 = super::palette::PANEL_TEXT;
pub(super) const CARD: Color32 = super::palette::CARD;
pub(super) const CARD_TEXT: Color32 = super::palette::CARD_TEXT;
pub(super) const ACCENT: Color32 = super::palette::ACCENT;
const MARGIN: f32 = 16.0;
pub(super) const PAD: f32 = 12.0;

/// Tessellated HUD of one frame, ready for `egui_wgpu::Renderer`.
pub struct HudFrame {
    /// Triangles to draw.
    pub primitives: Vec<ClippedPrimitive>,
    /// Font atlas uploads and frees.
    pub textures: TexturesDelta,
    /// Physical pixels per egui point.
    pub pixels_per_point: f32,
}

/// The egui context that lays out the HUD; keeps the font atlas between frames.
pub struct HudPainter {
    ctx: Context,
}

impl Default for HudPainter {
    fn default() -> Self {
        Self::new()
    }
}

/// Pixels per point so the reference layout fits a `width`×`height` pixel screen.
pub fn pixels_per_point(width: u32, height: u32) -> f32 {
    let s = (width as f32 / REFERENCE_SIZE[0]).min(height as f32 / REFERENCE_SIZE[1]);
    s.clamp(0.4, 4.0)
}

/// egui's input for one pass on a `width`×`height` pixel target: the screen in points at
/// [`pixels_per_point`], and its size in points.
pub fn input_for(width: u32, height: u32) -> (egui::RawInput, Vec2) {
    let ppp = pixels_per_point(width, height);
    let size = vec2(width as f32 / ppp, height as f32 / ppp);
    let mut input = egui::RawInput {
        screen_rect: Some(Rect::from_min_size(Pos2::ZERO, size)),
        ..Default::default()
    };
    input
        .viewports
        .entry(ViewportId::ROOT)
        .or_default()
        .native_pixels_per_point = Some(ppp);
    (input, size)
}

impl HudPainter {
    /// A HUD with egui's built-in fonts and Debian's Noto fonts behind them for the other
    /// scripts ([`super::fonts`]).
    pub fn new() -> Self {
        let ctx = Context::default();
        ctx.set_fonts(super::fonts::definitions());
        ctx.set_visuals(egui::Visuals::light());
        HudPainter { ctx }
    }

    /// Lays out and tessellates the HUD for `scene` on a `width`×`height` pixel target.
    pub fn run(&mut self, scene: &Scene, width: u32, height: u32) -> HudFrame {
        let (input, size) = input_for(width, height);
        let output = self.ctx.run_pass(input, |ctx| {
            let painter = ctx.layer_painter(LayerId::new(Order::Foreground, Id::unique("hud")));
            paint(&painter, scene, size, layout::neglected_side());
        });
        let primitives = self.ctx.tessellate(output.shapes, output.pixels_per_point);
        HudFrame {
            primitives,
            textures: output.textures_delta,
            pixels_per_point: output.pixels_per_point,
        }
    }
}

pub(super) fn galley(
    p: &Painter,
    text: impl Into<String>,
    size: f32,
    color: Color32,
) -> Arc<Galley> {
    super::text::line(p, &text.into(), FontId::proportional(size), color)
}

/// A dark rounded panel holding `lines` (text, size), anchored at `anchor` by `align`.
fn text_panel(p: &Painter, anchor: Pos2, align: Align2, lines: &[(String, f32)]) -> Rect {
    let galleys: Vec<_> = lines
        .iter()
        .map(|(t, s)| galley(p, t.clone(), *s, TEXT))
        .collect();
    let w = galleys.iter().map(|g| g.size().x).fold(0.0, f32::max) + 2.0 * PAD;
    let h = galleys.iter().map(|g| g.size().y).sum::<f32>() + 2.0 * PAD;
    let rect = align.anchor_size(anchor, vec2(w, h));
    p.rect_filled(rect, CornerRadius::same(12), PANEL);
    let mut y = rect.top() + PAD;
    for g in galleys {
        let x = match align.x() {
            egui::Align::Min => rect.left() + PAD,
            egui::Align::Center => rect.center().x - g.size().x / 2.0,
            egui::Align::Max => rect.right() - PAD - g.size().x,
        };
        let gh = g.size().y;
        p.galley(pos2(x, y), g, TEXT);
        y += gh;
    }
    rect
}

/// `m:ss` of a non-negative time, rounded up so "0:00" means the exercise is over.
pub fn format_time_left(seconds: f64) -> String {
    let s = seconds.max(0.0).ceil() as u64;
    format!("{}:{:02}", s / 60, s % 60)
}

/// How close to the middle of the lane the car keeps, in words, from the RMS distance (m).
pub fn middle_words(rms_lateral_m: f64) -> String {
    tr!(match rms_lateral_m {
        m if m < 0.3 => "hud-middle-close",
        m if m < 0.8 => "hud-middle-off",
        _ => "hud-middle-far",
    })
}

/// How well the black needle follows the red one, in words, from the RMS error (degrees).
pub fn dial_words(rms_error_deg: f64) -> String {
    tr!(dial_words_id(rms_error_deg))
}

/// The catalogue's id of [`dial_words`].
pub fn dial_words_id(rms_error_deg: f64) -> &'static str {
    match rms_error_deg {
        e if e < 5.0 => "hud-needle-close",
        e if e < 15.0 => "hud-needle-near",
        _ => "hud-needle-behind",
    }
}

fn score_lines(score: &LiveScore) -> Vec<(String, f32)> {
    match *score {
        LiveScore::None => vec![],
        LiveScore::Road {
            rms_lateral_m,
            in_lane_pct,
        } => vec![
            (tr!("hud-in-lane", percent = in_lane_pct.round()), 30.0),
            (middle_words(rms_lateral_m), MIN_TEXT_PT),
        ],
        // How far apart the needles are, in words only: degrees mean little to a patient.
        LiveScore::Dial { rms_error_deg } => vec![(dial_words(rms_error_deg), 30.0)],
        // The strength test draws its own instruction and bar (`strength_bar`).
        LiveScore::Strength { .. } => vec![],
    }
}

/// What the strength test asks now, in plain words (`side`: +1 left, −1 right, 0 rest).
pub fn strength_words(side: i8) -> String {
    tr!(match side {
        1 => "hud-push-left",
        -1 => "hud-push-right",
        _ => "hud-let-go",
    })
}

/// The strength test's instruction and a bar of the patient's torque (full at the ceiling),
/// in the middle of the screen.
fn strength_bar(p: &Painter, size: Vec2, side: i8, push_nm: f64, ceiling_nm: f64, mid_x: f32) {
    let words = galley(p, strength_words(side), 32.0, TEXT);
    let bar = vec2((size.x * 0.6).max(200.0), 48.0);
    let panel = vec2(
        words.size().x.max(bar.x) + 4.0 * PAD,
        words.size().y + bar.y + 3.0 * PAD,
    );
    let rect = Rect::from_center_size(pos2(mid_x, size.y * 0.5), panel);
    p.rect_filled(rect, CornerRadius::same(12), PANEL);
    let wh = words.size().y;
    p.galley(
        pos2(rect.center().x - words.size().x / 2.0, rect.top() + PAD),
        words,
        TEXT,
    );
    let track = Rect::from_center_size(
        pos2(rect.center().x, rect.top() + 2.0 * PAD + wh + bar.y / 2.0),
        bar,
    );
    p.rect_filled(track, CornerRadius::same(8), Color32::from_gray(90));
    let share = if ceiling_nm > 0.0 {
        (push_nm / ceiling_nm).clamp(0.0, 1.0) as f32
    } else {
        0.0
    };
    // The bar grows the way the patient pushes: from the right end for left, and back.
    let fill = if side < 0 {
        Rect::from_min_size(track.min, vec2(bar.x * share, bar.y))
    } else {
        Rect::from_min_size(
            pos2(track.max.x - bar.x * share, track.min.y),
            vec2(bar.x * share, bar.y),
        )
    };
    p.rect_filled(fill, CornerRadius::same(8), ACCENT);
}

/// Paints `scene` on a screen of `size` points for a patient who neglects `neglected`: the
/// HUD's panels mirrored and the cards moved off that side ([`super::layout`]).
pub fn paint(p: &Painter, scene: &Scene, size: Vec2, neglected: NeglectedSide) {
    if let ScreenState::Welcome(page) = &scene.screen {
        welcome::paint(p, page, size);
        return;
    }
    if let ScreenState::CheckIn(page) = &scene.screen {
        checkin::paint(p, page, size);
        return;
    }
    let hud = &scene.hud;
    let (w, h) = (size.x, size.y);
    // A HUD anchor (x, y, alignment) moved for the neglected side.
    let at = |x: f32, y: f32, align: Align2| {
        (
            pos2(layout::hud_x(x, w, neglected), y),
            layout::hud_align(align, neglected),
        )
    };
    if let Some(dial) = &scene.dial {
        if scene.has_road() {
            let r = 105.0;
            let (c, _) = at(w - MARGIN - r - 10.0, h * 0.5, Align2::CENTER_CENTER);
            paint_dial(p, dial, c, r, false);
        } else {
            let r = (w.min(h) * 0.33).max(40.0);
            let (c, _) = at(w * 0.5, h * 0.52, Align2::CENTER_CENTER);
            paint_dial(p, dial, c, r, true);
        }
    }
    if !hud.exercise.is_empty() {
        let (pos, align) = at(MARGIN, MARGIN, Align2::LEFT_TOP);
        text_panel(p, pos, align, &[(hud.exercise.clone(), 30.0)]);
    }
    let (pos, align) = at(w * 0.5, MARGIN, Align2::CENTER_TOP);
    text_panel(
        p,
        pos,
        align,
        &[
            (tr!("hud-time-left"), MIN_TEXT_PT),
            (format_time_left(hud.time_left_s), 44.0),
        ],
    );
    if let LiveScore::Strength {
        side,
        push_nm,
        ceiling_nm,
    } = hud.score
    {
        let mid_x = layout::hud_x(w * 0.5, w, neglected);
        strength_bar(p, size, side, push_nm, ceiling_nm, mid_x);
    }
    let score = score_lines(&hud.score);
    if !score.is_empty() {
        let (pos, align) = at(w - MARGIN, MARGIN, Align2::RIGHT_TOP);
        text_panel(p, pos, align, &score);
    }
    if scene.has_road() {
        let kmh = hud.speed_m_s * 3.6;
        let (pos, align) = at(MARGIN, h - MARGIN, Align2::LEFT_BOTTOM);
        text_panel(
            p,
            pos,
            align,
            &[(tr!("hud-speed", kmh = kmh.round()), 30.0)],
        );
    }
    let (pos, align) = at(
        MARGIN,
        h - MARGIN - if scene.has_road() { 78.0 } else { 0.0 },
        Align2::LEFT_BOTTOM,
    );
    assist_bar(p, pos, align, hud.assist_level);
    if !hud.devices.is_empty() {
        let lines: Vec<_> = hud
            .devices
            .iter()
            .map(|d| (d.clone(), MIN_TEXT_PT))
            .collect();
        let (pos, align) = at(w - MARGIN, h - MARGIN, Align2::RIGHT_BOTTOM);
        text_panel(p, pos, align, &lines);
    }
    if let Some(arm) = &scene.arm {
        arm_inset::paint(p, arm, arm_inset::anchor_for(p, size, neglected));
    }
    match &scene.screen {
        ScreenState::Running => {
            if let Some(notice) = &hud.notice {
                notice_panel(p, size, notice, neglected, notice_top(scene, size));
            }
        }
        ScreenState::Start => {
            let title = if hud.exercise.is_empty() {
                tr!("card-get-ready")
            } else {
                hud.exercise.clone()
            };
            card(p, size, &title, &[tr!("card-press-space-to-start")]);
        }
        // A pause no one answers here (a recording's, in the replay window): the pause sign
        // and its caption, no choices. The session's own pause is a choice page (a Welcome).
        ScreenState::Paused => picture_card::paint(
            p,
            size,
            super::Picture::Pause,
            &tr!("pause-title"),
            &[],
            neglected,
        ),
        ScreenState::Instruction { title, lines } => card(p, size, title, lines),
        ScreenState::Pictured {
            picture,
            title,
            lines,
        } => picture_card::paint(p, size, *picture, title, lines, neglected),
        ScreenState::Next(next) => {
            next_card::paint(p, size, next, neglected);
            // Before each exercise: the anchoring cue on the neglected side.
            layout::paint_cue(p, size, neglected, next.anim_s);
        }
        ScreenState::Summary(lines) => card(p, size, &tr!("card-all-done"), lines),
        ScreenState::Welcome(_) | ScreenState::CheckIn(_) => {}
    }
}

/// The height of the time-left panel at the top, points (its two lines and padding).
const TIME_PANEL_PT: f32 = MIN_TEXT_PT + 44.0 + 2.0 * PAD + 10.0;

/// Where the notice's top goes, points: under the time left; on the full-screen dial, over
/// the dial's lowest part instead, below where any needle points (targets stay within
/// ±129°, whose tips reach 0.63 of the way down), so it never hides the target.
fn notice_top(scene: &Scene, size: Vec2) -> f32 {
    if scene.dial.is_some() && !scene.has_road() {
        let r = (size.x.min(size.y) * 0.33).max(40.0);
        size.y * 0.52 + r * 0.72
    } else {
        MARGIN + TIME_PANEL_PT + PAD
    }
}

/// A short sentence for the patient over the running exercise (the gentle cue to sit up):
/// a calm white card with a green edge, its top at `top` (under the time left, or low on the
/// full-screen dial: [`notice_top`]), in the middle of the side the patient attends to, in
/// the size of a page's main sentence. No red, no flashing: it must not startle. Returns the
/// card's rectangle.
pub(crate) fn notice_panel(
    p: &Painter,
    size: Vec2,
    text: &str,
    neglected: NeglectedSide,
    top: f32,
) -> Rect {
    let g = galley(p, text, NOTICE_PT, CARD_TEXT);
    let w = g.size().x + 4.0 * PAD + NOTICE_EDGE_PT;
    let h = g.size().y + 2.0 * PAD;
    let cx = layout::hud_x(size.x / 2.0, size.x, neglected);
    let rect = Rect::from_min_size(pos2(cx - w / 2.0, top), vec2(w, h));
    p.rect_filled(rect, CornerRadius::same(14), CARD);
    p.rect_filled(
        Rect::from_min_size(rect.min, vec2(NOTICE_EDGE_PT, h)),
        CornerRadius {
            nw: 14,
            sw: 14,
            ne: 0,
            se: 0,
        },
        ACCENT,
    );
    let gh = g.size().y;
    p.galley(
        pos2(
            rect.left() + NOTICE_EDGE_PT + 2.0 * PAD,
            rect.center().y - gh / 2.0,
        ),
        g,
        CARD_TEXT,
    );
    rect
}

/// The notice's text size, points (a page's main sentence: 25′ at 2 m).
const NOTICE_PT: f32 = 40.0;
/// The width of the notice's green edge, points.
const NOTICE_EDGE_PT: f32 = 14.0;

/// "Help" label and a bar showing the assist level, bottom-left.
fn assist_bar(p: &Painter, anchor: Pos2, align: Align2, level: f64) {
    let label = galley(
        p,
        tr!("hud-help", percent = (level * 100.0).round()),
        MIN_TEXT_PT,
        TEXT,
    );
    let bar = vec2(180.0, 16.0);
    let size = vec2(
        label.size().x.max(bar.x) + 2.0 * PAD,
        label.size().y + bar.y + 8.0 + 2.0 * PAD,
    );
    let rect = align.anchor_size(anchor, size);
    p.rect_filled(rect, CornerRadius::same(12), PANEL);
    let lh = label.size().y;
    p.galley(rect.left_top() + vec2(PAD, PAD), label, TEXT);
    let track = Rect::from_min_size(rect.left_top() + vec2(PAD, PAD + lh + 8.0), bar);
    p.rect_filled(track, CornerRadius::same(8), Color32::from_gray(90));
    let fill = Rect::from_min_size(track.min, vec2(bar.x * level.clamp(0.0, 1.0) as f32, bar.y));
    p.rect_filled(fill, CornerRadius::same(8), ACCENT);
}

/// A white card in the middle of a dimmed screen: title and lines.
pub(super) fn card(p: &Painter, size: Vec2, title: &str, lines: &[String]) {
    p.rect_filled(
        Rect::from_min_size(Pos2::ZERO, size),
        CornerRadius::ZERO,
        Color32::from_black_alpha(110),
    );
    let title_g = galley(p, title, 48.0, CARD_TEXT);
    let line_g: Vec<_> = lines
        .iter()
        .map(|l| galley(p, l.clone(), 32.0, CARD_TEXT))
        .collect();
    let w = line_g
        .iter()
        .map(|g| g.size().x)
        .fold(title_g.size().x, f32::max)
        + 4.0 * PAD;
    let h =
        title_g.size().y + 12.0 + line_g.iter().map(|g| g.size().y + 4.0).sum::<f32>() + 4.0 * PAD;
    // Centred, or in the middle of the side the patient attends to.
    let cx = layout::hud_x(size.x / 2.0, size.x, layout::neglected_side());
    let rect = Rect::from_center_size(pos2(cx, size.y / 2.0), vec2(w.max(420.0), h));
    p.rect_filled(rect, CornerRadius::same(18), CARD);
    let mut y = rect.top() + 2.0 * PAD;
    let th = title_g.size().y;
    p.galley(
        pos2(rect.center().x - title_g.size().x / 2.0, y),
        title_g,
        CARD_TEXT,
    );
    y += th + 12.0;
    for g in line_g {
        let gh = g.size().y;
        p.galley(pos2(rect.center().x - g.size().x / 2.0, y), g, CARD_TEXT);
        y += gh + 4.0;
    }
}

/// A white tick, strokes `width` points wide, on a green disc of radius `r` at `c` (never
/// colour alone: the words beside it say it too).
pub(super) fn tick_mark(p: &Painter, c: Pos2, r: f32, width: f32) {
    let white = Stroke::new(width, Color32::WHITE);
    p.circle_filled(c, r, ACCENT);
    p.line_segment(
        [c + vec2(-0.5 * r, 0.0), c + vec2(-0.1 * r, 0.4 * r)],
        white,
    );
    p.line_segment(
        [c + vec2(-0.1 * r, 0.4 * r), c + vec2(0.5 * r, -0.4 * r)],
        white,
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Dial;
    use egui::TextureId;

    #[test]
    fn time_left_rounds_up_and_never_goes_negative() {
        assert_eq!(format_time_left(155.2), "2:36");
        assert_eq!(format_time_left(0.0), "0:00");
        assert_eq!(format_time_left(-3.0), "0:00");
        assert_eq!(format_time_left(59.0), "0:59");
    }

    #[test]
    fn layout_scale_fits_the_smaller_axis() {
        assert_eq!(pixels_per_point(1280, 720), 1.0);
        assert_eq!(pixels_per_point(2560, 1440), 2.0);
        assert_eq!(pixels_per_point(1280, 1440), 1.0);
    }

    #[test]
    fn the_notice_sits_under_the_time_left_and_on_the_dial_below_every_needle() {
        let size = vec2(REFERENCE_SIZE[0], REFERENCE_SIZE[1]);
        let point = |x_m| super::super::RoadPoint {
            x_m,
            y_m: 0.0,
            lane_width_m: 3.5,
        };
        let road = Scene {
            road: super::super::Road {
                centre: vec![point(0.0), point(2.0)],
                ..Default::default()
            },
            ..Scene::default()
        };
        let top = notice_top(&road, size);
        assert!(top > MARGIN + TIME_PANEL_PT && top < size.y * 0.3, "{top}");
        let dial = Scene {
            dial: Some(Dial {
                desired_rad: 0.0,
                actual_rad: 0.0,
            }),
            ..Scene::default()
        };
        let r = size.y * 0.33;
        let lowest_tip_y = size.y * 0.52 - r * 0.86 * 129f32.to_radians().cos();
        let top = notice_top(&dial, size);
        assert!(
            top > lowest_tip_y,
            "{top} above the needles' reach {lowest_tip_y}"
        );
        assert!(top + 80.0 < size.y, "{top}: on the screen");
    }

    /// egui's font atlas, the HUD's only texture.
    const FONT_TEXTURE: TextureId = TextureId::Managed(0);

    #[test]
    fn hud_produces_font_atlas_on_first_frame_only() {
        let mut hud = HudPainter::new();
        let scene = Scene {
            screen: ScreenState::Paused,
            ..Scene::default()
        };
        let mut first = hud.run(&scene, 640, 360);
        assert!(!first.primitives.is_empty());
        assert!(first.textures.set.iter().any(|(id, _)| *id == FONT_TEXTURE));
        first.textures.clear();
        let mut second = hud.run(&scene, 640, 360);
        // Later frames only patch the atlas (positioned deltas), never replace it whole.
        assert!(
            second
                .textures
                .set
                .iter()
                .all(|(id, ds)| *id != FONT_TEXTURE || ds.iter().all(|d| d.pos.is_some()))
        );
        second.textures.clear();
    }
}
