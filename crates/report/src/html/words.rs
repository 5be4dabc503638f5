//! The report's words for what a recording holds: sessions by date and time, exercises by the
//! names the patient saw, the kind of exercise trends compare, how a session ended and what
//! its arm set-up found.

use super::session::SessionData;
use regimen::exercise_kind;

/// The `end_reason` of a session that ran as prescribed (`session::end_reason::COMPLETE`).
const COMPLETE: &str = session::end_reason::COMPLETE;

/// Months as a clinician writes them.
const MONTHS: [&str; 12] = [
    "Jan", "Feb", "Mar", "Apr", "May", "Jun", "Jul", "Aug", "Sep", "Oct", "Nov", "Dec",
];

/// `(year, month 1–12, day, hour, minute)` of `unix_ns`, UTC.
fn civil(unix_ns: u64) -> (u64, usize, u64, u64, u64) {
    let (y, m, d, h, min, _) = civil_s(unix_ns);
    (y, m, d, h, min)
}

/// [`civil`] with the second.
fn civil_s(unix_ns: u64) -> (u64, usize, u64, u64, u64, u64) {
    let t = std::time::UNIX_EPOCH + std::time::Duration::from_nanos(unix_ns);
    let s = humantime::format_rfc3339_seconds(t).to_string();
    let n = |a: usize, b: usize| s.get(a..b).and_then(|d| d.parse().ok()).unwrap_or(0);
    (
        n(0, 4),
        n(5, 7) as usize,
        n(8, 10),
        n(11, 13),
        n(14, 16),
        n(17, 19),
    )
}

/// `27 Nov 2026`.
pub fn date(unix_ns: u64) -> String {
    let (y, m, d, _, _) = civil(unix_ns);
    format!("{d} {} {y}", MONTHS[m.clamp(1, 12) - 1])
}

/// `27 Nov 2026, 08:51 UTC`: a session named by when it started.
pub fn date_time(unix_ns: u64) -> String {
    let (_, _, _, h, min) = civil(unix_ns);
    format!("{}, {h:02}:{min:02} UTC", date(unix_ns))
}

/// `27 Nov 08:51`: a session on a chart's axis or a table's column.
pub fn short_date_time(unix_ns: u64) -> String {
    let (_, m, d, h, min) = civil(unix_ns);
    format!("{d} {} {h:02}:{min:02}", MONTHS[m.clamp(1, 12) - 1])
}

/// Labels of sessions on an axis or in a table's columns: [`short_date_time`], with the
/// seconds when two would read the same.
pub fn session_labels(starts_unix_ns: &[u64]) -> Vec<String> {
    let labels: Vec<String> = starts_unix_ns.iter().map(|&t| short_date_time(t)).collect();
    let clash = labels
        .iter()
        .enumerate()
        .any(|(i, l)| labels[..i].contains(l));
    if !clash {
        return labels;
    }
    starts_unix_ns
        .iter()
        .map(|&t| format!("{}:{:02}", short_date_time(t), civil_s(t).5))
        .collect()
}

/// `s` with its first letter lower-case, to go on after other words ("Ended early …" →
/// "ended early …"; the rest as written: "Esc" stays).
pub fn continuing(s: &str) -> String {
    let mut chars = s.chars();
    chars.next().map_or_else(String::new, |first| {
        first.to_lowercase().chain(chars).collect()
    })
}

/// A kind as a heading: `Road exercises`, `Dial exercises`, `Road and dial exercises`.
pub fn kind_title(kind: &str) -> String {
    let words: Vec<String> = kind
        .split('+')
        .map(|k| match k {
            "road" | "dial" => k.to_owned(),
            other => session::words::plain_name(other).to_lowercase(),
        })
        .collect();
    session::words::capitalised(&format!("{} exercises", words.join(" and ")))
}

/// The short names of a session's exercises in order: as its results name them, else as its
/// regimen prescribed them, else its one exercise.
pub fn exercise_shorts(s: &SessionData) -> Vec<String> {
    if !s.exercises.is_empty() {
        s.exercises.iter().map(|e| e.kind.clone()).collect()
    } else if !s.regimen_kinds.is_empty() {
        s.regimen_kinds.clone()
    } else {
        vec![s.exercise.clone()]
    }
}

/// The session's exercises in the patient's words: `Sine road, then Dial sine`.
pub fn exercises_in_words(s: &SessionData) -> String {
    let names: Vec<String> = if s.exercises.is_empty() {
        exercise_shorts(s)
            .iter()
            .map(|k| session::words::plain_name(k))
            .collect()
    } else {
        named_with_sweeps_grouped(&s.exercises)
    };
    names.join(", then ")
}

/// The exercises' names, the consecutive levels of one haptic sweep as one ("Haptic sweep of
/// the spring, 6 levels from 0 to 1 N·m/rad").
fn named_with_sweeps_grouped(exercises: &[record::ExerciseResult]) -> Vec<String> {
    let level_of = |e: &record::ExerciseResult| {
        e.scores
            .iter()
            .find_map(|(k, v)| exercises::SweepParameter::of_level_measure(k).map(|p| (p, *v)))
    };
    let mut out = Vec::new();
    let mut i = 0;
    while i < exercises.len() {
        let Some((p, first)) = level_of(&exercises[i]) else {
            out.push(exercises[i].name.clone());
            i += 1;
            continue;
        };
        let run = exercises[i..]
            .iter()
            .take_while(|e| level_of(e).is_some_and(|(q, _)| q == p))
            .count();
        let last = level_of(&exercises[i + run - 1]).map_or(first, |l| l.1);
        out.push(format!(
            "Haptic sweep of the {}, {run} level{} from {first} to {last} {}",
            p.name(),
            if run == 1 { "" } else { "s" },
            p.unit()
        ));
        i += run;
    }
    out
}

/// The session's kind for trends: its exercises' kinds in order, repeats left out, joined by
/// `+` (`road`, `dial+road`).
pub fn session_kind(s: &SessionData) -> String {
    let mut kinds: Vec<String> = Vec::new();
    for k in exercise_shorts(s).iter().map(|k| exercise_kind(k)) {
        if !kinds.contains(&k) {
            kinds.push(k);
        }
    }
    kinds.join("+")
}

/// Whether the session ran as prescribed (ended `complete`): only these are trended.
pub fn ran_as_prescribed(s: &SessionData) -> bool {
    s.end_reason.trim() == COMPLETE
}

/// Whom the report is for: the pseudonym the clinic knows, or that no clinic paired the
/// station (never the station's internal patient id).
pub fn patient(s: &SessionData) -> String {
    match &s.clinic {
        Some(c) if !c.patient_pseudonym.is_empty() => c.patient_pseudonym.clone(),
        Some(_) => "not named by the clinic (the station was paired by an older hub)".to_owned(),
        None => "not paired with a clinic".to_owned(),
    }
}

/// The arm calibration line: the segment lengths the session's arm set-up found, with their
/// uncertainty, how well the fit closes, and what to do about any warning it gave.
pub fn arm_line(arm: &record::ArmCalibrationSample) -> String {
    // One decimal, never "-0.0".
    let tenth = |x: f64| format!("{:.1}", (x * 10.0).round() / 10.0 + 0.0);
    let cm = |m: f64| tenth(m * 100.0);
    let found = [arm.upper_arm_m, arm.forearm_m]
        .iter()
        .all(|m| m.is_finite() && *m > 0.0);
    let mut line = if found {
        let quality = if arm.rms_residual_m <= 0.01 && arm.condition_number < 200.0 {
            "a good fit"
        } else {
            "a poor fit"
        };
        format!(
            "Arm calibration: upper arm {} cm (± {}), forearm {} cm (± {}); the fit closes to \
             {} mm (RMS) over {:.0} samples, {quality}.",
            cm(arm.upper_arm_m),
            cm(arm.upper_arm_se_m),
            cm(arm.forearm_m),
            cm(arm.forearm_se_m),
            tenth(arm.rms_residual_m * 1000.0),
            arm.samples,
        )
    } else {
        // A fit that found no arm gives no lengths to read.
        format!(
            "Arm calibration: no arm lengths found over {:.0} samples.",
            arm.samples
        )
    };
    for w in &arm.warnings {
        line.push_str(&format!(" To check: {}.", w.trim_end_matches('.')));
    }
    line
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_arm_fit_that_found_no_arm_gives_no_lengths_and_none_reads_minus_zero() {
        let none = record::ArmCalibrationSample {
            upper_arm_m: -1e-5,
            forearm_m: 0.0,
            samples: 55.0,
            warnings: vec!["the upper arm length -0.0 mm is not a human one".into()],
            ..Default::default()
        };
        let line = arm_line(&none);
        assert!(
            line.starts_with("Arm calibration: no arm lengths found over 55 samples."),
            "{line}"
        );
        let found = record::ArmCalibrationSample {
            upper_arm_m: 0.305,
            forearm_m: 0.26,
            upper_arm_se_m: -0.000_2,
            samples: 60.0,
            ..Default::default()
        };
        let line = arm_line(&found);
        assert!(line.contains("upper arm 30.5 cm (± 0.0)"), "{line}");
        assert!(!line.contains("-0.0"), "{line}");
    }

    #[test]
    fn sessions_are_named_by_date_and_time_in_words() {
        // 2026-11-27T08:51:25Z
        let ns = 1_795_769_485_000_000_000;
        assert_eq!(date_time(ns), "27 Nov 2026, 08:51 UTC");
        assert_eq!(short_date_time(ns), "27 Nov 08:51");
        assert_eq!(date(ns), "27 Nov 2026");
        assert_eq!(
            session_labels(&[ns, ns + 60_000_000_000]),
            ["27 Nov 08:51", "27 Nov 08:52"]
        );
        assert_eq!(
            session_labels(&[ns, ns + 7_000_000_000]),
            ["27 Nov 08:51:25", "27 Nov 08:51:32"],
            "the same minute: with seconds"
        );
        assert_eq!(continuing("Ended early (Esc)"), "ended early (Esc)");
    }

    #[test]
    fn kinds_group_roads_and_dials_and_read_as_headings() {
        assert_eq!(exercise_kind("sine-road"), "road");
        assert_eq!(exercise_kind("slalom"), "road");
        assert_eq!(exercise_kind("dial-step"), "dial");
        assert_eq!(kind_title("road"), "Road exercises");
        assert_eq!(kind_title("dial+road"), "Dial and road exercises");
    }

    #[test]
    fn the_arm_line_gives_lengths_in_cm_and_judges_the_fit() {
        let mut arm = record::ArmCalibrationSample {
            upper_arm_m: 0.305,
            forearm_m: 0.262,
            upper_arm_se_m: 0.004,
            forearm_se_m: 0.003,
            rms_residual_m: 0.0042,
            condition_number: 35.0,
            samples: 4000.0,
            ..Default::default()
        };
        let line = arm_line(&arm);
        assert!(line.contains("upper arm 30.5 cm (± 0.4)"), "{line}");
        assert!(line.contains("forearm 26.2 cm"), "{line}");
        assert!(
            line.contains("4.2 mm") && line.contains("a good fit"),
            "{line}"
        );
        arm.rms_residual_m = 0.03;
        arm.warnings = vec!["the grip moved only 20 mm; turn the wheel further".into()];
        let line = arm_line(&arm);
        assert!(
            line.contains(
                "a poor fit. To check: the grip moved only 20 mm; turn the wheel further."
            ),
            "{line}"
        );
    }
}
