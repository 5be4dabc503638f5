//! A session with the patient's window. The session runs on its own threads; the window runs
//! in a process of its own (`telerehab window-process`, the station's `commands::window_process`), fed the newest tick on
//! request over a socket ([`wire`]) by the calling (main) thread ([`supervisor`]). The window
//! shares no memory with the haptic loop, which only writes each tick into a wait-free triple
//! buffer: a slow, minimised, crashed or hung window changes nothing in the loop. When the
//! window dies or stops answering, the exercise pauses (the torque fades out) and a new
//! window is started.

pub mod channel;
pub mod supervisor;
pub mod wire;

use super::{Controls, LiveSummary, SessionObserver, SessionOptions, SessionReport};
use anyhow::Context;
use record::TickRecord;
use render::window::WindowOptions;
use std::sync::atomic::{AtomicBool, Ordering};
pub use supervisor::{EndPhase, WindowAccount};

/// Feeds the window's triple buffer with every tick before passing it on, and keeps the
/// patient's own arm lengths once the session has measured them (the arm inset switches).
struct ScreenFeed<'a> {
    screen: triple_buffer::Input<TickRecord>,
    arm_measured_m: &'a std::sync::OnceLock<[f64; 2]>,
    inner: &'a mut dyn SessionObserver,
}

impl SessionObserver for ScreenFeed<'_> {
    fn on_tick(&mut self, record: &TickRecord) {
        self.screen.write(*record);
        self.inner.on_tick(record);
    }

    fn on_summary(&mut self, summary: &LiveSummary) {
        if let Some(lengths) = summary.measured_arm_lengths_m() {
            let _ = self.arm_measured_m.set(lengths);
        }
        self.inner.on_summary(summary);
    }
}

/// Run the session on its own threads and the patient's window in its own process, showing
/// the session's course (the station's `screen::CourseView`); `observer` watches the session as in
/// [`super::run`]. Space pauses and resumes through `controls`; closing the window stops the
/// session. With `background_priority` the window runs below the session's threads (nice 10).
/// Without a usable GPU or display the session simply runs headless (the account is then
/// `None`).
pub fn run_with_window(
    opts: &SessionOptions,
    controls: &Controls,
    window: &WindowOptions,
    observer: &mut dyn SessionObserver,
    background_priority: bool,
) -> anyhow::Result<(SessionReport, Option<WindowAccount>)> {
    run_with_window_and_end_screen(opts, controls, window, observer, background_priority, None)
}

/// [`run_with_window`], then (if the session ran to its end, not stopped) the end screen
/// `end` builds from the session's report: the haptic loop has stopped (torque zero) and the
/// window stays up for the results and the check-in questions. The patient's answers are in
/// the account's [`WindowAccount::checkin`].
pub fn run_with_window_and_end_screen(
    opts: &SessionOptions,
    controls: &Controls,
    window: &WindowOptions,
    observer: &mut dyn SessionObserver,
    background_priority: bool,
    end: Option<&(dyn Fn(&SessionReport) -> wire::EndScreen + Sync)>,
) -> anyhow::Result<(SessionReport, Option<WindowAccount>)> {
    // The window process (started from this thread) stays off the haptic thread's core.
    super::haptic::cores::keep_off_the_haptic_core();
    let hello = wire::Hello {
        title: window.title.clone(),
        size: window.size,
        fullscreen: window.fullscreen,
        max_fps: window.max_fps,
        gated: window.draw_gate.is_some(),
        background_priority,
        config_toml: toml::to_string(&opts.config).context("the session's configuration")?,
        regimen_toml: opts
            .regimen
            .as_ref()
            .map(toml::to_string)
            .transpose()
            .context("the session's regimen")?,
        replaces_a_lost_window: false,
        message: controls
            .message
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .clone(),
        practice: controls.practice.load(Ordering::Relaxed),
    };
    let launcher =
        supervisor::Launcher::this_executable().context("cannot find the telerehab program")?;
    let (input, mut output) = triple_buffer::triple_buffer(&TickRecord::default());
    let done = AtomicBool::new(false);
    let arm_measured_m = std::sync::OnceLock::new();
    let end_phase = EndPhase::default();
    std::thread::scope(|scope| {
        let session = std::thread::Builder::new()
            .name("session".into())
            .spawn_scoped(scope, || {
                let r = super::run(
                    opts,
                    controls,
                    &mut ScreenFeed {
                        screen: input,
                        arm_measured_m: &arm_measured_m,
                        inner: observer,
                    },
                );
                // The loop has stopped: the end screen, for a session not stopped early.
                if let (Some(end), Ok(report)) = (end, &r)
                    && !controls.stop.load(Ordering::Relaxed)
                {
                    *end_phase
                        .screen
                        .lock()
                        .unwrap_or_else(std::sync::PoisonError::into_inner) = Some(end(report));
                }
                done.store(true, Ordering::Release);
                r
            })
            .context("cannot start the session thread")?;
        let account = supervisor::supervise(
            &supervisor::Supervised {
                launcher: &launcher,
                hello: &hello,
                gate: window.draw_gate.as_deref(),
                controls,
                done: &done,
                clock: &opts.clock,
                end_phase: end.is_some().then_some(&end_phase),
                arm_measured_m: &arm_measured_m,
            },
            &mut output,
        );
        let report = session
            .join()
            .map_err(|_| anyhow::anyhow!("session thread panicked (torque was zeroed)"))??;
        let answers = end_phase
            .answers
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .take();
        Ok((
            report,
            account.map(|a| WindowAccount {
                checkin: answers,
                ..a
            }),
        ))
    })
}
