//! The patient's screen: the road in perspective (thesis §3.3.4, Fig. 3-8), the rotary dial
//! task (§3.3.3, Fig. 3-7a), a HUD with large text, and start/pause/summary cards.
//!
//! One draw path, [`Renderer::draw`], serves the window ([`window::run`]) and the offscreen
//! screenshots ([`Renderer::render_to_rgba`], [`headless_frames`]). The renderer only reads a
//! [`Scene`], plain data the station builds from its latest state snapshot, so a slow or
//! minimised window can never hold up the haptic loop.
//!
//! On a machine without a GPU, Mesa's lavapipe (Vulkan) or llvmpipe (GL) draw the frames;
//! `WGPU_BACKEND=vulkan|gl` picks one. With no adapter at all the constructors return
//! [`RenderError::NoAdapter`] and the station runs the session headless.

pub mod camera;
mod checkin_page;
pub mod demo;
mod dial;
pub mod fonts;
mod gpu;
pub mod hud;
pub mod layout;
pub mod mesh;
pub mod palette;
pub mod pictures;
mod scene;
pub mod text;
pub mod window;

use std::path::{Path, PathBuf};
use std::time::Instant;

pub use checkin_page::{CheckInPage, CheckInScale, ScaleKind};
pub use gpu::{
    AdapterSummary, FRAME_UNIFORM_BYTES, MAX_SIZE_PX, MSAA_SAMPLES, Renderer, SKY_WGSL, WORLD_WGSL,
    probe_adapter,
};
pub use scene::{
    ArmInset, CameraMode, CarPose, Dial, Hud, LiveScore, MAX_COORD_M, Movement, NextCard, Picture,
    Road, RoadPoint, Scene, ScreenState, StatusLine, Welcome,
};

/// Everything that can go wrong while drawing the patient's screen.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RenderError {
    /// No GPU or software adapter: the session should run headless.
    #[error("no usable graphics adapter: {0}")]
    NoAdapter(String),
    /// The device could not be created or reported a validation error.
    #[error("graphics device error: {0}")]
    Device(String),
    /// A scene value is out of range; the message names the field.
    #[error("invalid scene: {0}")]
    InvalidScene(String),
    /// Requested image size is zero or too large.
    #[error("invalid size {width}x{height}: both sides must be in 1..={max}", max = MAX_SIZE_PX)]
    InvalidSize {
        /// Requested width, px.
        width: u32,
        /// Requested height, px.
        height: u32,
    },
    /// Copying the frame back from the GPU failed.
    #[error("reading the frame back: {0}")]
    Readback(String),
    /// The window or its surface failed.
    #[error("window: {0}")]
    Window(String),
    /// Writing a PNG failed.
    #[error("writing {path}: {message}")]
    Png {
        /// File being written.
        path: PathBuf,
        /// What failed.
        message: String,
    },
}

/// Writes RGBA8 pixels (`width × height × 4` bytes, rows top to bottom) as a PNG file.
pub fn save_png(path: &Path, rgba: &[u8], width: u32, height: u32) -> Result<(), RenderError> {
    let err = |message: String| RenderError::Png {
        path: path.to_path_buf(),
        message,
    };
    let expected = width as usize * height as usize * 4;
    if rgba.len() != expected {
        return Err(err(format!(
            "{} bytes of pixels for {width}x{height}, expected {expected}",
            rgba.len()
        )));
    }
    let file = std::fs::File::create(path).map_err(|e| err(e.to_string()))?;
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), width, height);
    enc.set_color(png::ColorType::Rgba);
    enc.set_depth(png::BitDepth::Eight);
    let mut writer = enc.write_header().map_err(|e| err(e.to_string()))?;
    writer
        .write_image_data(rgba)
        .map_err(|e| err(e.to_string()))?;
    writer.finish().map_err(|e| err(e.to_string()))
}

/// Reads an 8-bit RGBA or RGB PNG back as RGBA8 pixels: `(rgba, width, height)`.
pub fn load_png(path: &Path) -> Result<(Vec<u8>, u32, u32), RenderError> {
    let err = |message: String| RenderError::Png {
        path: path.to_path_buf(),
        message,
    };
    let file = std::fs::File::open(path).map_err(|e| err(e.to_string()))?;
    let mut reader = png::Decoder::new(std::io::BufReader::new(file))
        .read_info()
        .map_err(|e| err(e.to_string()))?;
    let size = reader
        .output_buffer_size()
        .ok_or_else(|| err("image too large".into()))?;
    let mut buf = vec![0; size];
    let info = reader
        .next_frame(&mut buf)
        .map_err(|e| err(e.to_string()))?;
    if info.bit_depth != png::BitDepth::Eight {
        return Err(err(format!("bit depth {:?}, expected 8", info.bit_depth)));
    }
    let rgba = match info.color_type {
        png::ColorType::Rgba => buf[..info.buffer_size()].to_vec(),
        png::ColorType::Rgb => buf[..info.buffer_size()]
            .chunks(3)
            .flat_map(|p| [p[0], p[1], p[2], 255])
            .collect(),
        other => return Err(err(format!("colour type {other:?}, expected RGB or RGBA"))),
    };
    Ok((rgba, info.width, info.height))
}

/// Adapter and frame-time figures of a headless run.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderStats {
    /// The adapter that drew the frames.
    pub adapter: AdapterSummary,
    /// Frames written.
    pub frames: usize,
    /// Mean time to draw and read back one frame (PNG encoding excluded), ms.
    pub mean_ms: f64,
    /// Median of the same, ms.
    pub p50_ms: f64,
    /// 99th percentile of the same, ms.
    pub p99_ms: f64,
    /// Slowest frame, ms.
    pub max_ms: f64,
}

impl RenderStats {
    fn from_times(adapter: AdapterSummary, mut times_ms: Vec<f64>) -> Self {
        times_ms.sort_by(f64::total_cmp);
        let n = times_ms.len();
        RenderStats {
            adapter,
            frames: n,
            mean_ms: if n == 0 {
                0.0
            } else {
                times_ms.iter().sum::<f64>() / n as f64
            },
            p50_ms: common::quantile(&times_ms, 0.5).unwrap_or(0.0),
            p99_ms: common::quantile(&times_ms, 0.99).unwrap_or(0.0),
            max_ms: times_ms.last().copied().unwrap_or(0.0),
        }
    }
}

/// Renders `scenes` offscreen at `width`×`height` into `out_dir/frame_0000.png`, … and
/// returns the adapter and per-frame timing. Prints the adapter and backend first.
pub fn headless_frames(
    scenes: impl IntoIterator<Item = Scene>,
    width: u32,
    height: u32,
    out_dir: &Path,
) -> Result<RenderStats, RenderError> {
    std::fs::create_dir_all(out_dir).map_err(|e| RenderError::Png {
        path: out_dir.to_path_buf(),
        message: format!("creating the output directory: {e}"),
    })?;
    let mut renderer = Renderer::new_headless(width, height)?;
    println!("render: adapter {}", renderer.adapter());
    let mut times = Vec::new();
    for (i, scene) in scenes.into_iter().enumerate() {
        // Frame time is measured around draw + readback only: it is what a window would spend
        // on the GPU side, without the PNG encoder.
        let t0 = Instant::now();
        let rgba = renderer.render_to_rgba(&scene)?;
        times.push(t0.elapsed().as_secs_f64() * 1e3);
        save_png(
            &out_dir.join(format!("frame_{i:04}.png")),
            &rgba,
            width,
            height,
        )?;
    }
    Ok(RenderStats::from_times(renderer.adapter().clone(), times))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_times_use_nearest_rank_quantiles() {
        let adapter = || AdapterSummary {
            name: "test".into(),
            backend: "Gl".into(),
            device_type: "Cpu".into(),
        };
        // Unsorted on purpose: the stats sort them.
        let d: Vec<f64> = (1..=100).rev().map(f64::from).collect();
        let s = RenderStats::from_times(adapter(), d);
        assert_eq!((s.p50_ms, s.p99_ms, s.max_ms), (50.0, 99.0, 100.0));
        assert_eq!((s.frames, s.mean_ms), (100, 50.5));
        let none = RenderStats::from_times(adapter(), Vec::new());
        assert_eq!((none.p50_ms, none.p99_ms, none.max_ms), (0.0, 0.0, 0.0));
    }

    #[test]
    fn png_round_trips_pixels() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.png");
        let rgba: Vec<u8> = (0..3 * 2 * 4).map(|i| (i * 10) as u8).collect();
        save_png(&path, &rgba, 3, 2).unwrap();
        let (back, w, h) = load_png(&path).unwrap();
        assert_eq!((w, h), (3, 2));
        assert_eq!(back, rgba);
    }

    #[test]
    fn save_png_rejects_wrong_pixel_count() {
        let dir = tempfile::tempdir().unwrap();
        let err = save_png(&dir.path().join("a.png"), &[0; 7], 1, 2).unwrap_err();
        assert!(err.to_string().contains("expected 8"), "{err}");
    }
}
