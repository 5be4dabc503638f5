//! The strength test end to end: a simulated `telerehab run --exercise strength` pushes left
//! then right against the ramped spring and records its peak and sustained torque each way,
//! in N·m within the torque ceiling at the motor.

use record::Recording;
use station::config::StationConfig;
use telerehab_tests::{assert_within_ceiling_and_slew, run_ok, sim_session_args};

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
    let cfg = StationConfig::from_toml(&rec.metadata.config_toml, "the recording").unwrap();
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
    let commanded: Vec<f64> = rec.wheel.iter().map(|w| w.data.commanded_nm).collect();
    let ceilings: Vec<f64> = rec.wheel.iter().map(|w| w.data.ceiling_nm).collect();
    assert_within_ceiling_and_slew(
        &commanded,
        &ceilings,
        cfg.haptic.safety.slew_nm_per_s,
        1.0 / cfg.session.loop_rate_hz,
        None,
    );
}
