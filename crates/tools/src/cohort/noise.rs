//! From the cohort's assessments to the noise table: every (part, measure)'s test–retest
//! reliability over the weekly occasions (`metrics::reliability::test_retest`), and the
//! verdicts of a held-out cohort against it (better or worse only beyond MDC95).

use std::collections::{BTreeMap, BTreeSet};

use metrics::assessment_noise::NoiseRow;
use metrics::change::{History, Verdict};
use metrics::reliability::{Reliability, test_retest};
use metrics::words::{Better, measure_words};

/// One patient's assessments, oldest first: each a map (part, measure) → score.
pub type Occasions = Vec<BTreeMap<(String, String), f64>>;

/// One assessment's scores by (part, measure), the part without its `assessment-` prefix.
pub fn scores_of(a: &hub::db::Assessment) -> BTreeMap<(String, String), f64> {
    let mut out = BTreeMap::new();
    for part in &a.parts {
        let name = part
            .kind
            .strip_prefix("assessment-")
            .unwrap_or(&part.kind)
            .to_owned();
        for (measure, v) in &part.scores {
            out.insert((name.clone(), measure.clone()), *v);
        }
    }
    out
}

/// A row of the reliability table.
#[derive(Debug, Clone)]
pub struct Row {
    /// The protocol's part.
    pub part: String,
    /// The measure's key.
    pub measure: String,
    /// Its reliability on the patients that had it on every occasion.
    pub reliability: Reliability,
}

impl Row {
    /// The noise table's row.
    pub fn noise_row(&self) -> NoiseRow {
        NoiseRow::new(&self.part, &self.measure, &self.reliability)
    }
}

/// Every (part, measure) some patient has, each with its reliability over the first `weeks`
/// occasions of the patients that have it finite on all of them (at least two needed; a
/// measure fewer have is left out and named in the second list).
pub fn reliability_table(cohort: &[Occasions], weeks: usize) -> (Vec<Row>, Vec<String>) {
    let keys: BTreeSet<(String, String)> = cohort
        .iter()
        .flat_map(|o| o.iter().flat_map(|w| w.keys().cloned()))
        .collect();
    let mut rows = Vec::new();
    let mut left_out = Vec::new();
    for key in keys {
        let table: Vec<Vec<f64>> = cohort
            .iter()
            .filter(|o| o.len() >= weeks)
            .filter_map(|o| {
                o[..weeks]
                    .iter()
                    .map(|w| w.get(&key).copied().filter(|v| v.is_finite()))
                    .collect::<Option<Vec<f64>>>()
            })
            .collect();
        match test_retest(&table) {
            Ok(reliability) => rows.push(Row {
                part: key.0,
                measure: key.1,
                reliability,
            }),
            Err(e) => left_out.push(format!("{} {}: {e}", key.0, key.1)),
        }
    }
    (rows, left_out)
}

/// The held-out cohort's verdicts: each patient's every later assessment against their first,
/// for every measure with a direction (the words table's `better`) and a row in `rows`.
#[derive(Debug, Clone, Default)]
pub struct Verdicts {
    /// Verdicts given.
    pub total: usize,
    /// Of them "better" or "worse" (false: the truth did not change).
    pub changed: usize,
    /// Per (part, measure): (verdicts, of them changed).
    pub per_measure: BTreeMap<(String, String), (usize, usize)>,
}

impl Verdicts {
    /// The rate of better/worse verdicts, in [0, 1].
    pub fn rate(&self) -> f64 {
        if self.total == 0 {
            0.0
        } else {
            self.changed as f64 / self.total as f64
        }
    }
}

/// The verdicts of `held_out` (unchanged patients) against the bands of `rows`.
pub fn verdicts(rows: &[Row], held_out: &[Occasions]) -> Verdicts {
    let mut v = Verdicts::default();
    for row in rows {
        let Some(words) = measure_words(&row.measure).filter(|w| w.better != Better::Neither)
        else {
            continue;
        };
        let key = (row.part.clone(), row.measure.clone());
        for patient in held_out {
            let Some(first) = patient.first().and_then(|w| w.get(&key)) else {
                continue;
            };
            for later in patient.iter().skip(1) {
                let Some(now) = later.get(&key) else {
                    continue;
                };
                // The console's verdict on this pair with the cohort's band (stated on the
                // measure's grid, compared as shown): `metrics::change`.
                let Some(said) = History::of(&[*first, *now])
                    .change(words, Some(row.reliability.mdc95))
                    .map(|c| c.verdict)
                else {
                    continue;
                };
                let changed = usize::from(matches!(said, Verdict::Better | Verdict::Worse));
                v.total += 1;
                v.changed += changed;
                let e = v.per_measure.entry(key.clone()).or_default();
                e.0 += 1;
                e.1 += changed;
            }
        }
    }
    v
}

/// The published reliability of `measure` where one exists, in words.
pub fn published(measure: &str) -> String {
    match measure {
        "sparc_median" => "ICC 0.81, SRD 34.7 % (SPARC, haptic peg task, J NeuroEng Rehabil \
                           2020 17:123); ICC > 0.9 (31 subacute patients, Cornec 2024)"
            .into(),
        "ldlj_median" => "ICC 0.89, SRD 23 % (log jerk, haptic peg task, J NeuroEng Rehabil \
                          2020 17:123); ICC > 0.9 (31 subacute patients, Cornec 2024)"
            .into(),
        _ => match measure_words(measure).and_then(|w| w.noise.map(|n| (n, w.source))) {
            Some((metrics::words::Noise::Relative(r), source)) => {
                format!("SRD {:.1} % ({source})", r * 100.0)
            }
            Some((metrics::words::Noise::Absolute(a), source)) => format!("SRD {a} ({source})"),
            None => "none found".into(),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn occasions(values: &[f64]) -> Occasions {
        values
            .iter()
            .map(|v| {
                BTreeMap::from([(
                    ("steps".to_owned(), "reaction_time_s_median".to_owned()),
                    *v,
                )])
            })
            .collect()
    }

    #[test]
    fn the_table_has_a_row_per_part_and_measure_and_leaves_out_a_patient_missing_an_occasion() {
        let mut cohort = vec![
            occasions(&[0.30, 0.32, 0.31]),
            occasions(&[0.45, 0.43, 0.46]),
            occasions(&[0.38, 0.40, 0.37]),
        ];
        // A fourth patient without the measure on one occasion does not count.
        let mut gap = occasions(&[0.5, 0.5, 0.5]);
        gap[1].clear();
        cohort.push(gap);
        let (rows, left_out) = reliability_table(&cohort, 3);
        assert!(left_out.is_empty(), "{left_out:?}");
        assert_eq!(rows.len(), 1);
        assert_eq!(rows[0].reliability.subjects, 3);
        assert!(rows[0].reliability.icc > 0.9, "{:?}", rows[0]);
    }

    #[test]
    fn a_held_out_change_counts_as_false_only_beyond_the_cohorts_band() {
        // A held-out patient who moved by more than the band once in two comparisons.
        let (rows, _) = reliability_table(
            &[
                occasions(&[0.30, 0.31]),
                occasions(&[0.45, 0.44]),
                occasions(&[0.38, 0.39]),
            ],
            2,
        );
        let band = rows[0].reliability.mdc95;
        let v = verdicts(
            &rows,
            &[occasions(&[0.40, 0.40 + band / 2.0, 0.40 - 2.0 * band])],
        );
        assert_eq!((v.total, v.changed), (2, 1));
        assert!((v.rate() - 0.5).abs() < 1e-12);
    }

    #[test]
    fn the_published_figures_are_named_where_they_exist() {
        assert!(published("sparc_median").contains("0.81"));
        assert!(published("ldlj_median").contains("23 %"));
        assert_eq!(published("strength_peak_left_nm"), "none found");
    }
}
