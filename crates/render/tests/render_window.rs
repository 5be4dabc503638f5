//! The window path: opens a real winit window, draws scenes through the same renderer as the
//! headless path, and returns when the scene source says the session is over.
//!
//! Needs a display: run it under `xvfb-run -a cargo test -p render --test render_window`.
//! Without `DISPLAY` / `WAYLAND_DISPLAY` it skips with a message.

use render::demo;
use render::window::{WindowOptions, run_with};

#[test]
fn window_draws_until_the_scene_source_ends_the_session() {
    if std::env::var_os("DISPLAY").is_none() && std::env::var_os("WAYLAND_DISPLAY").is_none() {
        eprintln!("SKIPPED: no display (run under xvfb-run to test the window)");
        return;
    }
    let options = WindowOptions {
        size: (480, 270),
        any_thread: true,
        ..WindowOptions::new("telerehab render test")
    };
    let mut pulled = 0;
    let result = run_with(
        &options,
        || {
            pulled += 1;
            (pulled <= 20).then(|| demo::sine_road(pulled as f64 / 30.0))
        },
        |_| {},
    );
    let stats = result.expect("window session");
    assert_eq!(pulled, 21, "the loop must stop at the first None");
    assert!(stats.frames_drawn >= 1, "{stats:?}");
    println!("window: {stats:?}");
}
