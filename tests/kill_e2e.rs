//! End-to-end: recording under pressure. A real-time session killed with SIGKILL at a
//! seeded-random moment recovers to every tick up to its last closed chunk, each torque within
//! the ceiling and the slew limit in N·m; a disk that runs low mid-session stops the recording
//! cleanly with a finished file; a session that would not fit on its disk does not start.
//!
//! The disk tests mount a small tmpfs (root with CAP_SYS_ADMIN); elsewhere they print
//! `SKIPPED`.

use record::Recording;
use session::config::StationConfig;
use std::path::Path;
use std::time::Duration;
use telerehab_tests::{
    Tmpfs, assert_within_ceiling_and_slew, run_ok, spawn_real_time_session,
    spawn_recording_session, wait_for_first_chunk,
};

/// splitmix64: a fixed seed gives the same "random" kill moment on every run.
fn splitmix64(seed: u64) -> u64 {
    let mut z = seed.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Every tick of `rec` in order from 0, each once; every torque within its ceiling and the
/// slew limit the session ran with.
fn assert_whole_and_safe(rec: &Recording) -> Vec<u64> {
    let ticks: Vec<u64> = rec.wheel.iter().map(|w| w.tick).collect();
    for (i, &t) in ticks.iter().enumerate() {
        assert_eq!(t, i as u64, "a gap or a duplicate at tick {i}");
    }
    let cfg = StationConfig::from_toml(&rec.metadata.config_toml, "the recording").unwrap();
    let commanded: Vec<f64> = rec.wheel.iter().map(|w| w.data.commanded_nm).collect();
    let ceiling: Vec<f64> = rec.wheel.iter().map(|w| w.data.ceiling_nm).collect();
    assert_within_ceiling_and_slew(
        &commanded,
        &ceiling,
        cfg.haptic.safety.slew_nm_per_s,
        1.0 / cfg.session.loop_rate_hz,
        None,
    );
    ticks
}

/// The `/wheel` blocks (100 ticks each) mcap's own streaming reader finds in a killed file
/// before its unreadable tail.
fn wheel_blocks_readable_in(killed: &Path) -> usize {
    let bytes = std::fs::read(killed).unwrap();
    let mut blocks = 0;
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        let Ok(m) = m else { break };
        blocks += usize::from(m.channel.topic == "/wheel");
    }
    // Blocks of 100 samples; only the last one before a flush can be shorter.
    blocks
}

#[test]
fn sigkill_at_a_random_moment_recovers_every_tick_up_to_the_last_closed_chunk() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("killed.mcap");
    let fixed = dir.path().join("fixed.mcap");
    // 1.5 to 4 s into the session: the first chunk closes at 1 s, then 0.5 to 3 s more.
    let extra_ms = 500 + splitmix64(17) % 2500;
    let mut child = spawn_recording_session(&path);
    wait_for_first_chunk(&path);
    std::thread::sleep(Duration::from_millis(extra_ms));
    child.kill().unwrap(); // SIGKILL: no chance to finish the file
    child.wait().unwrap();
    let on_disk_blocks = wheel_blocks_readable_in(&path);
    let out = run_ok(&[
        "recover",
        path.to_str().unwrap(),
        "--out",
        fixed.to_str().unwrap(),
    ]);
    println!(
        "killed {extra_ms} ms after the first chunk: {}",
        String::from_utf8_lossy(&out.stdout).trim()
    );
    let rec = Recording::open(&fixed).expect("the recovered file is finished and reads back");
    let ticks = assert_whole_and_safe(&rec);
    // Every closed chunk (one a second, 1000 ticks): at least the first; and every block a
    // streaming reader finds on the disk is in the recovered file.
    assert!(ticks.len() >= 1000, "{} ticks", ticks.len());
    assert!(
        ticks.len().div_ceil(100) >= on_disk_blocks,
        "{} ticks recovered, {on_disk_blocks} blocks on disk",
        ticks.len()
    );
    // Nothing past the kill: at most 60 s of session, and the kill came within ~5 s.
    assert!(ticks.len() < 10_000, "{} ticks", ticks.len());
}

#[test]
fn a_session_that_would_not_fit_on_its_disk_is_refused_before_it_starts() {
    let Some(disk) = Tmpfs::mount_or_skip(80) else {
        return;
    };
    let path = disk.path().join("long.mcap");
    // 600 s need 100 MB at 600 MB/h plus the 64 MB kept free: more than 80 MiB.
    let err = telerehab_tests::run_err(&[
        "run",
        "--sim",
        "--headless",
        "--speed",
        "max",
        "--duration",
        "600",
        "--record",
        path.to_str().unwrap(),
    ]);
    assert!(err.contains("not enough disk space"), "{err}");
    assert!(
        err.contains(path.to_str().unwrap()),
        "names the path: {err}"
    );
    assert!(err.contains("83.9 MB free"), "the free bytes: {err}");
    assert!(err.contains("needs 164.0 MB"), "the need: {err}");
    assert!(
        !path.exists(),
        "no recording for a session that never started"
    );
    // A short one fits.
    let short = disk.path().join("short.mcap");
    run_ok(&[
        "run",
        "--sim",
        "--headless",
        "--speed",
        "max",
        "--duration",
        "2",
        "--record",
        short.to_str().unwrap(),
    ]);
    assert!(Recording::open(&short).is_ok());
}

#[test]
fn a_disk_running_low_mid_session_stops_the_recording_with_a_finished_file() {
    let Some(disk) = Tmpfs::mount_or_skip(72) else {
        return;
    };
    let path = disk.path().join("low.mcap");
    let child = spawn_real_time_session("5", |c| c.arg("--record").arg(&path));
    wait_for_first_chunk(&path);
    disk.fill_under_the_reserve();
    let out = child.wait_with_output().unwrap();
    let report = String::from_utf8_lossy(&out.stdout);
    let log = String::from_utf8_lossy(&out.stderr);
    // The session went on to its end; the run says the recording stopped, when and why.
    assert!(!out.status.success(), "a stopped recording fails the run");
    assert!(report.contains("recording stopped at"), "{report}");
    assert!(
        report.contains("stopped before the disk filled up"),
        "{report}"
    );
    assert!(
        !report.contains("FAILED") && !report.contains("stopped early"),
        "{report}"
    );
    assert!(log.contains("recording stopped"), "said at once: {log}");
    // Finished while there was room: it reads without recover, from tick 0, none missing.
    let rec = Recording::open(&path).expect("a finished file");
    let ticks = assert_whole_and_safe(&rec);
    assert!((1000..5000).contains(&ticks.len()), "{} ticks", ticks.len());
    assert_eq!(ticks.len() % 1000, 0, "stopped where a chunk closed");
}
