//! The measures the report shows: each by the recording's key, in plain words with its unit,
//! and which way is better — read from the ONE table of measure words (`metrics::words`) the
//! hub's console, spreadsheet and FHIR export read too.

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
    /// What it measures, for the clinician (the words table's definition).
    pub(super) definition: &'static str,
}

/// Measure `key` as the ONE table of measure words (`metrics::words`) words it: plain name,
/// unit, meaningful decimals, which way is better (a key not in the table does not build).
const fn from_table(key: &str) -> Measure {
    let table = &metrics::words::MEASURES;
    let mut i = 0;
    while i < table.len() {
        if same(table[i].key, key) {
            let w = &table[i];
            return Measure {
                key: w.key,
                label: w.name,
                unit: w.unit,
                decimals: w.decimals as usize,
                definition: w.definition,
                better: match w.better {
                    metrics::words::Better::Higher => Better::Higher,
                    metrics::words::Better::Lower => Better::Lower,
                    metrics::words::Better::Neither => Better::Neither,
                },
            };
        }
        i += 1;
    }
    panic!("a measure the report shows must be in metrics::words::MEASURES")
}

/// The measures shown, in order (those a session lacks are left out).
pub(super) const MEASURES: [Measure; 42] = [
    from_table("session_s"),
    from_table("paused_s"),
    from_table("movements"),
    from_table("discrete_movements"),
    from_table("active_pct"),
    from_table("sparc_median"),
    from_table("ldlj_median"),
    from_table("movement_peak_speed_deg_s_median"),
    from_table("movement_time_s_median"),
    from_table("speed_peaks_median"),
    from_table("speed_metric_median"),
    from_table("reaction_time_s_median"),
    from_table("anticipation_pct"),
    from_table("initial_direction_error_deg_mean"),
    from_table("reaction_time_left_s_median"),
    from_table("reaction_time_right_s_median"),
    from_table("initial_direction_error_left_deg_mean"),
    from_table("initial_direction_error_right_deg_mean"),
    from_table("path_length_ratio_median"),
    from_table("movements_per_min"),
    from_table("reversals_per_min"),
    from_table("wheel_rom_deg"),
    from_table("shoulder_elevation_rom_deg"),
    from_table("elbow_flexion_rom_deg"),
    from_table("trunk_flexion_max_deg"),
    from_table("trunk_flexion_mean_deg"),
    from_table("trunk_lean_max_deg"),
    from_table("trunk_lean_mean_deg"),
    from_table("trunk_rotation_max_deg"),
    from_table("trunk_rotation_mean_deg"),
    from_table("trunk_beyond_pct"),
    from_table("trunk_compensated_movements_pct"),
    from_table("trunk_cues"),
    from_table("rms_lateral_m"),
    from_table("pct_in_lane"),
    from_table("dial_rms_error_deg"),
    from_table("strength_peak_left_nm"),
    from_table("strength_sustained_left_nm"),
    from_table("strength_peak_right_nm"),
    from_table("strength_sustained_right_nm"),
    from_table("assist_level_mean"),
    from_table("patient_work_pct"),
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
pub(super) const EXERCISE_MEASURES: [Measure; 41] = [
    shared("rms_lateral_m"),
    shared("pct_in_lane"),
    from_table("heading_rms_error_deg"),
    from_table("cone_hits"),
    from_table("completion_time_s"),
    from_table("tracking_rms_error_deg"),
    from_table("dial_mean_abs_error_deg"),
    from_table("dial_rms_error_deg"),
    shared("strength_peak_left_nm"),
    shared("strength_sustained_left_nm"),
    shared("strength_peak_right_nm"),
    shared("strength_sustained_right_nm"),
    shared("movements"),
    shared("discrete_movements"),
    shared("active_pct"),
    from_table("sparc_median"),
    from_table("ldlj_median"),
    shared("movement_peak_speed_deg_s_median"),
    shared("wheel_rom_deg"),
    shared("shoulder_elevation_rom_deg"),
    shared("elbow_flexion_rom_deg"),
    shared("trunk_flexion_max_deg"),
    shared("trunk_flexion_mean_deg"),
    shared("trunk_lean_max_deg"),
    shared("trunk_lean_mean_deg"),
    shared("trunk_rotation_max_deg"),
    shared("trunk_rotation_mean_deg"),
    shared("trunk_beyond_pct"),
    shared("trunk_compensated_movements_pct"),
    shared("trunk_cues"),
    shared("speed_metric_median"),
    shared("reaction_time_s_median"),
    shared("anticipation_pct"),
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

/// The measures charted across sessions: ONE measure a chart (its title, the y axis, its key).
pub(super) const PROGRESS: [(&str, &str, &[&str]); 11] = [
    (
        "Smoothness (closer to 0 is smoother)",
        "smoothness",
        &["sparc_median"],
    ),
    ("Wheel turning range", "range (°)", &["wheel_rom_deg"]),
    (
        "Shoulder lifting range",
        "range (°)",
        &["shoulder_elevation_rom_deg"],
    ),
    (
        "Elbow bending range",
        "range (°)",
        &["elbow_flexion_rom_deg"],
    ),
    (
        "Distance from the lane's centre",
        "distance (m)",
        &["rms_lateral_m"],
    ),
    (
        "Dial: distance from the angle asked",
        "distance (°)",
        &["dial_rms_error_deg"],
    ),
    (
        "Strength turning left, held 1 s",
        "torque (N·m)",
        &["strength_sustained_left_nm"],
    ),
    (
        "Strength turning right, held 1 s",
        "torque (N·m)",
        &["strength_sustained_right_nm"],
    ),
    ("Time moving", "time moving (%)", &["active_pct"]),
    (
        "Patient's share of the work",
        "share (%)",
        &["patient_work_pct"],
    ),
    (
        "Help from the wheel (0 none, 1 full)",
        "level (0–1)",
        &["assist_level_mean"],
    ),
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
