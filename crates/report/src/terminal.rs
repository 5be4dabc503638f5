//! The human summary printed at the end of a session.

use session::SessionReport;
use session::timing::Percentiles;
use std::fmt::Write as _;

/// Delivery figures of the therapist link, for the report.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LinkReport {
    /// Where the summaries went.
    pub address: String,
    /// Summaries produced.
    pub produced: u64,
    /// Summaries written to the network at least once.
    pub sent: u64,
    /// Summaries the therapist acknowledged.
    pub acked: u64,
    /// Summaries not delivered when the session ended.
    pub undelivered: u64,
    /// The last link error, if any.
    pub last_error: Option<String>,
    /// Summaries kept in the on-disk queue for the next run or `telerehab sync` (`None`
    /// without a queue, or when everything was delivered).
    pub queued: Option<u64>,
    /// What became of a regimen the hub prescribed during the session, if one came.
    pub regimen: Option<String>,
    /// The recording's upload to the hub, if the station queued one.
    pub upload: Option<String>,
}

/// Append one line to the report (a `String` never fails to take it).
macro_rules! line {
    ($s:expr, $($arg:tt)*) => {{
        let _ = writeln!($s, $($arg)*);
    }};
}

/// Render the end-of-session summary as text: one section after another.
pub fn render(r: &SessionReport, link: Option<&LinkReport>) -> String {
    let mut s = String::new();
    outcome(&mut s, r);
    loop_timing(&mut s, r);
    exercise(&mut s, r);
    each_exercise(&mut s, r);
    torque(&mut s, r);
    movement(&mut s, r);
    arm(&mut s, r);
    delivery(&mut s, r, link);
    s
}

/// How long the session ran, why it ended, its torque ceiling and its tick count.
fn outcome(s: &mut String, r: &SessionReport) {
    let duration_s = r.haptic.ticks as f64 / r.loop_rate_hz;
    let early = if r.haptic.stopped_early {
        " (stopped early)"
    } else {
        ""
    };
    line!(
        s,
        "── session summary ─────────────────────────────────────"
    );
    line!(
        s,
        "duration            {duration_s:.2} s session time{early}"
    );
    if r.haptic.wheel_replugs > 0 {
        line!(
            s,
            "wheel               unplugged and plugged back {} time(s): the exercise paused at zero torque, resumed with a soft start",
            r.haptic.wheel_replugs
        );
    }
    if r.haptic.write_failures > 0 {
        line!(
            s,
            "wheel commands      {} refused by the wheel (a run over {} ms stops the session)",
            r.haptic.write_failures,
            session::plant::MAX_REFUSED_WRITES_NS / 1_000_000
        );
    }
    if let Some(fault) = r.haptic.wheel_fault {
        line!(s, "ended because       {fault} (torque faded to zero)");
    }
    line!(s, "ended               {}", r.end_reason());
    let active_s = (r.recorder.road_ticks + r.recorder.dial_ticks) as f64 / r.loop_rate_hz;
    let paused_s = r.recorder.paused_ticks as f64 / r.loop_rate_hz;
    line!(
        s,
        "active time         {active_s:.1} s of exercise; the patient's stops {paused_s:.1} s (not counted)"
    );
    if let Some(c) = &r.haptic.ceiling {
        line!(s, "{c}");
    }
    if let Some((rate_hz, gap_ms)) = r.recorder.motor_update_rate() {
        let policy = r.haptic.motor_update_policy_hz.map_or(String::new(), |p| {
            format!(" (its rate policy allows {p:.0})")
        });
        line!(
            s,
            "motor updates       {rate_hz:.1} /s reached the motor{policy}; worst gap {gap_ms:.1} ms"
        );
    }
    if r.haptic.skipped_deadlines > 0 {
        line!(
            s,
            "skipped deadlines   {} (after stalls; the watchdog faded the torque)",
            r.haptic.skipped_deadlines
        );
    }
    line!(
        s,
        "ticks               {} ({} recorded, {} dropped)",
        r.haptic.ticks,
        r.recorder.records,
        r.haptic.dropped_records
    );
}

/// Each exercise's own results, one line each (a session of one exercise has none: its
/// results are the session's).
fn each_exercise(s: &mut String, r: &SessionReport) {
    let exercises = &r.recorder.exercises;
    if exercises.len() < 2 {
        return;
    }
    for e in exercises {
        line!(
            s,
            "exercise {:<10} {} ({}): {:.1} of {:.0} s; {}",
            e.index + 1,
            e.name,
            e.kind,
            e.active_s,
            e.prescribed_s,
            crate::html::exercise_words(e)
        );
    }
}

/// The loop's timing: on the wall clock in real time, the speed-up as fast as possible.
fn loop_timing(s: &mut String, r: &SessionReport) {
    let timing = &r.recorder.timing;
    if r.real_time {
        let rate = r.haptic.ticks as f64 / r.haptic.wall_s.max(1e-9);
        line!(
            s,
            "loop rate           {rate:.1} Hz achieved (nominal {:.0} Hz), wall {:.2} s",
            r.loop_rate_hz,
            r.haptic.wall_s
        );
        percentiles(s, "period error       ", timing.period_error());
        percentiles(s, "deadline lateness  ", timing.lateness());
        percentiles(s, "tick compute       ", timing.work());
        let prio = if r.haptic.realtime_priority {
            "granted"
        } else {
            "not granted (normal scheduling)"
        };
        line!(s, "real-time priority  {prio}");
    } else {
        let duration_s = r.haptic.ticks as f64 / r.loop_rate_hz;
        line!(
            s,
            "loop pacing         --speed max: {:.0}× real time, wall {:.2} s",
            duration_s / r.haptic.wall_s.max(1e-9),
            r.haptic.wall_s
        );
        percentiles(s, "tick compute       ", timing.work());
    }
}

/// One line of timing percentiles under `label`.
fn percentiles(s: &mut String, label: &str, p: Percentiles) {
    line!(
        s,
        "{label} p50 {:.1} µs  p99 {:.1} µs  max {:.1} µs",
        p.p50_us,
        p.p99_us,
        p.max_us
    );
}

/// The course and the patient's scores on it.
fn exercise(s: &mut String, r: &SessionReport) {
    let rec = &r.recorder;
    let score = &rec.last.score;
    line!(
        s,
        "exercises           {} ({} run)",
        r.exercises,
        score.exercise_index + 1
    );
    if rec.paused_ticks > 0 {
        line!(
            s,
            "paused              {:.1} s (not counted in the exercise time)",
            rec.paused_ticks as f64 / r.loop_rate_hz
        );
    }
    if r.haptic.rests > 0 {
        line!(
            s,
            "rests               {} ({:.1} s, within the pauses)",
            r.haptic.rests,
            r.haptic.rest_s
        );
    }
    if r.haptic.paused_too_long {
        line!(s, "ended               paused too long");
    }
    if rec.road_ticks > 0 {
        line!(
            s,
            "RMS lateral dev.    {:.3} m (max {:.3} m)",
            score.rms_lateral_m,
            score.max_lateral_m
        );
        line!(
            s,
            "time in lane        {:.1} %, cones hit {}",
            score.pct_in_lane,
            score.cone_hits
        );
    }
    let named = &rec.measures.named;
    // A strength test has no car either, but no needles: no dial line for it alone.
    let strength_alone = named.keys().any(|k| k.starts_with("strength_"))
        && !named.contains_key("dial_rms_error_deg");
    if rec.dial_ticks > 0 && !strength_alone {
        line!(
            s,
            "dial tracking       RMS error {:.2}° (thesis Appendix E: about 3°)",
            score.dial_rms_error_deg
        );
    }
    for side in ["left", "right"] {
        let m = |what: &str| named.get(&format!("strength_{what}_{side}_nm")).copied();
        if let (Some(peak), Some(held)) = (m("peak"), m("sustained")) {
            let ceiling = named.get(&format!("strength_{side}_at_ceiling")) == Some(&1.0);
            line!(
                s,
                "strength {side:<5}      peak {peak:.2} N·m, sustained 1 s {held:.2} N·m{}",
                if ceiling {
                    " (reached the ceiling)"
                } else {
                    ""
                }
            );
        }
    }
}

/// The torque the patient felt: peak, clipping, watchdog faults and the assist.
fn torque(s: &mut String, r: &SessionReport) {
    let rec = &r.recorder;
    let ticks = rec.records.max(1) as f64;
    line!(
        s,
        "torque              max |τ| {:.3} N·m, clipped {:.2} % of ticks, watchdog faults {} ticks",
        rec.max_abs_torque_nm,
        100.0 * rec.clipped_ticks as f64 / ticks,
        rec.fault_ticks
    );
    if rec.assist_ticks > 0 {
        let assisted = rec.assist_ticks as f64;
        line!(
            s,
            "assist              mean level {:.2}, RMS error {:.2}°, saturated {:.1} % of ticks",
            rec.assist_level_sum / assisted,
            (rec.assist_error_sq_sum / assisted).sqrt().to_degrees(),
            100.0 * rec.assist_saturated_ticks as f64 / assisted
        );
    }
}

/// The wheel's movements: how many, how smooth, how fast, how long active, and how much of
/// the work was the patient's.
fn movement(s: &mut String, r: &SessionReport) {
    let m = &r.recorder.measures;
    let n = |name: &str| m.named.get(name).copied();
    if let Some(e) = &m.error {
        line!(s, "movements           not measured: {e}");
    }
    if let (Some(count), Some(active)) = (n("movements"), n("active_s")) {
        let smooth = match (n("sparc_median"), n("ldlj_median")) {
            (Some(sparc), Some(ldlj)) => {
                format!(", smoothness SPARC {sparc:.2}, LDLJ {ldlj:.2} (medians)")
            }
            _ => String::new(),
        };
        line!(
            s,
            "movements           {count:.0} in {active:.1} s active{smooth}"
        );
    }
    if let (Some(peak), Some(time), Some(peaks)) = (
        n("movement_peak_speed_deg_s_median"),
        n("movement_time_s_median"),
        n("speed_peaks_median"),
    ) {
        line!(
            s,
            "a typical movement  {time:.2} s, peak speed {peak:.0}°/s, {peaks:.0} speed peaks (medians)"
        );
    }
    if let Some(pct) = n("patient_work_pct") {
        line!(
            s,
            "patient's work      {pct:.0} % of the work moving the wheel, {:.0} % by the assist",
            100.0 - pct
        );
    }
}

/// The arm: range of motion, why sensing stopped, and the calibrated segment lengths.
fn arm(s: &mut String, r: &SessionReport) {
    if let Some(rom) = r.haptic.range_of_motion_rad.map(|r| r.map(f64::to_degrees)) {
        line!(
            s,
            "arm range of motion shoulder elevation {:.1}°, plane {:.1}°, rotation {:.1}°; elbow flexion {:.1}°, pronation {:.1}°",
            rom[0],
            rom[1],
            rom[2],
            rom[3],
            rom[4]
        );
    }
    if let Some(why) = &r.haptic.arm_failure {
        line!(s, "arm sensing         off: {why}");
    }
    match &r.recorder.arm_calibration {
        Some(Ok(c)) => {
            let truth = r.sim_arm_truth_m.map_or(String::new(), |(u, f)| {
                format!(" (simulated truth {:.3} / {:.3} m)", u, f)
            });
            line!(
                s,
                "arm calibration     upper arm {:.3} ± {:.3} m, forearm {:.3} ± {:.3} m{truth}",
                c.upper_arm_m,
                c.upper_arm_se_m,
                c.forearm_m,
                c.forearm_se_m
            );
            for w in &c.warnings {
                line!(s, "                    note: {w}");
            }
        }
        Some(Err(e)) => line!(s, "arm calibration     not this time: {e}"),
        None => {}
    }
}

/// Where the session went: the recording and the therapist.
fn delivery(s: &mut String, r: &SessionReport, link: Option<&LinkReport>) {
    let rec = &r.recorder;
    match (&r.record, rec.mcap_bytes) {
        (Some(p), Some(b)) => {
            line!(
                s,
                "recording           {} ({:.2} MB)",
                p.display(),
                b as f64 / 1e6
            );
            // Stopped early but finished (low on disk space): readable as it is.
            if let (Some(t), Some(e)) = (rec.recording_stopped_s, &rec.error) {
                line!(
                    s,
                    "                    recording stopped at {t:.1} s (the session went on): {e}"
                );
            }
        }
        (Some(p), None) => {
            line!(
                s,
                "recording           {} FAILED: {}",
                p.display(),
                rec.error.as_deref().unwrap_or("unknown")
            );
            if let Some(t) = rec.recording_stopped_s {
                line!(
                    s,
                    "                    recording stopped at {t:.1} s (the session went on); \
                     `telerehab recover {}` keeps what reached the disk",
                    p.display()
                );
            }
        }
        (None, _) => line!(s, "recording           off"),
    }
    match link {
        Some(l) => {
            line!(
                s,
                "therapist {:<9} {} summaries: {} sent, {} acknowledged, {} NOT delivered",
                l.address,
                l.produced,
                l.sent,
                l.acked,
                l.undelivered
            );
            if let Some(e) = &l.last_error {
                line!(s, "therapist link      last error: {e}");
            }
            if let Some(r) = &l.regimen {
                line!(s, "therapist regimen   {r}");
            }
            if let Some(u) = &l.upload {
                line!(s, "recording upload    {u}");
            }
            if let Some(n) = l.queued {
                line!(
                    s,
                    "therapist queue     {n} summaries kept on disk; sent at the next run or by \
                     `telerehab sync`"
                );
            }
        }
        None => line!(
            s,
            "therapist           off ({} summaries produced)",
            r.summaries
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use haptic_wheel::{CeilingReport, WheelFault};
    use record::ArmCalibrationSample;
    use session::haptic::HapticOutcome;
    use session::outcome::RecorderOutcome;
    use session::timing::TimingStats;
    use std::path::PathBuf;

    /// A real-time session on a real wheel that shows every line the report can have.
    fn everything() -> SessionReport {
        let mut timing = TimingStats::new(1_000_000);
        for i in 1..=100u64 {
            timing.add(i * 700, 1_000_000 + i * 300 - 15_000, 40_000 + i * 100);
        }
        let mut recorder = RecorderOutcome {
            records: 9_000,
            timing,
            max_abs_torque_nm: 1.234_5,
            clipped_ticks: 45,
            road_ticks: 6_000,
            dial_ticks: 2_000,
            paused_ticks: 1_500,
            fault_ticks: 12,
            arm_lost_ns: 0,
            assist_ticks: 4_000,
            assist_level_sum: 1_800.0,
            assist_error_sq_sum: 4_000.0 * 0.03_f64.powi(2),
            assist_saturated_ticks: 80,
            arm_calibration: Some(Ok(ArmCalibrationSample {
                upper_arm_m: 0.301,
                upper_arm_se_m: 0.004,
                forearm_m: 0.327,
                forearm_se_m: 0.006,
                warnings: vec!["turn the wheel further".into()],
                ..Default::default()
            })),
            mcap_bytes: Some(2_345_678),
            measures: measures::Measures {
                named: [
                    ("movements", 14.0),
                    ("active_s", 5.25),
                    ("sparc_median", -1.734),
                    ("ldlj_median", -6.21),
                    ("movement_peak_speed_deg_s_median", 48.2),
                    ("movement_time_s_median", 0.84),
                    ("speed_peaks_median", 2.0),
                    ("patient_work_pct", 71.6),
                ]
                .into_iter()
                .map(|(k, v)| (k.to_owned(), v))
                .collect(),
                ..Default::default()
            },
            ..Default::default()
        };
        recorder.last.score.exercise_index = 2;
        recorder.last.score.rms_lateral_m = 0.123_4;
        recorder.last.score.max_lateral_m = 0.456_7;
        recorder.last.score.pct_in_lane = 97.25;
        recorder.last.score.cone_hits = 3;
        recorder.last.score.dial_rms_error_deg = 2.75;
        // A G29 held to 500 updates a second by its driver, over 8 s of active time.
        recorder.active_ns = 8_000_000_000;
        recorder.active_motor_updates = 3_996;
        recorder.last.wheel.motor_update_worst_gap_ms = Some(2.004);
        SessionReport {
            haptic: HapticOutcome {
                ticks: 9_000,
                dropped_records: 2,
                stopped_early: true,
                realtime_priority: true,
                wall_s: 9.01,
                range_of_motion_rad: Some([0.1, 0.2, 0.3, 0.4, 0.5]),
                arm_failure: Some("an IMU stopped answering (unplugged)".into()),
                wheel_fault: Some(WheelFault::Silent),
                wheel_replugs: 0,
                write_failures: 0,
                skipped_deadlines: 4,
                ceiling: Some(CeilingReport {
                    motor_nm: 2.5,
                    usable_max_nm: 2.5,
                    ceiling_nm: 1.5,
                    fraction_of_motor: 0.6,
                    assumed: false,
                }),
                motor_update_policy_hz: Some(500.0),
                rests: 0,
                rest_s: 0.0,
                paused_too_long: false,
                arm_sensor_unplugged: false,
                window_lost: false,
                exercise_scores: Vec::new(),
            },
            recorder,
            loop_rate_hz: 1000.0,
            record: Some(PathBuf::from("out/session.mcap")),
            summaries: 9,
            real_time: true,
            exercises: 4,
            sim_arm_truth_m: Some((0.3, 0.33)),
        }
    }

    /// A simulated session as fast as possible whose recording failed, without a therapist.
    fn as_fast_as_possible() -> SessionReport {
        let mut r = everything();
        r.real_time = false;
        r.haptic.stopped_early = false;
        r.haptic.realtime_priority = false;
        r.haptic.wall_s = 0.75;
        r.haptic.wheel_fault = None;
        r.haptic.skipped_deadlines = 0;
        r.haptic.range_of_motion_rad = None;
        r.haptic.arm_failure = None;
        r.recorder.paused_ticks = 0;
        r.recorder.dial_ticks = 0;
        r.recorder.assist_ticks = 0;
        r.recorder.arm_calibration = Some(Err("too little motion".into()));
        r.recorder.measures.named.clear();
        r.recorder.measures.error =
            Some("the exercise ran too briefly to measure (1 samples at 100 Hz)".into());
        r.recorder.mcap_bytes = None;
        r.recorder.error = Some("disk full".into());
        r
    }

    /// The smallest report: nothing optional happened.
    fn bare() -> SessionReport {
        SessionReport {
            haptic: HapticOutcome::default(),
            recorder: RecorderOutcome::default(),
            loop_rate_hz: 1000.0,
            record: None,
            summaries: 0,
            real_time: false,
            exercises: 1,
            sim_arm_truth_m: None,
        }
    }

    /// The report's text is the checked-in snapshot: a change to it shows as a diff of
    /// `src/snapshots/report_*.txt` (scripts and people read these lines).
    #[test]
    fn reports_match_the_snapshots() {
        let link = LinkReport {
            address: "127.0.0.1:7878".into(),
            produced: 9,
            sent: 9,
            acked: 8,
            undelivered: 1,
            last_error: Some("connection reset".into()),
            queued: Some(1),
            regimen: Some("p-1-v2 kept for the next session".into()),
            upload: Some("1 uploaded (2.35 MB sent), 0 still queued".into()),
        };
        let cases = [
            ("report_everything", render(&everything(), Some(&link))),
            ("report_max_speed", render(&as_fast_as_possible(), None)),
            ("report_bare", render(&bare(), None)),
        ];
        let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("src/snapshots");
        let update = std::env::var_os("UPDATE_SNAPSHOTS").is_some_and(|v| v == "1");
        let mut stale = Vec::new();
        for (name, now) in cases {
            let file = dir.join(format!("{name}.txt"));
            if update {
                std::fs::create_dir_all(&dir).unwrap();
                std::fs::write(&file, &now).unwrap();
            } else if std::fs::read_to_string(&file).ok().as_deref() != Some(now.as_str()) {
                stale.push(file.display().to_string());
            }
        }
        assert!(
            stale.is_empty(),
            "the session report changed for {stale:?}; if that is intended, run \
             `UPDATE_SNAPSHOTS=1 cargo test -p station --lib report` and commit the diff"
        );
    }
}
