//! End-to-end: the binary runs whole simulated sessions and records them.

use std::process::Command;
use std::time::{Duration, Instant};
use telerehab_tests::{
    by_topic, interrupted_recording_session, read_mcap, run_err, run_ok, sim_session_args,
    spawn_recording_session, wait_for_first_chunk,
};

#[test]
fn binary_reports_its_version() {
    let out = run_ok(&["--version"]);
    assert!(String::from_utf8_lossy(&out.stdout).starts_with("telerehab "));
}

#[test]
fn a_log_written_to_a_file_has_no_colour_codes() {
    let dir = tempfile::tempdir().unwrap();
    let mcap = dir.path().join("plain.mcap");
    let args = sim_session_args("0.2", &mcap, &[]);
    // stderr is a pipe here, as a file or a service's journal would be.
    let out = Command::new(telerehab_tests::telerehab_bin())
        .args(&args)
        .output()
        .unwrap();
    assert!(out.status.success());
    let log = String::from_utf8_lossy(&out.stderr);
    assert!(log.contains("INFO"), "{log}");
    assert!(
        !log.contains('\u{1b}'),
        "ANSI codes in a piped log: {log:?}"
    );
}

#[test]
fn short_session_records_every_tick_on_every_channel_with_schemas() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.mcap");
    let out = run_ok(&[
        "run",
        "--sim",
        "--headless",
        "--duration",
        "3",
        "--seed",
        "7",
        "--speed",
        "max",
        "--record",
        path.to_str().unwrap(),
    ]);
    let report = String::from_utf8_lossy(&out.stdout);
    assert!(report.contains("time in lane"), "{report}");

    // The summary section names every channel: the high-rate ones as protobuf blocks, the
    // low-rate ones as JSON with a JSON schema, and the arm's Foxglove 3-D scene.
    let bytes = std::fs::read(&path).unwrap();
    let summary = mcap::Summary::read(&bytes)
        .unwrap()
        .expect("finished file has a summary");
    let mut topics: Vec<(String, String, String)> = summary
        .channels
        .values()
        .map(|c| {
            let s = c.schema.as_ref().expect("schema");
            (
                c.topic.clone(),
                c.message_encoding.clone(),
                s.encoding.clone(),
            )
        })
        .collect();
    topics.sort();
    let json = |t: &str| (t.to_string(), "json".to_string(), "jsonschema".to_string());
    let proto = |t: &str| {
        (
            t.to_string(),
            "protobuf".to_string(),
            "protobuf".to_string(),
        )
    };
    assert_eq!(
        topics,
        vec![
            proto("/arm"),
            proto("/arm/scene"),
            json("/arm_calibration"),
            proto("/assist"),
            json("/metrics"),
            proto("/raw/imu"),
            proto("/raw/wheel"),
            json("/score"),
            proto("/timing"),
            proto("/vehicle"),
            proto("/wheel")
        ]
    );

    let msgs = by_topic(&read_mcap(&path));
    // 3 s at 1 kHz plus the 0.1 s fade-out (and the tick that sees zero); a score every 100 ms.
    for topic in ["/wheel", "/vehicle", "/assist", "/timing", "/arm"] {
        assert_eq!(msgs[topic].len(), 3101, "{topic}");
    }
    assert_eq!(msgs["/score"].len(), 31);
    // Every per-tick message carries its tick, in order, 1 ms apart in session time.
    let wheel = &msgs["/wheel"];
    for (i, m) in wheel.iter().enumerate() {
        assert_eq!(m.json["tick"], i as u64);
    }
    let t_ns = |m: &telerehab_tests::Msg| (m.json["t_s"].as_f64().unwrap() * 1e9).round() as u64;
    for pair in wheel.windows(2) {
        assert_eq!(t_ns(&pair[1]) - t_ns(&pair[0]), 1_000_000);
    }
    // Each sample has the fields its channel's JSON schema requires, and no field it does not
    // describe (an optional field is left out, never null): the block channels' samples
    // against the record types' schemas, the JSON channels' against the file's.
    for (topic, list) in &msgs {
        let spec = record::Channel::from_topic(topic).unwrap().spec();
        let schema = spec.schema();
        let described = schema["properties"].as_object().unwrap();
        let required: Vec<&str> = schema["required"]
            .as_array()
            .unwrap()
            .iter()
            .map(|k| k.as_str().unwrap())
            .collect();
        for m in list {
            let fields = m.json.as_object().unwrap();
            assert!(
                required.iter().all(|k| fields.contains_key(*k)),
                "{topic}: {fields:?} lacks one of {required:?}"
            );
            assert!(
                fields.keys().all(|k| described.contains_key(k)),
                "{topic}: {fields:?} has a field the schema does not describe"
            );
            assert!(fields.values().all(|v| !v.is_null()), "{topic}: a null");
        }
    }
    // The arm pose from the simulated IMUs follows the simulated truth.
    let arm = &msgs["/arm"];
    let err_sq: Vec<f64> = arm
        .iter()
        .filter(|m| m.json["t_s"].as_f64().unwrap() > 1.0)
        .map(|m| {
            let d = m.json["shoulder_elevation_rad"].as_f64().unwrap()
                - m.json["true_shoulder_elevation_rad"].as_f64().unwrap();
            d * d
        })
        .collect();
    let rms_deg = (err_sq.iter().sum::<f64>() / err_sq.len() as f64)
        .sqrt()
        .to_degrees();
    assert!(rms_deg < 3.0, "shoulder elevation RMS error {rms_deg}°");
    // The torque never leaves the thesis wheel's ±1.87 N·m and ends at zero.
    for m in wheel {
        assert!(m.json["commanded_nm"].as_f64().unwrap().abs() <= 1.87);
    }
    assert_eq!(
        wheel.last().unwrap().json["commanded_nm"].as_f64().unwrap(),
        0.0
    );
    // The recording holds all it takes to re-run the session bit for bit.
    let out = run_ok(&["replay", path.to_str().unwrap()]);
    let said = String::from_utf8_lossy(&out.stdout);
    assert!(said.contains("replay: identical"), "{said}");
}

fn simulation_payloads(path: &std::path::Path) -> Vec<(String, serde_json::Value)> {
    read_mcap(path)
        .into_iter()
        // Timing is the wall clock's; the raw inputs also say when the arm solver's thread
        // answered, which the seed does not fix (the outputs do not depend on it).
        .filter(|m| m.topic != "/timing" && !m.topic.starts_with("/raw/"))
        .map(|m| (m.topic, m.json))
        .collect()
}

#[test]
fn same_seed_gives_identical_simulation_data_and_another_seed_does_not() {
    let dir = tempfile::tempdir().unwrap();
    let run = |seed: &str, name: &str| {
        let p = dir.path().join(name);
        run_ok(&[
            "run",
            "--sim",
            "--headless",
            "--duration",
            "2",
            "--seed",
            seed,
            "--speed",
            "max",
            "--record",
            p.to_str().unwrap(),
        ]);
        simulation_payloads(&p)
    };
    let a = run("11", "a.mcap");
    let b = run("11", "b.mcap");
    let c = run("12", "c.mcap");
    // Four per-tick channels, a score every 100 ms and the session's measures once at the end
    // (no arm calibration: 2 s of data do not determine the arm, and a fit outside the
    // anthropometric bounds is rejected, never recorded as a result). The fade-out after 2 s
    // lasts as long as the torque at the end takes to reach zero (a tick or two).
    let ticks = a.iter().filter(|(topic, _)| topic == "/wheel").count();
    assert!((2100..=2110).contains(&ticks), "{ticks} ticks");
    assert_eq!(a.len(), ticks * 4 + (ticks - 1) / 100 + 1);
    assert!(
        a == b,
        "same seed must give identical recorded simulation data"
    );
    assert!(
        a != c,
        "another seed must change the simulated patient's noise"
    );
}

#[test]
fn real_time_session_is_paced_at_the_loop_rate() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("rt.mcap");
    let t0 = Instant::now();
    run_ok(&[
        "run",
        "--sim",
        "--headless",
        "--duration",
        "1",
        "--seed",
        "7",
        "--record",
        path.to_str().unwrap(),
    ]);
    // 1.1 s of ticks (with the fade-out) cannot finish sooner in real time.
    assert!(t0.elapsed() >= Duration::from_millis(1100));
    // 1000 ticks plus the fade-out (100 ticks from full scale).
    let ticks = by_topic(&read_mcap(&path))["/wheel"].len();
    assert!((1100..=1101).contains(&ticks), "{ticks}");
}

#[test]
fn sigint_ends_the_session_cleanly_with_a_readable_recording() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("int.mcap");
    let out = interrupted_recording_session(&path);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}\n{}",
        stdout,
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains("stopped early"), "{stdout}");
    let bytes = std::fs::read(&path).unwrap();
    assert!(
        mcap::Summary::read(&bytes).unwrap().is_some(),
        "the MCAP file was finalised"
    );
    let wheel = &by_topic(&read_mcap(&path))["/wheel"];
    assert!(wheel.len() > 500 && wheel.len() < 30_000, "{}", wheel.len());
    assert_eq!(
        wheel.last().unwrap().json["commanded_nm"].as_f64().unwrap(),
        0.0
    );
    // The stop was the patient's input: a replay runs the whole session, says why it will
    // differ, and names where it first does (the stop's fade-out).
    let out = Command::new(telerehab_tests::telerehab_bin())
        .args(["replay", path.to_str().unwrap()])
        .output()
        .unwrap();
    let (said, err) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    assert!(!out.status.success(), "{said}");
    assert!(said.contains("the session was stopped after"), "{said}");
    assert!(
        err.contains("replay differs: first at /wheel sample"),
        "{err}"
    );
}

#[test]
fn bad_config_value_is_reported_by_field_and_range() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = dir.path().join("bad.toml");
    std::fs::write(&cfg, "[haptic.safety]\nceiling_nm = 9.0\n").unwrap();
    let err = run_err(&[
        "run",
        "--sim",
        "--headless",
        "--config",
        cfg.to_str().unwrap(),
    ]);
    assert!(
        err.contains("haptic.safety") && err.contains("ceiling_nm") && err.contains("1.87"),
        "{err}"
    );
}

#[test]
fn motion_assist_keeps_a_weak_simulated_patient_in_lane_and_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let weak = "[sim_patient]\nmax_torque_nm = 0.3\n";
    let run_with = |name: &str, toml: &str| {
        let cfg = dir.path().join(name);
        std::fs::write(&cfg, toml).unwrap();
        let out = run_ok(&[
            "run",
            "--sim",
            "--headless",
            "--duration",
            "20",
            "--speed",
            "max",
            "--config",
            cfg.to_str().unwrap(),
        ]);
        String::from_utf8_lossy(&out.stdout).into_owned()
    };
    let alone = run_with("weak.toml", weak);
    let assisted = run_with(
        "assisted.toml",
        &format!("{weak}[assist.mode]\nkind = \"motion\"\n"),
    );
    let (e_alone, e_assisted) = (
        report_number(&alone, "RMS lateral dev."),
        report_number(&assisted, "RMS lateral dev."),
    );
    assert!(
        e_alone > 1.0,
        "a weak patient alone should leave the lane: {alone}"
    );
    assert!(
        e_assisted < 0.5 * e_alone,
        "assist should at least halve the error: {e_assisted} vs {e_alone}"
    );
    assert!(!alone.contains("\nassist "), "{alone}");
    assert!(
        assisted.contains("\nassist              mean level"),
        "{assisted}"
    );
}

#[test]
fn devices_without_hardware_explains_and_exits_zero() {
    let out = run_ok(&["devices"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("Wheels:") && text.contains("IMUs:"), "{text}");
    assert!(
        text.contains("--sim"),
        "the message should point at the simulated session: {text}"
    );
}

#[test]
fn real_session_without_a_wheel_fails_clearly_and_records_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("none.mcap");
    let err = run_err(&[
        "run",
        "--headless",
        "--duration",
        "1",
        "--record",
        path.to_str().unwrap(),
    ]);
    assert!(err.contains("telerehab devices"), "{err}");
    assert!(
        !path.exists(),
        "no recording for a session that never started"
    );
}

#[test]
fn killed_session_loses_at_most_the_last_second_and_recovers_to_a_finished_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("killed.mcap");
    let fixed = dir.path().join("fixed.mcap");
    let mut child = spawn_recording_session(&path);
    wait_for_first_chunk(&path);
    std::thread::sleep(Duration::from_millis(300));
    child.kill().unwrap(); // SIGKILL: no chance to finish the file
    child.wait().unwrap();
    let out = run_ok(&[
        "recover",
        path.to_str().unwrap(),
        "--out",
        fixed.to_str().unwrap(),
    ]);
    assert!(String::from_utf8_lossy(&out.stdout).contains("recovered"));
    let bytes = std::fs::read(&fixed).unwrap();
    assert!(
        mcap::Summary::read(&bytes).unwrap().is_some(),
        "the recovered file is finished"
    );
    let msgs = by_topic(&read_mcap(&fixed));
    // Every closed chunk survives (the recorder closes one at least every second), in order,
    // from tick 0; only the unfinished tail is lost.
    let wheel = &msgs["/wheel"];
    assert!(wheel.len() >= 500, "{}", wheel.len());
    for (i, m) in wheel.iter().enumerate() {
        assert_eq!(m.json["tick"], i as u64);
    }
    assert!(msgs["/vehicle"].len().abs_diff(wheel.len()) <= 1);
    // Never over a file, above all not over its input (the only copy of the session).
    let before = std::fs::read(&path).unwrap();
    for out in [&path, &fixed] {
        let err = run_err(&[
            "recover",
            path.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(err.contains("never writes over an existing file"), "{err}");
    }
    assert_eq!(
        std::fs::read(&path).unwrap(),
        before,
        "the input is untouched"
    );
}

/// A second session asked to record over the first one's file is refused before it starts,
/// and the first recording is untouched.
#[test]
fn a_recording_is_never_overwritten() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.mcap");
    let record = sim_session_args("1", &path, &[]);
    run_ok(&record);
    let first = std::fs::read(&path).unwrap();
    let err = run_err(&record);
    assert!(
        err.contains("already exists") && err.contains("never overwritten"),
        "{err}"
    );
    assert_eq!(std::fs::read(&path).unwrap(), first);
}

#[test]
fn max_speed_gives_the_same_simulation_data_as_real_time() {
    let dir = tempfile::tempdir().unwrap();
    let run = |speed: &str| {
        let p = dir.path().join(format!("{speed}.mcap"));
        run_ok(&[
            "run",
            "--sim",
            "--headless",
            "--duration",
            "1",
            "--seed",
            "5",
            "--speed",
            speed,
            "--record",
            p.to_str().unwrap(),
        ]);
        simulation_payloads(&p)
    };
    let (real_time, max) = (run("realtime"), run("max"));
    assert!(!max.is_empty());
    assert!(real_time == max, "pacing must not change the simulation");
}

/// A number after `label` in the report (e.g. `"time in lane"` → 100.0).
fn report_number(report: &str, label: &str) -> f64 {
    let line = report
        .lines()
        .find(|l| l.starts_with(label))
        .unwrap_or_else(|| panic!("{label} in {report}"));
    line[label.len()..]
        .split(|c: char| !(c.is_ascii_digit() || c == '.'))
        .find(|t| !t.is_empty())
        .and_then(|t| t.parse().ok())
        .unwrap_or_else(|| panic!("{line}"))
}

#[test]
fn simulated_patient_drives_every_exercise_of_the_library() {
    for name in exercises::EXERCISE_NAMES {
        let out = run_ok(&[
            "run",
            "--sim",
            "--headless",
            "--duration",
            "20",
            "--speed",
            "max",
            "--exercise",
            name,
        ]);
        let report = String::from_utf8_lossy(&out.stdout);
        if name == "strength" {
            let peak = report_number(&report, "strength left");
            assert!(peak > 0.5, "{name}: {peak} N·m\n{report}");
        } else if name.starts_with("dial") || name == "haptic-sweep" {
            let err = report_number(&report, "dial tracking");
            // RMS over the whole run, step transients included: the simulated arm sees
            // dial-step's jumps of the target after a visual reaction time (0.22 s) and its
            // inertia (0.06 kg·m² with the rim's 0.02) answers them in about a second (37° RMS
            // over 20 s; 29° before the reaction time; 9.5° on the sine, 1.5° on the chirp).
            assert!(err < 42.0, "{name}: dial RMS error {err}°\n{report}");
        } else {
            let in_lane = report_number(&report, "time in lane");
            assert!(in_lane >= 90.0, "{name}: {in_lane} % in lane\n{report}");
        }
    }
}

#[test]
fn regimen_runs_its_exercises_in_order_and_ends_the_session() {
    let out = run_ok(&[
        "run",
        "--sim",
        "--headless",
        "--speed",
        "max",
        "--regimen",
        concat!(env!("CARGO_MANIFEST_DIR"), "/../regimens/easy.toml"),
    ]);
    let report = String::from_utf8_lossy(&out.stdout);
    assert!(report.contains("exercises           3 (3 run)"), "{report}");
    assert!(!report.contains("stopped early"), "{report}");
    assert!(
        report.contains("dial tracking") && report.contains("time in lane"),
        "{report}"
    );
}

#[test]
fn unknown_exercise_lists_the_known_ones() {
    let err = run_err(&["run", "--sim", "--headless", "--exercise", "moon-road"]);
    assert!(
        err.contains("moon-road") && err.contains("sine-road"),
        "{err}"
    );
}

#[test]
fn assist_prescribed_for_one_exercise_of_a_regimen_is_reported() {
    let dir = tempfile::tempdir().unwrap();
    let regimen = dir.path().join("r.toml");
    std::fs::write(
        &regimen,
        "[[exercise]]\nkind = \"dial\"\nduration_s = 5.0\n[exercise.assist.mode]\nkind = \"motion\"\n\n\
         [[exercise]]\nkind = \"straight\"\nlength_m = 100.0\n",
    )
    .unwrap();
    let out = run_ok(&[
        "run",
        "--sim",
        "--headless",
        "--speed",
        "max",
        "--regimen",
        regimen.to_str().unwrap(),
    ]);
    let report = String::from_utf8_lossy(&out.stdout);
    assert!(
        report.contains("\nassist              mean level"),
        "{report}"
    );
}

/// A real-time session with the guided arm procedure (its mounting solved on a thread of its
/// own) replays bit for bit as fast as possible; the replay says so.
#[test]
fn a_real_time_session_replays_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("station.toml");
    std::fs::write(&config, "[arm]\nsim_mounting = \"guided\"\n").unwrap();
    let path = dir.path().join("s.mcap");
    run_ok(&[
        "run",
        "--sim",
        "--headless",
        "--config",
        config.to_str().unwrap(),
        "--duration",
        "12",
        "--seed",
        "11",
        "--record",
        path.to_str().unwrap(),
    ]);
    let arm = by_topic(&read_mcap(&path)).remove("/arm").unwrap();
    assert!(
        arm.iter().any(|m| m.json["setup"] == "tracking"),
        "the procedure finished within the session"
    );
    let out = run_ok(&["replay", path.to_str().unwrap()]);
    let said = String::from_utf8_lossy(&out.stdout);
    assert!(said.contains("replay: identical"), "{said}");
}

/// Two recorded sessions make one self-contained HTML report: measures, charts, progress.
#[test]
fn report_of_two_sessions_is_one_self_contained_html_file() {
    let dir = tempfile::tempdir().unwrap();
    let mut paths = Vec::new();
    // A lane change has discrete movements (rest between the shifts) for smoothness to be
    // measured on; a continuously steered sine road has none.
    for (seed, exercise) in [("1", "lane-change"), ("2", "dial-sine")] {
        let p = dir.path().join(format!("s{seed}.mcap"));
        run_ok(&sim_session_args(
            "8",
            &p,
            &["--seed", seed, "--exercise", exercise],
        ));
        paths.push(p.to_str().unwrap().to_owned());
    }
    let out = dir.path().join("report.html");
    let mut args = vec!["report"];
    args.extend(paths.iter().map(String::as_str));
    args.extend(["--out", out.to_str().unwrap()]);
    let said = String::from_utf8_lossy(&run_ok(&args).stdout).into_owned();
    assert!(said.contains("report: 2 sessions"), "{said}");
    let html = std::fs::read_to_string(&out).unwrap();
    assert!(html.starts_with("<!DOCTYPE html>"));
    for text in [
        "Progress",
        "Smoothness (closer to 0 is smoother)",
        "Distance from the lane",
        "Dial: distance from the angle asked",
        "Wheel speed",
    ] {
        assert!(html.contains(text), "{text} missing");
    }
    assert!(html.matches("<svg").count() >= 8, "charts inline");
    assert!(
        !html.contains("<script") && !html.contains("src=\"http"),
        "self-contained"
    );
    let err = run_err(&[
        "report",
        &paths[0],
        "--out",
        dir.path().join("r.pdf").to_str().unwrap(),
    ]);
    assert!(err.contains("must name an .html file"), "{err}");
}

#[test]
fn bench_recording_shows_the_compact_encoding_under_a_fifth_of_the_json_bytes() {
    let out = run_ok(&["bench", "recording", "--duration", "3", "--repeats", "1"]);
    let said = String::from_utf8_lossy(&out.stdout);
    let line = said
        .lines()
        .find(|l| l.starts_with("compact / all-JSON: bytes "))
        .unwrap_or_else(|| panic!("{said}"));
    let ratio: f64 = line["compact / all-JSON: bytes ".len()..]
        .split_whitespace()
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!(ratio > 0.0 && ratio <= 0.2, "{said}");
}

/// A 1 s simulated session with `home` as the station's home; its stdout (the summary).
fn session_in_home(home: &std::path::Path) -> String {
    let out = run_ok(&[
        "run",
        "--sim",
        "--headless",
        "--duration",
        "1",
        "--speed",
        "max",
        "--home",
        home.to_str().unwrap(),
    ]);
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// The session log file the summary names.
fn log_named_in(summary: &str) -> std::path::PathBuf {
    let line = summary
        .lines()
        .find_map(|l| l.strip_prefix("session log "))
        .unwrap_or_else(|| panic!("no `session log` line in the summary:\n{summary}"));
    std::path::PathBuf::from(line.trim())
}

#[test]
fn each_session_writes_its_own_plain_log_file_in_the_home_named_in_the_summary() {
    let home = tempfile::tempdir().unwrap();
    let first = log_named_in(&session_in_home(home.path()));
    let second = log_named_in(&session_in_home(home.path()));
    assert_ne!(first, second);
    for log in [&first, &second] {
        assert_eq!(log.parent(), Some(home.path().join("logs").as_path()));
        let text = std::fs::read_to_string(log).unwrap();
        assert!(text.contains("starting session"), "{text}");
        assert!(
            !text.contains('\u{1b}'),
            "ANSI codes in {}: {text:?}",
            log.display()
        );
    }
    let files = std::fs::read_dir(home.path().join("logs")).unwrap().count();
    assert_eq!(files, 2);
}

#[test]
fn a_session_start_keeps_the_last_30_session_logs() {
    let home = tempfile::tempdir().unwrap();
    let logs = home.path().join("logs");
    std::fs::create_dir_all(&logs).unwrap();
    for i in 0..32 {
        let old = logs.join(format!("session-2026-01-01T00-00-{i:02}.000Z.log"));
        std::fs::write(old, "old\n").unwrap();
    }
    let new = log_named_in(&session_in_home(home.path()));
    let mut left: Vec<_> = std::fs::read_dir(&logs)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    left.sort();
    assert_eq!(left.len(), 30, "{left:?}");
    assert!(left.contains(&new));
    // The three oldest went; the 29 newest old ones stay.
    assert!(
        left[0].ends_with("session-2026-01-01T00-00-03.000Z.log"),
        "{left:?}"
    );
}

/// The simulated wheel takes every command: its session's summary, its recording's `/wheel`
/// ticks and its measures say 1000 torque updates a second reached the motor, 1 ms apart at
/// worst, and a replay reproduces them.
#[test]
fn a_simulated_session_reports_1000_motor_updates_a_second_and_a_worst_gap_of_1_ms() {
    let dir = tempfile::tempdir().unwrap();
    let mcap = dir.path().join("rate.mcap");
    let out = run_ok(&sim_session_args("3", &mcap, &["--seed", "5"]));
    let report = String::from_utf8_lossy(&out.stdout);
    let rate_hz = report_number(&report, "motor updates");
    assert!((rate_hz - 1000.0).abs() < 1.0, "{report}");
    assert!(
        report.contains("its rate policy allows 1000); worst gap 1.0 ms"),
        "{report}"
    );
    let rec = record::Recording::open(&mcap).unwrap();
    let measures = &rec.metrics.last().unwrap().data.measures;
    assert!(
        (measures["motor_update_rate_hz"] - 1000.0).abs() < 1.0,
        "{measures:?}"
    );
    assert!((measures["motor_update_worst_gap_ms"] - 1.0).abs() < 1e-9);
    // Every tick wrote one update: the count grows by one a tick.
    let wheel = &rec.wheel;
    let (first, last) = (&wheel[0].data, &wheel.last().unwrap().data);
    assert_eq!(
        last.motor_updates - first.motor_updates,
        wheel.len() as u64 - 1
    );
    assert_eq!(
        last.motor_update_worst_gap_ms,
        Some(measures["motor_update_worst_gap_ms"])
    );
    let replay = run_ok(&["replay", mcap.to_str().unwrap()]);
    let said = String::from_utf8_lossy(&replay.stdout);
    assert!(said.contains("replay: identical"), "{said}");
}
