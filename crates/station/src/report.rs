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
    let last = &r.recorder.last;
    let duration_s = last.t_ns as f64 * 1e-9 + 1.0 / r.loop_rate_hz;
    let rate = if r.haptic.wall_s > 0.0 {
        r.haptic.ticks as f64 / r.haptic.wall_s
    } else {
        0.0
    };
    let pe = r.recorder.timing.period_error();
    let late = r.recorder.timing.lateness();
    let work = r.recorder.timing.work();
    let _ = writeln!(
        s,
        "── session summary ─────────────────────────────────────"
    );
    let _ = writeln!(
        s,
        "duration            {duration_s:.2} s session time{}",
        if r.haptic.stopped_early {
            " (stopped early)"
        } else {
            ""
        }
    );
    let _ = writeln!(
        s,
        "ticks               {} ({} recorded, {} dropped)",
        r.haptic.ticks, r.recorder.records, r.haptic.dropped_records
    );
    let _ = writeln!(
        s,
        "loop rate           {rate:.1} Hz achieved (nominal {:.0} Hz), wall {:.2} s",
        r.loop_rate_hz, r.haptic.wall_s
    );
    let _ = writeln!(
        s,
        "period error        p50 {:.1} µs  p99 {:.1} µs  max {:.1} µs",
        pe.p50_us, pe.p99_us, pe.max_us
    );
    let _ = writeln!(
        s,
        "deadline lateness   p50 {:.1} µs  p99 {:.1} µs  max {:.1} µs",
        late.p50_us, late.p99_us, late.max_us
    );
    let _ = writeln!(
        s,
        "tick compute        p50 {:.1} µs  p99 {:.1} µs  max {:.1} µs",
        work.p50_us, work.p99_us, work.max_us
    );
    let _ = writeln!(
        s,
        "real-time priority  {}",
        if r.haptic.realtime_priority {
            "granted"
        } else {
            "not granted (normal scheduling)"
        }
    );
    let _ = writeln!(
        s,
        "RMS lateral dev.    {:.3} m (max {:.3} m)",
        last.score.rms_lateral_m, last.score.max_lateral_m
    );
    let _ = writeln!(s, "time in lane        {:.1} %", last.score.pct_in_lane);
    let _ = writeln!(
        s,
        "max |torque|        {:.3} N·m",
        r.recorder.max_abs_torque_nm
    );
    match (&r.record, r.recorder.mcap_bytes) {
        (Some(p), Some(b)) => {
            let _ = writeln!(
                s,
                "recording           {} ({:.2} MB)",
                p.display(),
                b as f64 / 1e6
            );
        }
        (Some(p), None) => {
            let _ = writeln!(
                s,
                "recording           {} FAILED: {}",
                p.display(),
                r.recorder.error.as_deref().unwrap_or("unknown")
            );
        }
        (None, _) => {
            let _ = writeln!(s, "recording           off");
        }
    }
    match link {
        Some(l) => {
            let _ = writeln!(
                s,
                "therapist {:<9} {} summaries: {} sent, {} acknowledged, {} NOT delivered",
                l.address, l.produced, l.sent, l.acked, l.undelivered
            );
            if let Some(e) = &l.last_error {
                let _ = writeln!(s, "therapist link      last error: {e}");
            }
        }
        None => {
            let _ = writeln!(
                s,
                "therapist           off ({} summaries produced)",
                r.summaries
            );
        }
    }
    s
}
