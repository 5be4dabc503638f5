//! The standard assessment's measurement noise, measured on a simulated cohort (issue 42):
//! for each protocol part and measure, the test–retest reliability ([`Reliability`]: ICC(2,1),
//! SEM, MDC95) of patients whose truth did not change between weekly assessments.
//!
//! The table is data, not code: `telerehab hub cohort --write-noise` measures it and writes
//! `crates/metrics/data/assessment-noise-v<protocol>.json`; it is compiled in here so that the
//! hub, the station and Python read one table. A measure the table lacks has no cohort noise
//! ([`cohort_mdc95`] gives `None`): callers fall back to the words table's published noise.

use std::sync::OnceLock;

use serde::{Deserialize, Serialize};

use crate::reliability::Reliability;

/// The table of protocol 1 as the cohort command wrote it.
const PROTOCOL_1_JSON: &str = include_str!("../data/assessment-noise-v1.json");

/// One row: a measure of one part of the protocol and its reliability on the cohort.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NoiseRow {
    /// The protocol's part (`range`, `tracking-slow`, `steps`, `strength`, …: the part's
    /// exercise kind without its `assessment-` prefix).
    pub part: String,
    /// The measure's key in the words table (`reaction_time_s_median`).
    pub measure: String,
    /// ICC(2,1).
    pub icc: f64,
    /// Standard error of measurement, in the measure's unit.
    pub sem: f64,
    /// Minimal detectable change (95 %), in the measure's unit.
    pub mdc95: f64,
    /// The mean of all scores, in the measure's unit.
    pub grand_mean: f64,
}

/// The cohort's noise table of one protocol version.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NoiseTable {
    /// The assessment protocol's version the table was measured with.
    pub protocol: u32,
    /// The command (and commit) that measured it.
    pub generated_by: String,
    /// The day-to-day variation model of the simulated cohort, in words, with its sources.
    pub model: String,
    /// Simulated patients.
    pub subjects: usize,
    /// Weekly assessments per patient.
    pub occasions: usize,
    /// The cohort's seed.
    pub seed: u64,
    /// One row per part and measure.
    pub rows: Vec<NoiseRow>,
}

impl NoiseTable {
    /// Parses a table as the cohort command writes it.
    pub fn from_json(text: &str) -> Result<Self, serde_json::Error> {
        serde_json::from_str(text)
    }

    /// The row of `measure` in `part`, if the cohort measured it.
    pub fn row(&self, part: &str, measure: &str) -> Option<&NoiseRow> {
        self.rows
            .iter()
            .find(|r| r.part == part && r.measure == measure)
    }
}

impl NoiseRow {
    /// The row of a measured reliability.
    pub fn new(part: &str, measure: &str, r: &Reliability) -> Self {
        Self {
            part: part.to_owned(),
            measure: measure.to_owned(),
            icc: r.icc,
            sem: r.sem,
            mdc95: r.mdc95,
            grand_mean: r.grand_mean,
        }
    }
}

/// The compiled-in table of `protocol`, if one was measured.
pub fn table(protocol: u32) -> Option<&'static NoiseTable> {
    static PROTOCOL_1: OnceLock<NoiseTable> = OnceLock::new();
    match protocol {
        1 => Some(PROTOCOL_1.get_or_init(|| {
            NoiseTable::from_json(PROTOCOL_1_JSON)
                .expect("data/assessment-noise-v1.json parses (checked by its test)")
        })),
        _ => None,
    }
}

/// The cohort's MDC95 of `measure` in `part` of `protocol`, in the measure's unit.
pub fn cohort_mdc95(protocol: u32, part: &str, measure: &str) -> Option<f64> {
    table(protocol)?.row(part, measure).map(|r| r.mdc95)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_compiled_in_table_of_protocol_1_parses_and_names_its_protocol() {
        let t = NoiseTable::from_json(PROTOCOL_1_JSON).expect("parses");
        assert_eq!(t.protocol, 1);
        assert!(table(2).is_none());
        for r in &t.rows {
            assert!(r.mdc95.is_finite() && r.mdc95 >= 0.0, "{r:?}");
        }
    }
}
