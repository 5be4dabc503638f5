//! The measures the report shows: each by the recording's key, in plain words with its unit,
//! and which way is better.

/// Which way a measure is better.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Better {
    Higher,
    Lower,
    Neither,
}

/// A measure as a therapist reads it: the recording's name, plain words, unit, decimals.
#[derive(Clone, Copy)]
pub(super) struct Measure {
    pub(super) key: &'static str,
    pub(super) label: &'static str,
    pub(super) unit: &'static str,
    pub(super) decimals: usize,
    pub(super) better: Better,
}

const fn m(
    key: &'static str,
    label: &'static str,
    unit: &'static str,
    decimals: usize,
    better: Better,
) -> Measure {
    Measure {
        key,
        label,
        unit,
        decimals,
        better,
    }
}

/// The measures shown, in order (those a session lacks are left out).
pub(super) const MEASURES: [Measure; 31] = [
    m("session_s", "Session length", "s", 0, Better::Neither),
    m("paused_s", "Paused", "s", 0, Better::Neither),
    m("movements", "Movements", "", 0, Better::Neither),
    m("active_pct", "Time moving", "%", 0, Better::Higher),
    m(
        "sparc_median",
        "Smoothness, SPARC (median; closer to 0 is smoother)",
        "",
        2,
        Better::Higher,
    ),
    m(
        "ldlj_median",
        "Smoothness, LDLJ (median; closer to 0 is smoother)",
        "",
        2,
        Better::Higher,
    ),
    m(
        "movement_peak_speed_deg_s_median",
        "Peak speed of a movement (median)",
        "°/s",
        0,
        Better::Higher,
    ),
    m(
        "movement_time_s_median",
        "Duration of a movement (median)",
        "s",
        2,
        Better::Neither,
    ),
    m(
        "speed_peaks_median",
        "Speed peaks in a movement (median)",
        "",
        0,
        Better::Lower,
    ),
    m(
        "speed_metric_median",
        "Speed metric: mean over peak speed of a movement (median; Rohrer 2002)",
        "",
        2,
        Better::Higher,
    ),
    m(
        "reaction_time_s_median",
        "Reaction time to a step of the target (median)",
        "s",
        2,
        Better::Lower,
    ),
    m(
        "initial_direction_error_deg_mean",
        "Initial direction error (mean; 180° = every start the wrong way)",
        "°",
        0,
        Better::Lower,
    ),
    // By side, for a patient who neglects one (targets on the left against the right).
    m(
        "reaction_time_left_s_median",
        "Reaction time, targets on the left (median)",
        "s",
        2,
        Better::Lower,
    ),
    m(
        "reaction_time_right_s_median",
        "Reaction time, targets on the right (median)",
        "s",
        2,
        Better::Lower,
    ),
    m(
        "initial_direction_error_left_deg_mean",
        "Initial direction error, targets on the left (mean)",
        "°",
        0,
        Better::Lower,
    ),
    m(
        "initial_direction_error_right_deg_mean",
        "Initial direction error, targets on the right (mean)",
        "°",
        0,
        Better::Lower,
    ),
    m(
        "path_length_ratio_median",
        "Path length ratio: wheel path over the distance needed (median)",
        "",
        2,
        Better::Lower,
    ),
    m(
        "movements_per_min",
        "Dose: movements per active minute",
        "/min",
        1,
        Better::Higher,
    ),
    m(
        "reversals_per_min",
        "Dose: steering reversals per active minute",
        "/min",
        1,
        Better::Neither,
    ),
    m(
        "wheel_rom_deg",
        "Wheel range of motion",
        "°",
        0,
        Better::Higher,
    ),
    m(
        "shoulder_elevation_rom_deg",
        "Shoulder elevation range",
        "°",
        0,
        Better::Higher,
    ),
    m(
        "elbow_flexion_rom_deg",
        "Elbow flexion range",
        "°",
        0,
        Better::Higher,
    ),
    m(
        "rms_lateral_m",
        "Lane keeping: lateral deviation (RMS)",
        "m",
        3,
        Better::Lower,
    ),
    m("pct_in_lane", "Time in lane", "%", 1, Better::Higher),
    m(
        "dial_rms_error_deg",
        "Tracking error (RMS)",
        "°",
        2,
        Better::Lower,
    ),
    m(
        "strength_peak_left_nm",
        "Strength pushing left: peak",
        "N·m",
        2,
        Better::Higher,
    ),
    m(
        "strength_sustained_left_nm",
        "Strength pushing left: held 1 s",
        "N·m",
        2,
        Better::Higher,
    ),
    m(
        "strength_peak_right_nm",
        "Strength pushing right: peak",
        "N·m",
        2,
        Better::Higher,
    ),
    m(
        "strength_sustained_right_nm",
        "Strength pushing right: held 1 s",
        "N·m",
        2,
        Better::Higher,
    ),
    m(
        "assist_level_mean",
        "Assist level (mean, 0–1)",
        "",
        2,
        Better::Lower,
    ),
    m(
        "patient_work_pct",
        "Patient's share of the work",
        "%",
        0,
        Better::Higher,
    ),
];

/// `a == b`, at compile time.
const fn same(a: &str, b: &str) -> bool {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}

/// The session table's measure `key`, for a table that shows it in the same words (a key not
/// in [`MEASURES`] does not build).
const fn shared(key: &str) -> Measure {
    let mut i = 0;
    while i < MEASURES.len() {
        if same(MEASURES[i].key, key) {
            return MEASURES[i];
        }
        i += 1;
    }
    panic!("a measure shared with the session table must be in it")
}

/// An exercise's own results shown in the per-exercise table, in order (rows no exercise has
/// are left out).
pub(super) const EXERCISE_MEASURES: [Measure; 30] = [
    shared("rms_lateral_m"),
    shared("pct_in_lane"),
    m(
        "heading_rms_error_deg",
        "Heading error (RMS)",
        "°",
        1,
        Better::Lower,
    ),
    m("cone_hits", "Cones hit", "", 0, Better::Lower),
    m(
        "completion_time_s",
        "Completion time",
        "s",
        1,
        Better::Neither,
    ),
    m(
        "tracking_rms_error_deg",
        "Tracking error: wheel to the ideal angle (RMS)",
        "°",
        2,
        Better::Lower,
    ),
    m(
        "dial_mean_abs_error_deg",
        "Dial angle error (mean absolute, as the thesis's Appendix E)",
        "°",
        2,
        Better::Lower,
    ),
    m(
        "dial_rms_error_deg",
        "Dial angle error (RMS)",
        "°",
        2,
        Better::Lower,
    ),
    shared("strength_peak_left_nm"),
    shared("strength_sustained_left_nm"),
    shared("strength_peak_right_nm"),
    shared("strength_sustained_right_nm"),
    shared("movements"),
    shared("active_pct"),
    m(
        "sparc_median",
        "Smoothness, SPARC (median)",
        "",
        2,
        Better::Higher,
    ),
    m(
        "ldlj_median",
        "Smoothness, LDLJ (median)",
        "",
        2,
        Better::Higher,
    ),
    shared("movement_peak_speed_deg_s_median"),
    shared("wheel_rom_deg"),
    shared("shoulder_elevation_rom_deg"),
    shared("elbow_flexion_rom_deg"),
    shared("speed_metric_median"),
    shared("reaction_time_s_median"),
    shared("initial_direction_error_deg_mean"),
    shared("reaction_time_left_s_median"),
    shared("reaction_time_right_s_median"),
    shared("initial_direction_error_left_deg_mean"),
    shared("initial_direction_error_right_deg_mean"),
    shared("path_length_ratio_median"),
    shared("movements_per_min"),
    shared("reversals_per_min"),
];

/// An exercise's results in words for the text report, in the table's order: "Lane keeping:
/// lateral deviation (RMS) 0.123 m, Time in lane 99.5 %, …".
pub(crate) fn exercise_words(e: &record::ExerciseResult) -> String {
    EXERCISE_MEASURES
        .iter()
        .filter_map(|m| {
            let v = e.scores.get(m.key)?;
            let unit = if m.unit.is_empty() {
                String::new()
            } else {
                format!(" {}", m.unit)
            };
            Some(format!("{} {:.*}{unit}", m.label, m.decimals, v))
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// The measures charted across sessions, each chart's lines by key.
pub(super) const PROGRESS: [(&str, &str, &[&str]); 7] = [
    (
        "Smoothness (SPARC, median; closer to 0 is smoother)",
        "SPARC",
        &["sparc_median"],
    ),
    (
        "Ranges of motion",
        "range (°)",
        &[
            "wheel_rom_deg",
            "shoulder_elevation_rom_deg",
            "elbow_flexion_rom_deg",
        ],
    ),
    (
        "Lane keeping",
        "lateral deviation, RMS (m)",
        &["rms_lateral_m"],
    ),
    ("Tracking error", "RMS error (°)", &["dial_rms_error_deg"]),
    (
        "Strength",
        "torque held 1 s (N·m)",
        &["strength_sustained_left_nm", "strength_sustained_right_nm"],
    ),
    (
        "Time moving and the patient's share of the work",
        "%",
        &["active_pct", "patient_work_pct"],
    ),
    ("Assist level", "level (0–1)", &["assist_level_mean"]),
];

pub(super) fn measure(key: &str) -> Option<&'static Measure> {
    MEASURES.iter().find(|m| m.key == key)
}

/// ` (unit)`, or nothing for a measure without a unit.
pub(super) fn unit_suffix(unit: &str) -> String {
    if unit.is_empty() {
        String::new()
    } else {
        format!(" ({unit})")
    }
}
