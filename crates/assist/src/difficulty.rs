//! Session-to-session difficulty adaptation that keeps the success rate near a target
//! (≈ 70 %, the usual choice for motor training; FIELD-NOTES).
//!
//! Two rules, both with bounded steps and a bounded difficulty in `[0, 1]`:
//!
//! * per trial, the *weighted up-down staircase* of Kaernbach (1991, "Simple adaptive testing
//!   with the weighted up-down method", Perception & Psychophysics 49:227–229): after a
//!   success the difficulty rises by `Δ_up`, after a failure it falls by
//!   `Δ_down = Δ_up · p/(1 − p)`. The expected drift `s·Δ_up − (1 − s)·Δ_down` vanishes at
//!   `s/(1 − s) = p/(1 − p)`, i.e. the staircase settles where the success rate `s = p`.
//! * per session, a proportional–integral step on the session's success rate `s`:
//!   `Δ = clamp(k_p (s − p) + k_i Σ(s − p), ±Δ_max)`; the integral is clamped as well so a
//!   long run of sessions at a bound does not wind up.

use crate::error::{AssistError, check_range};
use serde::{Deserialize, Serialize};

/// Parameters of [`DifficultyAdapter`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct DifficultyParams {
    /// Target success rate `p`, in [0.5, 0.95].
    pub target_success: f64,
    /// Staircase step after a success, `Δ_up`, in (0, 0.2].
    pub trial_step_up: f64,
    /// Proportional gain on the session success-rate error, in [0, 2].
    pub session_kp: f64,
    /// Integral gain on the session success-rate error, in [0, 1].
    pub session_ki: f64,
    /// Largest difficulty change per session, in (0, 0.5].
    pub session_max_step: f64,
}

impl Default for DifficultyParams {
    fn default() -> Self {
        Self {
            target_success: 0.7,
            trial_step_up: 0.02,
            session_kp: 0.5,
            session_ki: 0.1,
            session_max_step: 0.1,
        }
    }
}

impl DifficultyParams {
    /// Check every field's range.
    pub fn validate(&self) -> Result<(), AssistError> {
        check_range(
            "difficulty.target_success",
            self.target_success,
            0.5,
            0.95,
            "[0.5, 0.95]",
        )?;
        check_range(
            "difficulty.trial_step_up",
            self.trial_step_up,
            1e-6,
            0.2,
            "(0, 0.2]",
        )?;
        check_range("difficulty.session_kp", self.session_kp, 0.0, 2.0, "[0, 2]")?;
        check_range("difficulty.session_ki", self.session_ki, 0.0, 1.0, "[0, 1]")?;
        check_range(
            "difficulty.session_max_step",
            self.session_max_step,
            1e-6,
            0.5,
            "(0, 0.5]",
        )
    }
}

/// The adapter's state: a difficulty in `[0, 1]` (the regimen maps it to amplitude, speed,
/// tolerance or assistance).
#[derive(Clone, Debug)]
pub struct DifficultyAdapter {
    params: DifficultyParams,
    difficulty: f64,
    integral: f64,
}

impl DifficultyAdapter {
    /// Start at `difficulty` (clamped to `[0, 1]`).
    pub fn new(params: DifficultyParams, difficulty: f64) -> Result<Self, AssistError> {
        params.validate()?;
        check_range("difficulty.initial", difficulty, 0.0, 1.0, "[0, 1]")?;
        Ok(Self {
            params,
            difficulty,
            integral: 0.0,
        })
    }

    /// Current difficulty in `[0, 1]`.
    pub fn difficulty(&self) -> f64 {
        self.difficulty
    }

    /// Moves to `difficulty` (clamped to `[0, 1]`), keeping the integral: when something
    /// besides the success rate set the last session's difficulty (the patient's own word,
    /// the therapist's bounds).
    pub fn set_difficulty(&mut self, difficulty: f64) {
        if difficulty.is_finite() {
            self.difficulty = difficulty.clamp(0.0, 1.0);
        }
    }

    /// Weighted up-down step after one trial; returns the new difficulty.
    pub fn record_trial(&mut self, success: bool) -> f64 {
        let p = self.params.target_success;
        let up = self.params.trial_step_up;
        let delta = if success { up } else { -up * p / (1.0 - p) };
        self.difficulty = (self.difficulty + delta).clamp(0.0, 1.0);
        self.difficulty
    }

    /// PI step after a session with `success_rate` ∈ [0, 1] (a non-finite rate is ignored);
    /// returns the new difficulty.
    pub fn end_session(&mut self, success_rate: f64) -> f64 {
        if !success_rate.is_finite() {
            return self.difficulty;
        }
        let p = &self.params;
        let e = success_rate.clamp(0.0, 1.0) - p.target_success;
        let i_max = if p.session_ki > 0.0 {
            p.session_max_step / p.session_ki
        } else {
            0.0
        };
        self.integral = (self.integral + e).clamp(-i_max, i_max);
        let delta = (p.session_kp * e + p.session_ki * self.integral)
            .clamp(-p.session_max_step, p.session_max_step);
        self.difficulty = (self.difficulty + delta).clamp(0.0, 1.0);
        self.difficulty
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// A simulated patient whose success probability falls linearly with difficulty:
    /// P(success | d) = 1 − d. The 70 % point is d = 0.3.
    fn p_success(d: f64) -> f64 {
        1.0 - d
    }

    #[test]
    fn weighted_staircase_settles_near_the_target_success_rate() {
        let mut a = DifficultyAdapter::new(DifficultyParams::default(), 0.9).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let (mut hits, mut n) = (0, 0);
        for trial in 0..20_000 {
            let ok = rng.random::<f64>() < p_success(a.difficulty());
            a.record_trial(ok);
            if trial >= 2_000 {
                hits += ok as u32;
                n += 1;
            }
        }
        let rate = hits as f64 / n as f64;
        assert!((rate - 0.7).abs() < 0.02, "success rate {rate}");
    }

    #[test]
    fn session_pi_converges_to_the_difficulty_giving_the_target_rate() {
        let mut a = DifficultyAdapter::new(DifficultyParams::default(), 0.9).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let mut last = Vec::new();
        for session in 0..60 {
            let d = a.difficulty();
            let ok = (0..50)
                .filter(|_| rng.random::<f64>() < p_success(d))
                .count();
            let before = a.difficulty();
            a.end_session(ok as f64 / 50.0);
            assert!((a.difficulty() - before).abs() <= 0.1 + 1e-12);
            if session >= 40 {
                last.push(a.difficulty());
            }
        }
        let mean = last.iter().sum::<f64>() / last.len() as f64;
        assert!((mean - 0.3).abs() < 0.06, "mean difficulty {mean}");
    }

    #[test]
    fn out_of_range_target_is_named() {
        let p = DifficultyParams {
            target_success: 1.2,
            ..Default::default()
        };
        let e = p.validate().unwrap_err().to_string();
        assert!(
            e.contains("difficulty.target_success") && e.contains("[0.5, 0.95]"),
            "{e}"
        );
    }
}
