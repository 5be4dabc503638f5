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

/// Press `key` in the window titled "telerehab" with xdotool (the X test path a real
/// keyboard takes: focus, then a key event).
/// The window tests share one X display, and both windows are named "telerehab": run them one
/// at a time, or a key press meant for one window can land in the other.
static ONE_WINDOW_AT_A_TIME: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// The X display, held for one window test at a time; `None` (saying SKIPPED) without one.
fn the_display() -> Option<std::sync::MutexGuard<'static, ()>> {
    let held = ONE_WINDOW_AT_A_TIME
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    if std::env::var_os("DISPLAY").is_none() {
        eprintln!("SKIPPED: no display (run under xvfb-run to test the window)");
        return None;
    }
    Some(held)
}

fn press(key: &str) {
    press_in("^telerehab$", key);
}

/// Press `key` in the first window whose name matches `name` (a regular expression), waiting
/// for it to open.
fn press_in(name: &str, key: &str) {
    let search = Command::new("xdotool")
        .args(["search", "--sync", "--name", name])
        .output()
        .expect("xdotool (installed by scripts/setup.sh)");
    let window = String::from_utf8_lossy(&search.stdout)
        .lines()
        .next()
        .expect("the patient window")
        .to_string();
    for args in [
        vec!["windowfocus", "--sync", window.as_str()],
        vec!["key", key],
    ] {
        assert!(
            Command::new("xdotool")
                .args(&args)
                .status()
                .unwrap()
                .success()
        );
    }
}

#[test]
fn space_in_the_patient_window_starts_pauses_and_resumes_the_exercise_and_esc_ends_it() {
    let Some(_display) = the_display() else {
        return;
    };
    use std::io::{BufRead, BufReader};
    let dir = tempfile::tempdir().unwrap();
    let mcap = dir.path().join("paused.mcap");
    let mut child = Command::new(telerehab_bin())
        .args([
            "run",
            "--sim",
            "--duration",
            "120",
            "--seed",
            "7",
            "--record",
        ])
        .arg(&mcap)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    // The window prints its adapter once it can draw.
    let mut stdout = BufReader::new(child.stdout.take().unwrap());
    let mut line = String::new();
    while stdout.read_line(&mut line).unwrap() > 0 && !line.contains("render: adapter") {
        line.clear();
    }
    assert!(line.contains("render: adapter"), "the window never opened");
    // The exercise waits for Space; then Space pauses it and Space again resumes it.
    std::thread::sleep(std::time::Duration::from_millis(500));
    press("space");
    std::thread::sleep(std::time::Duration::from_millis(1000));
    press("space");
    std::thread::sleep(std::time::Duration::from_millis(2000));
    press("space");
    // Long enough for the resumed exercise to record a score (every 100 ms of exercise time)
    // on a loaded machine, whose loop skips deadlines and so runs the clock slower than the wall.
    std::thread::sleep(std::time::Duration::from_millis(1500));
    press("Escape");
    let mut report = String::new();
    std::io::Read::read_to_string(&mut stdout, &mut report).unwrap();
    assert!(child.wait().unwrap().success(), "{report}");
    let paused_s: f64 = report
        .lines()
        .find_map(|l| l.strip_prefix("paused"))
        .and_then(|l| l.split_whitespace().next()?.parse().ok())
        .unwrap_or_else(|| panic!("no pause in the report:\n{report}"));
    assert!(paused_s >= 2.0, "paused {paused_s} s");
    // The recording shows both waits: before the start (exercise clock at 0) and the pause
    // (clock held at a later time), with the exercise running between and after them.
    let msgs = telerehab_tests::read_mcap(&mcap);
    let scores: Vec<(bool, f64)> = telerehab_tests::by_topic(&msgs)["/score"]
        .iter()
        .map(|m| {
            (
                m.json["paused"] == true,
                m.json["active_s"].as_f64().unwrap(),
            )
        })
        .collect();
    let mut stretches: Vec<(bool, Vec<f64>)> = Vec::new();
    for (paused, t) in scores {
        match stretches.last_mut() {
            Some((p, ts)) if *p == paused => ts.push(t),
            _ => stretches.push((paused, vec![t])),
        }
    }
    let kinds: Vec<bool> = stretches.iter().map(|s| s.0).collect();
    assert_eq!(
        kinds,
        [true, false, true, false],
        "waiting, running, paused, running"
    );
    assert!(stretches[0].1.iter().all(|&t| t == 0.0));
    // Held at a time after the start. How much exercise time one wall second of running gives
    // depends on the machine's load: the loop skips deadlines it missed instead of bursting
    // through them, so a loaded machine runs the exercise clock slower than the wall.
    let held = &stretches[2].1;
    assert!(
        held.len() >= 15 && held.iter().all(|&t| t == held[0] && t > 0.05),
        "{held:?}"
    );
}

#[test]
fn replay_window_plays_a_recording_and_seeks_with_the_arrow_keys() {
    let Some(_display) = the_display() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let mcap = dir.path().join("played.mcap");
    run_ok(&telerehab_tests::sim_session_args("3", &mcap, &[]));
    let child = Command::new(telerehab_bin())
        .args(["replay", "--window", "--play-speed", "0.125"])
        .arg(&mcap)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    // At an eighth of real time the 3.1 s recording would take 25 s; → jumps 5 s, to its end.
    press_in("^telerehab replay", "Right");
    std::thread::sleep(std::time::Duration::from_millis(300));
    press_in("^telerehab replay", "Escape");
    let out = child.wait_with_output().unwrap();
    let said = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{said}");
    assert!(said.contains("replay: played to 3.1 of 3.1 s"), "{said}");
}

#[test]
fn bench_window_reports_loop_timing_with_drawing_on_and_off() {
    let Some(_display) = the_display() else {
        return;
    };
    let out = run_ok(&[
        "bench",
        "window",
        "--duration",
        "6",
        "--phase",
        "1",
        "--size",
        "320x180",
    ]);
    let report = String::from_utf8_lossy(&out.stdout);
    // Phases of 1 s: 0–1 warm-up, then idle 2, 4 and drawing 3, 5 (0.25 s settling each).
    for (phase, ticks) in [("drawing", 1500), ("idle", 1500)] {
        let line = report
            .lines()
            .find(|l| l.starts_with(phase))
            .unwrap_or_else(|| panic!("no {phase} line in:\n{report}"));
        let n: usize = line.split_whitespace().nth(1).unwrap().parse().unwrap();
        assert!(n.abs_diff(ticks) <= 2, "{phase}: {n} ticks\n{report}");
    }
    assert!(report.contains("p99 ratio drawing / idle"), "{report}");
    assert!(report.contains("frames drawn"), "{report}");
}
