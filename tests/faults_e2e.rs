//! End-to-end: faults injected into simulated sessions (`--fault KIND@SECONDS`), each checked
//! in N·m at the motor from the recording: the commanded torque never leaves the ceiling nor
//! the slew limit, reaches zero within the stated bound when it must, and the session ends or
//! goes on as designed with the reason in its report.

use record::Recording;
use session::config::StationConfig;
use std::path::Path;
use telerehab_tests::{
    TherapistHub, assert_within_ceiling_and_slew, run_ok, sim_session_args, stored_seqs,
};

/// What a faulted session recorded: every tick's commanded torque, ceiling and watchdog state,
/// the slew limit and loop period it ran with, and its printed report.
struct Faulted {
    report: String,
    t_s: Vec<f64>,
    commanded_nm: Vec<f64>,
    ceiling_nm: Vec<f64>,
    watchdog: Vec<String>,
    slew_nm_per_s: f64,
    dt_s: f64,
}

fn faulted_session(seconds: &str, fault: &str) -> Faulted {
    faulted_session_with(seconds, &[fault])
}

/// A recorded max-speed session of `seconds` with every fault of `faults` injected.
fn faulted_session_with(seconds: &str, faults: &[&str]) -> Faulted {
    let dir = tempfile::tempdir().unwrap();
    let mcap = dir.path().join("faulted.mcap");
    let extra: Vec<&str> = faults.iter().flat_map(|f| ["--fault", f]).collect();
    let out = run_ok(&sim_session_args(seconds, &mcap, &extra));
    faulted_recording(&mcap, &out)
}

/// What the recording `mcap` of a session whose run printed `out` holds.
fn faulted_recording(mcap: &Path, out: &std::process::Output) -> Faulted {
    let rec = Recording::open(mcap).unwrap();
    let cfg = StationConfig::from_toml(&rec.metadata.config_toml, "the recording").unwrap();
    Faulted {
        report: String::from_utf8_lossy(&out.stdout).into_owned(),
        t_s: rec.wheel.iter().map(|w| w.t_s).collect(),
        commanded_nm: rec.wheel.iter().map(|w| w.data.commanded_nm).collect(),
        ceiling_nm: rec.wheel.iter().map(|w| w.data.ceiling_nm).collect(),
        watchdog: rec
            .wheel
            .iter()
            .map(|w| w.data.watchdog.to_string())
            .collect(),
        slew_nm_per_s: cfg.haptic.safety.slew_nm_per_s,
        dt_s: 1.0 / cfg.session.loop_rate_hz,
    }
}

impl Faulted {
    /// Every tick: |torque| ≤ ceiling, and no step larger than the slew limit allows.
    fn assert_within_ceiling_and_slew(&self) {
        self.assert_within_ceiling_and_slew_with_gap(None);
    }

    /// The same, the tick `gap.0` coming `gap.1` s later than the loop period (a stalled
    /// loop: the slew limit holds over the real time between two commands).
    fn assert_within_ceiling_and_slew_with_gap(&self, gap: Option<(usize, f64)>) {
        assert_within_ceiling_and_slew(
            &self.commanded_nm,
            &self.ceiling_nm,
            self.slew_nm_per_s,
            self.dt_s,
            gap,
        );
    }

    /// The index of the first tick at or after `t_s`.
    fn tick_at(&self, t_s: f64) -> usize {
        self.t_s.iter().position(|&t| t >= t_s - 1e-9).unwrap()
    }

    /// A reading fault from `t_s` that makes no reading (NaN, saturated): the supervisor
    /// calls it stale within 50 ticks, the torque fades to zero within the fade-out, and
    /// after it the exercise goes on to its end with torque again (a soft start).
    fn assert_faded_as_stale_and_resumed(&self, t_s: f64) {
        let at = self.tick_at(t_s);
        assert!(
            self.watchdog[at..at + 50]
                .iter()
                .any(|w| w == "fault-stale-reading")
        );
        self.assert_zero_within(t_s, 0.25 + 0.002);
        assert!(*self.t_s.last().unwrap() >= 6.0);
        let after = self.tick_at(t_s + 2.0);
        assert!(self.commanded_nm[after..].iter().any(|c| c.abs() > 0.01));
        assert!(!self.report.contains("stopped early"), "{}", self.report);
    }

    /// The torque is zero at some tick within `bound_s` after `t_s`.
    fn assert_zero_within(&self, t_s: f64, bound_s: f64) {
        let from = self.tick_at(t_s);
        let to = self.tick_at((t_s + bound_s).min(*self.t_s.last().unwrap()));
        assert!(
            self.commanded_nm[from..=to].contains(&0.0),
            "no zero torque within {bound_s} s of {t_s} s: {:?}",
            &self.commanded_nm[from..=to.min(from + 20)]
        );
    }
}

#[test]
fn an_unplugged_wheel_not_back_within_the_grace_ends_the_session_at_zero_torque_with_the_reason() {
    let f = faulted_session("6", "wheel-unplug@3");
    f.assert_within_ceiling_and_slew();
    // Zero torque within the fade-out, and for the whole grace (30 s by default) it waited,
    // paused, for the wheel to come back.
    f.assert_zero_within(3.0, 0.25 + 0.002);
    let gone = f.tick_at(3.25);
    assert!(f.commanded_nm[gone..].iter().all(|&c| c == 0.0));
    // The session ends when the grace is over: the recording stops a fade-out after 33 s.
    let last = *f.t_s.last().unwrap();
    assert!((33.0..33.5).contains(&last), "last tick at {last} s");
    assert_eq!(*f.commanded_nm.last().unwrap(), 0.0);
    assert!(f.report.contains("stopped early"), "{}", f.report);
    assert!(
        f.report.to_lowercase().contains("unplugged"),
        "{}",
        f.report
    );
}

#[test]
fn a_wheel_refusing_the_force_commands_ends_the_session_on_a_safety_stop_that_names_it() {
    let f = faulted_session("6", "wheel-write-fail@3");
    f.assert_within_ceiling_and_slew();
    // 20 ms of refusals make the fault; the session ends within a fade-out after it (the
    // wheel then closed, which stops its effects).
    let last = *f.t_s.last().unwrap();
    assert!(
        (3.02..3.02 + 0.25 + 0.002).contains(&last),
        "last tick at {last} s"
    );
    assert!(
        f.report
            .contains("safety stop: the wheel stopped taking the station's force commands"),
        "{}",
        f.report
    );
    assert!(f.report.contains("refused by the wheel"), "{}", f.report);
}

#[test]
fn a_wheel_sending_nan_has_its_torque_faded_out_and_the_session_goes_on() {
    let f = faulted_session("6", "wheel-nan@3+0.3");
    f.assert_within_ceiling_and_slew();
    // A NaN angle is no reading: the supervisor calls it stale and fades the torque out; then
    // the exercise goes on to its end, the torque back after a soft start.
    f.assert_faded_as_stale_and_resumed(3.0);
}

#[test]
fn a_stalled_wheel_fades_the_torque_out_and_recovers() {
    for stall in ["0.05", "0.5"] {
        let f = faulted_session("6", &format!("wheel-stall@3+{stall}"));
        f.assert_within_ceiling_and_slew();
        let at = f.tick_at(3.0);
        // Readings older than the supervisor's 20 ms limit are stale: both stalls are faults,
        // and the torque fades to zero within the fade-out (0.25 s) after the limit.
        assert!(
            f.watchdog[at..at + 600]
                .iter()
                .any(|w| w == "fault-stale-reading"),
            "a {stall} s stall is a stale reading"
        );
        f.assert_zero_within(3.0, 0.02 + 0.25 + 0.002);
        assert!(*f.t_s.last().unwrap() >= 6.0, "the session went on");
        assert_eq!(f.watchdog.last().map(String::as_str), Some("stopped"));
    }
}

#[test]
fn a_haptic_loop_stalled_past_the_watchdog_fades_the_torque_out_and_recovers() {
    let f = faulted_session("6", "haptic-stall@3+0.1");
    let at = f.tick_at(3.0);
    // The tick after the stall comes 0.1 s late: the supervisor sees the missed deadline.
    assert_eq!(
        f.watchdog[at],
        "fault-missed-deadline",
        "{:?}",
        &f.watchdog[at - 2..at + 2]
    );
    f.assert_within_ceiling_and_slew_with_gap(Some((at, 0.1)));
    f.assert_zero_within(3.0, 0.25 + 0.002);
    assert!(*f.t_s.last().unwrap() >= 6.0, "the session went on");
    assert!(
        f.commanded_nm[f.tick_at(5.0)..]
            .iter()
            .any(|c| c.abs() > 0.01)
    );
}

#[test]
fn an_arm_sensor_not_plugged_back_freezes_the_pose_the_exercise_waits_and_the_session_ends_unplugged()
 {
    let dir = tempfile::tempdir().unwrap();
    let mcap = dir.path().join("imu.mcap");
    let out = run_ok(&sim_session_args("6", &mcap, &["--fault", "imu-unplug@3"]));
    let report = String::from_utf8_lossy(&out.stdout);
    let rec = Recording::open(&mcap).unwrap();
    let at = |t: f64| rec.arm.iter().position(|a| a.t_s >= t - 1e-9).unwrap();
    assert_eq!(rec.arm[at(2.9)].data.setup.as_str(), "tracking");
    assert!(
        rec.arm[at(3.0)..]
            .iter()
            .all(|a| a.data.setup.as_str() == "sensor-lost")
    );
    // Frozen, not wandering: the same pose from the loss on.
    let frozen = rec.arm[at(3.0)].data.elbow_flexion_rad;
    assert!(
        rec.arm[at(3.0)..]
            .iter()
            .all(|a| a.data.elbow_flexion_rad == frozen)
    );
    // The exercise waited on the sensor's page for the replug grace (30 s), then the session
    // ended: 3 s of exercise, not 6.
    let last_s = *rec.wheel.last().map(|w| &w.t_s).unwrap();
    assert!((32.5..34.5).contains(&last_s), "ended at {last_s} s");
    assert!(report.contains("stopped early"), "{report}");
    assert!(
        report.contains(&format!(
            "ended               {}",
            session::end_reason::ARM_SENSOR_UNPLUGGED
        )),
        "{report}"
    );
    assert!(report.contains("unplugged (injected fault)"), "{report}");
    let measures = &rec.metrics.last().unwrap().data.measures;
    assert_eq!(measures["arm_sensors_lost"], 1.0);
    faulted_recording(&mcap, &out).assert_within_ceiling_and_slew();
}

#[test]
fn nan_from_the_arm_sensors_never_reaches_the_pose_is_recorded_as_sent_and_tracking_resumes() {
    let dir = tempfile::tempdir().unwrap();
    let mcap = dir.path().join("imu-nan.mcap");
    run_ok(&sim_session_args("6", &mcap, &["--fault", "imu-nan@3+0.5"]));
    let rec = Recording::open(&mcap).unwrap();
    for a in &rec.arm {
        let d = &a.data;
        let angles = [
            d.shoulder_elevation_rad,
            d.elbow_flexion_rad,
            d.forearm_pronation_rad,
        ];
        assert!(
            angles.iter().all(|x| x.is_finite()),
            "t = {} s: {angles:?}",
            a.t_s
        );
        assert!(
            d.upper_orientation_wxyz.iter().all(|x| x.is_finite()),
            "t = {} s",
            a.t_s
        );
    }
    let last = &rec.arm.last().unwrap().data;
    assert_eq!(
        last.setup.as_str(),
        "tracking",
        "tracking goes on after the NaNs"
    );
    let f = faulted_session("6", "imu-nan@3+0.5");
    f.assert_within_ceiling_and_slew();
}

#[test]
fn a_fault_on_a_real_wheel_or_of_an_unknown_kind_is_refused_by_name() {
    let err = telerehab_tests::run_err(&["run", "--headless", "--fault", "wheel-nan@1"]);
    assert!(err.contains("add --sim"), "{err}");
    let err = telerehab_tests::run_err(&["run", "--sim", "--headless", "--fault", "wheel-melt@1"]);
    assert!(err.contains("unknown fault kind \"wheel-melt\""), "{err}");
}

#[test]
fn a_full_disk_stops_the_recording_not_the_session_and_recover_keeps_what_reached_the_disk() {
    let dir = tempfile::tempdir().unwrap();
    let mcap = dir.path().join("full.mcap");
    let out = std::process::Command::new(telerehab_tests::telerehab_bin())
        .args(sim_session_args("6", &mcap, &["--fault", "disk-full@3"]))
        .output()
        .unwrap();
    let report = String::from_utf8_lossy(&out.stdout);
    let err = String::from_utf8_lossy(&out.stderr);
    // The session ran to its end; the run says the recording failed, and why, in words.
    assert!(!out.status.success(), "a failed recording fails the run");
    assert!(
        report.contains("FAILED") && report.contains("no storage space"),
        "{report}"
    );
    assert!(report.contains("recording stopped at 3.0 s"), "{report}");
    assert!(
        report.contains("session time") && !report.contains("stopped early"),
        "{report}"
    );
    assert!(
        err.contains("recording stopped"),
        "said at once in the log: {err}"
    );
    // Every tick up to the last chunk closed before the disk filled (one a second) is kept.
    let fixed = dir.path().join("fixed.mcap");
    run_ok(&[
        "recover",
        mcap.to_str().unwrap(),
        "--out",
        fixed.to_str().unwrap(),
    ]);
    let rec = Recording::open(&fixed).unwrap();
    let ticks: Vec<u64> = rec.wheel.iter().map(|w| w.tick).collect();
    assert!(
        ticks.len() >= 2000 && ticks.len() <= 3000,
        "{} ticks kept",
        ticks.len()
    );
    assert!(
        ticks.iter().enumerate().all(|(i, &t)| t == i as u64),
        "no tick missing"
    );
}

#[test]
fn a_wheel_plugged_back_within_the_grace_resumes_the_paused_exercise_with_a_soft_start() {
    let f = faulted_session_with("6", &["wheel-unplug@3", "wheel-replug@5"]);
    f.assert_within_ceiling_and_slew();
    // Away: zero torque within the fade-out, and until it is back.
    f.assert_zero_within(3.0, 0.25 + 0.002);
    let (gone, back) = (f.tick_at(3.25), f.tick_at(5.0));
    assert!(f.commanded_nm[gone..back].iter().all(|&c| c == 0.0));
    // Back: the exercise resumes from paused with a soft start (the slew check above holds
    // across it), and the session runs its 6 s of exercise: 2 s longer for the pause.
    let resumed = (back..f.t_s.len())
        .find(|&i| f.watchdog[i] == "soft-start")
        .expect("a soft start after the replug");
    assert_eq!(f.commanded_nm[resumed - 1], 0.0);
    assert!(
        f.commanded_nm[resumed..].iter().any(|c| c.abs() > 0.01),
        "torque again"
    );
    assert!(*f.t_s.last().unwrap() >= 8.0, "the pause lengthened it");
    assert!(!f.report.contains("stopped early"), "{}", f.report);
    assert!(
        f.report.contains("unplugged and plugged back 1 time"),
        "{}",
        f.report
    );
}

#[test]
fn a_frozen_or_saturated_wheel_encoder_never_takes_the_torque_out_of_its_limits() {
    // A frozen angle cannot be told from a still hand: the torque stays within its limits and
    // the exercise goes on.
    let f = faulted_session("6", "wheel-frozen@3+1");
    f.assert_within_ceiling_and_slew();
    assert!(*f.t_s.last().unwrap() >= 6.0);
    assert!(!f.report.contains("stopped early"), "{}", f.report);
    // A saturated one (the end of its range, reached by a jump no hand makes) is no reading:
    // the torque fades out as for a stale reading, then soft-starts again.
    let f = faulted_session("6", "wheel-saturated@3+0.3");
    f.assert_within_ceiling_and_slew();
    f.assert_faded_as_stale_and_resumed(3.0);
}

/// The estimated shoulder elevation's largest error against the simulated truth between
/// `from_s` and `to_s`, rad (the elbow's is set by the wheel's angle; the shoulder's follows the
/// IMUs' orientations).
fn shoulder_error_rad(rec: &Recording, from_s: f64, to_s: f64) -> f64 {
    rec.arm
        .iter()
        .filter(|a| (from_s..to_s).contains(&a.t_s))
        .map(|a| (a.data.shoulder_elevation_rad - a.data.true_shoulder_elevation_rad).abs())
        .fold(0.0, f64::max)
}

/// Largest error of the shoulder elevation the arm sensing may make, rad (2.5°, seed 7 on the
/// default 6.5 m sine road: 1.25° without faults, 2.13° over a 1 s freeze held rather than
/// integrated, 1.03° over 0.3 s of saturation; on the former 4 m road 0.8° without faults,
/// 3° with a 1 s freeze integrated and 78° with 0.3 s of saturation integrated).
const SHOULDER_ERROR_RAD: f64 = 2.5 * std::f64::consts::PI / 180.0;

#[test]
fn an_arm_sensor_plugged_back_resumes_tracking_and_the_measures_count_the_lost_second() {
    let dir = tempfile::tempdir().unwrap();
    let mcap = dir.path().join("imu-replug.mcap");
    let out = run_ok(&sim_session_args(
        "6",
        &mcap,
        &["--fault", "imu-unplug@3", "--fault", "imu-replug@4"],
    ));
    let report = String::from_utf8_lossy(&out.stdout);
    let rec = Recording::open(&mcap).unwrap();
    let at = |t: f64| rec.arm.iter().position(|a| a.t_s >= t - 1e-9).unwrap();
    let setup = |i: usize| rec.arm[i].data.setup.as_str();
    assert_eq!(setup(at(2.99)), "tracking");
    assert!((at(3.0)..at(4.0)).all(|i| setup(i) == "sensor-lost"));
    assert!((at(4.0)..rec.arm.len()).all(|i| setup(i) == "tracking"));
    // Tracking again, not frozen: the pose moves with the arm, as close to the truth as
    // before the loss (the orientation re-acquired from the arm chain).
    let after = &rec.arm[at(4.1)..];
    assert!(
        after
            .iter()
            .any(|a| a.data.shoulder_elevation_rad != after[0].data.shoulder_elevation_rad)
    );
    let resumed = shoulder_error_rad(&rec, 4.1, 6.0);
    assert!(
        resumed <= SHOULDER_ERROR_RAD,
        "shoulder elevation off by {resumed} rad after the replug"
    );
    let measures = &rec.metrics.last().unwrap().data.measures;
    assert_eq!(measures["arm_sensors_lost"], 0.0, "back at the end");
    assert!(
        (measures["arm_sensor_lost_s"] - 1.0).abs() < 0.01,
        "{}",
        measures["arm_sensor_lost_s"]
    );
    assert!(!report.contains("stopped early"), "{report}");
    assert!(!report.contains("arm sensing         off"), "{report}");
    // The exercise waited for the second the sensor was away: 6 s of exercise, ending at 7 s.
    let last_s = *rec.wheel.last().map(|w| &w.t_s).unwrap();
    assert!((6.9..7.5).contains(&last_s), "ended at {last_s} s");
    faulted_recording(&mcap, &out).assert_within_ceiling_and_slew();
}

#[test]
fn frozen_or_saturated_arm_sensors_never_move_the_pose_away_from_the_arm() {
    for fault in ["imu-frozen@3+1", "imu-saturated@3+0.3"] {
        let dir = tempfile::tempdir().unwrap();
        let mcap = dir.path().join("imu.mcap");
        let out = run_ok(&sim_session_args("6", &mcap, &["--fault", fault]));
        let rec = Recording::open(&mcap).unwrap();
        assert!(
            rec.arm.iter().all(|a| a.data.setup.as_str() == "tracking"),
            "{fault}: tracking throughout"
        );
        let during = shoulder_error_rad(&rec, 1.0, 6.0);
        assert!(
            during <= SHOULDER_ERROR_RAD,
            "{fault}: shoulder elevation off by {during} rad"
        );
        faulted_recording(&mcap, &out).assert_within_ceiling_and_slew();
    }
}

#[test]
fn the_hub_going_away_and_back_loses_no_summary_duplicates_none_and_leaves_the_torque_alone() {
    let dir = tempfile::tempdir().unwrap();
    let (store, home) = (dir.path().join("store"), dir.path().join("home"));
    let mcap = dir.path().join("hub-down.mcap");
    let hub = TherapistHub::start(&store);
    // In real time, so that the hub is away for 2 s of wall time: the link's connection is
    // cut, its reconnections refused, and the summaries wait in the on-disk queue.
    let out = std::process::Command::new(telerehab_tests::telerehab_bin())
        .args([
            "run",
            "--sim",
            "--headless",
            "--duration",
            "6",
            "--therapist",
            &hub.addr,
            "--home",
            home.to_str().unwrap(),
            "--record",
            mcap.to_str().unwrap(),
            "--fault",
            "hub-down@2",
            "--fault",
            "hub-up@4",
        ])
        .output()
        .unwrap();
    let report = String::from_utf8_lossy(&out.stdout);
    let log = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{report}\n{log}");
    assert!(
        log.contains("hub went away") && log.contains("hub is back"),
        "{log}"
    );
    // Every summary delivered exactly once, in order: 61 (every 100 ms of 6 s, and the last).
    assert!(
        report.contains("61 summaries") && report.contains("0 NOT delivered"),
        "{report}"
    );
    assert_eq!(
        stored_seqs(&store, "station-1"),
        [(0..61).collect::<Vec<u64>>()]
    );
    // The torque is the one a session without the fault commands, tick for tick.
    let f = faulted_recording(&mcap, &out);
    f.assert_within_ceiling_and_slew();
    let calm = dir.path().join("calm.mcap");
    let calm_out = run_ok(&sim_session_args("6", &calm, &[]));
    assert_eq!(
        f.commanded_nm,
        faulted_recording(&calm, &calm_out).commanded_nm
    );
    assert!(!report.contains("stopped early"), "{report}");
}
