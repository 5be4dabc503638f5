//! The ONE table of measure words (issue 41): every measure a session stores, with the plain
//! name a clinician reads, its unit, how many decimals are meaningful, the axis range a chart
//! starts from, its measurement noise where a study measured it, and which way is better; and
//! one wording per way a session ends. The station's report, the hub's spreadsheet, its FHIR
//! export and the console (served as JSON by the hub, `GET /api/measures/words`) all read it:
//! nothing else re-types a measure's words.
//!
//! Engineering names (`sparc_median`, "SPARC", "RMS") live in [`MeasureWords::key`] and
//! [`MeasureWords::technical`] only: pages show them behind "details".

use serde::Serialize;

/// Which way a measure is better.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Better {
    /// A larger value is progress.
    Higher,
    /// A smaller value is progress.
    Lower,
    /// Neither: a count or a time that describes the session, not the patient's progress.
    Neither,
}

/// How much a measure varies between two sessions of an unchanged patient (the smallest real
/// difference a study found): a change within it is not a change.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "kind", content = "value", rename_all = "lowercase")]
pub enum Noise {
    /// In the measure's own unit.
    Absolute(f64),
    /// A fraction of the value (0.347 = 34.7 %).
    Relative(f64),
}

impl Noise {
    /// The half-width of the noise band around `value`, in the measure's unit.
    pub fn around(self, value: f64) -> f64 {
        match self {
            Self::Absolute(a) => a,
            Self::Relative(r) => (r * value).abs(),
        }
    }
}

/// A measure in a clinician's words.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct MeasureWords {
    /// The stored name (`pct_in_lane`): the spreadsheet's technical header, FHIR's code.
    pub key: &'static str,
    /// The plain name (`Time in lane`).
    pub name: &'static str,
    /// The engineering name, shown only behind "details" (`RMS lateral deviation`).
    pub technical: &'static str,
    /// The unit as printed after a number (`%`, `°`, `N·m`, `s`); empty for a count or a ratio.
    pub unit: &'static str,
    /// Decimals that are meaningful (the resolution is 10^-decimals of the unit).
    pub decimals: u8,
    /// The range a chart's axis starts from, in the unit ([low, high]; grown to fit a value
    /// outside it, never shrunk to the data).
    pub range: [f64; 2],
    /// Measurement noise, where a study measured it.
    pub noise: Option<Noise>,
    /// Which way is better.
    pub better: Better,
    /// What it measures and how, in one or two sentences for a clinician (English; the
    /// console's words are its catalogues' `words-definition-<key>`).
    pub definition: &'static str,
    /// Where the measure (or its formula) comes from: a paper, the thesis' section, or this
    /// product's own definition (docs/DESIGN.md).
    pub source: &'static str,
}

impl MeasureWords {
    /// The words with their `definition` and `source` (every entry of [`MEASURES`] has both).
    pub const fn defined(self, definition: &'static str, source: &'static str) -> Self {
        Self {
            definition,
            source,
            ..self
        }
    }

    /// `v` rounded to the meaningful decimals.
    pub fn round(&self, v: f64) -> f64 {
        round_to(v, self.decimals)
    }

    /// `v` as a clinician reads it: rounded, with its unit (`12.5 °`, `3 N·m`, `0.42`); `-0`
    /// reads `0`.
    pub fn format(&self, v: f64) -> String {
        let n = self.number(v);
        if self.unit.is_empty() {
            n
        } else {
            format!("{n} {}", self.unit)
        }
    }

    /// `v` rounded, without its unit (`12.5`).
    pub fn number(&self, v: f64) -> String {
        let r = self.round(v);
        let r = if r == 0.0 { 0.0 } else { r };
        format!("{r:.*}", usize::from(self.decimals))
    }

    /// The plain name with its unit, as a column header: `Time in lane (%)`.
    pub fn header(&self) -> String {
        if self.unit.is_empty() {
            self.name.to_owned()
        } else {
            format!("{} ({})", self.name, self.unit)
        }
    }
}

/// `v` rounded to `decimals`.
pub fn round_to(v: f64, decimals: u8) -> f64 {
    let scale = 10f64.powi(i32::from(decimals));
    (v * scale).round() / scale
}

#[allow(clippy::too_many_arguments)]
const fn w(
    key: &'static str,
    name: &'static str,
    technical: &'static str,
    unit: &'static str,
    decimals: u8,
    range: [f64; 2],
    noise: Option<Noise>,
    better: Better,
) -> MeasureWords {
    MeasureWords {
        key,
        name,
        technical,
        unit,
        decimals,
        range,
        noise,
        better,
        definition: "",
        source: "",
    }
}

use Better::{Higher, Lower, Neither};

/// SPARC's smallest real difference on a haptic task, 34.7 % (J NeuroEng Rehabil 2020,
/// 17:123, Table 3).
const SPARC_NOISE: Option<Noise> = Some(Noise::Relative(0.347));
/// Log dimensionless jerk's smallest real difference on the same task, 23 %.
const LDLJ_NOISE: Option<Noise> = Some(Noise::Relative(0.23));

/// Every measure with words, in the order a clinician reads them (the session, then
/// movement quality, then the exercises' own results, then strength and help).
pub const MEASURES: [MeasureWords; 48] = [
    w(
        "active_s",
        "Active time",
        "active_s",
        "s",
        0,
        [0.0, 1800.0],
        None,
        Higher,
    )
    .defined(
        "Time the wheel was moving: the sum of the movements' durations, pauses left out.",
        "speed-threshold segmentation (Rohrer et al. 2002, J Neurosci 22:8297)",
    ),
    w(
        "session_s",
        "Session length",
        "session_s",
        "s",
        0,
        [0.0, 1800.0],
        None,
        Neither,
    )
    .defined(
        "Time from the session's start to its end, pauses included.",
        "telerehab's own session record (docs/DESIGN.md)",
    ),
    w(
        "paused_s",
        "Time paused",
        "paused_s",
        "s",
        0,
        [0.0, 600.0],
        None,
        Neither,
    )
    .defined(
        "Time the session was paused by the patient or for rest.",
        "telerehab's own session record (docs/DESIGN.md)",
    ),
    w(
        "active_pct",
        "Time moving",
        "active_pct",
        "%",
        0,
        [0.0, 100.0],
        None,
        Higher,
    )
    .defined(
        "Share of the exercise time the wheel was moving (Active time over the exercise's time).",
        "speed-threshold segmentation (Rohrer et al. 2002, J Neurosci 22:8297)",
    ),
    w(
        "movements",
        "Movements",
        "movements (count)",
        "",
        0,
        [0.0, 200.0],
        None,
        Neither,
    )
    .defined(
        "Movements of the wheel: runs of its speed above 5 % of the session's peak (at least 2.9 °/s), gaps under 0.1 s joined, runs under 0.2 s dropped.",
        "speed-threshold segmentation (Rohrer et al. 2002, J Neurosci 22:8297)",
    ),
    w(
        "discrete_movements",
        "Movements from rest to rest",
        "discrete movements (count)",
        "",
        0,
        [0.0, 200.0],
        None,
        Neither,
    )
    .defined(
        "Movements from rest to rest: at least 0.2 s still before and after, at most 5 s long. Only these are scored for smoothness.",
        "discrete movement: Hogan & Sternad 2007, Exp Brain Res 181:13-30; smoothness on discrete movements: Balasubramanian et al. 2015, J NeuroEng Rehabil 12:112",
    ),
    w(
        "movements_per_min",
        "Movements a minute",
        "movements per active minute",
        "/min",
        1,
        [0.0, 60.0],
        None,
        Higher,
    )
    .defined(
        "Movements per minute of exercise: the dose of practice.",
        "Lang et al. 2009, Arch Phys Med Rehabil 90(10):1692-1698",
    ),
    w(
        "reversals_per_min",
        "Changes of steering direction a minute",
        "steering reversals per active minute",
        "/min",
        1,
        [0.0, 60.0],
        None,
        Neither,
    )
    .defined(
        "Changes of the wheel's turning direction by at least 2° per minute of exercise.",
        "Markkula & Engstrom 2006, ITS World Congress, London",
    ),
    w(
        "sparc_median",
        "Smoothness (closer to 0 is smoother)",
        "SPARC (spectral arc length), median of discrete movements",
        "",
        2,
        [-5.0, 0.0],
        SPARC_NOISE,
        Higher,
    )
    .defined(
        "Spectral arc length of the wheel's speed, median over the discrete movements; none for a continuous task. Closer to 0 is smoother.",
        "Balasubramanian, Melendez-Calderon, Roby-Brami & Burdet 2015, J NeuroEng Rehabil 12:112, eq. 4-5 (reference code siva82kb/SPARC)",
    ),
    w(
        "ldlj_median",
        "Smoothness of acceleration (closer to 0 is smoother)",
        "LDLJ (log dimensionless jerk), median of discrete movements",
        "",
        1,
        [-30.0, 0.0],
        LDLJ_NOISE,
        Higher,
    )
    .defined(
        "Log dimensionless jerk of the wheel's speed, median over the discrete movements; none for a continuous task. Closer to 0 is smoother.",
        "Hogan & Sternad 2009, J Mot Behav 41(6):529-534; Balasubramanian et al. 2012, IEEE Trans Biomed Eng 59(8):2126-2136 (monalysa)",
    ),
    w(
        "movement_peak_speed_deg_s_median",
        "Top turning speed of a movement",
        "movement peak speed, median (°/s)",
        "°/s",
        0,
        [0.0, 360.0],
        None,
        Higher,
    )
    .defined(
        "Highest turning speed within a movement, median over the movements.",
        "Coderre et al. 2010, Neurorehabil Neural Repair 24(6):528-541",
    ),
    w(
        "movement_time_s_median",
        "Length of a movement",
        "movement time, median",
        "s",
        1,
        [0.0, 5.0],
        None,
        Neither,
    )
    .defined(
        "Duration of a movement, from the speed rising above the threshold to falling back, median.",
        "Coderre et al. 2010, Neurorehabil Neural Repair 24(6):528-541",
    ),
    w(
        "speed_peaks_median",
        "Stops and starts in a movement",
        "speed peaks per movement, median",
        "",
        0,
        [0.0, 10.0],
        None,
        Lower,
    )
    .defined(
        "Peaks of speed within a movement (at least 10 % of its top speed), median; 1 is a single smooth movement.",
        "Rohrer et al. 2002, J Neurosci 22(18):8297-8304",
    ),
    w(
        "speed_metric_median",
        "Evenness of speed (1 is even)",
        "speed metric: mean over peak speed, median (Rohrer et al. 2002)",
        "",
        2,
        [0.0, 1.0],
        None,
        Higher,
    )
    .defined(
        "A movement's mean speed over its top speed, median; rises as movements fill out with recovery.",
        "Rohrer et al. 2002, J Neurosci 22(18):8297-8304",
    ),
    w(
        "reaction_time_s_median",
        "Reaction time",
        "reaction time to an unpredictable target step, median",
        "s",
        2,
        [0.0, 2.0],
        None,
        Lower,
    )
    .defined(
        "Time from an unpredictable step of the target (a dial's random jump) to the wheel starting its response (10 % of the response's top speed, held 0.1 s; a movement still going at the step is not its start), median.",
        "Coderre et al. 2010, Neurorehabil Neural Repair 24(6):528-541; onsets sooner than 0.1 s are anticipations (Pain & Hibbs 2007, J Sports Sci 25(1):79-86)",
    ),
    w(
        "anticipation_pct",
        "Lane changes started before they came",
        "anticipation share: onsets sooner than 0.1 s after a predictable cue",
        "%",
        0,
        [0.0, 100.0],
        None,
        Neither,
    )
    .defined(
        "Share of predictable cues (a lane shift seen ahead) met by a turn starting sooner than 0.1 s after the cue: anticipated, not reacted to.",
        "minimum reaction 0.1 s: World Athletics TR 16.6; Pain & Hibbs 2007, J Sports Sci 25(1):79-86",
    ),
    w(
        "initial_direction_error_deg_mean",
        "Wrong-way start of a movement",
        "initial direction error, mean (180° = every start the wrong way)",
        "°",
        0,
        [0.0, 180.0],
        None,
        Lower,
    )
    .defined(
        "Whether a movement after a step starts the wrong way: 0° the right way, 180° the wrong way, mean (180° times the share of wrong starts).",
        "Coderre et al. 2010, Neurorehabil Neural Repair 24(6):528-541",
    ),
    // By side, for a patient who neglects one (targets on the left against the right).
    w(
        "reaction_time_left_s_median",
        "Reaction time, targets on the left",
        "reaction time to an unpredictable target step to the left, median",
        "s",
        2,
        [0.0, 2.0],
        None,
        Lower,
    )
    .defined(
        "Reaction time to unpredictable steps of the target to the left, median.",
        "Coderre et al. 2010, Neurorehabil Neural Repair 24(6):528-541; onsets sooner than 0.1 s are anticipations (Pain & Hibbs 2007, J Sports Sci 25(1):79-86)",
    ),
    w(
        "reaction_time_right_s_median",
        "Reaction time, targets on the right",
        "reaction time to an unpredictable target step to the right, median",
        "s",
        2,
        [0.0, 2.0],
        None,
        Lower,
    )
    .defined(
        "Reaction time to unpredictable steps of the target to the right, median.",
        "Coderre et al. 2010, Neurorehabil Neural Repair 24(6):528-541; onsets sooner than 0.1 s are anticipations (Pain & Hibbs 2007, J Sports Sci 25(1):79-86)",
    ),
    w(
        "initial_direction_error_left_deg_mean",
        "Wrong-way start, targets on the left",
        "initial direction error toward left targets, mean",
        "°",
        0,
        [0.0, 180.0],
        None,
        Lower,
    )
    .defined(
        "Wrong-way starts towards targets on the left, mean (0° right way, 180° wrong way).",
        "Coderre et al. 2010, Neurorehabil Neural Repair 24(6):528-541",
    ),
    w(
        "initial_direction_error_right_deg_mean",
        "Wrong-way start, targets on the right",
        "initial direction error toward right targets, mean",
        "°",
        0,
        [0.0, 180.0],
        None,
        Lower,
    )
    .defined(
        "Wrong-way starts towards targets on the right, mean (0° right way, 180° wrong way).",
        "Coderre et al. 2010, Neurorehabil Neural Repair 24(6):528-541",
    ),
    w(
        "path_length_ratio_median",
        "Turning beyond what was needed (1 is none)",
        "path length ratio, median",
        "",
        2,
        [1.0, 3.0],
        None,
        Lower,
    )
    .defined(
        "Wheel turning travelled after a step over the turning needed to reach the new target, median; 1 is direct.",
        "Coderre et al. 2010, Neurorehabil Neural Repair 24(6):528-541",
    ),
    w(
        "wheel_rom_deg",
        "Wheel turning range",
        "wheel range of motion",
        "°",
        0,
        [0.0, 360.0],
        None,
        Higher,
    )
    .defined(
        "Largest minus smallest wheel angle over the exercise.",
        "telerehab's own session record (docs/DESIGN.md)",
    ),
    w(
        "shoulder_elevation_rom_deg",
        "Shoulder lifting range",
        "shoulder elevation range of motion",
        "°",
        0,
        [0.0, 180.0],
        None,
        Higher,
    )
    .defined(
        "Largest minus smallest shoulder lifting angle while the arm sensors tracked.",
        "Jadhav 2004 thesis, chapter 4 (arm angles from the rate sensors and the wheel)",
    ),
    w(
        "elbow_flexion_rom_deg",
        "Elbow bending range",
        "elbow flexion range of motion",
        "°",
        0,
        [0.0, 150.0],
        None,
        Higher,
    )
    .defined(
        "Largest minus smallest elbow bending angle while the arm sensors tracked.",
        "Jadhav 2004 thesis, chapter 4 (arm angles from the rate sensors and the wheel)",
    ),
    // Trunk compensation from the sternum IMU (gyro_imu::trunk), from the start posture.
    w(
        "trunk_flexion_max_deg",
        "Trunk bending forward, furthest",
        "trunk flexion, maximum excursion",
        "°",
        0,
        [0.0, 45.0],
        None,
        Lower,
    )
    .defined(
        "Largest forward bend of the trunk from its start posture, from the sternum sensor.",
        "Wu et al. 2005, J Biomech 38:981 (ISB thorax angles); Cirstea & Levin 2000, Brain 123:940 (trunk compensation in stroke)",
    ),
    w(
        "trunk_flexion_mean_deg",
        "Trunk bending forward, on average",
        "trunk flexion, mean excursion",
        "°",
        0,
        [0.0, 30.0],
        None,
        Lower,
    )
    .defined(
        "Mean forward bend of the trunk from its start posture, from the sternum sensor.",
        "Wu et al. 2005, J Biomech 38:981 (ISB thorax angles); Cirstea & Levin 2000, Brain 123:940 (trunk compensation in stroke)",
    ),
    w(
        "trunk_lean_max_deg",
        "Trunk leaning sideways, furthest",
        "trunk lateral lean, maximum excursion",
        "°",
        0,
        [0.0, 45.0],
        None,
        Lower,
    )
    .defined(
        "Largest sideways lean of the trunk from its start posture, from the sternum sensor.",
        "Wu et al. 2005, J Biomech 38:981 (ISB thorax angles); Cirstea & Levin 2000, Brain 123:940 (trunk compensation in stroke)",
    ),
    w(
        "trunk_lean_mean_deg",
        "Trunk leaning sideways, on average",
        "trunk lateral lean, mean excursion",
        "°",
        0,
        [0.0, 30.0],
        None,
        Lower,
    )
    .defined(
        "Mean sideways lean of the trunk from its start posture, from the sternum sensor.",
        "Wu et al. 2005, J Biomech 38:981 (ISB thorax angles); Cirstea & Levin 2000, Brain 123:940 (trunk compensation in stroke)",
    ),
    w(
        "trunk_rotation_max_deg",
        "Trunk twisting, furthest",
        "trunk rotation, maximum excursion",
        "°",
        0,
        [0.0, 45.0],
        None,
        Lower,
    )
    .defined(
        "Largest twist of the trunk from its start posture, from the sternum sensor.",
        "Wu et al. 2005, J Biomech 38:981 (ISB thorax angles); Cirstea & Levin 2000, Brain 123:940 (trunk compensation in stroke)",
    ),
    w(
        "trunk_rotation_mean_deg",
        "Trunk twisting, on average",
        "trunk rotation, mean excursion",
        "°",
        0,
        [0.0, 30.0],
        None,
        Lower,
    )
    .defined(
        "Mean twist of the trunk from its start posture, from the sternum sensor.",
        "Wu et al. 2005, J Biomech 38:981 (ISB thorax angles); Cirstea & Levin 2000, Brain 123:940 (trunk compensation in stroke)",
    ),
    w(
        "trunk_beyond_pct",
        "Time the trunk moved too far",
        "share of time with trunk excursion beyond the threshold",
        "%",
        0,
        [0.0, 100.0],
        None,
        Lower,
    )
    .defined(
        "Share of the exercise time with any trunk angle beyond the station's threshold.",
        "Wu et al. 2005, J Biomech 38:981 (ISB thorax angles); Cirstea & Levin 2000, Brain 123:940 (trunk compensation in stroke)",
    ),
    w(
        "trunk_compensated_movements_pct",
        "Turns helped by the trunk",
        "share of movements with trunk compensation",
        "%",
        0,
        [0.0, 100.0],
        None,
        Lower,
    )
    .defined(
        "Share of wheel movements during which the trunk moved beyond the threshold.",
        "Wu et al. 2005, J Biomech 38:981 (ISB thorax angles); Cirstea & Levin 2000, Brain 123:940 (trunk compensation in stroke)",
    ),
    w(
        "trunk_cues",
        "Reminders to sit up",
        "trunk cues given",
        "",
        0,
        [0.0, 10.0],
        None,
        Neither,
    )
    .defined(
        "Times the station asked the patient to sit up straight: the trunk stayed beyond the therapist's cue threshold for a second; at most one in 20 s.",
        "telerehab's own cue (docs/DESIGN.md, trunk compensation); Cirstea & Levin 2000, Brain 123:940 (trunk compensation in stroke)",
    ),
    w(
        "pct_in_lane",
        "Time in lane",
        "pct_in_lane",
        "%",
        0,
        [0.0, 100.0],
        None,
        Higher,
    )
    .defined(
        "Share of driving time with the car inside its lane.",
        "Jadhav 2004 thesis, section 3.3.4 (deviation from the road's centre as the performance measure)",
    ),
    w(
        "rms_lateral_m",
        "Distance from the lane's centre",
        "RMS lateral deviation",
        "m",
        2,
        [0.0, 2.0],
        None,
        Lower,
    )
    .defined(
        "Root mean square distance of the car from the lane's centre.",
        "Jadhav 2004 thesis, section 3.3.4 (deviation from the road's centre as the performance measure)",
    ),
    w(
        "heading_rms_error_deg",
        "Heading off the road's direction",
        "RMS heading error",
        "°",
        1,
        [0.0, 45.0],
        None,
        Lower,
    )
    .defined(
        "Root mean square angle between the car's heading and the road's direction.",
        "Jadhav 2004 thesis, section 3.3.4 (deviation from the road's centre as the performance measure)",
    ),
    w(
        "cone_hits",
        "Cones hit",
        "cone hits (count)",
        "",
        0,
        [0.0, 10.0],
        None,
        Lower,
    )
    .defined(
        "Cones the car touched.",
        "telerehab's own session record (docs/DESIGN.md)",
    ),
    w(
        "completion_time_s",
        "Time to finish",
        "completion time",
        "s",
        0,
        [0.0, 600.0],
        None,
        Neither,
    )
    .defined(
        "Time to reach the end of the course.",
        "telerehab's own session record (docs/DESIGN.md)",
    ),
    w(
        "tracking_rms_error_deg",
        "Distance from the angle asked",
        "RMS tracking error",
        "°",
        1,
        [0.0, 90.0],
        None,
        Lower,
    )
    .defined(
        "Root mean square difference between the wheel angle asked and the wheel's angle.",
        "Jadhav 2004 thesis, section 3.3.3 and Appendix E (tracking error of the dial)",
    ),
    w(
        "dial_rms_error_deg",
        "Dial: distance from the angle asked",
        "RMS dial angle error",
        "°",
        1,
        [0.0, 90.0],
        None,
        Lower,
    )
    .defined(
        "Root mean square difference between the dial's target angle and the wheel's needle.",
        "Jadhav 2004 thesis, section 3.3.3 and Appendix E (tracking error of the dial)",
    ),
    w(
        "dial_mean_abs_error_deg",
        "Dial: average distance from the angle asked",
        "mean absolute dial angle error",
        "°",
        1,
        [0.0, 90.0],
        None,
        Lower,
    )
    .defined(
        "Mean absolute difference between the dial's target angle and the wheel's needle.",
        "Jadhav 2004 thesis, section 3.3.3 and Appendix E (tracking error of the dial)",
    ),
    w(
        "strength_peak_left_nm",
        "Strength turning left, at its peak",
        "peak torque, left",
        "N·m",
        1,
        [0.0, 10.0],
        None,
        Higher,
    )
    .defined(
        "Highest torque turning left against the wheel's spring, the wheel held nearly still.",
        "telerehab's strength test: the spring's torque at the held wheel (docs/DESIGN.md)",
    ),
    w(
        "strength_sustained_left_nm",
        "Strength turning left, held 1 s",
        "torque held 1 s, left",
        "N·m",
        1,
        [0.0, 10.0],
        None,
        Higher,
    )
    .defined(
        "Highest torque turning left held for at least 1 s.",
        "telerehab's strength test: the spring's torque at the held wheel (docs/DESIGN.md)",
    ),
    w(
        "strength_peak_right_nm",
        "Strength turning right, at its peak",
        "peak torque, right",
        "N·m",
        1,
        [0.0, 10.0],
        None,
        Higher,
    )
    .defined(
        "Highest torque turning right against the wheel's spring, the wheel held nearly still.",
        "telerehab's strength test: the spring's torque at the held wheel (docs/DESIGN.md)",
    ),
    w(
        "strength_sustained_right_nm",
        "Strength turning right, held 1 s",
        "torque held 1 s, right",
        "N·m",
        1,
        [0.0, 10.0],
        None,
        Higher,
    )
    .defined(
        "Highest torque turning right held for at least 1 s.",
        "telerehab's strength test: the spring's torque at the held wheel (docs/DESIGN.md)",
    ),
    w(
        "assist_level_mean",
        "Help from the wheel (0 none, 1 full)",
        "assist level, mean",
        "",
        2,
        [0.0, 1.0],
        None,
        Lower,
    )
    .defined(
        "How much the wheel helped, mean over the exercise: 0 no help, 1 full help.",
        "Guidali et al. 2013, J Rehabil Res Dev 50(3):339-352",
    ),
    w(
        "patient_work_pct",
        "Patient's share of the work",
        "patient work share",
        "%",
        0,
        [0.0, 100.0],
        None,
        Higher,
    )
    .defined(
        "Patient's share of the mechanical work done on the wheel (the patient's and the assist's together).",
        "Guidali et al. 2013, J Rehabil Res Dev 50(3):339-352",
    ),
];

/// The words of measure `key`, if the table has it.
pub fn measure_words(key: &str) -> Option<&'static MeasureWords> {
    MEASURES.iter().find(|m| m.key == key)
}

/// `docs/MEASURES.md`: every measure of [`MEASURES`] with its definition and source, one
/// table, in reading order (written by `crates/station/tests/measures_doc.rs`).
pub fn measures_markdown() -> String {
    let cell = |s: &str| s.replace('|', "\\|");
    let mut out = String::from(
        "# Measures\n\n\
         Every measure a session stores: its stored key, the name a clinician reads, its unit, \
         which way is better, what it measures and where it comes from. Generated from the one \
         table of measure words, `crates/metrics/src/words.rs` (`MEASURES`); after changing it, \
         run `UPDATE_SNAPSHOTS=1 cargo test -p station --test measures_doc` and commit the diff.\n\n\
         Smoothness (SPARC, LDLJ) is scored only on discrete movements (from rest to rest, at \
         most 5 s; `crates/metrics/src/segment.rs`); reaction time only on unpredictable steps \
         (a dial's random jumps), a lane shift seen ahead giving an anticipation share instead \
         (`crates/metrics/src/robot.rs`). In an exercise whose target steps (the stepping dial, \
         the standard assessment's steps), a movement is the response to one step: from its \
         onset (the first run of the speed above 10 % of the response's peak that starts after \
         the step and lasts 0.1 s: a movement still going at the step or a tremor's burst is \
         no onset) to its rest before the next step; the per-movement measures (smoothness, \
         movement time, peak speed, speed peaks, evenness) are those of these responses, a \
         response cut by the next step left out.\n\n\
         | Key | Name | Unit | Better | Definition | Source |\n|---|---|---|---|---|---|\n",
    );
    for m in &MEASURES {
        let better = match m.better {
            Higher => "higher",
            Lower => "lower",
            Neither => "neither",
        };
        out.push_str(&format!(
            "| `{}` | {} | {} | {better} | {} | {} |\n",
            m.key,
            cell(m.name),
            cell(m.unit),
            cell(m.definition),
            cell(m.source)
        ));
    }
    out
}

/// A stored value of a measure the table lacks, rounded to 4 significant digits: never
/// `999.9999999999999`.
pub fn round_unknown(v: f64) -> f64 {
    if v == 0.0 || !v.is_finite() {
        return v;
    }
    let digits = 3 - v.abs().log10().floor() as i32;
    let scale = 10f64.powi(digits);
    (v * scale).round() / scale
}

/// How a session ended, one wording each, from the station's stored `end_reason` (its
/// `session::end_reason`): the same words on the caseload, in the sessions' list, in the
/// report and in the spreadsheet.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum EndKind {
    /// Ran as prescribed.
    Complete,
    /// The patient stopped it (Esc, window closed, stop signal).
    StoppedByPatient,
    /// Paused longer than the regimen allows.
    PausedTooLong,
    /// The patient's screen failed again and again.
    ScreenFailed,
    /// The wheel was unplugged.
    WheelUnplugged,
    /// An arm sensor was unplugged and not plugged back in time.
    ArmSensorUnplugged,
    /// The safety check switched the wheel's force off.
    SafetyStop,
    /// Still running (no end reported).
    Running,
    /// Ended without saying how (an older station, or a connection lost for good).
    Unreported,
    /// A reason these words do not know (a newer station).
    Other,
}

impl EndKind {
    /// Every kind, for the table served to the console.
    pub const ALL: [EndKind; 10] = [
        Self::Complete,
        Self::StoppedByPatient,
        Self::PausedTooLong,
        Self::ScreenFailed,
        Self::WheelUnplugged,
        Self::ArmSensorUnplugged,
        Self::SafetyStop,
        Self::Running,
        Self::Unreported,
        Self::Other,
    ];

    /// The kind of the stored `reason` (`None` while the session runs).
    pub fn of(reason: Option<&str>) -> Self {
        let Some(r) = reason.map(str::trim) else {
            return Self::Running;
        };
        let first = r.split(';').next().unwrap_or_default().trim();
        match first {
            "complete" => Self::Complete,
            r if r.starts_with("ended early") => Self::StoppedByPatient,
            "paused too long" => Self::PausedTooLong,
            r if r.starts_with("window lost") => Self::ScreenFailed,
            "wheel unplugged" => Self::WheelUnplugged,
            "arm sensor unplugged" => Self::ArmSensorUnplugged,
            r if r.starts_with("safety stop") => Self::SafetyStop,
            _ => Self::Other,
        }
    }

    /// The one wording: `Completed`, `Stopped early: wheel unplugged`.
    pub fn words(self) -> &'static str {
        match self {
            Self::Complete => "Completed",
            Self::StoppedByPatient => "Stopped early by the patient",
            Self::PausedTooLong => "Stopped early: paused too long",
            Self::ScreenFailed => "Stopped early: the screen failed",
            Self::WheelUnplugged => "Stopped early: wheel unplugged",
            Self::ArmSensorUnplugged => "Stopped early: arm sensor unplugged",
            Self::SafetyStop => "Stopped early: safety stop (the wheel's force was switched off)",
            Self::Running => "Still running",
            Self::Unreported => "Ended; how was not reported",
            Self::Other => "Stopped early",
        }
    }
}

/// The wording of a stored `end_reason`, with "; the recording stopped early" when the
/// station's recording stopped before the session did.
pub fn end_words(reason: Option<&str>) -> String {
    let kind = EndKind::of(reason);
    let recording = reason.is_some_and(|r| r.contains("recording stopped"));
    if recording {
        format!("{}; the recording stopped early", kind.words())
    } else {
        kind.words().to_owned()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_measure_has_one_entry_a_range_and_a_plain_name_without_engineering_words() {
        for (i, m) in MEASURES.iter().enumerate() {
            assert!(
                MEASURES[..i].iter().all(|o| o.key != m.key),
                "{} twice",
                m.key
            );
            assert!(m.range[0] < m.range[1], "{}", m.key);
            for word in ["SPARC", "LDLJ", "RMS", "_", "metric"] {
                assert!(!m.name.contains(word), "{}: {word} in {}", m.key, m.name);
            }
            assert!(
                m.decimals <= 2,
                "{}: more decimals than are meaningful",
                m.key
            );
        }
        assert!(measure_words("sparc_median").unwrap().noise.is_some());
    }

    /// Issue 42: every measure carries its definition and its source, so a measure added to
    /// the table without them fails here.
    #[test]
    fn every_measure_has_a_definition_and_a_source() {
        for m in &MEASURES {
            assert!(
                m.definition.len() > 20 && m.definition.ends_with('.'),
                "{}: no definition (a sentence ending in '.'), see MeasureWords::defined",
                m.key
            );
            assert!(m.source.len() > 10, "{}: no source", m.key);
            assert!(
                !m.definition.contains('\n') && !m.source.contains('\n'),
                "{}: one line each",
                m.key
            );
        }
        let doc = measures_markdown();
        assert!(doc.contains("| `sparc_median` | Smoothness"), "{doc}");
        assert_eq!(
            doc.lines().filter(|l| l.starts_with("| `")).count(),
            MEASURES.len()
        );
    }

    #[test]
    fn numbers_are_rounded_to_the_meaningful_decimals_with_their_unit() {
        let rom = measure_words("wheel_rom_deg").unwrap();
        assert_eq!(rom.format(268.42), "268 °");
        let lane = measure_words("pct_in_lane").unwrap();
        assert_eq!(lane.format(100.0), "100 %");
        assert_eq!(lane.format(99.96), "100 %");
        let torque = measure_words("strength_sustained_left_nm").unwrap();
        assert_eq!(torque.format(-0.058), "-0.1 N·m");
        assert_eq!(torque.format(-0.04), "0.0 N·m", "no minus zero");
        assert_eq!(lane.round(999.9999999999999), 1000.0);
        assert_eq!(round_unknown(999.9999999999999), 1000.0);
        assert_eq!(round_unknown(0.066_123_4), 0.06612);
        assert_eq!(lane.header(), "Time in lane (%)");
        assert_eq!(measure_words("cone_hits").unwrap().header(), "Cones hit");
    }

    #[test]
    fn each_end_reason_has_one_wording() {
        assert_eq!(end_words(Some("complete")), "Completed");
        assert_eq!(
            end_words(Some(
                "ended early by the patient (Esc, window closed or stop signal)"
            )),
            "Stopped early by the patient"
        );
        assert_eq!(
            end_words(Some("wheel unplugged")),
            "Stopped early: wheel unplugged"
        );
        assert_eq!(
            EndKind::of(Some("arm sensor unplugged")),
            EndKind::ArmSensorUnplugged
        );
        assert_eq!(
            EndKind::of(Some("safety stop: torque faded out on a fault")),
            EndKind::SafetyStop
        );
        assert_eq!(
            end_words(Some("complete; recording stopped: disk full at 12 s")),
            "Completed; the recording stopped early"
        );
        assert_eq!(end_words(None), "Still running");
        for k in EndKind::ALL {
            for word in ["ended early", "Esc", "torque"] {
                assert!(!k.words().contains(word), "{k:?}");
            }
        }
    }
}
