//! Why a session ended, in plain words: what the station's `Bye` carries to the hub (stored
//! as the session's `end_reason`, shown in the console instead of "running") and what the
//! end-of-run report says.

use super::SessionReport;
use super::haptic::HapticOutcome;
use super::outcome::RecorderOutcome;
use haptic_wheel::WheelFault;

/// The exercises ran their prescription.
pub const COMPLETE: &str = "complete";
/// A stop was asked before the end: Esc or the window closed by the patient, or a stop signal.
pub const ENDED_EARLY: &str = "ended early by the patient (Esc, window closed or stop signal)";
/// The exercise stayed paused longer than `[session] pause_limit_s`.
pub const PAUSED_TOO_LONG: &str = "paused too long";
/// The patient's window failed again and again
/// ([`crate::window::supervisor::MAX_FAILURES_IN_A_ROW`] times in a row): nobody could see the
/// exercise.
pub const WINDOW_LOST: &str = "window lost (the patient's screen failed again and again)";
/// The wheel went away.
pub const WHEEL_UNPLUGGED: &str = "wheel unplugged";
/// An arm sensor went away and was not plugged back in within the replug grace.
pub const ARM_SENSOR_UNPLUGGED: &str = "arm sensor unplugged";
/// The start of the reason for any other wheel fault the safety supervisor stopped on.
pub const SAFETY_STOP: &str = "safety stop";
/// The start of what is added when the recording stopped because the disk filled up.
pub const DISK_FULL: &str = "recording stopped: disk full";

impl SessionReport {
    /// Why the session ended: [`COMPLETE`], [`PAUSED_TOO_LONG`], [`WINDOW_LOST`], [`ENDED_EARLY`],
    /// [`WHEEL_UNPLUGGED`], [`ARM_SENSOR_UNPLUGGED`] or
    /// "[`SAFETY_STOP`]: …"; with "; [`DISK_FULL`] at N s" (or "; recording stopped: …") when
    /// the recording stopped while the session went on.
    pub fn end_reason(&self) -> String {
        with_recording(ended_by(&self.haptic), &self.recorder)
    }
}

/// Why the haptic loop ended ([`SessionReport::end_reason`] without the recording's part).
pub fn ended_by(haptic: &HapticOutcome) -> String {
    match haptic.wheel_fault {
        Some(WheelFault::Unplugged) => WHEEL_UNPLUGGED.to_owned(),
        Some(fault) => format!("{SAFETY_STOP}: {}", fault.describe()),
        None if haptic.arm_sensor_unplugged => ARM_SENSOR_UNPLUGGED.to_owned(),
        None if haptic.paused_too_long => PAUSED_TOO_LONG.to_owned(),
        None if haptic.window_lost => WINDOW_LOST.to_owned(),
        None if haptic.stopped_early => ENDED_EARLY.to_owned(),
        None => COMPLETE.to_owned(),
    }
}

/// `reason` with "; [`DISK_FULL`] at N s" (or "; recording stopped at N s") when the
/// recorder's account says the recording stopped while the session went on.
pub fn with_recording(mut reason: String, recorder: &RecorderOutcome) -> String {
    if let Some(t_s) = recorder.recording_stopped_s {
        let error = recorder.error.as_deref().unwrap_or_default();
        let disk_full = ["disk", "space", "ENOSPC", "os error 28"]
            .iter()
            .any(|w| error.contains(w));
        if disk_full {
            reason.push_str(&format!("; {DISK_FULL} at {t_s:.0} s"));
        } else {
            reason.push_str(&format!("; recording stopped at {t_s:.0} s"));
        }
    }
    reason
}

/// How a session ended in the report's words: "Ended: complete", "Ended early by the
/// patient (…)", "Ended: wheel unplugged" (the stored reason after "Ended: " unless it says
/// "ended" itself); "How it ended is not recorded" for a recording older than the reason.
pub fn sentence(reason: &str) -> String {
    match reason.trim() {
        "" => "How it ended is not recorded".to_owned(),
        r if r.starts_with("ended") => crate::words::capitalised(r),
        r => format!("Ended: {r}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::StationConfig;
    use crate::config::faults::FaultSpec;
    use crate::{Controls, SessionOptions};
    use std::sync::atomic::Ordering;

    /// The end reason of a 3 s simulated sine-road session under `faults`, recorded in a
    /// temporary directory, stopped by the patient when `stop` is set.
    fn reason(faults: &[&str], stop: bool) -> String {
        reason_with(faults, stop, false)
    }

    /// [`reason`], with the window's supervisor having given the window up when
    /// `window_lost` is set (it sets that with the stop).
    fn reason_with(faults: &[&str], stop: bool, window_lost: bool) -> String {
        let mut cfg = StationConfig::default();
        cfg.session.duration_s = 3.0;
        cfg.session.loop_rate_hz = 250.0;
        cfg.haptic.replug_grace_s = 0.5;
        cfg.faults = faults
            .iter()
            .map(|f| FaultSpec::parse(f).unwrap())
            .collect();
        cfg.validate().unwrap();
        let dir = tempfile::tempdir().unwrap();
        let opts = SessionOptions {
            record: Some(dir.path().join("s.mcap")),
            ..SessionOptions::simulated(cfg)
        };
        let controls = Controls::default();
        controls.stop.store(stop || window_lost, Ordering::Relaxed);
        controls.window_lost.store(window_lost, Ordering::Relaxed);
        crate::run(&opts, &controls, &mut ()).unwrap().end_reason()
    }

    #[test]
    fn each_way_a_session_ends_gives_its_own_reason() {
        assert_eq!(reason(&[], false), COMPLETE);
        assert_eq!(reason(&[], true), ENDED_EARLY);
        assert_eq!(reason(&["wheel-unplug@1"], false), WHEEL_UNPLUGGED);
        assert_eq!(reason_with(&[], false, true), WINDOW_LOST);
        let full = reason(&["disk-full@1"], false);
        assert!(
            full.starts_with(&format!("{COMPLETE}; {DISK_FULL} at ")),
            "{full}"
        );
    }
}
