//! Golden-image tests: a few reference frames rendered offscreen (lavapipe / llvmpipe on CI)
//! compared with stored PNGs under a tolerance, so driver differences in rasterisation and
//! anti-aliasing do not flap while a real change in the picture fails.
//!
//! Regenerate after an intended change with
//! `UPDATE_GOLDEN=1 cargo test -p render --test render_golden` and look at the PNGs.

mod common;

use std::path::{Path, PathBuf};

use render::{self, CameraMode, RenderError, Renderer, Scene, ScreenState, demo};

const W: u32 = 640;
const H: u32 = 360;
/// Mean absolute difference per channel allowed, 0–255.
const MAX_MEAN_ABS_DIFF: f64 = 2.5;
/// A pixel "differs" when any channel is off by more than this.
const PIXEL_THRESHOLD: u8 = 48;
/// Share of differing pixels allowed.
const MAX_DIFFERING_SHARE: f64 = 0.01;

fn golden_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/golden")
}

fn renderer_or_skip() -> Option<Renderer> {
    common::renderer_or_skip(W, H)
}

/// (mean absolute channel difference, share of pixels differing by more than the threshold)
fn compare(a: &[u8], b: &[u8]) -> (f64, f64) {
    assert_eq!(a.len(), b.len());
    let total: u64 = a
        .iter()
        .zip(b)
        .map(|(x, y)| u64::from(x.abs_diff(*y)))
        .sum();
    let differing = a
        .chunks(4)
        .zip(b.chunks(4))
        .filter(|(p, q)| {
            p.iter()
                .zip(q.iter())
                .any(|(x, y)| x.abs_diff(*y) > PIXEL_THRESHOLD)
        })
        .count();
    (
        total as f64 / a.len() as f64,
        differing as f64 / (a.len() / 4) as f64,
    )
}

fn check_golden(renderer: &mut Renderer, name: &str, scene: &Scene) {
    let rgba = renderer.render_to_rgba(scene).unwrap();
    let path = golden_dir().join(format!("{name}.png"));
    if std::env::var_os("UPDATE_GOLDEN").is_some() {
        render::save_png(&path, &rgba, W, H).unwrap();
        return;
    }
    let (golden, gw, gh) = render::load_png(&path).unwrap_or_else(|e| {
        panic!("{e}: create it with UPDATE_GOLDEN=1 cargo test -p render --test render_golden")
    });
    assert_eq!((gw, gh), (W, H), "{name}: golden size");
    let (mad, share) = compare(&rgba, &golden);
    if mad > MAX_MEAN_ABS_DIFF || share > MAX_DIFFERING_SHARE {
        let out = std::env::temp_dir().join(format!("render_golden_{name}_actual.png"));
        render::save_png(&out, &rgba, W, H).unwrap();
        panic!(
            "{name}: mean abs diff {mad:.2} (max {MAX_MEAN_ABS_DIFF}), differing pixels {:.2} % \
             (max {:.2} %); actual frame written to {}",
            share * 100.0,
            MAX_DIFFERING_SHARE * 100.0,
            out.display()
        );
    }
}

fn goldens() -> Vec<(&'static str, Scene)> {
    let mut driver = demo::sine_road(4.0);
    driver.camera = CameraMode::Driver;
    let mut summary = demo::slalom(20.0);
    summary.screen = ScreenState::Summary(vec![
        "In lane 96 % of the time".into(),
        "Average distance from centre 0.31 m".into(),
    ]);
    let mut start = demo::dial(0.0);
    start.screen = ScreenState::Start;
    // The arm inset once the session has measured the patient's arm: the words and a tick.
    let mut measured = demo::sine_road(6.0);
    if let Some(arm) = measured.arm.as_mut() {
        arm.measured = true;
    }
    vec![
        ("straight_chase", demo::straight(2.0)),
        ("sine_road_chase", demo::sine_road(5.0)),
        ("sine_road_driver", driver),
        ("slalom_chase", demo::slalom(3.0)),
        ("dial", demo::dial(1.3)),
        ("slalom_summary", summary),
        ("dial_start", start),
        ("sine_road_arm_measured", measured),
    ]
}

#[test]
fn reference_frames_match_goldens_within_tolerance() {
    let Some(mut r) = renderer_or_skip() else {
        return;
    };
    // The goldens are drawn in English, whatever the machine's LANG.
    i18n::use_language("en").unwrap();
    println!("adapter: {}", r.adapter());
    for (name, scene) in goldens() {
        check_golden(&mut r, name, &scene);
    }
}

#[test]
fn comparison_detects_a_moved_car() {
    // The tolerance must not hide a real change: the car one lane-width to the side fails.
    let Some(mut r) = renderer_or_skip() else {
        return;
    };
    let a = r.render_to_rgba(&demo::straight(2.0)).unwrap();
    let mut moved = demo::straight(2.0);
    moved.car.y_m += 3.0;
    let b = r.render_to_rgba(&moved).unwrap();
    let (mad, share) = compare(&a, &b);
    assert!(
        mad > MAX_MEAN_ABS_DIFF || share > MAX_DIFFERING_SHARE,
        "mad {mad}, share {share}"
    );
}

#[test]
fn same_scene_renders_identically_twice() {
    let Some(mut r) = renderer_or_skip() else {
        return;
    };
    let a = r.render_to_rgba(&demo::slalom(1.0)).unwrap();
    let b = r.render_to_rgba(&demo::slalom(1.0)).unwrap();
    assert_eq!(compare(&a, &b), (0.0, 0.0));
}

#[test]
fn invalid_scene_is_an_error_and_the_renderer_keeps_working() {
    let Some(mut r) = renderer_or_skip() else {
        return;
    };
    let mut bad = demo::straight(0.0);
    bad.car.yaw_rad = f64::NAN;
    let err = r.render_to_rgba(&bad).unwrap_err();
    assert!(
        matches!(err, RenderError::InvalidScene(ref m) if m.contains("car.yaw_rad")),
        "{err}"
    );
    let ok = r.render_to_rgba(&demo::straight(0.0)).unwrap();
    assert_eq!(ok.len(), (W * H * 4) as usize);
}

#[test]
fn zero_size_is_rejected_before_touching_the_gpu() {
    assert!(matches!(
        Renderer::new_headless(0, 10),
        Err(RenderError::InvalidSize { .. })
    ));
    assert!(matches!(
        Renderer::new_headless(10, 100_000),
        Err(RenderError::InvalidSize { .. })
    ));
}

#[test]
fn resize_changes_the_output_size() {
    let Some(mut r) = renderer_or_skip() else {
        return;
    };
    r.resize(320, 200).unwrap();
    let rgba = r.render_to_rgba(&demo::dial(0.5)).unwrap();
    assert_eq!(rgba.len(), 320 * 200 * 4);
}

#[test]
fn headless_frames_writes_numbered_pngs_and_reports_timing() {
    if renderer_or_skip().is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let scenes = (0..3).map(|i| demo::sine_road(i as f64 * 0.1));
    let stats = render::headless_frames(scenes, 160, 90, dir.path()).unwrap();
    assert_eq!(stats.frames, 3);
    assert!(stats.p50_ms > 0.0 && stats.max_ms >= stats.p99_ms && stats.p99_ms >= stats.p50_ms);
    assert!(!stats.adapter.backend.is_empty());
    for i in 0..3 {
        let p: &Path = &dir.path().join(format!("frame_{i:04}.png"));
        let (_, w, h) = render::load_png(p).unwrap();
        assert_eq!((w, h), (160, 90));
    }
    assert!(!dir.path().join("frame_0003.png").exists());
}
