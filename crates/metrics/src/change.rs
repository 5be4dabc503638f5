//! Real change told from measurement noise, per patient (issue 42): the ONE verdict on a
//! measure of the standard assessment that the hub serves and the console and its print show.
//!
//! For one patient's measure in one part of one protocol, read oldest first ([`History`]):
//!
//! - the **change** is the latest value less the patient's first (their baseline);
//! - the **band** is the MDC95 ([`crate::reliability`]: a change of two measurements of an
//!   unchanged patient stays inside it 95 % of the time, Weir 2005 eq. 8) from, in order:
//!   1. the patient's **own** repeats once there are [`OWN_NOISE_MIN_REPEATS`](crate::reliability::OWN_NOISE_MIN_REPEATS)
//!      ([`OwnNoise`]: successive differences, robust to the patient's own recovery trend);
//!   2. the simulated **cohort**'s ([`crate::assessment_noise::cohort_mdc95`]);
//!   3. the **published** smallest real difference of the words table ([`MeasureWords::noise`],
//!      a relative one taken around the baseline);
//!   4. else there is no noise figure, and no verdict ([`Verdict::NoNoiseFigure`]).
//!
//!   The band is stated on the measure's grid: rounded UP to its meaningful decimals (noise is
//!   never understated) and never narrower than one step of them (a change of one last
//!   decimal is not told from rounding).
//! - the **verdict**: the change, rounded as it is shown, beyond the band is better or worse
//!   by the measure's [`Better`]; a measure that is better neither way gets [`Verdict::Changed`];
//!   inside the band (its edge included) it is [`Verdict::WithinNoise`] whatever the direction.

use serde::Serialize;

use crate::assessment_noise::cohort_mdc95;
use crate::reliability::OwnNoise;
use crate::words::{Better, MeasureWords, measure_words};

/// Where a noise band comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum BandSource {
    /// The patient's own repeats ([`OWN_NOISE_MIN_REPEATS`](crate::reliability::OWN_NOISE_MIN_REPEATS) or more).
    Own,
    /// The simulated cohort's test–retest MDC95 of the protocol's part.
    Cohort,
    /// A study's smallest real difference (the words table's noise).
    Published,
}

/// What a change means.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Verdict {
    /// Beyond the band, the way that is progress.
    Better,
    /// Beyond the band, the other way.
    Worse,
    /// Beyond the band, of a measure neither way of which is progress.
    Changed,
    /// Inside the band: not told from measurement noise.
    WithinNoise,
    /// No noise figure for the measure yet: no verdict.
    NoNoiseFigure,
}

/// A measure's change since the patient's first assessment, its noise band and the verdict.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Change {
    /// The first value (the baseline), in the measure's unit.
    pub baseline: f64,
    /// The latest value, in the measure's unit.
    pub latest: f64,
    /// `latest − baseline`, in the measure's unit.
    pub change: f64,
    /// The noise band's half-width as stated (on the measure's grid, see the module), in the
    /// measure's unit; `None` without a noise figure.
    pub band: Option<f64>,
    /// The MDC95 the band comes from, unrounded, in the measure's unit.
    pub mdc95: Option<f64>,
    /// Where the band comes from.
    pub band_source: Option<BandSource>,
    /// The patient's repeats of the measure so far (the first included).
    pub repeats: usize,
    /// What the change means.
    pub verdict: Verdict,
}

/// One patient's values of one measure, read oldest first in constant memory: the first, the
/// latest and their own noise.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct History {
    baseline: Option<f64>,
    latest: f64,
    noise: OwnNoise,
}

impl History {
    /// The history of `values` (oldest first).
    pub fn of(values: &[f64]) -> Self {
        let mut h = Self::default();
        values.iter().for_each(|v| h.push(*v));
        h
    }

    /// Reads the next value (a non-finite one is skipped).
    pub fn push(&mut self, value: f64) {
        if !value.is_finite() {
            return;
        }
        self.baseline.get_or_insert(value);
        self.latest = value;
        self.noise.push(value);
    }

    /// Finite values read.
    pub fn repeats(&self) -> usize {
        self.noise.repeats()
    }

    /// The latest value's change since the first, with `words`' polarity and decimals, the
    /// band from the patient's own repeats, else `cohort_mdc95` (the measure's unit), else the
    /// published noise; `None` before a second value.
    pub fn change(&self, words: &MeasureWords, cohort_mdc95: Option<f64>) -> Option<Change> {
        let baseline = self.baseline?;
        if self.repeats() < 2 {
            return None;
        }
        let source = match (self.noise.mdc95(), cohort_mdc95, words.noise) {
            (Some(own), _, _) => Some((own, BandSource::Own)),
            (None, Some(cohort), _) if cohort.is_finite() => Some((cohort, BandSource::Cohort)),
            (None, _, Some(published)) => Some((published.around(baseline), BandSource::Published)),
            _ => None,
        };
        let change = self.latest - baseline;
        let stated = source.map(|(mdc95, _)| stated_band(mdc95, words.decimals));
        Some(Change {
            baseline,
            latest: self.latest,
            change,
            band: stated,
            mdc95: source.map(|(mdc95, _)| mdc95),
            band_source: source.map(|(_, s)| s),
            repeats: self.repeats(),
            verdict: verdict(change, stated, words),
        })
    }
}

/// [`History::change`] of `measure` (a key of the words table) in `part` of assessment
/// protocol `protocol`, the cohort's band from the compiled-in table; `None` for a measure the
/// words table lacks or before a second value.
pub fn assessment_change(
    protocol: u32,
    part: &str,
    measure: &str,
    history: &History,
) -> Option<Change> {
    let words = measure_words(measure)?;
    history.change(words, cohort_mdc95(protocol, part, measure))
}

/// Steps of `10^-decimals` in `v` rounded up (a hair of floating-point error is not a step).
fn steps_up(v: f64, decimals: u8) -> f64 {
    (v.abs() * 10f64.powi(i32::from(decimals)) - 1e-9)
        .ceil()
        .max(1.0)
}

/// An MDC95 as the band is stated: rounded up to `decimals`, at least one step of them.
fn stated_band(mdc95: f64, decimals: u8) -> f64 {
    steps_up(mdc95, decimals) / 10f64.powi(i32::from(decimals))
}

/// The verdict on `change` against the stated band `band` (`None`: no noise figure), compared
/// as shown: the change rounded to the measure's decimals.
pub fn verdict(change: f64, band: Option<f64>, words: &MeasureWords) -> Verdict {
    let Some(band) = band else {
        return Verdict::NoNoiseFigure;
    };
    let scale = 10f64.powi(i32::from(words.decimals));
    let change_steps = (change.abs() * scale).round();
    let band_steps = (band * scale).round();
    if change_steps <= band_steps {
        return Verdict::WithinNoise;
    }
    let up = change > 0.0;
    match words.better {
        Better::Neither => Verdict::Changed,
        Better::Higher if up => Verdict::Better,
        Better::Lower if !up => Verdict::Better,
        _ => Verdict::Worse,
    }
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;
    use crate::words::Noise;

    fn words(key: &str) -> &'static MeasureWords {
        measure_words(key).expect("in the words table")
    }

    #[test]
    fn one_value_has_no_change_and_two_compare_the_latest_with_the_first() {
        let rom = words("wheel_rom_deg");
        assert_eq!(History::of(&[120.0]).change(rom, Some(5.0)), None);
        let c = History::of(&[120.0, 150.0, 131.0])
            .change(rom, Some(5.0))
            .unwrap();
        assert_eq!((c.baseline, c.latest, c.change), (120.0, 131.0, 11.0));
        assert_eq!(
            (c.band, c.band_source),
            (Some(5.0), Some(BandSource::Cohort))
        );
        assert_eq!((c.repeats, c.verdict), (3, Verdict::Better));
    }

    #[test]
    fn the_band_is_the_patients_own_from_six_repeats_then_the_cohorts_then_the_published() {
        let sparc = words("sparc_median");
        let five = [-2.0, -1.9, -2.1, -1.95, -2.05];
        let c = History::of(&five).change(sparc, Some(0.3)).unwrap();
        assert_eq!(c.band_source, Some(BandSource::Cohort));
        // Without the cohort's: the published 34.7 % of the baseline, 0.694 stated as 0.70.
        let c = History::of(&five).change(sparc, None).unwrap();
        assert_eq!(c.band_source, Some(BandSource::Published));
        assert!((c.mdc95.unwrap() - 0.694).abs() < 1e-12, "{c:?}");
        assert_eq!(c.band, Some(0.7));
        let mut six = five.to_vec();
        six.push(-1.9);
        let c = History::of(&six).change(sparc, Some(0.3)).unwrap();
        assert_eq!(c.band_source, Some(BandSource::Own));
        assert_eq!(c.mdc95, crate::reliability::own_mdc95(&six));
        // A measure without any noise figure: the change, and no verdict.
        let c = History::of(&[100.0, 140.0])
            .change(words("wheel_rom_deg"), None)
            .unwrap();
        assert_eq!((c.band, c.band_source), (None, None));
        assert_eq!(c.verdict, Verdict::NoNoiseFigure);
    }

    #[test]
    fn a_lower_is_better_measure_that_falls_beyond_the_band_is_better() {
        let rt = words("reaction_time_s_median");
        let down = History::of(&[0.60, 0.40]).change(rt, Some(0.1)).unwrap();
        assert_eq!(down.verdict, Verdict::Better);
        let up = History::of(&[0.40, 0.60]).change(rt, Some(0.1)).unwrap();
        assert_eq!(up.verdict, Verdict::Worse);
        let rom = words("wheel_rom_deg");
        let less = History::of(&[150.0, 120.0]).change(rom, Some(5.0)).unwrap();
        assert_eq!(less.verdict, Verdict::Worse);
        // Movement time is better neither way: beyond the band it changed, no more.
        let mt = words("movement_time_s_median");
        assert_eq!(mt.better, Better::Neither);
        let c = History::of(&[1.0, 2.0]).change(mt, Some(0.2)).unwrap();
        assert_eq!(c.verdict, Verdict::Changed);
        let c = History::of(&[1.0, 1.1]).change(mt, Some(0.2)).unwrap();
        assert_eq!(c.verdict, Verdict::WithinNoise);
    }

    #[test]
    fn the_band_is_stated_rounded_up_to_the_decimals_and_never_below_one_step() {
        let rom = words("wheel_rom_deg"); // 0 decimals
        let c = History::of(&[120.0, 124.6]).change(rom, Some(4.2)).unwrap();
        // The change reads 5 °, the band 5 °: the edge is within noise.
        assert_eq!((c.band, c.verdict), (Some(5.0), Verdict::WithinNoise));
        let c = History::of(&[120.0, 120.6]).change(rom, Some(0.0)).unwrap();
        assert_eq!((c.band, c.verdict), (Some(1.0), Verdict::WithinNoise));
        // Floating-point error is not a step: 0.3 stays 0.3, not 0.4.
        assert_eq!(stated_band(0.1 + 0.2, 1), 0.3);
    }

    #[test]
    fn non_finite_values_are_skipped_and_every_verdict_has_its_wire_name() {
        let h = History::of(&[f64::NAN, 1.0, f64::INFINITY, 2.0]);
        assert_eq!(h.repeats(), 2);
        let c = h.change(words("speed_metric_median"), Some(0.5)).unwrap();
        assert_eq!((c.baseline, c.latest), (1.0, 2.0));
        let names: Vec<String> = [
            Verdict::Better,
            Verdict::Worse,
            Verdict::Changed,
            Verdict::WithinNoise,
            Verdict::NoNoiseFigure,
        ]
        .iter()
        .map(|v| {
            serde_json::to_value(v)
                .unwrap()
                .as_str()
                .unwrap()
                .to_owned()
        })
        .collect();
        assert_eq!(
            names,
            [
                "better",
                "worse",
                "changed",
                "within-noise",
                "no-noise-figure"
            ]
        );
        assert_eq!(
            serde_json::to_value(BandSource::Published).unwrap(),
            "published"
        );
    }

    #[test]
    fn an_assessment_change_reads_the_words_table_and_the_cohorts_table() {
        let h = History::of(&[-2.0, -1.0]);
        // A measure the words table lacks gets none.
        assert_eq!(assessment_change(1, "steps", "no_such_measure", &h), None);
        let c = assessment_change(1, "steps", "sparc_median", &h).unwrap();
        let cohort = cohort_mdc95(1, "steps", "sparc_median");
        let expected = if cohort.is_some() {
            BandSource::Cohort
        } else {
            BandSource::Published
        };
        assert_eq!(c.band_source, Some(expected));
        assert_eq!(c.mdc95, cohort.or(Some(0.347 * 2.0)));
    }

    /// Every measure of the words table, by index.
    fn any_measure() -> impl Strategy<Value = &'static MeasureWords> {
        (0..crate::words::MEASURES.len()).prop_map(|i| &crate::words::MEASURES[i])
    }

    proptest! {
        /// A change inside the stated band is never better or worse, whatever the measure, the
        /// band's source or the values.
        #[test]
        fn a_change_inside_the_band_is_never_better_or_worse(
            m in any_measure(),
            values in prop::collection::vec(-500.0f64..500.0, 2..12),
            cohort in prop::option::of(0.0f64..200.0),
        ) {
            let c = History::of(&values).change(m, cohort).unwrap();
            if let Some(band) = c.band {
                let shown = m.round(c.change).abs();
                if shown <= band + 1e-9 {
                    prop_assert_eq!(c.verdict, Verdict::WithinNoise, "{:?}", c);
                } else {
                    prop_assert_ne!(c.verdict, Verdict::WithinNoise, "{:?}", c);
                }
                prop_assert!(band + 1e-9 >= c.mdc95.unwrap(), "never understated: {:?}", c);
            } else {
                prop_assert_eq!(c.verdict, Verdict::NoNoiseFigure);
            }
        }

        /// Better and worse follow the measure's polarity and the change's sign.
        #[test]
        fn better_and_worse_follow_the_polarity(
            m in any_measure(),
            baseline in -100.0f64..100.0,
            change in -100.0f64..100.0,
            band in 0.0f64..10.0,
        ) {
            let c = History::of(&[baseline, baseline + change]).change(m, Some(band)).unwrap();
            let want = match (c.verdict, m.better) {
                (Verdict::WithinNoise, _) => true,
                (Verdict::Changed, Better::Neither) => true,
                (Verdict::Better, Better::Higher) | (Verdict::Worse, Better::Lower) => c.change > 0.0,
                (Verdict::Better, Better::Lower) | (Verdict::Worse, Better::Higher) => c.change < 0.0,
                _ => false,
            };
            prop_assert!(want, "{:?} of {}", c, m.key);
        }
    }

    #[test]
    fn a_published_relative_noise_is_taken_around_the_baseline() {
        let mut ldlj = *words("ldlj_median");
        assert_eq!(ldlj.noise, Some(Noise::Relative(0.23)));
        let c = History::of(&[-10.0, -7.0]).change(&ldlj, None).unwrap();
        assert_eq!((c.band, c.verdict), (Some(2.3), Verdict::Better));
        ldlj.noise = Some(Noise::Absolute(4.0));
        let c = History::of(&[-10.0, -7.0]).change(&ldlj, None).unwrap();
        assert_eq!((c.band, c.verdict), (Some(4.0), Verdict::WithinNoise));
    }
}
