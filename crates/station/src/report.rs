//! The human summary printed at the end of a session.

use crate::session::SessionReport;
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
}

/// Render the end-of-session summary as text.
pub fn render(r: &SessionReport, link: Option<&LinkReport>) -> String {
    let mut s = String::new();
    macro_rules! line {
        ($($arg:tt)*) => {{
            let _ = writeln!(s, $($arg)*);
        }};
    }
    let rec = &r.recorder;
    let last = &rec.last;
    let ticks = rec.records.max(1) as f64;
    let duration_s = r.haptic.ticks as f64 / r.loop_rate_hz;
    let early = if r.haptic.stopped_early {
        " (stopped early)"
    } else {
        ""
    };
    line!("── session summary ─────────────────────────────────────");
    line!("duration            {duration_s:.2} s session time{early}");
    if let Some(fault) = r.haptic.wheel_fault {
        line!("ended because       {fault} (torque faded to zero)");
    }
    if let Some(c) = &r.haptic.ceiling {
        line!("{c}");
    }
    if r.haptic.skipped_deadlines > 0 {
        line!(
            "skipped deadlines   {} (after stalls; the watchdog faded the torque)",
            r.haptic.skipped_deadlines
        );
    }
    line!(
        "ticks               {} ({} recorded, {} dropped)",
        r.haptic.ticks,
        rec.records,
        r.haptic.dropped_records
    );
    if r.real_time {
        let rate = r.haptic.ticks as f64 / r.haptic.wall_s.max(1e-9);
        let (pe, late, work) = (
            rec.timing.period_error(),
            rec.timing.lateness(),
            rec.timing.work(),
        );
        line!(
            "loop rate           {rate:.1} Hz achieved (nominal {:.0} Hz), wall {:.2} s",
            r.loop_rate_hz,
            r.haptic.wall_s
        );
        line!(
            "period error        p50 {:.1} µs  p99 {:.1} µs  max {:.1} µs",
            pe.p50_us,
            pe.p99_us,
            pe.max_us
        );
        line!(
            "deadline lateness   p50 {:.1} µs  p99 {:.1} µs  max {:.1} µs",
            late.p50_us,
            late.p99_us,
            late.max_us
        );
        line!(
            "tick compute        p50 {:.1} µs  p99 {:.1} µs  max {:.1} µs",
            work.p50_us,
            work.p99_us,
            work.max_us
        );
        let prio = if r.haptic.realtime_priority {
            "granted"
        } else {
            "not granted (normal scheduling)"
        };
        line!("real-time priority  {prio}");
    } else {
        let work = rec.timing.work();
        line!(
            "loop pacing         --speed max: {:.0}× real time, wall {:.2} s",
            duration_s / r.haptic.wall_s.max(1e-9),
            r.haptic.wall_s
        );
        line!(
            "tick compute        p50 {:.1} µs  p99 {:.1} µs  max {:.1} µs",
            work.p50_us,
            work.p99_us,
            work.max_us
        );
    }
    line!(
        "exercises           {} ({} run)",
        r.exercises,
        last.score.exercise_index + 1
    );
    if rec.paused_ticks > 0 {
        line!(
            "paused              {:.1} s (not counted in the exercise time)",
            rec.paused_ticks as f64 / r.loop_rate_hz
        );
    }
    if rec.road_ticks > 0 {
        line!(
            "RMS lateral dev.    {:.3} m (max {:.3} m)",
            last.score.rms_lateral_m,
            last.score.max_lateral_m
        );
        line!(
            "time in lane        {:.1} %, cones hit {}",
            last.score.pct_in_lane,
            last.score.cone_hits
        );
    }
    if rec.dial_ticks > 0 {
        line!(
            "dial tracking       RMS error {:.2}° (thesis Appendix E: about 3°)",
            last.score.dial_rms_error_deg
        );
    }
    line!(
        "torque              max |τ| {:.3} N·m, clipped {:.2} % of ticks, watchdog faults {} ticks",
        rec.max_abs_torque_nm,
        100.0 * rec.clipped_ticks as f64 / ticks,
        rec.fault_ticks
    );
    if rec.assist_ticks > 0 {
        line!(
            "assist              mean level {:.2}, RMS error {:.2}°, saturated {:.1} % of ticks",
            rec.assist_level_sum / rec.assist_ticks as f64,
            (rec.assist_error_sq_sum / rec.assist_ticks as f64)
                .sqrt()
                .to_degrees(),
            100.0 * rec.assist_saturated_ticks as f64 / rec.assist_ticks as f64
        );
    }
    if let Some(rom) = r.haptic.range_of_motion_rad.map(|r| r.map(f64::to_degrees)) {
        line!(
            "arm range of motion shoulder elevation {:.1}°, plane {:.1}°, rotation {:.1}°; elbow flexion {:.1}°, pronation {:.1}°",
            rom[0],
            rom[1],
            rom[2],
            rom[3],
            rom[4]
        );
    }
    if let Some(why) = &r.haptic.arm_failure {
        line!("arm sensing         off: {why}");
    }
    match &rec.arm_calibration {
        Some(Ok(c)) => {
            let truth = r.sim_arm_truth_m.map_or(String::new(), |(u, f)| {
                format!(" (simulated truth {:.3} / {:.3} m)", u, f)
            });
            line!(
                "arm calibration     upper arm {:.3} ± {:.3} m, forearm {:.3} ± {:.3} m{truth}",
                c.upper_arm_m,
                c.upper_arm_se_m,
                c.forearm_m,
                c.forearm_se_m
            );
            for w in &c.warnings {
                line!("                    note: {w}");
            }
        }
        Some(Err(e)) => line!("arm calibration     not this time: {e}"),
        None => {}
    }
    match (&r.record, rec.mcap_bytes) {
        (Some(p), Some(b)) => line!(
            "recording           {} ({:.2} MB)",
            p.display(),
            b as f64 / 1e6
        ),
        (Some(p), None) => line!(
            "recording           {} FAILED: {}",
            p.display(),
            rec.error.as_deref().unwrap_or("unknown")
        ),
        (None, _) => line!("recording           off"),
    }
    match link {
        Some(l) => {
            line!(
                "therapist {:<9} {} summaries: {} sent, {} acknowledged, {} NOT delivered",
                l.address,
                l.produced,
                l.sent,
                l.acked,
                l.undelivered
            );
            if let Some(e) = &l.last_error {
                line!("therapist link      last error: {e}");
            }
        }
        None => line!(
            "therapist           off ({} summaries produced)",
            r.summaries
        ),
    }
    s
}
