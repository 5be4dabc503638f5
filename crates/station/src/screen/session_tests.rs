//! A simulated session watched as its window is fed: the arm the patient's screen draws,
//! with the configured lengths until the session has measured the patient's own, then those.

use super::CourseView;
use render::ScreenState;
use session::config::StationConfig;
use session::{Controls, LiveSummary, SessionObserver, SessionOptions};

/// Each live summary's arm lengths and calibration flag: (t_s, upper arm, forearm, calibrated);
/// and what the patient's screen draws of the arm at that tick (as its window is fed: the
/// measured lengths from the summaries): (t_s, upper arm, forearm, measured).
#[derive(Default)]
struct KeepArmLengths {
    summaries: Vec<(f64, f64, f64, f64)>,
    screen: Vec<(f64, f64, f64, bool)>,
    view: Option<CourseView>,
}

impl SessionObserver for KeepArmLengths {
    fn on_summary(&mut self, s: &LiveSummary) {
        let x = |k: &str| s.extra.get(k).copied().unwrap_or(f64::NAN);
        let t_s = s.record.t_ns as f64 * 1e-9;
        self.summaries
            .push((t_s, x("upper_arm_m"), x("forearm_m"), x("arm_calibrated")));
        let measured = s.measured_arm_lengths_m();
        if let Some(arm) = self.view.as_ref().and_then(|v| {
            v.scene_with_arm(&s.record, ScreenState::Running, measured)
                .arm
        }) {
            self.screen
                .push((t_s, arm.upper_arm_m, arm.forearm_m, arm.measured));
        }
    }
}

#[test]
fn a_default_simulated_session_moves_the_grip_enough_and_the_live_pose_and_screen_switch_to_the_arm_calibrated_online()
 {
    let mut cfg = StationConfig::default();
    cfg.session.seed = 7;
    let configured = (cfg.arm.geometry.upper_arm_m, cfg.arm.geometry.forearm_m);
    let truth = (
        cfg.sim_arm.geometry.upper_arm_m,
        cfg.sim_arm.geometry.forearm_m,
    );
    let mut keep = KeepArmLengths {
        view: Some(CourseView::new(&cfg, None).unwrap()),
        ..KeepArmLengths::default()
    };
    let report = session::run(
        &SessionOptions::simulated(cfg),
        &Controls::default(),
        &mut keep,
    )
    .unwrap();
    let online = report
        .recorder
        .online_arm_calibration
        .clone()
        .expect("the online estimate converges in the default session");
    let batch = report
        .recorder
        .arm_calibration
        .clone()
        .expect("arm sensing ran");
    println!(
        "during the session, at {:.0} s: upper arm {:.4} m, forearm {:.4} m, RMS residual {:.4} m; \
         recursive then: {:.4} m, {:.4} m, RMS residual {:.4} m; truth {:.4} m, {:.4} m",
        online.converged_at_s,
        online.upper_arm_m,
        online.forearm_m,
        online.rms_residual_m,
        online.recursive_upper_arm_m,
        online.recursive_forearm_m,
        online.recursive_rms_residual_m,
        truth.0,
        truth.1
    );
    if let Ok(b) = &batch {
        println!(
            "end of session (batch): upper arm {:.4} m, forearm {:.4} m, RMS residual {:.4} m",
            b.upper_arm_m, b.forearm_m, b.rms_residual_m
        );
    }
    // The grip moves enough for the calibration (no "the grip moved only … mm" warning).
    let warnings = batch
        .as_ref()
        .expect("the batch fit succeeds")
        .warnings
        .clone();
    assert!(
        !warnings.iter().any(|w| w.contains("grip moved only")),
        "{warnings:?}"
    );
    let err_pct = |est: f64, truth: f64| 100.0 * (est - truth).abs() / truth;
    assert!(
        err_pct(online.upper_arm_m, truth.0) < 5.0 && err_pct(online.forearm_m, truth.1) < 5.0,
        "{online:?} against {truth:?}"
    );
    let (before, after): (Vec<&(f64, f64, f64, f64)>, Vec<_>) = keep
        .summaries
        .iter()
        .partition(|s| s.0 < online.converged_at_s);
    assert!(!before.is_empty() && !after.is_empty());
    // Before: the configured lengths, not calibrated; from its summary on: the online ones.
    assert!(
        before
            .iter()
            .all(|s| (s.1, s.2) == configured && s.3 != 1.0),
        "{before:?}"
    );
    assert!(
        after
            .iter()
            .all(|s| (s.1, s.2) == (online.upper_arm_m, online.forearm_m) && s.3 == 1.0),
        "{after:?}"
    );
    // The patient's screen draws the arm with the same lengths, and says it is measured.
    let (before, after): (Vec<&(f64, f64, f64, bool)>, Vec<_>) = keep
        .screen
        .iter()
        .partition(|s| s.0 < online.converged_at_s);
    assert!(!before.is_empty() && !after.is_empty());
    assert!(
        before.iter().all(|s| (s.1, s.2) == configured && !s.3),
        "{before:?}"
    );
    assert!(
        after
            .iter()
            .all(|s| (s.1, s.2) == (online.upper_arm_m, online.forearm_m) && s.3),
        "{after:?}"
    );
    // The recording's calibration carries it.
    if let Ok(b) = batch {
        assert_eq!(b.online.as_ref(), Some(&online));
    }
}
