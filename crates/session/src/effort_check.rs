//! How well the patient's torque is estimated (`assist::effort`): a short simulated session
//! of one exercise under one assist mode, the estimate on every tick compared with the
//! simulated patient's true hand torque, and the share of the work computed both ways. The
//! station's test holds every exercise and mode to the bound; `cargo run -p session --example
//! hand_torque_estimate` prints the table of BENCHMARKS.md.

use super::course;
use super::plant::Plant;
use crate::config::StationConfig;
use anyhow::Context;
use std::collections::VecDeque;

/// The assist modes a regimen can prescribe, by their `kind` (`assist::AssistMode`), and
/// `none` for no assist at all.
pub const ASSIST_MODES: [&str; 6] = [
    "none",
    "resist",
    "motion",
    "force",
    "hybrid",
    "assist_as_needed",
];

/// Time the observer and the soft start are given before the comparison starts, s.
pub const SETTLE_S: f64 = 0.5;

/// The estimate against the truth over one session.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EffortFigures {
    /// RMS of the simulated patient's true hand torque, N·m.
    pub rms_hand_nm: f64,
    /// RMS of the estimate's error, N·m.
    pub rms_error_nm: f64,
    /// The patient's share of the positive work, from the estimate, %.
    pub patient_work_pct: f64,
    /// The same share from the true hand torque (the check), %.
    pub patient_work_true_pct: f64,
    /// Share of the compared ticks with no estimate (the rim at its end stop), %.
    pub absent_pct: f64,
    /// The wheel's Coulomb friction, N·m: a hand torque it holds moves nothing, and no
    /// estimate from the wheel's motion can see it (the floor of [`EffortFigures::holds`]).
    pub floor_nm: f64,
}

impl EffortFigures {
    /// The RMS error as a share of the RMS hand torque, %.
    pub fn error_pct(&self) -> f64 {
        100.0 * self.rms_error_nm / self.rms_hand_nm
    }

    /// The estimate meets its bound: an RMS error of at most `share_pct` % of the RMS hand
    /// torque, or — for a hand whose torque is of the order of the wheel's friction, which
    /// the wheel's motion cannot show — at most that friction.
    pub fn holds(&self, share_pct: f64) -> bool {
        self.rms_error_nm <= (share_pct / 100.0 * self.rms_hand_nm).max(self.floor_nm)
    }
}

/// Run `exercise` (a name of `exercises::EXERCISE_NAMES`) for `duration_s` under the assist
/// `mode` (one of [`ASSIST_MODES`], its default parameters) with the simulated patient and
/// wheel of the default configuration, seeded with `seed`.
///
/// The estimate of tick `k` is compared with the hand torque of tick `k − 1 − D`, `D` the
/// estimate's stated lag ([`assist::HAND_ESTIMATE_LAG_S`]): the angle read at tick `k` is the
/// wheel's after the step the hand of tick `k − 1` pushed it through, and the estimate is of
/// the hand `D` before. The work is the estimate times the wheel's velocity of its own time.
pub fn run(
    exercise: &str,
    mode: &str,
    duration_s: f64,
    seed: u64,
) -> anyhow::Result<EffortFigures> {
    let mut cfg = StationConfig::default();
    cfg.session.exercise = exercise.into();
    cfg.session.duration_s = duration_s;
    cfg.session.seed = seed;
    if mode != "none" {
        let spec = format!("[mode]\nkind = \"{mode}\"\n");
        cfg.assist = Some(toml::from_str(&spec).with_context(|| format!("assist mode {mode}"))?);
    }
    cfg.validate()?;
    let mut plant = Plant::simulated(&cfg, course::build(&cfg, None)?)?;
    let ticks = (duration_s / plant.dt_s()).round() as u64;
    let settle = (SETTLE_S / plant.dt_s()).round() as u64;
    let (mut sq_hand, mut sq_err, mut n, mut absent) = (0.0, 0.0, 0u64, 0u64);
    let (mut work_est, mut work_true, mut work_assist) = (0.0, 0.0, 0.0);
    let lag = (assist::HAND_ESTIMATE_LAG_S / plant.dt_s()).round() as usize;
    // The last `lag + 1` ticks' true hand (of the tick before) and velocity, oldest first.
    let mut past: VecDeque<(f64, f64)> = VecDeque::new();
    let mut last_hand = 0.0;
    for k in 0..ticks {
        let r = plant.tick();
        let w = &r.wheel;
        past.push_back((last_hand, w.velocity_rad_s));
        if past.len() > lag + 1 {
            past.pop_front();
        }
        last_hand = w.hand_nm.context("the simulation records the true hand")?;
        if k < settle {
            continue;
        }
        if r.assist.active {
            work_assist += (r.assist.torque_nm * w.velocity_rad_s).max(0.0);
        }
        let Some(est) = w.hand_est_nm else {
            absent += 1;
            continue;
        };
        let (hand, v) = past[0];
        sq_hand += hand * hand;
        sq_err += (est - hand) * (est - hand);
        n += 1;
        work_est += (est * v).max(0.0);
        work_true += (hand * v).max(0.0);
    }
    let absent_pct = 100.0 * absent as f64 / (n + absent).max(1) as f64;
    let n = n.max(1) as f64;
    let share = |p: f64| 100.0 * p / (p + work_assist).max(f64::MIN_POSITIVE);
    Ok(EffortFigures {
        rms_hand_nm: (sq_hand / n).sqrt(),
        rms_error_nm: (sq_err / n).sqrt(),
        patient_work_pct: share(work_est),
        patient_work_true_pct: share(work_true),
        absent_pct,
        floor_nm: cfg.sim_wheel.coulomb_nm,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every exercise under `mode`, 4 s each: the estimate within 20 % RMS of the hand's
    /// torque (or the wheel's friction, see [`EffortFigures::holds`]) and the patient's share
    /// of the work within 5 points of the truth.
    fn holds_the_bound_under(mode: &str) {
        for exercise in exercises::EXERCISE_NAMES {
            let f = run(exercise, mode, 4.0, 7).unwrap();
            assert!(
                f.holds(20.0),
                "{exercise} / {mode}: RMS error {:.4} N·m is {:.1} % of the RMS hand torque {:.3}",
                f.rms_error_nm,
                f.error_pct(),
                f.rms_hand_nm
            );
            assert!(
                (f.patient_work_pct - f.patient_work_true_pct).abs() < 5.0,
                "{exercise} / {mode}: patient's share {:.1} % estimated, {:.1} % true",
                f.patient_work_pct,
                f.patient_work_true_pct
            );
            assert!(f.absent_pct < 20.0, "{exercise} / {mode}: {f:?}");
        }
    }

    #[test]
    fn the_estimated_hand_torque_is_within_20_percent_rms_on_every_exercise_without_assist() {
        holds_the_bound_under("none");
    }

    #[test]
    fn the_estimated_hand_torque_is_within_20_percent_rms_on_every_exercise_under_resistance() {
        holds_the_bound_under("resist");
    }

    #[test]
    fn the_estimated_hand_torque_is_within_20_percent_rms_on_every_exercise_under_motion_assist() {
        holds_the_bound_under("motion");
    }

    #[test]
    fn the_estimated_hand_torque_is_within_20_percent_rms_on_every_exercise_under_force_assist() {
        holds_the_bound_under("force");
    }

    #[test]
    fn the_estimated_hand_torque_is_within_20_percent_rms_on_every_exercise_under_hybrid_assist() {
        holds_the_bound_under("hybrid");
    }

    #[test]
    fn the_estimated_hand_torque_is_within_20_percent_rms_on_every_exercise_under_assist_as_needed()
    {
        holds_the_bound_under("assist_as_needed");
    }

    #[test]
    fn the_bound_is_the_friction_only_for_a_hand_no_stronger_than_it() {
        let f = EffortFigures {
            rms_hand_nm: 1.0,
            rms_error_nm: 0.21,
            floor_nm: 0.03,
            ..EffortFigures::default()
        };
        assert!(!f.holds(20.0));
        let weak = EffortFigures {
            rms_hand_nm: 0.02,
            rms_error_nm: 0.02,
            ..f
        };
        assert!(weak.holds(20.0));
    }
}
