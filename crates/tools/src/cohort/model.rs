//! The simulated cohort (issue 42): patients whose impairment spans mild to severe, each
//! assessed weekly while their truth does not change, every occasion perturbed by a
//! day-to-day variation of their state.
//!
//! **Between patients.** A severity `s`, uniform in [0, 1] (0 mild, 1 severe), sets every
//! impairment of the simulated arm (`assist::human::HumanArmParams`), each with its own
//! scatter so that two patients of one severity differ:
//!
//! | impairment | mild (s = 0) → severe (s = 1) | scatter (SD) |
//! |---|---|---|
//! | weakness (share of strength lost) | 0.10 → 0.80 | 0.05 |
//! | visual reaction time, s | 0.30 → 0.50 | 0.03 |
//! | sensorimotor (feedback) delay, s | 0.05 → 0.15 | — |
//! | motor noise, N·m RMS | 0.02 → 0.04 | — |
//! | tremor, N·m RMS | 0 → 0.03 | — |
//! | active range of motion, ± deg | 180 → 50 | 10 |
//!
//! Reaction time after stroke: 0.40–0.47 s (SD 0.13–0.14) against 0.33 s in age-matched
//! controls (Pauley et al. 2015, simple and choice reaction time of stroke survivors with
//! right or left hemiplegia); the healthy adult's simple visual reaction time is 0.21–0.23 s
//! (Woods et al. 2015, Front Hum Neurosci 9:131). The severe end's weakness, delay, tremor and
//! range are those of `HumanArmParams::weak_patient`.
//!
//! **Day to day.** Each weekly occasion multiplies the patient's true state by log-normal
//! factors `exp(N(0, cv²))` drawn for that occasion, and runs with a new session seed (the
//! steps' timing and sides, the motor noise and tremor):
//!
//! | state | within-subject CV | source |
//! |---|---|---|
//! | strength (1 − weakness) | 8 % | grip strength after stroke, test–retest 3–7 days apart: ICC 0.85–0.98, smallest real difference 2.9 kg of the more affected hand (Chen et al. 2009, Neurorehabil Neural Repair 23:435); 8 % a day is within it |
//! | visual reaction time | 7 % | simple visual reaction time retested weekly: ICC 0.83 (Woods et al. 2015, Front Hum Neurosci 9:540) |
//! | motor noise and tremor amplitude | 15 % | none found: an assumption, larger than strength's |
//! | active range of motion | 3 % | goniometric active range retested: a few degrees (none found for a wheel: an assumption) |
//!
//! The truth itself never changes: what the assessment measures differently from week to
//! week is measurement noise by construction, which is what the cohort is for.

use assist::human::HumanArmParams;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Within-subject coefficient of variation of strength from day to day.
pub const STRENGTH_CV: f64 = 0.08;
/// Within-subject coefficient of variation of the visual reaction time from day to day.
pub const REACTION_CV: f64 = 0.07;
/// Within-subject coefficient of variation of motor noise and tremor from day to day.
pub const NOISE_CV: f64 = 0.15;
/// Within-subject coefficient of variation of the active range of motion from day to day.
pub const RANGE_CV: f64 = 0.03;

/// The model in one paragraph, for the noise table and the reliability page.
pub const MODEL: &str = "Severity uniform mild→severe sets weakness 0.10→0.80, visual reaction \
    time 0.30→0.50 s (Pauley et al. 2015; healthy 0.22 s, Woods et al. 2015 Front Hum Neurosci \
    9:131), feedback delay 0.05→0.15 s, motor noise 0.02→0.04 N·m, tremor 0→0.03 N·m, active \
    range ±180°→±50°. Each weekly occasion multiplies the unchanged truth by log-normal \
    day-to-day factors: strength CV 8 % (grip retest after stroke, Chen et al. 2009 Neurorehabil \
    Neural Repair 23:435), reaction time CV 7 % (weekly retest ICC 0.83, Woods et al. 2015 Front \
    Hum Neurosci 9:540), motor noise and tremor CV 15 % and range CV 3 % (assumptions: none \
    found), and runs with a new session seed.";

/// One simulated patient: their unchanging truth.
#[derive(Debug, Clone, PartialEq)]
pub struct Patient {
    /// Severity in [0, 1] (0 mild, 1 severe).
    pub severity: f64,
    /// Their arm as it truly is.
    pub truth: HumanArmParams,
}

/// A normal sample (Box–Muller), mean 0 and SD 1.
fn normal(rng: &mut impl Rng) -> f64 {
    let u1: f64 = rng.random_range(f64::EPSILON..1.0);
    let u2: f64 = rng.random::<f64>();
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

/// The seed of a patient's draws: the cohort's seed and the patient's index mixed.
fn patient_rng(cohort_seed: u64, patient: usize, occasion: Option<usize>) -> ChaCha8Rng {
    let occasion = occasion.map_or(0, |w| w as u64 + 1);
    ChaCha8Rng::seed_from_u64(
        cohort_seed
            ^ (patient as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
            ^ occasion.wrapping_mul(0xC2B2_AE3D_27D4_EB4F),
    )
}

/// Patient `index` of the cohort of `seed`, the arm built on `base` (the station's simulated
/// patient: its grip gains and strength).
pub fn patient(seed: u64, index: usize, base: &HumanArmParams) -> Patient {
    let mut rng = patient_rng(seed, index, None);
    let s: f64 = rng.random::<f64>();
    let lerp = |a: f64, b: f64| a + (b - a) * s;
    let truth = HumanArmParams {
        weakness: (lerp(0.10, 0.80) + 0.05 * normal(&mut rng)).clamp(0.0, 0.9),
        reaction_s: (lerp(0.30, 0.50) + 0.03 * normal(&mut rng)).clamp(0.2, 0.8),
        delay_s: lerp(0.05, 0.15),
        noise_nm: lerp(0.02, 0.04),
        tremor_nm: lerp(0.0, 0.03),
        range_of_motion_rad: (lerp(180.0, 50.0) + 10.0 * normal(&mut rng))
            .clamp(30.0, 180.0)
            .to_radians(),
        ..base.clone()
    };
    Patient { severity: s, truth }
}

impl Patient {
    /// The patient's arm on occasion `week` (from 0) of the cohort of `seed`: the truth times
    /// the day's log-normal factors; the same for the same seed, patient and week.
    pub fn on_occasion(&self, seed: u64, index: usize, week: usize) -> HumanArmParams {
        let mut rng = patient_rng(seed, index, Some(week));
        let mut factor = |cv: f64| (cv * normal(&mut rng)).exp();
        let t = &self.truth;
        let strength = ((1.0 - t.weakness) * factor(STRENGTH_CV)).clamp(0.05, 1.0);
        let noise = factor(NOISE_CV);
        HumanArmParams {
            weakness: 1.0 - strength,
            reaction_s: (t.reaction_s * factor(REACTION_CV)).clamp(0.1, 2.0),
            noise_nm: t.noise_nm * noise,
            tremor_nm: t.tremor_nm * noise,
            range_of_motion_rad: (t.range_of_motion_rad * factor(RANGE_CV))
                .min(std::f64::consts::PI),
            ..t.clone()
        }
    }
}

/// The session seed of occasion `week` of patient `index` (the steps, motor noise, tremor).
pub fn session_seed(seed: u64, index: usize, week: usize) -> u64 {
    patient_rng(seed, index, Some(week)).random::<u64>() >> 12
}

#[cfg(test)]
mod tests {
    use super::*;

    fn base() -> HumanArmParams {
        session::config::default_sim_patient()
    }

    #[test]
    fn the_cohort_spans_mild_to_severe_and_repeats_for_its_seed() {
        let cohort: Vec<Patient> = (0..40).map(|i| patient(5, i, &base())).collect();
        assert_eq!(
            cohort,
            (0..40).map(|i| patient(5, i, &base())).collect::<Vec<_>>()
        );
        assert_ne!(cohort[0], patient(6, 0, &base()));
        let weak: Vec<f64> = cohort.iter().map(|p| p.truth.weakness).collect();
        let (lo, hi) = weak
            .iter()
            .fold((1.0f64, 0.0f64), |(a, b), &w| (a.min(w), b.max(w)));
        assert!(lo < 0.25 && hi > 0.65, "weakness {lo}..{hi}");
        for p in &cohort {
            p.truth.validate().unwrap();
            assert!((0.2..=0.8).contains(&p.truth.reaction_s), "{p:?}");
            // Severity orders the reaction time (its scatter is small beside its span).
            assert!((p.truth.reaction_s - (0.30 + 0.20 * p.severity)).abs() < 0.15);
        }
    }

    #[test]
    fn each_week_perturbs_the_state_by_the_stated_day_to_day_variation_around_an_unchanged_truth() {
        let p = patient(9, 3, &base());
        let weeks: Vec<HumanArmParams> = (0..400).map(|w| p.on_occasion(9, 3, w)).collect();
        assert_eq!(weeks[7], p.on_occasion(9, 3, 7));
        let log_cv = |f: &dyn Fn(&HumanArmParams) -> f64, truth: f64| {
            let logs: Vec<f64> = weeks.iter().map(|a| (f(a) / truth).ln()).collect();
            let mean = logs.iter().sum::<f64>() / logs.len() as f64;
            let sd = (logs.iter().map(|l| (l - mean).powi(2)).sum::<f64>()
                / (logs.len() - 1) as f64)
                .sqrt();
            (mean, sd)
        };
        let (m, sd) = log_cv(&|a| a.reaction_s, p.truth.reaction_s);
        assert!(
            m.abs() < 0.02 && (sd - REACTION_CV).abs() < 0.01,
            "{m} {sd}"
        );
        let (m, sd) = log_cv(&|a| 1.0 - a.weakness, 1.0 - p.truth.weakness);
        assert!(
            m.abs() < 0.02 && (sd - STRENGTH_CV).abs() < 0.015,
            "{m} {sd}"
        );
        for w in &weeks {
            w.validate().unwrap();
            assert_eq!(w.delay_s, p.truth.delay_s);
        }
        assert_ne!(session_seed(9, 3, 0), session_seed(9, 3, 1));
    }
}
