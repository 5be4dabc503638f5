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
