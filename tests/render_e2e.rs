//! End-to-end: the patient's screen, headless on Mesa's software renderer.

use std::process::Command;
use telerehab_tests::windowed::screenshot;
use telerehab_tests::{Reaper, run_ok, telerehab_bin, xdotool_in};

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

/// Presses `key` until `done` holds (checked for 5 s after each press, at most 8 presses): on a
/// loaded machine a window can take its first keys late, and a key sent before it does is lost.
fn press_until(key: &str, done: impl Fn() -> bool) {
    for _ in 0..8 {
        press(key);
        for _ in 0..100 {
            if done() {
                return;
            }
            std::thread::sleep(std::time::Duration::from_millis(50));
        }
    }
    panic!("pressing {key} changed nothing");
}

fn press(key: &str) {
    press_in("^telerehab$", key);
}

/// The station's log (its standard error), read line by line on a thread of its own, so a
/// test can wait for what it says instead of sleeping and hoping.
struct StationLog {
    lines: std::sync::Arc<std::sync::Mutex<Vec<String>>>,
    reader: std::thread::JoinHandle<()>,
}

/// What the station logs each time the exercise is paused or resumed (the first at its start,
/// waiting for the patient's Space).
const PAUSE_CHANGED: &str = "exercise paused or resumed";

impl StationLog {
    fn of(station: &mut std::process::Child) -> Self {
        use std::io::BufRead;
        let lines = std::sync::Arc::new(std::sync::Mutex::new(Vec::<String>::new()));
        let stderr = std::io::BufReader::new(station.stderr.take().expect("stderr piped"));
        let kept = lines.clone();
        let reader = std::thread::spawn(move || {
            for line in stderr.lines().map_while(Result::ok) {
                kept.lock().unwrap().push(line);
            }
        });
        Self { lines, reader }
    }

    /// Lines said so far that contain `needle`.
    fn count(&self, needle: &str) -> usize {
        let lines = self.lines.lock().unwrap();
        lines.iter().filter(|l| l.contains(needle)).count()
    }

    /// Waits (on a loaded machine, long: 30 s) until the log has said `needle` `times` times.
    fn wait_for(&self, needle: &str, times: usize) {
        for _ in 0..600 {
            if self.count(needle) >= times {
                return;
            }
            std::thread::sleep(std::time::Duration::from_millis(50));
        }
        panic!("the station did not say {needle:?} {times} times");
    }

    /// The whole log, once the station has ended.
    fn text(self) -> String {
        self.reader.join().unwrap();
        self.lines.lock().unwrap().join("\n")
    }
}

/// End the session as a patient does: Esc, which asks (and the exercise waits), then Esc again.
fn end_the_session() {
    press("Escape");
    std::thread::sleep(std::time::Duration::from_millis(1000));
    press("Escape");
}

/// Press `key` in the first window whose name matches `name` (a regular expression), waiting
/// for it to open.
fn press_in(name: &str, key: &str) {
    xdotool_in(name, &["key", key]);
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
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let _reaper = Reaper(child.id());
    let log = StationLog::of(&mut child);
    // The window prints its adapter once it can draw.
    let mut stdout = BufReader::new(child.stdout.take().unwrap());
    let mut line = String::new();
    while stdout.read_line(&mut line).unwrap() > 0 && !line.contains("render: adapter") {
        line.clear();
    }
    assert!(line.contains("render: adapter"), "the window never opened");
    // The exercise waits for Space (1: paused at the start); Space starts it (2), once the
    // window maps and takes keys; then Space pauses it (3) and Space again resumes it (4). The
    // sleeps between are how long the patient lets it run or stay paused, not waits.
    log.wait_for(PAUSE_CHANGED, 1);
    press_until("space", || log.count(PAUSE_CHANGED) >= 2);
    std::thread::sleep(std::time::Duration::from_millis(1000));
    press_until("space", || log.count(PAUSE_CHANGED) >= 3);
    std::thread::sleep(std::time::Duration::from_millis(2000));
    press_until("space", || log.count(PAUSE_CHANGED) >= 4);
    // Long enough for the resumed exercise to record a score (every 100 ms of exercise time)
    // on a loaded machine, whose loop skips deadlines and so runs the clock slower than the wall
    // (1.5 s once was not, with the whole suite running beside it).
    std::thread::sleep(std::time::Duration::from_millis(3000));
    end_the_session();
    let mut report = String::new();
    std::io::Read::read_to_string(&mut stdout, &mut report).unwrap();
    let log = log.text();
    assert!(child.wait().unwrap().success(), "{report}\n{log}");
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
        [true, false, true, false, true],
        "waiting, running, paused, running, waiting while asked to end"
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
    let _reaper = Reaper(child.id());
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

/// The pid of `parent`'s child process whose command line contains `needle`, waiting for it.
fn child_process(parent: u32, needle: &str) -> u32 {
    for _ in 0..300 {
        for entry in std::fs::read_dir("/proc").unwrap().flatten() {
            let Ok(pid) = entry.file_name().to_string_lossy().parse::<u32>() else {
                continue;
            };
            let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).unwrap_or_default();
            // The parent's pid is the second field after the command name in parentheses.
            let ppid = stat
                .rsplit_once(')')
                .and_then(|(_, rest)| rest.split_whitespace().nth(1)?.parse::<u32>().ok());
            let cmdline = std::fs::read(format!("/proc/{pid}/cmdline")).unwrap_or_default();
            if ppid == Some(parent) && String::from_utf8_lossy(&cmdline).contains(needle) {
                return pid;
            }
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    panic!("process {parent} has no child running {needle}");
}

/// Read `stdout` until a line contains `needle`; false at its end.
fn wait_for_line(stdout: &mut impl std::io::BufRead, needle: &str) -> bool {
    let mut line = String::new();
    loop {
        line.clear();
        if stdout.read_line(&mut line).unwrap() == 0 {
            return false;
        }
        if line.contains(needle) {
            return true;
        }
    }
}

/// A windowed session whose window process is sent `signal` while the exercise runs: the
/// exercise must pause, the torque fade to zero, a new window open and Space resume it. Returns
/// the report and the station's log; the recording is `window-lost.mcap` in `dir`.
fn session_losing_its_window(dir: &std::path::Path, signal: &str) -> (String, String) {
    use std::io::{BufReader, Read};
    let mcap = dir.join("window-lost.mcap");
    let mut station = Command::new(telerehab_bin())
        .args(["run", "--sim", "--duration", "120", "--seed", "7"])
        .arg("--record")
        .arg(&mcap)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let _reaper = Reaper(station.id());
    let log = StationLog::of(&mut station);
    let mut stdout = BufReader::new(station.stdout.take().unwrap());
    assert!(
        wait_for_line(&mut stdout, "render: adapter"),
        "the window never opened"
    );
    // 1: paused at the start; 2: Space started it (once the window maps and takes keys).
    std::thread::sleep(std::time::Duration::from_millis(1000));
    press_until("space", || log.count(PAUSE_CHANGED) >= 2);
    std::thread::sleep(std::time::Duration::from_millis(1000));
    let window = child_process(station.id(), "window-process");
    assert!(
        Command::new("kill")
            .args([signal, &window.to_string()])
            .status()
            .unwrap()
            .success()
    );
    // 3: paused when the window was lost. A new window opens (after the hang timeout for a
    // stopped one); 4: Space resumes.
    log.wait_for(PAUSE_CHANGED, 3);
    assert!(
        wait_for_line(&mut stdout, "render: adapter"),
        "no new window"
    );
    assert_ne!(child_process(station.id(), "window-process"), window);
    // The new process has chosen its adapter; give its window time to map and take keys
    // (a key sent before is lost, and the wait below would time out).
    std::thread::sleep(std::time::Duration::from_millis(1000));
    press_until("space", || log.count(PAUSE_CHANGED) >= 4);
    // Long enough for the resumed exercise to record scores (every 100 ms of exercise time)
    // on a loaded machine, whose loop runs the exercise clock slower than the wall.
    std::thread::sleep(std::time::Duration::from_millis(1500));
    end_the_session();
    let mut report = String::new();
    stdout.read_to_string(&mut report).unwrap();
    let log = log.text();
    assert!(station.wait().unwrap().success(), "{report}\n{log}");
    (report, log)
}

/// From the recording in `dir`: the exercise ran, paused when the window was lost (the torque
/// fading to zero within the supervisor's fade-out and staying there), and ran again; every
/// tick's torque within the ceiling in N·m.
fn assert_paused_safely_while_the_window_was_lost(dir: &std::path::Path) {
    let rec = record::Recording::open(dir.join("window-lost.mcap")).unwrap();
    let cfg =
        session::config::StationConfig::from_toml(&rec.metadata.config_toml, "recording").unwrap();
    // Every tick's pause (the `/score` samples come every 100 ticks only, and a loop slowed
    // by a loaded machine can pass a whole pause between two of them).
    let scores = &rec.raw_wheel;
    let mut stretches: Vec<(bool, usize)> = Vec::new();
    for (i, s) in scores.iter().enumerate() {
        if stretches.last().is_none_or(|l| l.0 != s.data.paused) {
            stretches.push((s.data.paused, i));
        }
    }
    let kinds: Vec<bool> = stretches.iter().map(|s| s.0).collect();
    assert_eq!(
        kinds,
        [true, false, true, false, true],
        "waiting, running, paused when the window was lost, running, waiting while asked to end"
    );
    let paused_at_s = scores[stretches[2].1].t_s;
    let resumed_at_s = scores[stretches[3].1].t_s;
    let fade_s = cfg.haptic.safety.fade_out_s;
    for w in &rec.wheel {
        assert!(
            w.data.commanded_nm.abs() <= w.data.ceiling_nm + 1e-6,
            "{} N·m over {} at {} s",
            w.data.commanded_nm,
            w.data.ceiling_nm,
            w.t_s
        );
        // The torque fades out from the first paused tick; 100 ms of margin before the
        // resume.
        if w.t_s > paused_at_s + fade_s && w.t_s < resumed_at_s - 0.1 {
            assert_eq!(
                w.data.commanded_nm, 0.0,
                "torque {} N·m at {} s while the window was lost",
                w.data.commanded_nm, w.t_s
            );
        }
    }
}

#[test]
fn killing_the_window_process_pauses_the_exercise_and_a_new_window_takes_over() {
    let Some(_display) = the_display() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let (report, log) = session_losing_its_window(dir.path(), "-KILL");
    assert!(log.contains("killed by signal 9"), "{log}");
    assert!(log.contains("the exercise is paused"), "{log}");
    assert!(
        report.contains("patient window      restarted 1 time"),
        "{report}"
    );
    assert_paused_safely_while_the_window_was_lost(dir.path());
}

#[test]
fn a_window_process_that_stops_answering_is_replaced_and_the_exercise_paused() {
    let Some(_display) = the_display() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let (report, log) = session_losing_its_window(dir.path(), "-STOP");
    assert!(log.contains("stopped answering"), "{log}");
    assert!(
        report.contains("patient window      restarted 1 time"),
        "{report}"
    );
    assert_paused_safely_while_the_window_was_lost(dir.path());
}

#[test]
fn a_prescribed_rest_counts_down_between_exercises_and_esc_asks_before_ending() {
    let Some(_display) = the_display() else {
        return;
    };
    use std::io::{BufReader, Read};
    let dir = tempfile::tempdir().unwrap();
    let regimen = dir.path().join("rest.toml");
    std::fs::write(
        &regimen,
        "[[exercise]]\nkind = \"sine\"\nduration_s = 2.0\nrest_s = 60.0\n\n\
         [[exercise]]\nkind = \"dial\"\nduration_s = 30.0\n",
    )
    .unwrap();
    let mut child = Command::new(telerehab_bin())
        .args(["run", "--sim", "--seed", "7", "--regimen"])
        .arg(&regimen)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let mut stdout = BufReader::new(child.stdout.take().unwrap());
    assert!(
        wait_for_line(&mut stdout, "render: adapter"),
        "the window never opened"
    );
    // The first exercise's card, then Space starts it; 2 s of exercise (twice the wall time
    // on a loaded machine) and its rest begins, 60 s long.
    std::thread::sleep(std::time::Duration::from_millis(1500));
    screenshot("session-1-next-exercise");
    press("space");
    std::thread::sleep(std::time::Duration::from_millis(6000));
    screenshot("session-2-rest-countdown");
    // Esc asks, and the session goes on: Space answers "go on".
    press("Escape");
    std::thread::sleep(std::time::Duration::from_millis(1500));
    screenshot("session-3-end-confirmation");
    assert!(child.try_wait().unwrap().is_none(), "one Esc ended it");
    press("space");
    std::thread::sleep(std::time::Duration::from_millis(1000));
    assert!(
        child.try_wait().unwrap().is_none(),
        "Space after Esc ended it"
    );
    end_the_session();
    let mut report = String::new();
    stdout.read_to_string(&mut report).unwrap();
    assert!(child.wait().unwrap().success(), "{report}");
    // One rest, under way when the session was ended (less than its 60 s).
    let rest = report
        .lines()
        .find_map(|l| l.strip_prefix("rests"))
        .unwrap_or_else(|| panic!("no rest in the report:\n{report}"));
    let mut words = rest.split_whitespace();
    assert_eq!(words.next(), Some("1"), "{rest}");
    let rest_s: f64 = words
        .next()
        .and_then(|w| w.trim_start_matches('(').parse().ok())
        .unwrap_or_else(|| panic!("{rest}"));
    assert!(rest_s > 1.0 && rest_s < 60.0, "rested {rest_s} s");
}

#[test]
fn a_session_without_a_wheel_says_why_on_the_screen_until_a_key_then_fails_saying_so() {
    let Some(_display) = the_display() else {
        return;
    };
    let cfg = session::config::StationConfig::default();
    if station::front_door::checks::check_devices(&cfg.wheel, None).wheel_ready {
        eprintln!("SKIPPED: a wheel is plugged in");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let child = Command::new(telerehab_bin())
        .args(["run", "--duration", "5"])
        .env("TELEREHAB_HOME", dir.path())
        .env("TELEREHAB_LANGUAGE", "en")
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // The card stays until a key: still there after a while.
    std::thread::sleep(std::time::Duration::from_millis(2500));
    screenshot("session-4-no-wheel");
    press("space");
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(stderr.contains("the session cannot start"), "{stderr}");
    // The check's line as the catalogue words it (English: the language the station was given).
    i18n::use_language("en").unwrap();
    assert!(
        stderr.contains(&i18n::tr!("front-device-no-wheel")),
        "{stderr}"
    );
}
