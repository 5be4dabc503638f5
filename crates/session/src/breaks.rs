//! Breaks on the haptic thread: the card between two prescribed exercises, the rests the
//! regimen prescribes, the rests the patient asks for, and the limit on a pause. A break is a
//! pause to the plant (the exercise clock stops and the torque fades out exactly as for Space),
//! so rests are never exercise time and a replay follows them as it follows pauses.

use super::controls::{BreakKind, Controls};
use super::course::BreakSettings;
use super::plant::Plant;
use record::TickRecord;
use std::sync::atomic::Ordering;

/// The breaks of one session, kept by the haptic thread.
#[derive(Debug)]
pub struct BreakClock {
    settings: BreakSettings,
    dt_s: f64,
    kind: BreakKind,
    left_ticks: u64,
    /// "Ready?" after a rest: the next exercise waits for the patient (no countdown).
    waiting: bool,
    /// After the break in progress, if it is a rest: the "Ready?" countdown, s (`None`: wait
    /// for the patient).
    then_ready: Option<Option<f64>>,
    /// Ticks the wheel has been away (unplugged) so far.
    away_ticks: u64,
    /// The exercise of the last tick.
    segment: u32,
    /// Ticks the patient's pause has lasted so far.
    paused_ticks: u64,
    /// Rests taken (prescribed or asked for).
    pub rests: u32,
    /// Ticks spent resting.
    pub rest_ticks: u64,
    /// The patient's pause lasted longer than the limit.
    pub paused_too_long: bool,
    /// Ticks an arm sensor has been away (unplugged) so far; the exercise waits meanwhile.
    arm_away_ticks: u64,
    /// An arm sensor stayed away longer than the replug grace: the session ends.
    pub arm_sensor_unplugged: bool,
}

impl BreakClock {
    /// No break yet, for a loop of period `dt_s`.
    pub fn new(settings: BreakSettings, dt_s: f64) -> Self {
        Self {
            settings,
            dt_s,
            kind: BreakKind::None,
            left_ticks: 0,
            waiting: false,
            then_ready: None,
            away_ticks: 0,
            segment: 0,
            paused_ticks: 0,
            rests: 0,
            rest_ticks: 0,
            paused_too_long: false,
            arm_away_ticks: 0,
            arm_sensor_unplugged: false,
        }
    }

    fn start(&mut self, kind: BreakKind, length_s: f64) {
        self.kind = kind;
        self.left_ticks = (length_s / self.dt_s).round() as u64;
        self.rests += u32::from(kind.is_rest());
    }

    /// Before a tick: take the patient's requests; true when the exercise must be paused
    /// (the patient paused it, or a break is in progress).
    pub fn before_tick(&mut self, plant: &Plant, controls: &Controls) -> bool {
        if controls.rest.swap(false, Ordering::Relaxed) {
            // A rest in place of a pause: the countdown shows, and the exercise goes on by
            // itself after it. (Before the exercise started there is nothing to rest from:
            // it starts.)
            controls.pause.store(false, Ordering::Relaxed);
            if self.left_ticks == 0 && plant.active_ticks() > 0 {
                self.start(BreakKind::Asked, self.settings.asked_rest_s);
            }
        }
        if controls.end_break.swap(false, Ordering::Relaxed) {
            self.left_ticks = 0;
            self.waiting = false;
            // Going on from a rest now skips its "Ready?" too: the patient said so.
            self.then_ready = None;
        }
        // An arm sensor unplugged mid-session: the exercise waits for it (a pause to the plant,
        // recorded as one, so a replay follows it) for the replug grace, then the session ends.
        let arm_away = plant.arm_sensor_away();
        // Counted in a replay too (where the recorded pause stands in for the wait): the
        // session ends on the same tick.
        self.arm_away_ticks = if plant.arm_sensor_lost() {
            self.arm_away_ticks + 1
        } else {
            0
        };
        let grace_s = plant.replug_grace_ns() as f64 * 1e-9;
        if self.arm_away_ticks as f64 * self.dt_s > grace_s {
            self.arm_sensor_unplugged = true;
        }
        if controls.end_asked.load(Ordering::Relaxed) || arm_away {
            // "End now?" is up, or the arm sensor's page: the exercise waits.
            return true;
        }
        let paused = controls.pause.load(Ordering::Relaxed);
        // Waiting for the patient after a rest is held to the pause's limit too.
        self.paused_ticks = if paused || self.waiting {
            self.paused_ticks + 1
        } else {
            0
        };
        if self.paused_ticks as f64 * self.dt_s > self.settings.pause_limit_s {
            self.paused_too_long = true;
        }
        paused || self.left_ticks > 0 || self.waiting
    }

    /// After a tick: start the break after an exercise that just ended, count the one in
    /// progress down, and tell `controls` (for the patient's screen).
    pub fn after_tick(&mut self, rec: &TickRecord, plant: &Plant, controls: &Controls) {
        let segment = rec.score.exercise_index;
        if segment != self.segment {
            if let Some(b) = plant.break_after(self.segment as usize) {
                let kind = if b.rest {
                    BreakKind::Prescribed
                } else {
                    BreakKind::Next
                };
                self.start(kind, b.length_s);
                self.then_ready = b.rest.then_some(b.start_after_s);
            }
            self.segment = segment;
        }
        if self.left_ticks > 0 {
            self.left_ticks -= 1;
            self.rest_ticks += u64::from(self.kind.is_rest());
        }
        if self.left_ticks == 0 && !self.waiting {
            match self.then_ready.take() {
                // After a rest: "Ready?", waiting for the patient or counting down.
                Some(None) => {
                    self.kind = BreakKind::Ready;
                    self.waiting = true;
                }
                Some(Some(s)) if s > 0.0 => self.start(BreakKind::Ready, s),
                _ => self.kind = BreakKind::None,
            }
        }
        self.away_ticks = if plant.wheel_away() {
            self.away_ticks + 1
        } else {
            0
        };
        let grace_s = plant.replug_grace_ns() as f64 * 1e-9;
        let away_left_s = (grace_s - self.away_ticks as f64 * self.dt_s).max(0.0);
        controls
            .wheel_away_left_ms
            .store((away_left_s * 1e3).round() as u64, Ordering::Relaxed);
        let arm_left_s = (grace_s - self.arm_away_ticks as f64 * self.dt_s).max(0.0);
        controls
            .arm_away_left_ms
            .store((arm_left_s * 1e3).round() as u64, Ordering::Relaxed);
        controls
            .arm_away
            .store(self.arm_away_ticks > 0, Ordering::Relaxed);
        controls
            .break_kind
            .store(self.kind.as_u8(), Ordering::Relaxed);
        controls.break_left_ms.store(
            (self.left_ticks as f64 * self.dt_s * 1e3).round() as u64,
            Ordering::Relaxed,
        );
    }

    /// Time spent resting, s.
    pub fn rest_s(&self) -> f64 {
        self.rest_ticks as f64 * self.dt_s
    }
}
