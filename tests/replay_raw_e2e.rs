//! `telerehab replay --from-raw`: a simulated session re-run from its recorded raw inputs
//! (`/raw/wheel`, `/raw/imu`) instead of its seed — the simulated body replaced by what it
//! delivered, as a real-device session is always replayed — reproduces every recorded output
//! bit for bit. That proves the raw inputs are enough, on the paths a real session takes:
//! the guided arm procedure solved on its own thread, sensor faults, the patient's stop.

use telerehab_tests::{
    by_topic, interrupted_recording_session, read_mcap, run_err, run_ok, sim_session_args,
};

/// `telerehab replay ARGS` run to success: what it said.
fn replay_ok(args: &[&str]) -> String {
    let out = run_ok(&[&["replay"], args].concat());
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// A session with the guided arm procedure and faults on the wheel and the IMUs replays bit
/// for bit from its raw inputs, and the raw channels read back with their units.
#[test]
fn a_session_with_sensor_faults_replays_bit_for_bit_from_its_raw_inputs() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("station.toml");
    std::fs::write(&config, "[arm]\nsim_mounting = \"guided\"\n").unwrap();
    let path = dir.path().join("faults.mcap");
    let config = config.to_str().unwrap();
    run_ok(&sim_session_args(
        "30",
        &path,
        &[
            "--config",
            config,
            "--seed",
            "3",
            // After the guided procedure (solved at about 18 s).
            "--fault",
            "wheel-unplug@20",
            "--fault",
            "wheel-replug@20.5",
            "--fault",
            "imu-unplug@21",
            "--fault",
            "imu-replug@21.5",
            "--fault",
            "wheel-nan@22+0.05",
            "--fault",
            "wheel-stall@23+0.2",
            "--fault",
            "imu-nan@24+0.1",
            "--fault",
            "imu-unplug@27",
        ],
    ));
    let topics = by_topic(&read_mcap(&path));
    let raw = &topics["/raw/wheel"];
    assert_eq!(
        raw.len(),
        topics["/wheel"].len(),
        "raw inputs on every tick"
    );
    assert!(raw.iter().any(|m| m.json["solver_answered"] == true));
    assert!(raw.iter().any(|m| m.json["arm_lost"] == true));
    assert!(raw.iter().any(|m| m.json["arm_regained"] == true));
    assert!(
        raw.iter().any(|m| m.json["read"] == "unplugged"),
        "the wheel was away"
    );
    assert!(
        raw.iter().any(|m| m.json["angle_rad"].is_null()),
        "the NaN the wheel sent is recorded as sent"
    );
    let imu = &topics["/raw/imu"];
    assert!(
        imu.len() > raw.len(),
        "two sensors, a sample each most ticks"
    );
    assert!(
        imu.iter().any(|m| m.json["gyro_x_rad_s"].is_null()),
        "imu-nan"
    );

    let said = replay_ok(&["--from-raw", path.to_str().unwrap()]);
    assert!(
        said.contains("replay: identical") && said.contains("from the recorded raw inputs"),
        "{said}"
    );
    // The seed reproduces it too.
    let said = replay_ok(&[path.to_str().unwrap()]);
    assert!(said.contains("replay: identical"), "{said}");
}

/// The patient's stop is a recorded input: a session stopped by a signal, which the seed
/// alone cannot reproduce, replays bit for bit from its raw inputs.
#[test]
fn a_session_stopped_by_the_patient_replays_bit_for_bit_from_its_raw_inputs() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("int.mcap");
    let out = interrupted_recording_session(&path);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let raw = by_topic(&read_mcap(&path)).remove("/raw/wheel").unwrap();
    let stop = raw
        .iter()
        .position(|m| m.json["stop"] == true)
        .expect("the stop was recorded");
    assert!(stop > 1000 && stop < 59_000, "{stop}");

    let err = run_err(&["replay", path.to_str().unwrap()]);
    assert!(err.contains("replay differs"), "{err}");
    let said = replay_ok(&["--from-raw", path.to_str().unwrap()]);
    assert!(said.contains("replay: identical"), "{said}");
}

/// A wheel that refused the station's force commands: each refusal is a recorded input, so a
/// short one and the run that ended the session replay bit for bit, from the raw inputs and
/// from the seed alike, stopping where the session stopped.
#[test]
fn a_session_ended_by_refused_commands_replays_bit_for_bit_stopping_where_it_did() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("refused.mcap");
    run_ok(&sim_session_args(
        "10",
        &path,
        &[
            "--fault",
            "wheel-write-fail@3+0.01",
            "--fault",
            "wheel-write-fail@5",
        ],
    ));
    let topics = by_topic(&read_mcap(&path));
    let refused = topics["/raw/wheel"]
        .iter()
        .filter(|m| m.json["write_failed"] == true)
        .count();
    // The short refusal (10), the 20 ms run that makes the fault (21), and the fade-out's
    // commands, still refused, until the session ended.
    assert!(refused > 31, "{refused}");
    let last = topics["/wheel"].last().unwrap();
    assert_eq!(
        last.json["write_failures"], refused,
        "counted on /wheel as recorded"
    );
    for args in [
        &["--from-raw", path.to_str().unwrap()][..],
        &[path.to_str().unwrap()],
    ] {
        let said = replay_ok(args);
        assert!(said.contains("replay: identical"), "{args:?}: {said}");
    }
}

/// The raw inputs are re-run, never played in the window: the two flags do not go together.
#[test]
fn replay_from_raw_refuses_the_window_flag() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.mcap");
    run_ok(&sim_session_args("1", &path, &[]));
    let err = run_err(&["replay", "--from-raw", "--window", path.to_str().unwrap()]);
    assert!(
        err.contains("--window") && err.contains("--from-raw"),
        "{err}"
    );
}

/// A regimen that gives the pedals to the patient: the simulated foot starts the car from
/// rest and drives it at the exercise's speed at most; the pedals are a recorded input, so
/// the session replays bit for bit from its raw inputs; an exercise with automatic speed
/// after it leaves them released.
#[test]
fn pedals_drive_the_car_from_rest_within_the_exercise_speed_and_replay_from_the_raw_inputs() {
    let dir = tempfile::tempdir().unwrap();
    let regimen = dir.path().join("pedals.toml");
    std::fs::write(
        &regimen,
        "[[exercise]]\nkind = \"sine\"\nspeed_m_s = 12.0\nduration_s = 8.0\npedals = true\n\n\
         [[exercise]]\nkind = \"straight\"\nspeed_m_s = 12.0\nduration_s = 2.0\n",
    )
    .unwrap();
    let path = dir.path().join("pedals.mcap");
    run_ok(&sim_session_args(
        "60",
        &path,
        &["--regimen", regimen.to_str().unwrap()],
    ));
    let topics = by_topic(&read_mcap(&path));
    let (raw, vehicle) = (&topics["/raw/wheel"], &topics["/vehicle"]);
    let f = |j: &serde_json::Value, k: &str| j[k].as_f64().unwrap_or(0.0);
    let speeds: Vec<f64> = vehicle.iter().map(|m| f(&m.json, "ux_m_s")).collect();
    assert!(speeds[0] < 0.1, "the car starts at rest: {} m/s", speeds[0]);
    let top = speeds.iter().copied().fold(0.0, f64::max);
    assert!(top > 9.0 && top <= 12.0 + 1e-6, "top speed {top} m/s");
    let throttle: Vec<f64> = raw.iter().map(|m| f(&m.json, "throttle")).collect();
    assert!(
        throttle[..1000].iter().any(|&t| t > 0.9),
        "full throttle from rest"
    );
    // The automatic exercise at the end: the foot rests, the speed is the exercise's.
    assert!(throttle[throttle.len() - 500..].iter().all(|&t| t == 0.0));
    assert!(
        (speeds[speeds.len() - 1] - 12.0).abs() < 0.5,
        "{}",
        speeds[speeds.len() - 1]
    );

    let said = replay_ok(&["--from-raw", path.to_str().unwrap()]);
    assert!(said.contains("replay: identical"), "{said}");
}
