//! What a session's recorder hands back when the session ends ([`RecorderOutcome`]): every
//! tick tallied (time, torque, pauses, faults, assistance), the arm calibrations, the
//! session's measures ([`Measures`]) and the recording's fate. Plain data: the recorder fills
//! it, the measures read its tallies, the end reason its recording error, the report all of it.

use crate::timing::TimingStats;
use measures::Measures;
use record::{ArmCalibrationSample, ArmSetup, TickRecord};
use std::collections::BTreeMap;

/// What the recorder hands back when the session ends.
#[derive(Debug, Default)]
pub struct RecorderOutcome {
    /// Records received from the haptic thread.
    pub records: u64,
    /// Loop timing statistics.
    pub timing: TimingStats,
    /// Last record (final score, pose).
    pub last: TickRecord,
    /// Largest |commanded torque|, N·m.
    pub max_abs_torque_nm: f64,
    /// Ticks on which the safety chain limited the torque.
    pub clipped_ticks: u64,
    /// Ticks spent on road exercises (not paused).
    pub road_ticks: u64,
    /// Ticks spent on the dial task (not paused).
    pub dial_ticks: u64,
    /// Ticks the patient had the exercise paused.
    pub paused_ticks: u64,
    /// Ticks on which the safety supervisor saw a fault (missed deadline, stale reading).
    pub fault_ticks: u64,
    /// Session time the arm sensing was lost (an IMU stopped answering), ns.
    pub arm_lost_ns: u64,
    /// Ticks with an active assist controller.
    pub assist_ticks: u64,
    /// Sum of the assistance level over assisted ticks.
    pub assist_level_sum: f64,
    /// Sum of the squared assist tracking error over assisted ticks, rad².
    pub assist_error_sq_sum: f64,
    /// Assisted ticks on which a torque limit cut the assist.
    pub assist_saturated_ticks: u64,
    /// The arm calibrated from this session's data, or why not (None without arm sensing).
    pub arm_calibration: Option<Result<ArmCalibrationSample, String>>,
    /// The arm calibrated during the session, when it converged (None if it did not).
    pub online_arm_calibration: Option<record::OnlineArmCalibrationSample>,
    /// The session's movement measures, computed at its end.
    pub measures: Measures,
    /// Each exercise's own results, computed at its end (as `/metrics` records them).
    pub exercises: Vec<record::ExerciseResult>,
    /// Size of the finished MCAP file, bytes (None without recording).
    pub mcap_bytes: Option<u64>,
    /// The first recording error, if any (recording stops, the session goes on).
    pub error: Option<String>,
    /// Session time recording stopped at after an error, s.
    pub recording_stopped_s: Option<f64>,
    /// Loop time of the ticks not paused, ns.
    pub active_ns: u64,
    /// Torque updates the wheel's backend wrote to the device during those ticks.
    pub active_motor_updates: u64,
}

impl RecorderOutcome {
    /// Account for one tick.
    pub fn add(&mut self, rec: &TickRecord) {
        self.records += 1;
        self.timing.add(
            rec.timing.lateness_ns,
            rec.timing.period_ns,
            rec.timing.work_ns,
        );
        self.max_abs_torque_nm = self.max_abs_torque_nm.max(rec.wheel.commanded_nm.abs());
        self.clipped_ticks += u64::from(rec.wheel.clipped);
        let active = !rec.score.paused;
        self.road_ticks += u64::from(active && rec.vehicle.is_some());
        self.dial_ticks += u64::from(active && rec.vehicle.is_none());
        self.paused_ticks += u64::from(!active);
        self.fault_ticks += u64::from(rec.wheel.watchdog.is_fault());
        // Rates count from the first record on: its updates are those before it.
        if active && self.records > 1 {
            self.active_ns += rec.t_ns.saturating_sub(self.last.t_ns);
            let (now, before) = (rec.wheel.motor_updates, self.last.wheel.motor_updates);
            self.active_motor_updates += now.saturating_sub(before);
        }
        if rec.arm.is_some_and(|a| a.setup == ArmSetup::SensorLost) {
            self.arm_lost_ns += rec.t_ns.saturating_sub(self.last.t_ns);
        }
        if rec.assist.active {
            self.assist_ticks += 1;
            self.assist_level_sum += rec.assist.assistance_level;
            self.assist_error_sq_sum += rec.assist.error_rad * rec.assist.error_rad;
            self.assist_saturated_ticks += u64::from(rec.assist.saturated);
        }
        self.last = *rec;
    }

    /// The torque updates that reached the motor: updates written per second of active
    /// (not paused) time, and the largest gap between two so far, ms. `None` before any
    /// active time, or with a wheel backend that does not count its updates (a replay).
    pub fn motor_update_rate(&self) -> Option<(f64, f64)> {
        let gap_ms = self.last.wheel.motor_update_worst_gap_ms?;
        (self.active_ns > 0).then(|| {
            (
                self.active_motor_updates as f64 / (self.active_ns as f64 * 1e-9),
                gap_ms,
            )
        })
    }

    /// Time, scores, torque, safety and assistance of the whole session by name (unit in the
    /// name), a tick being `tick_s`: what the session's measures name beside the movements'
    /// (`measures::MeasureCollector::finish`).
    pub fn session_figures(&self, tick_s: f64) -> BTreeMap<String, f64> {
        let mut named = BTreeMap::new();
        let score = &self.last.score;
        let mut put = |name: &str, v: f64| {
            named.insert(name.to_owned(), v);
        };
        put("session_s", self.records as f64 * tick_s);
        put("paused_s", self.paused_ticks as f64 * tick_s);
        put("road_s", self.road_ticks as f64 * tick_s);
        put("dial_s", self.dial_ticks as f64 * tick_s);
        if self.road_ticks > 0 {
            put("rms_lateral_m", score.rms_lateral_m);
            put("max_lateral_m", score.max_lateral_m);
            put("pct_in_lane", score.pct_in_lane);
            put("cone_hits", f64::from(score.cone_hits));
        }
        if self.dial_ticks > 0 {
            put("dial_rms_error_deg", score.dial_rms_error_deg);
        }
        put("max_abs_torque_nm", self.max_abs_torque_nm);
        if self.assist_ticks > 0 {
            put("assist_s", self.assist_ticks as f64 * tick_s);
        }
        named.extend(self.safety_and_assist());
        named
    }

    /// Safety and assistance so far, by name (unit in the name): the share of ticks the
    /// safety chain limited, the watchdog's fault ticks, the torque updates' rate at the motor
    /// and worst gap (with a backend that counts them), whether the arm sensors were lost
    /// (with arm sensing) and, with assistance, its mean level,
    /// RMS tracking error and saturated share. In every live summary and in the session's
    /// measures.
    pub fn safety_and_assist(&self) -> BTreeMap<String, f64> {
        let mut figures = BTreeMap::from([
            (
                "clipped_pct".to_owned(),
                100.0 * self.clipped_ticks as f64 / self.records.max(1) as f64,
            ),
            ("watchdog_fault_ticks".to_owned(), self.fault_ticks as f64),
        ]);
        if let Some((rate_hz, gap_ms)) = self.motor_update_rate() {
            figures.insert("motor_update_rate_hz".to_owned(), rate_hz);
            figures.insert("motor_update_worst_gap_ms".to_owned(), gap_ms);
        }
        // Arm sensors that stopped answering or never set up: 1, else 0 (with arm sensing).
        if let Some(arm) = &self.last.arm {
            let lost = matches!(arm.setup, ArmSetup::SensorLost | ArmSetup::Failed);
            figures.insert("arm_sensors_lost".to_owned(), f64::from(u8::from(lost)));
            // How long they were lost, s, however it ended (plugged back or not).
            figures.insert(
                "arm_sensor_lost_s".to_owned(),
                self.arm_lost_ns as f64 * 1e-9,
            );
        }
        if self.assist_ticks > 0 {
            let n = self.assist_ticks as f64;
            figures.extend([
                ("assist_level_mean".to_owned(), self.assist_level_sum / n),
                (
                    "assist_rms_error_deg".to_owned(),
                    (self.assist_error_sq_sum / n).sqrt().to_degrees(),
                ),
                (
                    "assist_saturated_pct".to_owned(),
                    100.0 * self.assist_saturated_ticks as f64 / n,
                ),
            ]);
        }
        figures
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use measures::MeasureCollector;
    use record::{AssistSample, ScoreSample, WheelSample};

    #[test]
    fn the_session_figures_count_paused_and_exercise_time_and_fit_the_link_with_the_measures() {
        // 2 s paused (the arm procedure), then 3 s of the dial task turned there and back with
        // assistance, at 1 kHz.
        let recs: Vec<TickRecord> = (0..5000_u64)
            .map(|k| {
                let t = k as f64 * 1e-3;
                TickRecord {
                    tick: k,
                    t_ns: k * 1_000_000,
                    wheel: WheelSample {
                        angle_rad: 0.6 * (std::f64::consts::PI * (t - 2.0).max(0.0) / 3.0).sin(),
                        hand_est_nm: Some(0.2),
                        ..WheelSample::default()
                    },
                    assist: AssistSample {
                        active: k >= 2000,
                        assistance_level: 0.5,
                        ..AssistSample::default()
                    },
                    score: ScoreSample {
                        paused: k < 2000,
                        ..ScoreSample::default()
                    },
                    ..TickRecord::default()
                }
            })
            .collect();
        let mut out = RecorderOutcome::default();
        let mut c = MeasureCollector::new(1000.0, 5000);
        for rec in &recs {
            out.add(rec);
            c.add(rec);
        }
        let figures = out.session_figures(c.tick_s());
        assert!((figures["session_s"] - 5.0).abs() < 1e-9);
        assert!((figures["paused_s"] - 2.0).abs() < 1e-9);
        assert!((figures["dial_s"] - 3.0).abs() < 1e-9);
        assert_eq!(figures["road_s"], 0.0);
        assert!(!figures.contains_key("rms_lateral_m"), "no road, no lane");
        assert!((figures["assist_s"] - 3.0).abs() < 1e-9);
        assert_eq!(figures["assist_level_mean"], 0.5);
        // The session's measures name them beside the movements', within the protocol's
        // limit on named values.
        let m = c.finish(figures);
        assert!((m.named["paused_s"] - 2.0).abs() < 1e-9);
        assert!(m.named.contains_key("patient_work_j") && m.named.contains_key("movements"));
        assert!(m.named.len() <= netlink::frame::MAX_EXTRA_ENTRIES);
    }
}
