//! End-to-end: the patient's screen, headless on Mesa's software renderer.

use std::process::Command;
use telerehab_tests::{run_ok, telerehab_bin};

#[test]
fn render_command_writes_the_requested_frames_of_a_simulated_session() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("frames");
    let report = run_ok(&[
        "render",
        "--exercise",
        "sine-road",
        "--seed",
        "7",
        "--frames",
        "3",
        "--size",
        "320x180",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(String::from_utf8_lossy(&report.stdout).contains("rendered 3 frames"));
    let mut pngs: Vec<_> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    pngs.sort();
    assert_eq!(pngs, ["frame_0000.png", "frame_0001.png", "frame_0002.png"]);
    // A real picture: PNG signature and far more than a blank frame compresses to.
    let bytes = std::fs::read(out.join("frame_0002.png")).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    assert!(bytes.len() > 5_000, "{} bytes", bytes.len());
}

#[test]
fn session_without_a_display_runs_headless_and_says_so() {
    let out = Command::new(telerehab_bin())
        .args(["run", "--sim", "--duration", "1", "--speed", "max"])
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(String::from_utf8_lossy(&out.stderr).contains("no patient window"));
    assert!(String::from_utf8_lossy(&out.stdout).contains("session summary"));
}
