//! Shows the renderer's demo scenes, in a window or as PNG frames.
//!
//! ```text
//! cargo run -p render --example render_demo -- headless sine-road 120 1280x720 /tmp/frames
//! cargo run -p render --example render_demo -- window slalom     # Esc to quit
//! ```
//! Scenes: straight, sine-road, slalom, dial. Frames are 1/30 s apart.

use std::path::PathBuf;
use std::time::Instant;

use render::{self, demo, window};

fn usage() -> ! {
    eprintln!(
        "usage: render_demo headless SCENE FRAMES WxH OUT_DIR | render_demo window SCENE\n\
         scenes: {}",
        demo::NAMES.join(", ")
    );
    std::process::exit(2)
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let scene_name = args.get(1).cloned().unwrap_or_else(|| usage());
    if demo::by_name(&scene_name, 0.0).is_none() {
        usage();
    }
    let result = match args.first().map(String::as_str) {
        Some("headless") if args.len() == 5 => {
            let frames: usize = args[2].parse().unwrap_or_else(|_| usage());
            let (w, h) = args[3].split_once('x').unwrap_or_else(|| usage());
            let (w, h): (u32, u32) = (
                w.parse().unwrap_or_else(|_| usage()),
                h.parse().unwrap_or_else(|_| usage()),
            );
            let scenes = (0..frames)
                .map(|i| demo::by_name(&scene_name, i as f64 / 30.0).expect("checked name"));
            render::headless_frames(scenes, w, h, &PathBuf::from(&args[4])).map(|s| {
                println!(
                    "{} frames on {}: mean {:.2} ms, p50 {:.2} ms, p99 {:.2} ms, max {:.2} ms",
                    s.frames, s.adapter, s.mean_ms, s.p50_ms, s.p99_ms, s.max_ms
                );
            })
        }
        Some("window") if args.len() == 2 => {
            let start = Instant::now();
            let mut paused_at: Option<f64> = None;
            let mut offset = 0.0;
            let (tx, rx) = std::sync::mpsc::channel();
            window::run(
                "telerehab render demo",
                move || {
                    let now = start.elapsed().as_secs_f64();
                    while let Ok(window::UserRequest::TogglePause) = rx.try_recv() {
                        match paused_at.take() {
                            Some(p) => offset += now - p,
                            None => paused_at = Some(now),
                        }
                    }
                    let t = paused_at.unwrap_or(now) - offset;
                    let mut scene = demo::by_name(&scene_name, t).expect("checked name");
                    if paused_at.is_some() {
                        scene.screen = render::ScreenState::Paused;
                    }
                    Some(scene)
                },
                move |req| {
                    let _ = tx.send(req);
                },
            )
        }
        _ => usage(),
    };
    if let Err(e) = result {
        eprintln!("render_demo: {e}");
        std::process::exit(1);
    }
}
