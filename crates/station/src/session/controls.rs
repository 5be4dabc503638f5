//! What other threads may ask of a running session (kept apart from the session's wiring so
//! that the haptic thread depends on it and nothing else of [`super`]).

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU32};

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
}

impl Controls {
    /// Controls around an existing stop flag (such as the one signal handlers set).
    pub fn with_stop(stop: Arc<AtomicBool>) -> Self {
        Self {
            stop,
            ..Self::default()
        }
    }
}
