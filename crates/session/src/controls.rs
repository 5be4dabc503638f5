//! What other threads may ask of a running session (kept apart from the session's wiring so
//! that the haptic thread depends on it and nothing else of [`super`]).

use serde::{Deserialize, Serialize};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU8, AtomicU32, AtomicU64, Ordering};

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
    /// The patient held a wheel button (a long press, [`HOLD`]): the window asks "End now?"
    /// and the exercise waits; a short press then ends, another long press goes on.
    pub end_asked: AtomicBool,
    /// Paused: what the wheel's turns chose on the pause page ([`PauseChoice`] as a number);
    /// a press does it.
    pub pause_choice: AtomicU8,
    /// Told by the haptic thread: how long an unplugged wheel is still waited for before the
    /// session ends, ms (meaningful while [`Controls::wheel_away`] is set).
    pub wheel_away_left_ms: AtomicU64,
    /// Told by the haptic thread: an arm sensor (IMU) is away mid-session, within the replug
    /// grace; the exercise waits for it.
    pub arm_away: AtomicBool,
    /// Told by the haptic thread: how long an unplugged arm sensor is still waited for before
    /// the session ends, ms (meaningful while [`Controls::arm_away`] is set).
    pub arm_away_left_ms: AtomicU64,
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
    /// The session is the practice (the first-run page's try-out): every screen says so.
    pub practice: AtomicBool,
    /// Told by the patient window's supervisor: when the message was first drawn on the
    /// screen, ms since the Unix epoch; 0 until then.
    pub message_shown_unix_ms: AtomicU64,
}

/// How long a wheel button is held for a long press (go back, or ask to end), ms: long
/// enough that a tremor or a slow press is not one, short enough for a tired hand.
pub const HOLD: std::time::Duration = std::time::Duration::from_millis(1500);

/// The patient's answers to the end screen given with the wheel or a gamepad, kept in the
/// order given until the window's supervisor passes them on: turns of the wheel choose (+1
/// right, −1 left), a button confirms, a long press or a gamepad's B skips. The order matters:
/// a confirm then a turn is the next question's answer, not this one's.
#[derive(Debug, Default)]
pub struct EndAnswers {
    said: std::sync::Mutex<Vec<EndAnswer>>,
}

/// One thing said to the end screen.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EndAnswer {
    /// Choice steps: positive to the right (higher), negative to the left.
    Step(i32),
    /// Confirm the page.
    Confirm,
    /// Skip the page.
    Skip,
}

/// [`EndAnswers`] taken at once, counted (their order is in [`EndAnswers::take_in_order`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct EndAnswersTaken {
    /// Net choice steps: positive to the right (higher), negative to the left.
    pub steps: i32,
    /// Confirmations.
    pub confirms: u32,
    /// Skipped pages.
    pub skips: u32,
}

impl EndAnswers {
    fn say(&self, a: EndAnswer) {
        self.said
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .push(a);
    }

    /// The wheel turned one step: +1 right, −1 left.
    pub fn step(&self, by: i32) {
        self.say(EndAnswer::Step(by));
    }

    /// A button confirmed.
    pub fn confirm(&self) {
        self.say(EndAnswer::Confirm);
    }

    /// A long press or a gamepad's B skipped the page.
    pub fn skip(&self) {
        self.say(EndAnswer::Skip);
    }

    /// Everything said since the last take, in the order said.
    pub fn take_in_order(&self) -> Vec<EndAnswer> {
        std::mem::take(
            &mut *self
                .said
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner),
        )
    }

    /// Everything said since the last take, counted.
    pub fn take(&self) -> EndAnswersTaken {
        let mut t = EndAnswersTaken::default();
        for a in self.take_in_order() {
            match a {
                EndAnswer::Step(by) => t.steps += by,
                EndAnswer::Confirm => t.confirms += 1,
                EndAnswer::Skip => t.skips += 1,
            }
        }
        t
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
    pub fn set_pedals(&self, pedals: exercises::Pedals) {
        let p = pedals.clamped();
        let bits = (u64::from((p.throttle as f32).to_bits()) << 32)
            | u64::from((p.brake as f32).to_bits());
        self.pedals_bits.store(bits, Ordering::Relaxed);
    }

    /// The pedals as last read (released until a reader tells otherwise).
    pub fn pedals(&self) -> exercises::Pedals {
        let bits = self.pedals_bits.load(Ordering::Relaxed);
        exercises::Pedals {
            throttle: f64::from(f32::from_bits((bits >> 32) as u32)),
            brake: f64::from(f32::from_bits(bits as u32)),
        }
    }

    /// The break in progress, as the haptic thread last told it.
    pub fn break_now(&self) -> BreakNow {
        let away = self.wheel_away.load(Ordering::Relaxed);
        let arm_away = self.arm_away.load(Ordering::Relaxed);
        BreakNow {
            kind: BreakKind::from_u8(self.break_kind.load(Ordering::Relaxed)),
            left_s: self.break_left_ms.load(Ordering::Relaxed) as f64 * 1e-3,
            end_asked: self.end_asked.load(Ordering::Relaxed),
            pause_choice: PauseChoice::from_u8(self.pause_choice.load(Ordering::Relaxed)),
            wheel_away_left_s: away
                .then(|| self.wheel_away_left_ms.load(Ordering::Relaxed) as f64 * 1e-3),
            arm_away_left_s: arm_away
                .then(|| self.arm_away_left_ms.load(Ordering::Relaxed) as f64 * 1e-3),
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
    /// After a prescribed rest: "Ready?" — the next exercise waits for a wheel button, or
    /// starts after the countdown the therapist set (`[patient] start_after_rest_s`).
    Ready,
}

impl BreakKind {
    /// The number kept in [`Controls::break_kind`].
    pub fn as_u8(self) -> u8 {
        match self {
            Self::None => 0,
            Self::Next => 1,
            Self::Prescribed => 2,
            Self::Asked => 3,
            Self::Ready => 4,
        }
    }

    /// Back from [`BreakKind::as_u8`] (an unknown number reads as none).
    pub fn from_u8(n: u8) -> Self {
        match n {
            1 => Self::Next,
            2 => Self::Prescribed,
            3 => Self::Asked,
            4 => Self::Ready,
            _ => Self::None,
        }
    }

    /// A rest (prescribed or asked for), recorded as rest time.
    pub fn is_rest(self) -> bool {
        matches!(self, Self::Prescribed | Self::Asked)
    }
}

/// The pause page's choices, left to right: the wheel turns between them and a press does
/// the one chosen.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum PauseChoice {
    /// Go on with the exercise (chosen when the pause begins: a stray press changes nothing
    /// the patient did not see).
    #[default]
    GoOn,
    /// Take a rest.
    Rest,
    /// End the session: asks "End now?" first, as a long press and Esc do.
    End,
}

impl PauseChoice {
    /// The choices in the order the page shows them.
    pub const ALL: [PauseChoice; 3] = [PauseChoice::GoOn, PauseChoice::Rest, PauseChoice::End];

    /// The number kept in [`Controls::pause_choice`]: its place on the page.
    pub fn as_u8(self) -> u8 {
        match self {
            Self::GoOn => 0,
            Self::Rest => 1,
            Self::End => 2,
        }
    }

    /// Back from [`PauseChoice::as_u8`] (an unknown number reads as going on).
    pub fn from_u8(n: u8) -> Self {
        match n {
            1 => Self::Rest,
            2 => Self::End,
            _ => Self::GoOn,
        }
    }

    /// The choice `by` places along (right positive), stopping at the ends.
    pub fn step(self, by: i32) -> Self {
        let at = (i32::from(self.as_u8()) + by).clamp(0, Self::ALL.len() as i32 - 1);
        Self::ALL[at as usize]
    }
}

/// The break in progress and what is left of it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct BreakNow {
    /// Which kind.
    pub kind: BreakKind,
    /// What is left of it, s (a [`BreakKind::Ready`] that waits for the patient: 0).
    pub left_s: f64,
    /// The patient held a wheel button: the window asks "End now?".
    #[serde(default)]
    pub end_asked: bool,
    /// Paused: what the wheel chose on the pause page (a press does it).
    #[serde(default)]
    pub pause_choice: PauseChoice,
    /// The wheel is unplugged: how long it is still waited for before the session ends, s.
    #[serde(default)]
    pub wheel_away_left_s: Option<f64>,
    /// An arm sensor is unplugged: how long it is still waited for before the session ends,
    /// s.
    #[serde(default)]
    pub arm_away_left_s: Option<f64>,
}
