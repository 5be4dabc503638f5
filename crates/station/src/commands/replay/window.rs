//! `telerehab replay --window`: the recording played back in the patient's window, with play,
//! pause, seek and speed from the keyboard. Nothing is re-run: the window shows what was
//! recorded, at 100 frames per second of session time (every tenth tick at 1 kHz), so an
//! hour's playback holds 360 000 ticks, not 3.6 million.

use super::ReplayArgs;
use crate::screen::{CourseView, live_screen_state};
use anyhow::Context;
use record::{Channel, StreamLimits, TickRecord, TickStream};
use render::window::{UserRequest, WindowOptions};
use std::cell::RefCell;
use std::time::Instant;

/// Ticks kept per second of session time for playback.
const FRAMES_PER_S: f64 = 100.0;
/// How far ← and → move, s of session time.
pub const SEEK_S: f64 = 5.0;
/// The slowest and fastest playback speeds.
const SPEEDS: (f64, f64) = (0.125, 64.0);

/// A recording's ticks played back on a clock: where the cursor is, how fast it moves, and
/// whether it moves. Pure state: the window drives it with wall time and the keys.
#[derive(Debug, Clone)]
pub struct Playback {
    frames: Vec<TickRecord>,
    /// Cursor, s of session time since the first frame.
    position_s: f64,
    speed: f64,
    playing: bool,
}

impl Playback {
    /// Play `ticks` (in order) from the start at `speed` (1 = real time).
    pub fn new(ticks: impl Iterator<Item = TickRecord>, loop_rate_hz: f64, speed: f64) -> Self {
        let every = ((loop_rate_hz / FRAMES_PER_S).round() as usize).max(1);
        Self {
            frames: ticks.step_by(every).collect(),
            position_s: 0.0,
            speed: speed.clamp(SPEEDS.0, SPEEDS.1),
            playing: true,
        }
    }

    /// Session time of frame `i` since the first, s.
    fn time_of(&self, i: usize) -> f64 {
        let t0 = self.frames.first().map_or(0, |f| f.t_ns);
        self.frames
            .get(i)
            .map_or(0.0, |f| (f.t_ns - t0) as f64 * 1e-9)
    }

    /// Length of the recording, s.
    pub fn duration_s(&self) -> f64 {
        self.time_of(self.frames.len().saturating_sub(1))
    }

    /// The cursor, s.
    pub fn position_s(&self) -> f64 {
        self.position_s
    }

    /// The playback speed (1 = real time).
    pub fn speed(&self) -> f64 {
        self.speed
    }

    /// The cursor moves.
    pub fn playing(&self) -> bool {
        self.playing
    }

    /// The cursor is at the end.
    pub fn at_end(&self) -> bool {
        self.position_s >= self.duration_s()
    }

    /// Move the cursor by `wall_s` of wall time at the playback speed; it stops at the end.
    pub fn advance(&mut self, wall_s: f64) {
        if self.playing {
            self.position_s = (self.position_s + wall_s * self.speed).min(self.duration_s());
            if self.at_end() {
                self.playing = false;
            }
        }
    }

    /// Act on a key.
    pub fn apply(&mut self, request: UserRequest) {
        let end = self.duration_s();
        match request {
            UserRequest::TogglePause if self.at_end() => {
                self.position_s = 0.0;
                self.playing = true;
            }
            UserRequest::TogglePause => self.playing = !self.playing,
            UserRequest::SeekBack => self.position_s = (self.position_s - SEEK_S).max(0.0),
            UserRequest::SeekForward => self.position_s = (self.position_s + SEEK_S).min(end),
            UserRequest::Faster => self.speed = (self.speed * 2.0).min(SPEEDS.1),
            UserRequest::Slower => self.speed = (self.speed / 2.0).max(SPEEDS.0),
            UserRequest::Restart => self.position_s = 0.0,
            _ => {}
        }
    }

    /// The frame at the cursor: the last at or before it.
    pub fn frame(&self) -> Option<&TickRecord> {
        let t0 = self.frames.first()?.t_ns;
        let cursor_ns = t0 + (self.position_s * 1e9).round() as u64;
        let i = self.frames.partition_point(|f| f.t_ns <= cursor_ns);
        self.frames.get(i.saturating_sub(1))
    }

    /// The status line shown in the window.
    pub fn status(&self) -> String {
        format!(
            "REPLAY {:.1} / {:.1} s · ×{} · {} — Space play/pause · ←/→ {SEEK_S} s · ↑/↓ speed · Home restart",
            self.position_s,
            self.duration_s(),
            self.speed,
            if self.playing { "playing" } else { "paused" }
        )
    }
}

/// `telerehab replay --window`.
pub(super) fn play(args: &ReplayArgs) -> anyhow::Result<()> {
    anyhow::ensure!(
        args.play_speed.is_finite() && (SPEEDS.0..=SPEEDS.1).contains(&args.play_speed),
        "--play-speed must be {} to {}",
        SPEEDS.0,
        SPEEDS.1
    );
    let path = &args.recording;
    let unreadable = || format!("{} is not a readable recording", path.display());
    // Streamed: only the frames played back are kept (100 a second), never the whole file.
    let drawn = [
        Channel::Vehicle,
        Channel::Score,
        Channel::Assist,
        Channel::Timing,
        Channel::Arm,
    ];
    let limits = StreamLimits::default();
    let stream = TickStream::open_path(path, limits, &drawn).with_context(unreadable)?;
    let meta = stream.metadata().clone();
    let (config, regimen) = super::recorded_plan(&meta)?;
    let view = CourseView::new(&config, regimen.as_ref())?;
    let mut failed = None;
    let ticks = stream.map_while(|t| t.map_err(|e| failed = Some(e)).ok());
    let playback = Playback::new(ticks, meta.loop_rate_hz, args.play_speed);
    if let Some(e) = failed {
        return Err(e).with_context(unreadable);
    }
    let playback = RefCell::new(playback);
    anyhow::ensure!(
        playback.borrow().frame().is_some(),
        "{} has no ticks to play",
        path.display()
    );
    let last = RefCell::new(Instant::now());
    let source = || {
        let now = Instant::now();
        let mut p = playback.borrow_mut();
        p.advance((now - last.replace(now)).as_secs_f64());
        if args.close_at_end && p.at_end() {
            return None;
        }
        let rec = p.frame()?;
        let mut scene = view.scene(rec, live_screen_state(rec));
        scene.hud.devices.push(p.status());
        Some(scene)
    };
    let on_request = |r: UserRequest| playback.borrow_mut().apply(r);
    let title = format!("telerehab replay — {}", path.display());
    let stats = render::window::run_with(&WindowOptions::new(&title), source, on_request)
        .context("cannot open the replay window (is there a display? try xvfb-run -a)")?;
    let p = playback.borrow();
    println!(
        "replay: played to {:.1} of {:.1} s; {} frames drawn",
        p.position_s(),
        p.duration_s(),
        stats.frames_drawn
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ticks(n: u64) -> impl Iterator<Item = TickRecord> {
        (0..n).map(|tick| TickRecord {
            tick,
            t_ns: tick * 1_000_000,
            ..Default::default()
        })
    }

    #[test]
    fn playback_keeps_a_tenth_of_the_ticks_and_moves_at_its_speed() {
        let mut p = Playback::new(ticks(10_001), 1000.0, 1.0);
        assert_eq!(p.frames.len(), 1001);
        assert_eq!(p.duration_s(), 10.0);
        p.advance(0.5);
        assert_eq!(p.frame().unwrap().tick, 500);
        p.apply(UserRequest::Faster);
        p.advance(0.5);
        assert_eq!(p.frame().unwrap().tick, 1500);
        p.apply(UserRequest::TogglePause);
        p.advance(3.0);
        assert_eq!(p.frame().unwrap().tick, 1500, "paused: the cursor stays");
        assert!(p.status().contains("paused"), "{}", p.status());
    }

    #[test]
    fn seeking_stays_within_the_recording_and_the_end_stops_playback() {
        let mut p = Playback::new(ticks(8_001), 1000.0, 1.0);
        p.apply(UserRequest::SeekBack);
        assert_eq!(p.position_s(), 0.0);
        p.apply(UserRequest::SeekForward);
        assert_eq!(p.frame().unwrap().tick, 5000);
        p.apply(UserRequest::SeekForward);
        assert_eq!(p.position_s(), 8.0);
        p.advance(1.0);
        assert!(p.at_end() && !p.playing());
        // Space at the end plays again from the start.
        p.apply(UserRequest::TogglePause);
        assert!(p.playing() && p.position_s() == 0.0);
        p.advance(2.0);
        p.apply(UserRequest::Restart);
        assert_eq!(p.frame().unwrap().tick, 0);
    }

    #[test]
    fn the_speed_is_bounded() {
        let mut p = Playback::new(ticks(10), 1000.0, 100.0);
        assert_eq!(p.speed(), 64.0);
        for _ in 0..20 {
            p.apply(UserRequest::Slower);
        }
        assert_eq!(p.speed(), 0.125);
    }
}
