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
