//! The strength test end to end: a simulated `telerehab run --exercise strength` pushes left
//! then right against the ramped spring and records its peak and sustained torque each way,
//! in N·m within the torque ceiling at the motor.

use record::Recording;
use session::config::StationConfig;
use std::path::Path;
use telerehab_tests::{assert_recording_within_ceiling_and_slew, run_ok, sim_session_args};

#[test]
fn a_simulated_strength_session_records_peak_and_sustained_torque_each_way_within_the_ceiling() {
    let dir = tempfile::tempdir().unwrap();
    let mcap = dir.path().join("strength.mcap");
    let out = run_ok(&sim_session_args(
        "40",
        &mcap,
        &["--seed", "7", "--exercise", "strength"],
    ));
    let report = String::from_utf8_lossy(&out.stdout);
    assert!(
        report.contains("strength left") && report.contains("strength right"),
        "{report}"
    );
    // Strength has no needles: no dial figure in its report.
    assert!(!report.contains("dial tracking"), "{report}");
    let rec = Recording::open(&mcap).unwrap();
    let ceiling_nm = rec
        .wheel
        .iter()
        .map(|w| w.data.ceiling_nm)
        .fold(0.0, f64::max);
    let metrics = &rec.metrics.last().expect("the session's measures").data;
    for side in ["left", "right"] {
        let m = |name: String| {
            *metrics
                .measures
                .get(&name)
                .unwrap_or_else(|| panic!("{name} in {:?}", metrics.measures))
        };
        let peak = m(format!("strength_peak_{side}_nm"));
        let held = m(format!("strength_sustained_{side}_nm"));
        // The simulated patient (4 N·m at most) is stronger than the wheel's ceiling: each
        // side ends at the ceiling, its sustained torque below the peak.
        assert!(
            peak <= ceiling_nm && peak >= 0.9 * ceiling_nm,
            "{side}: {peak}"
        );
        assert!(
            held > 0.3 * peak && held <= peak,
            "{side}: {held} of {peak}"
        );
        assert_eq!(m(format!("strength_{side}_at_ceiling")), 1.0, "{side}");
        // The same figure in the exercise's own results.
        let own = &metrics.exercises[0];
        assert_eq!(own.kind, "strength");
        assert_eq!(own.scores[&format!("strength_peak_{side}_nm")], peak);
    }
    assert!(!metrics.measures.contains_key("dial_rms_error_deg"));
    // Safety as every path: the torque at the motor within the ceiling and the slew limit.
    assert_recording_within_ceiling_and_slew(&rec);
}

/// The largest minimum of `x` over any `n` consecutive samples (the torque held that long).
fn held_over(x: &[f64], n: usize) -> f64 {
    x.windows(n)
        .map(|w| w.iter().copied().fold(f64::INFINITY, f64::min))
        .fold(0.0, f64::max)
}

/// `x` averaged over blocks of `n` samples.
fn block_means(x: &[f64], n: usize) -> Vec<f64> {
    x.chunks(n)
        .map(|c| c.iter().sum::<f64>() / c.len() as f64)
        .collect()
}

/// A simulated 20 s strength session recorded to `mcap` with the station settings `toml`.
fn run_strength_with(dir: &Path, toml: &str, mcap: &Path) -> String {
    let cfg = dir.join("station.toml");
    std::fs::write(&cfg, toml).unwrap();
    let out = run_ok(&sim_session_args(
        "20",
        mcap,
        &[
            "--seed",
            "7",
            "--exercise",
            "strength",
            "--config",
            cfg.to_str().unwrap(),
        ],
    ));
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// A patient weaker than the wheel (1 N·m at most against a ceiling near 1.9 N·m) never
/// brings the spring to the ceiling: each side runs to its time limit, and its peak and
/// sustained torque are the simulated hand's true torque (the spring balances it).
#[test]
fn a_weak_simulated_patient_stops_below_the_ceiling_with_its_true_peak_and_sustained_torque() {
    let dir = tempfile::tempdir().unwrap();
    let mcap = dir.path().join("weak.mcap");
    let strongest_nm = 1.0;
    let report = run_strength_with(
        dir.path(),
        &format!("[sim_patient]\nmax_torque_nm = {strongest_nm}\n"),
        &mcap,
    );
    assert!(report.contains("strength left"), "{report}");
    let rec = Recording::open(&mcap).unwrap();
    let cfg = StationConfig::from_toml(&rec.metadata.config_toml, "the recording").unwrap();
    let ceiling_nm = rec
        .wheel
        .iter()
        .map(|w| w.data.ceiling_nm)
        .fold(0.0, f64::max);
    assert!(strongest_nm < 0.7 * ceiling_nm, "{ceiling_nm}");
    let metrics = &rec.metrics.last().expect("the session's measures").data;
    let m = |name: String| {
        *metrics
            .measures
            .get(&name)
            .unwrap_or_else(|| panic!("{name} in {:?}", metrics.measures))
    };
    let tick_s = 1.0 / cfg.session.loop_rate_hz;
    // The session's 20 s prescribed to the test: its sides' time limit.
    let prescribed = exercises::ExerciseSpec::from_name("strength")
        .unwrap()
        .with_duration_s(20.0);
    let exercises::ExerciseSpec::Strength(spec) = prescribed else {
        unreachable!()
    };
    for (side, sign) in [("left", 1.0), ("right", -1.0)] {
        // The true hand torque the way the side asks, while the test aims that way.
        let truth: Vec<f64> = rec
            .wheel
            .iter()
            .filter(|w| w.data.target_rad * sign > 0.0)
            .map(|w| sign * w.data.hand_nm.expect("simulated hand torque"))
            .collect();
        assert!(truth.len() > 1000, "{side}: {} ticks", truth.len());
        // Averaged over 20 ms: the motor noise of each tick is no torque the wheel feels.
        let per = (0.02 / tick_s).round() as usize;
        let smooth = block_means(&truth, per);
        let true_peak = smooth.iter().copied().fold(0.0, f64::max);
        let true_held = held_over(&smooth, (1.0 / (per as f64 * tick_s)).round() as usize);
        let peak = m(format!("strength_peak_{side}_nm"));
        let held = m(format!("strength_sustained_{side}_nm"));
        eprintln!(
            "{side}: peak {peak:.3} N·m (true {true_peak:.3}), sustained {held:.3} \
             (true {true_held:.3}), {:.2} s",
            m(format!("strength_{side}_s"))
        );
        assert_eq!(m(format!("strength_{side}_at_ceiling")), 0.0, "{side}");
        assert!(peak < 0.7 * ceiling_nm, "{side}: {peak} of {ceiling_nm}");
        assert!(
            (peak - true_peak).abs() <= 0.05 * true_peak,
            "{side}: {peak} vs the hand's {true_peak}"
        );
        assert!(
            (held - true_held).abs() <= 0.05 * true_held,
            "{side}: {held} vs the hand's {true_held}"
        );
        // The hand's strength limit is what the test finds held; its peak also carries the
        // arm's own inertial torque as the spring stops the push (the hand on the rim is the
        // muscles' torque less the arm's inertia's, so it may pass the muscles' limit).
        assert!(
            (0.9 * strongest_nm..=1.05 * strongest_nm).contains(&held),
            "{held}"
        );
        assert!(
            (0.9 * strongest_nm..=1.3 * strongest_nm).contains(&peak),
            "{peak}"
        );
        // Not at the ceiling: the side ran to its time limit (or the patient let go).
        let lasted_s = m(format!("strength_{side}_s"));
        assert!(
            lasted_s > 0.5 * spec.side_s && lasted_s <= spec.side_s + 0.01,
            "{lasted_s}"
        );
    }
}
