//! End-to-end: faults injected into simulated sessions (`--fault KIND@SECONDS`), each checked
//! in N·m at the motor from the recording: the commanded torque never leaves the ceiling nor
//! the slew limit, reaches zero within the stated bound when it must, and the session ends or
//! goes on as designed with the reason in its report.

use station::config::StationConfig;
use station::record::Recording;
use telerehab_tests::{assert_within_ceiling_and_slew, run_ok, sim_session_args};

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
    let dir = tempfile::tempdir().unwrap();
    let mcap = dir.path().join("faulted.mcap");
    let out = run_ok(&sim_session_args(seconds, &mcap, &["--fault", fault]));
    let rec = Recording::open(&mcap).unwrap();
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
fn an_unplugged_wheel_ends_the_session_at_zero_torque_with_the_reason() {
    let f = faulted_session("6", "wheel-unplug@3");
    f.assert_within_ceiling_and_slew();
    // The session ends where the wheel went: the recording stops a fade-out after 3 s.
    let last = *f.t_s.last().unwrap();
    assert!((3.0..3.5).contains(&last), "last tick at {last} s");
    assert_eq!(*f.commanded_nm.last().unwrap(), 0.0);
    assert!(f.report.contains("stopped early"), "{}", f.report);
    assert!(
        f.report.to_lowercase().contains("unplugged"),
        "{}",
        f.report
    );
}

#[test]
fn a_wheel_sending_nan_has_its_torque_faded_out_and_the_session_goes_on() {
    let f = faulted_session("6", "wheel-nan@3+0.3");
    f.assert_within_ceiling_and_slew();
    let at = f.tick_at(3.0);
    // A NaN angle is no reading: the supervisor calls it stale and fades the torque out.
    assert!(
        f.watchdog[at..at + 50]
            .iter()
            .any(|w| w == "fault-stale-reading")
    );
    f.assert_zero_within(3.0, 0.25 + 0.002);
    // Then the exercise goes on to its end, the torque back after a soft start.
    assert!(*f.t_s.last().unwrap() >= 6.0);
    let after = f.tick_at(5.0);
    assert!(f.commanded_nm[after..].iter().any(|c| c.abs() > 0.01));
    assert!(!f.report.contains("stopped early"), "{}", f.report);
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
fn an_unplugged_arm_sensor_freezes_the_pose_and_the_exercise_goes_on() {
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
    assert!(
        *rec.wheel.last().map(|w| &w.t_s).unwrap() >= 6.0,
        "the exercise went on"
    );
    assert!(!report.contains("stopped early"), "{report}");
    assert!(report.contains("unplugged (injected fault)"), "{report}");
    let measures = &rec.metrics.last().unwrap().data.measures;
    assert_eq!(measures["arm_sensors_lost"], 1.0);
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
