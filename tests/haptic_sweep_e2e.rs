//! Thesis Appendix E's parameter studies end to end: a simulated `telerehab run` of a
//! regimen sweeping the spring K and the sine's frequency records each level's tracking
//! error, the session's sweep figures and the report's chart of error against level; the
//! simulated patient gives the shape stated below, within the torque ceiling and slew limit
//! at the motor as every exercise does.
//!
//! The bands are from a measured run (seed 7, 5 s a level; seeds 8 and 9 give the same
//! figures to 0.01°): mean absolute error 6.1, 8.3, 11.1° at K = 0, 0.5, 1 N·m/rad and 2.8,
//! 10.4, 17.3° at 0.5, 1.5, 2.5 rad/s (BENCHMARKS.md, "Haptic parameter studies").

use record::Recording;
use telerehab_tests::{assert_recording_within_ceiling_and_slew, run_ok, sim_session_args};

/// A short sweep of each kind: three levels of 5 s.
const SWEEPS: &str = "[[exercise]]\nkind = \"haptic-sweep\"\nparameter = \"spring\"\n\
                      levels = [0.0, 0.5, 1.0]\nlevel_s = 5.0\n\n\
                      [[exercise]]\nkind = \"haptic-sweep\"\nparameter = \"frequency\"\n\
                      levels = [0.5, 1.5, 2.5]\nlevel_s = 5.0\n";

#[test]
fn a_simulated_sweep_records_error_against_level_rising_with_frequency_and_banded_with_the_spring()
{
    let dir = tempfile::tempdir().unwrap();
    let regimen = dir.path().join("sweep.toml");
    std::fs::write(&regimen, SWEEPS).unwrap();
    let mcap = dir.path().join("sweep.mcap");
    let regimen_arg = regimen.to_str().unwrap();
    run_ok(&sim_session_args(
        "600",
        &mcap,
        &["--seed", "7", "--regimen", regimen_arg],
    ));
    let rec = Recording::open(&mcap).unwrap();
    let metrics = &rec.metrics.last().expect("the session's measures").data;
    let levels = |key: &str| -> Vec<(f64, f64)> {
        metrics
            .exercises
            .iter()
            .filter_map(|e| Some((*e.scores.get(key)?, e.scores["dial_mean_abs_error_deg"])))
            .collect()
    };
    let spring = levels("sweep_spring_nm_per_rad");
    let frequency = levels("sweep_frequency_rad_s");
    assert_eq!(
        spring.iter().map(|p| p.0).collect::<Vec<_>>(),
        [0.0, 0.5, 1.0]
    );
    assert_eq!(
        frequency.iter().map(|p| p.0).collect::<Vec<_>>(),
        [0.5, 1.5, 2.5]
    );
    assert!(metrics.exercises.iter().all(|e| e.kind == "haptic-sweep"));
    // The frequency test: the error rises at every step, several times over the range
    // (measured ×6.1).
    assert!(
        frequency.windows(2).all(|w| w[1].1 > w[0].1 + 2.0),
        "{frequency:?}"
    );
    assert!(frequency[2].1 > 4.0 * frequency[0].1, "{frequency:?}");
    // The spring: within a band at every level (measured 6.1 to 11.1°). Unlike the thesis's
    // subject, whose error stayed about 3° whatever K, the simulated arm (a PID with a
    // reaction delay, no feed-forward of the load) is pulled off its aim by the spring.
    for (k, e) in &spring {
        assert!((4.0..=14.0).contains(e), "K {k}: {e}°");
    }
    // The session's figures for the hub: levels and the slope of error against level.
    let m = |k: &str| {
        *metrics
            .measures
            .get(k)
            .unwrap_or_else(|| panic!("{k} in {:?}", metrics.measures.keys()))
    };
    assert_eq!(m("sweep_spring_levels"), 3.0);
    assert_eq!(m("sweep_frequency_levels"), 3.0);
    let slope_f = m("sweep_frequency_error_slope_deg_per_rad_s");
    assert!((5.0..=10.0).contains(&slope_f), "{slope_f}");
    let slope_k = m("sweep_spring_error_slope_deg_per_nm_per_rad");
    assert!((0.0..=8.0).contains(&slope_k), "{slope_k}");
    // The report draws it as Appendix E does, with its numbers.
    let html = dir.path().join("report.html");
    run_ok(&[
        "report",
        "--out",
        html.to_str().unwrap(),
        mcap.to_str().unwrap(),
    ]);
    let html = std::fs::read_to_string(&html).unwrap();
    for text in [
        "Fig. E-I)",
        "Fig. E-IV)",
        "spring K (N·m/rad)",
        "of error per rad/s",
    ] {
        assert!(html.contains(text), "{text}");
    }
    // Safety as every path: every level's model through the chain, within the ceiling and
    // the slew limit at the motor.
    assert_recording_within_ceiling_and_slew(&rec);
}
