//! A session with the patient's window: the session on its own threads, the window on the
//! calling (main) thread. The window only reads the latest tick through a wait-free triple
//! buffer, so a slow, minimised or closed window changes nothing in the haptic loop.

use super::{Controls, LiveSummary, SessionObserver, SessionOptions, SessionReport};
use crate::record::TickRecord;
use crate::render::Scene;
use crate::render::window::{UserRequest, WindowOptions, WindowStats};
use anyhow::Context;
use std::sync::atomic::{AtomicBool, Ordering};

/// Feeds the window's triple buffer with every tick before passing it on.
struct ScreenFeed<'a> {
    screen: triple_buffer::Input<TickRecord>,
    inner: &'a mut dyn SessionObserver,
}

impl SessionObserver for ScreenFeed<'_> {
    fn on_tick(&mut self, record: &TickRecord) {
        self.screen.write(*record);
        self.inner.on_tick(record);
    }

    fn on_summary(&mut self, summary: &LiveSummary) {
        self.inner.on_summary(summary);
    }
}

/// Run the session on its own threads and the patient's window on this (the main) thread,
/// drawing the latest tick as `scene` makes it (e.g. [`crate::screen::CourseView::scene`]);
/// `observer` watches the session as in [`super::run`]. Space pauses and
/// resumes through `controls`, closing the window stops the session. With `idle_priority` the
/// window and its renderer get only the CPU time the session leaves over. Without a usable
/// GPU or display the session simply runs headless (the stats are then `None`).
pub fn run_with_window(
    opts: &SessionOptions,
    controls: &Controls,
    scene: impl Fn(&TickRecord) -> Scene,
    window: &WindowOptions,
    observer: &mut dyn SessionObserver,
    idle_priority: bool,
) -> anyhow::Result<(SessionReport, Option<WindowStats>)> {
    // The window and its (possibly software) renderer stay off the haptic thread's core.
    super::haptic::cores::keep_off_the_haptic_core();
    let (input, mut output) = triple_buffer::triple_buffer(&TickRecord::default());
    let done = AtomicBool::new(false);
    std::thread::scope(|scope| {
        let session = std::thread::Builder::new()
            .name("session".into())
            .spawn_scoped(scope, || {
                let r = super::run(
                    opts,
                    controls,
                    &mut ScreenFeed {
                        screen: input,
                        inner: observer,
                    },
                );
                done.store(true, Ordering::Release);
                r
            })
            .context("cannot start the session thread")?;
        // The session's threads are started: from here on, this thread and the renderer's
        // workers take only the CPU time they leave over.
        if idle_priority {
            let idle = super::haptic::request_idle_priority();
            tracing::debug!(idle, "patient window at idle scheduling priority");
        }
        let source = || {
            if done.load(Ordering::Acquire) {
                return None;
            }
            let rec = *output.read();
            Some(scene(&rec))
        };
        let on_request = |r: UserRequest| match r {
            UserRequest::Quit => controls.stop.store(true, Ordering::Relaxed),
            UserRequest::TogglePause => {
                controls.pause.fetch_xor(true, Ordering::Relaxed);
            }
            // Seeking and speed are a replay's; a live session has neither.
            _ => {}
        };
        let stats = crate::render::window::run_with(window, source, on_request)
            .inspect_err(|e| {
                tracing::warn!("no patient window ({e}); the session continues headless");
                // Nobody can press Space now: start (or resume) the exercise.
                controls.pause.store(false, Ordering::Relaxed);
            })
            .ok();
        let report = session
            .join()
            .map_err(|_| anyhow::anyhow!("session thread panicked (torque was zeroed)"))??;
        Ok((report, stats))
    })
}
