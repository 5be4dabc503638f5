//! What other threads may ask of a running session (kept apart from the session's wiring so
//! that the haptic thread depends on it and nothing else of [`super`]).

use serde::{Deserialize, Serialize};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicI32, AtomicU8, AtomicU32, AtomicU64, Ordering};

/// What other threads (a signal handler, the patient's window) may ask of a running session.
#[derive(Debug, Default)]
pub struct Controls {
    /// End the session: the torque fades out and everything is recorded and delivered.
    pub stop: Arc<AtomicBool>,
    /// While set, the exercise is paused (see [`super::plant::Plant::set_paused`]).
    pub pause: AtomicBool,
    /// Told by the haptic thread: the wheel is away (unplugged, within the replug grace) or
    /// settling after it came back.
    pub wheel_away: AtomicBool,
    /// Told by the haptic thread: times the wheel was unplugged and came back.
    pub wheel_replugs: AtomicU32,
    /// The patient asked for a rest (R, or a wheel button): the haptic thread takes it.
    pub rest: AtomicBool,
    /// The patient wants to go on now, ending the break in progress.
    pub end_break: AtomicBool,
    /// Told by the haptic thread: the break in progress ([`BreakKind`] as a number).
    pub break_kind: AtomicU8,
    /// Told by the haptic thread: what is left of the break in progress, ms.
    pub break_left_ms: AtomicU64,
    /// Told by the window's supervisor with the stop: the patient's window failed again and
    /// again, so the session ends ("window lost").
    pub window_lost: AtomicBool,
    /// The pedals as last read (throttle and brake as `f32` bits, high and low half).
    pedals_bits: AtomicU64,
    /// Told by the window's supervisor: the end screen is up, so the wheel and a gamepad
    /// answer its questions ([`EndAnswers`]) instead of pausing.
    pub end_screen_up: AtomicBool,
    /// What the wheel and a gamepad said to the end screen, not yet passed on.
    pub end_answers: EndAnswers,
    /// The therapist's message for the session's start card, if any (set before the session
    /// starts; the patient window shows it).
    pub message: std::sync::Mutex<Option<String>>,
    /// Told by the patient window's supervisor: when the message was first drawn on the
    /// screen, ms since the Unix epoch; 0 until then.
    pub message_shown_unix_ms: AtomicU64,
}

/// The patient's answers to the end screen given with the wheel or a gamepad, counted until
/// the window's supervisor passes them on: turns of the wheel choose (+1 right, −1 left), a
/// button confirms, a gamepad's B skips.
#[derive(Debug, Default)]
pub struct EndAnswers {
    steps: AtomicI32,
    confirms: AtomicU32,
    skips: AtomicU32,
}

/// [`EndAnswers`] taken at once, in the order the window applies them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct EndAnswersTaken {
    /// Net choice steps: positive to the right (higher), negative to the left.
    pub steps: i32,
    /// Confirmations, after the steps.
    pub confirms: u32,
    /// Skipped pages, after those.
    pub skips: u32,
}

impl EndAnswers {
    /// The wheel turned one step: +1 right, −1 left.
    pub fn step(&self, by: i32) {
        self.steps.fetch_add(by, Ordering::Relaxed);
    }

    /// A button confirmed.
    pub fn confirm(&self) {
        self.confirms.fetch_add(1, Ordering::Relaxed);
    }

    /// A gamepad's B skipped the page.
    pub fn skip(&self) {
        self.skips.fetch_add(1, Ordering::Relaxed);
    }

    /// Everything said since the last take.
    pub fn take(&self) -> EndAnswersTaken {
        EndAnswersTaken {
            steps: self.steps.swap(0, Ordering::Relaxed),
            confirms: self.confirms.swap(0, Ordering::Relaxed),
            skips: self.skips.swap(0, Ordering::Relaxed),
        }
    }
}

impl Controls {
    /// Controls around an existing stop flag (such as the one signal handlers set).
    pub fn with_stop(stop: Arc<AtomicBool>) -> Self {
        Self {
            stop,
            ..Self::default()
        }
    }

    /// Tell the haptic thread where the pedals are now (each clamped to [0, 1]).
    pub fn set_pedals(&self, pedals: vehicle::Pedals) {
        let p = pedals.clamped();
        let bits = (u64::from((p.throttle as f32).to_bits()) << 32)
            | u64::from((p.brake as f32).to_bits());
        self.pedals_bits.store(bits, Ordering::Relaxed);
    }

    /// The pedals as last read (released until a reader tells otherwise).
    pub fn pedals(&self) -> vehicle::Pedals {
        let bits = self.pedals_bits.load(Ordering::Relaxed);
        vehicle::Pedals {
            throttle: f64::from(f32::from_bits((bits >> 32) as u32)),
            brake: f64::from(f32::from_bits(bits as u32)),
        }
    }

    /// The break in progress, as the haptic thread last told it.
    pub fn break_now(&self) -> BreakNow {
        BreakNow {
            kind: BreakKind::from_u8(self.break_kind.load(Ordering::Relaxed)),
            left_s: self.break_left_ms.load(Ordering::Relaxed) as f64 * 1e-3,
        }
    }
}

/// What kind of break the exercise is in.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum BreakKind {
    /// None: the exercise runs (or is paused by the patient).
    #[default]
    None,
    /// The short card between two exercises that says what comes next.
    Next,
    /// A rest the regimen prescribes after an exercise.
    Prescribed,
    /// A rest the patient asked for.
    Asked,
}

impl BreakKind {
    /// The number kept in [`Controls::break_kind`].
    pub fn as_u8(self) -> u8 {
        match self {
            Self::None => 0,
            Self::Next => 1,
            Self::Prescribed => 2,
            Self::Asked => 3,
        }
    }

    /// Back from [`BreakKind::as_u8`] (an unknown number reads as none).
    pub fn from_u8(n: u8) -> Self {
        match n {
            1 => Self::Next,
            2 => Self::Prescribed,
            3 => Self::Asked,
            _ => Self::None,
        }
    }

    /// A rest (prescribed or asked for), recorded as rest time.
    pub fn is_rest(self) -> bool {
        matches!(self, Self::Prescribed | Self::Asked)
    }
}

/// The break in progress and what is left of it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct BreakNow {
    /// Which kind.
    pub kind: BreakKind,
    /// What is left of it, s.
    pub left_s: f64,
}
