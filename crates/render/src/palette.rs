//! The colours of the patient's screen: calm, muted, high contrast where it matters
//! (lane markings against asphalt, needles against the dial face, text against panels).
//!
//! Values are display-space (sRGB-encoded) RGBA in 0–1; the render target is a non-sRGB
//! format, so they reach the screen unchanged.

/// RGBA from a 0xRRGGBB literal.
const fn rgb(hex: u32) -> [f32; 4] {
    [
        ((hex >> 16) & 0xff) as f32 / 255.0,
        ((hex >> 8) & 0xff) as f32 / 255.0,
        (hex & 0xff) as f32 / 255.0,
        1.0,
    ]
}

/// Sky colour at the horizon; also the fog colour.
pub const SKY_HORIZON: [f32; 4] = rgb(0xCFE0EE);
/// Sky colour overhead.
pub const SKY_ZENITH: [f32; 4] = rgb(0x6E9CCB);
/// Grass, first checker tone.
pub const GRASS_A: [f32; 4] = rgb(0x86A865);
/// Grass, second checker tone.
pub const GRASS_B: [f32; 4] = rgb(0x7EA25E);
/// Road surface.
pub const ASPHALT: [f32; 4] = rgb(0x5E636B);
/// Gravel shoulder beside the lane.
pub const SHOULDER: [f32; 4] = rgb(0xB8AC90);
/// Solid edge lines.
pub const EDGE_LINE: [f32; 4] = rgb(0xF4F4F0);
/// Dashed centre guide (warm yellow so it reads as "aim here").
pub const CENTRE_DASH: [f32; 4] = rgb(0xF2CE4E);
/// Traffic cone.
pub const CONE: [f32; 4] = rgb(0xEC7A2C);
/// Reflective band on a cone.
pub const CONE_BAND: [f32; 4] = rgb(0xF6F6F6);
/// Cone base.
pub const CONE_BASE: [f32; 4] = rgb(0x3A3A3A);
/// Barrier walls.
pub const BARRIER: [f32; 4] = rgb(0xD8D4CC);
/// Dark strip along the foot of the barriers.
pub const BARRIER_BASE: [f32; 4] = rgb(0x6E7178);
/// Barrier tops.
pub const BARRIER_TOP: [f32; 4] = rgb(0xE3E6EA);
/// The patient's car.
pub const CAR_BODY: [f32; 4] = rgb(0x2F6DB5);
/// Car windows.
pub const CAR_CABIN: [f32; 4] = rgb(0x2B3440);
/// Tyres.
pub const TYRE: [f32; 4] = rgb(0x1E1E1E);
/// Tail lights.
pub const TAIL_LIGHT: [f32; 4] = rgb(0xD23B3B);
/// Soft shadow under the car.
pub const SHADOW: [f32; 4] = rgb(0x474B52);
/// Background of the 2D dial screen.
pub const DIAL_BACKGROUND: [f32; 4] = rgb(0xE8EEF3);

// Text and the panels behind it (egui colours, sRGB). Every pair a patient reads is listed in
// [`TEXT_ON`] and checked against WCAG 2.2's contrast minimum (AA: 4.5:1, large text 3:1).

/// The white cards (start, next exercise, rest, pause, end).
pub const CARD: egui::Color32 = egui::Color32::from_rgb(0xFB, 0xFB, 0xF8);
/// Text on the cards (16:1).
pub const CARD_TEXT: egui::Color32 = egui::Color32::from_rgb(0x1A, 0x1F, 0x26);
/// The keys' line on the cards (9:1).
pub const CARD_KEYS: egui::Color32 = egui::Color32::from_gray(70);
/// Green for headings on the cards ("Get ready", "Rest · next", the therapist's message),
/// the ticks and the bars: 4.9:1 on a card, AA for text of any size (the earlier 0x4FA36B
/// measured 2.99:1).
pub const ACCENT: egui::Color32 = egui::Color32::from_rgb(0x2E, 0x7D, 0x46);
/// The HUD's dark, see-through panels (premultiplied: 190/255 opaque).
pub const PANEL: egui::Color32 = egui::Color32::from_rgba_premultiplied(18, 24, 32, 190);
/// Text on the HUD's panels.
pub const PANEL_TEXT: egui::Color32 = egui::Color32::WHITE;

/// A text colour, its background, and whether the text is large (WCAG: at least 18 pt, or
/// 14 pt bold; the cards' headings are 30 pt and more).
#[derive(Debug, Clone, Copy)]
pub struct TextOn {
    /// What the pair is, for the test's message.
    pub name: &'static str,
    /// The text's colour.
    pub text: egui::Color32,
    /// The background it is read on (a see-through panel over the brightest scene colour).
    pub background: egui::Color32,
    /// Large text: 3:1 suffices.
    pub large: bool,
}

/// `over` (premultiplied, maybe see-through) composited over the opaque `under`.
pub fn over(over: egui::Color32, under: egui::Color32) -> egui::Color32 {
    let a = 1.0 - f32::from(over.a()) / 255.0;
    let mix = |o: u8, u: u8| (f32::from(o) + a * f32::from(u)).round().min(255.0) as u8;
    egui::Color32::from_rgb(
        mix(over.r(), under.r()),
        mix(over.g(), under.g()),
        mix(over.b(), under.b()),
    )
}

/// The brightest thing that can be behind a HUD panel: the sky at the horizon.
fn brightest_scene() -> egui::Color32 {
    let [r, g, b, _] = SKY_HORIZON.map(|c| (c * 255.0).round() as u8);
    egui::Color32::from_rgb(r, g, b)
}

/// Every text colour of the patient's screen on its background.
pub fn text_on() -> Vec<TextOn> {
    let panel = over(PANEL, brightest_scene());
    vec![
        TextOn {
            name: "card text",
            text: CARD_TEXT,
            background: CARD,
            large: false,
        },
        TextOn {
            name: "card keys",
            text: CARD_KEYS,
            background: CARD,
            large: false,
        },
        TextOn {
            name: "card heading (green)",
            text: ACCENT,
            background: CARD,
            large: false,
        },
        TextOn {
            name: "HUD text on its panel",
            text: PANEL_TEXT,
            background: panel,
            large: false,
        },
        TextOn {
            name: "white tick on green",
            text: egui::Color32::WHITE,
            background: ACCENT,
            large: true,
        },
    ]
}

/// WCAG 2.2 relative luminance of an opaque sRGB colour.
pub fn luminance(c: egui::Color32) -> f64 {
    let lin = |v: u8| {
        let v = f64::from(v) / 255.0;
        if v <= 0.04045 {
            v / 12.92
        } else {
            ((v + 0.055) / 1.055).powf(2.4)
        }
    };
    0.2126 * lin(c.r()) + 0.7152 * lin(c.g()) + 0.0722 * lin(c.b())
}

/// WCAG 2.2 contrast ratio of two opaque colours (1–21).
pub fn contrast(a: egui::Color32, b: egui::Color32) -> f64 {
    let (la, lb) = (luminance(a), luminance(b));
    (la.max(lb) + 0.05) / (la.min(lb) + 0.05)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_text_colour_meets_wcag_aa_on_its_background() {
        for t in text_on() {
            let need = if t.large { 3.0 } else { 4.5 };
            let got = contrast(t.text, t.background);
            assert!(got >= need, "{}: {got:.2}:1, needs {need}:1", t.name);
        }
    }

    #[test]
    fn the_old_green_measured_under_three_to_one() {
        // The formula itself: the green the cards used before, and black on white.
        let old = egui::Color32::from_rgb(0x4F, 0xA3, 0x6B);
        assert!((contrast(old, CARD) - 2.99).abs() < 0.01);
        assert!((contrast(egui::Color32::BLACK, egui::Color32::WHITE) - 21.0).abs() < 1e-9);
    }
}
