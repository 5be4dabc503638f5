//! The station's side of the patient window: start `telerehab window-process`, answer its
//! pulls with the newest tick, pass its keys to the session, and notice when it dies or stops
//! answering. Then the exercise pauses (the haptic loop fades the torque out, as for Space)
//! and a new window is started; the patient resumes with Space when it shows.
//!
//! Nothing here runs on the haptic thread, and nothing the window does can block it: the
//! haptic thread only ever writes the newest tick into a wait-free triple buffer.

use super::channel::{self, WindowSocket};
use super::wire::{self, EndScreen, FromWindow, Hello, ToWindow};
use crate::Controls;
use clock::Clock;
use record::TickRecord;
use render::AdapterSummary;
use render::window::UserRequest;
use std::process::{Child, Command};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Mutex, mpsc};
use std::time::Duration;

/// Longest a window may take to open (a software rasteriser compiles its pipelines first).
pub const OPEN_TIMEOUT: Duration = Duration::from_secs(30);
/// A window that has not pulled a frame for this long has hung: it is killed and replaced.
/// Long enough for a window at the lowest priority on a busy machine, short for a patient.
pub const HANG_TIMEOUT: Duration = Duration::from_secs(5);
/// How long a closing window may take to say goodbye before it is killed.
const CLOSE_TIMEOUT: Duration = Duration::from_secs(3);
/// A window that fails this many times in a row (without drawing in between) ends the
/// session: the patient cannot see the exercise.
pub const MAX_FAILURES_IN_A_ROW: u32 = 3;
/// How often the supervisor looks at the clock and the session.
const WATCH_PERIOD: Duration = Duration::from_millis(20);

/// What the patient window did over a session.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WindowAccount {
    /// The adapter that drew the frames (the last window's).
    pub adapter: Option<AdapterSummary>,
    /// Frames drawn and presented, over every window of the session.
    pub frames_drawn: u64,
    /// Windows started again after one died or hung.
    pub restarts: u32,
    /// The patient's answers on the end screen, if it was shown and answered.
    pub checkin: Option<netlink::CheckIn>,
}

/// The end screen of a session: what it shows (set by the session's thread once the haptic
/// loop has stopped, before the session is marked done) and the patient's answers.
#[derive(Debug, Default)]
pub struct EndPhase {
    /// What to show; `None`: no end screen (the window closes when the session ends).
    pub screen: Mutex<Option<EndScreen>>,
    /// The answers, once the window sent them.
    pub answers: Mutex<Option<netlink::CheckIn>>,
    /// The end screen was sent to the window.
    sent: AtomicBool,
}

impl EndPhase {
    /// The screen to send the window now, once (the session is over).
    fn take_screen_to_send(&self) -> Option<EndScreen> {
        let screen = lock(&self.screen).clone()?;
        (!self.sent.swap(true, Ordering::AcqRel)).then_some(screen)
    }

    /// The window should stay up for the end screen: there is one and it is not answered.
    fn asking(&self) -> bool {
        lock(&self.screen).is_some() && lock(&self.answers).is_none()
    }

    /// The longest the station keeps the window up for the end screen: every page's timeout
    /// and a margin.
    fn limit(&self) -> Duration {
        let per_page = lock(&self.screen)
            .as_ref()
            .map_or(0, |s| s.question_timeout_s);
        Duration::from_secs(per_page * 5 + 10)
    }
}

fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// Why one window process ended.
#[derive(Debug)]
enum Ending {
    /// The session is over and the window closed (or was closed).
    SessionOver,
    /// The patient closed the window or pressed Esc: the session is told to stop.
    Quit,
    /// It never opened: why.
    NeverOpened(String),
    /// It opened, then died or hung: why.
    Lost(String),
}

/// How the station starts a window process.
pub struct Launcher {
    /// The executable (the `telerehab` binary itself).
    pub program: std::path::PathBuf,
    /// Its arguments.
    pub args: Vec<String>,
}

impl Launcher {
    /// This very executable, as `telerehab window-process`.
    pub fn this_executable() -> std::io::Result<Self> {
        Ok(Self {
            program: std::env::current_exe()?,
            args: vec!["window-process".into()],
        })
    }
}

/// Everything one window needs from the session.
pub struct Supervised<'a> {
    /// How to start it.
    pub launcher: &'a Launcher,
    /// Its first message.
    pub hello: &'a Hello,
    /// The draw gate (a benchmark's); `None` always draws.
    pub gate: Option<&'a AtomicBool>,
    /// The session's pause and stop.
    pub controls: &'a Controls,
    /// Set when the session has ended.
    pub done: &'a AtomicBool,
    /// The session's clock: every deadline here (open, hang, close, back-off) is read from
    /// it. A window runs only beside a live session, whose clock is the real one.
    pub clock: &'a Clock,
    /// The end screen, if the session has one: the window stays up for it after the session.
    pub end_phase: Option<&'a EndPhase>,
    /// The patient's own arm lengths (upper arm, elbow to grip, m) once the session has
    /// measured them: sent with each frame for the arm inset.
    pub arm_measured_m: &'a std::sync::OnceLock<[f64; 2]>,
}

/// Time on `clock` since `since_ns` (zero if the clock has not moved on).
fn elapsed(clock: &Clock, since_ns: u64) -> Duration {
    Duration::from_nanos(clock.now_ns().saturating_sub(since_ns))
}

/// Run patient windows until the session ends: `Ok(None)` if the first one never opened (the
/// session goes on headless and the exercise is started, as nobody can press Space).
pub fn supervise(
    s: &Supervised<'_>,
    output: &mut triple_buffer::Output<TickRecord>,
) -> Option<WindowAccount> {
    let mut account = WindowAccount::default();
    let mut ever_opened = false;
    let mut failures_in_a_row = 0;
    while !s.done.load(Ordering::Acquire) {
        let outcome = run_one(s, output, account.restarts > 0).unwrap_or_else(|e| Outcome {
            ending: Ending::NeverOpened(format!("cannot start it: {e}")),
            opened: false,
            closed: None,
        });
        if let Some((frames, adapter)) = outcome.closed {
            account.frames_drawn += frames;
            account.adapter = adapter.or(account.adapter.take());
        }
        ever_opened |= outcome.opened;
        let why = match outcome.ending {
            Ending::SessionOver | Ending::Quit => break,
            Ending::NeverOpened(why) if !ever_opened && account.restarts == 0 => {
                tracing::warn!("no patient window ({why}); the session continues headless");
                // Nobody can press Space now: start (or resume) the exercise.
                s.controls.pause.store(false, Ordering::Relaxed);
                return None;
            }
            Ending::NeverOpened(why) => {
                failures_in_a_row += 1;
                format!("the new patient window did not open ({why})")
            }
            Ending::Lost(why) => {
                failures_in_a_row = 1;
                why
            }
        };
        if s.done.load(Ordering::Acquire) || s.controls.stop.load(Ordering::Relaxed) {
            break;
        }
        // The patient cannot see the exercise: pause it (the torque fades out) before anything
        // else, then bring the screen back.
        s.controls.pause.store(true, Ordering::Relaxed);
        if failures_in_a_row >= MAX_FAILURES_IN_A_ROW {
            tracing::error!(
                "{why}; the patient window failed {failures_in_a_row} times in a row: ending the session"
            );
            s.controls.window_lost.store(true, Ordering::Relaxed);
            s.controls.stop.store(true, Ordering::Relaxed);
            break;
        }
        tracing::warn!("{why}: the exercise is paused and a new patient window is starting");
        account.restarts += 1;
        wait_or_done(s, Duration::from_millis(250 * u64::from(failures_in_a_row)));
    }
    Some(account)
}

/// What the wheel and a gamepad said to the end screen since the last frame, as the keys
/// that mean the same (nothing before the end screen is up).
fn end_answers(controls: &Controls) -> Vec<UserRequest> {
    if !controls.end_screen_up.load(Ordering::Acquire) {
        return Vec::new();
    }
    use crate::EndAnswer;
    let mut keys = Vec::new();
    // In the order said: a confirm then a turn answers the next question.
    for a in controls.end_answers.take_in_order() {
        match a {
            EndAnswer::Step(by) => {
                let step = if by > 0 {
                    UserRequest::SeekForward
                } else {
                    UserRequest::SeekBack
                };
                keys.extend(std::iter::repeat_n(step, by.unsigned_abs() as usize));
            }
            EndAnswer::Confirm => keys.push(UserRequest::Confirm),
            EndAnswer::Skip => keys.push(UserRequest::Quit),
        }
    }
    keys
}

/// Sleep `d` on the session's clock, or less if the session ends.
fn wait_or_done(s: &Supervised<'_>, d: Duration) {
    let start_ns = s.clock.now_ns();
    while elapsed(s.clock, start_ns) < d && !s.done.load(Ordering::Acquire) {
        std::thread::sleep(WATCH_PERIOD);
    }
}

/// What the window's reader thread tells the watcher.
enum Heard {
    Pulled,
    Said(FromWindow),
    Gone(Option<String>),
}

/// How one window process went: how it ended, whether it opened, and what it said it drew.
struct Outcome {
    ending: Ending,
    opened: bool,
    /// Frames drawn and the adapter, from its goodbye.
    closed: Option<(u64, Option<AdapterSummary>)>,
}

/// One window process from start to end (`replacing`: one that was lost).
fn run_one(
    s: &Supervised<'_>,
    output: &mut triple_buffer::Output<TickRecord>,
    replacing: bool,
) -> std::io::Result<Outcome> {
    let mut command = Command::new(&s.launcher.program);
    command
        .args(&s.launcher.args)
        // The window speaks the language chosen for the session.
        .env(crate::language::ENV, i18n::current().tag());
    // In a process group of its own (Ctrl-C in the terminal stops the session, which then
    // closes the window, rather than killing the window first).
    let (mut child, ours) = channel::spawn_connected(&mut command, OPEN_TIMEOUT)?;
    let mut to_window = ours.try_clone()?;
    let mut from_window = ours.try_clone()?;
    let outcome = std::thread::scope(|scope| {
        let (tx, rx) = mpsc::channel();
        let hello = Hello {
            replaces_a_lost_window: replacing,
            ..s.hello.clone()
        };
        if let Err(e) = wire::send(&mut to_window, &ToWindow::Hello(Box::new(hello))) {
            return Outcome {
                ending: Ending::NeverOpened(format!("cannot say hello to it: {e}")),
                opened: false,
                closed: None,
            };
        }
        let (gate, done, end_phase) = (s.gate, s.done, s.end_phase);
        let (controls, arm_measured_m) = (s.controls, s.arm_measured_m);
        scope.spawn(move || {
            let gone = loop {
                match wire::recv::<FromWindow>(&mut from_window) {
                    Ok(Some(FromWindow::Pull)) => {
                        // Once the session is over, the next pull is answered with the end
                        // screen (once); the window keeps pulling as its heartbeat.
                        let end = done
                            .load(Ordering::Acquire)
                            .then(|| end_phase.and_then(EndPhase::take_screen_to_send))
                            .flatten();
                        let answers = end_answers(controls);
                        let frame = match end {
                            Some(screen) => {
                                controls.end_screen_up.store(true, Ordering::Release);
                                ToWindow::EndScreen(Box::new(screen))
                            }
                            None if !answers.is_empty() => ToWindow::EndInput(answers),
                            None => ToWindow::Frame {
                                record: Box::new(*output.read()),
                                draw: gate.is_none_or(|g| g.load(Ordering::Relaxed)),
                                brk: controls.break_now(),
                                arm_measured_m: arm_measured_m.get().copied(),
                            },
                        };
                        // A frame that cannot be sent (the session is over and our side is
                        // shut, or the window is going) is no reason to stop listening: its
                        // goodbye may still come, and its end shows as the end of the stream.
                        match wire::send(&mut to_window, &frame) {
                            Ok(()) => {
                                let _ = tx.send(Heard::Pulled);
                            }
                            // Said, so a window later taken for hung shows why it starved.
                            Err(e) => tracing::debug!("cannot send the window a frame: {e}"),
                        }
                    }
                    Ok(Some(m)) => {
                        let _ = tx.send(Heard::Said(m));
                    }
                    Ok(None) => break None,
                    Err(e) => break Some(e.to_string()),
                }
            };
            let _ = tx.send(Heard::Gone(gone));
        });
        let outcome = watch(s, &rx, &ours);
        // Whatever happened, this window is finished: closing the socket ends the reader
        // thread (even one blocked sending to a hung window).
        let _ = ours.shutdown(std::net::Shutdown::Both);
        outcome
    });
    let status = finish(
        &mut child,
        matches!(outcome.ending, Ending::SessionOver | Ending::Quit),
        s.clock,
    );
    // When only the socket told us, say how the process ended.
    let ending = match outcome.ending {
        Ending::Lost(why) if why.is_empty() => Ending::Lost(format!("the patient window {status}")),
        Ending::NeverOpened(why) if why.is_empty() => {
            Ending::NeverOpened(format!("the window process {status}"))
        }
        other => other,
    };
    Ok(Outcome { ending, ..outcome })
}

/// Watch one window until it ends, the session ends, or it hangs.
fn watch(s: &Supervised<'_>, rx: &mpsc::Receiver<Heard>, socket: &WindowSocket) -> Outcome {
    let started_ns = s.clock.now_ns();
    let mut last_heard_ns = started_ns;
    let mut opened = false;
    let mut quit = false;
    let mut closing_since_ns: Option<u64> = None;
    // When the end screen began (the session ended with the window up).
    let mut end_since_ns: Option<u64> = None;
    let mut closed = None;
    let mut failed: Option<String> = None;
    loop {
        match rx.recv_timeout(WATCH_PERIOD) {
            Ok(Heard::Pulled) => last_heard_ns = s.clock.now_ns(),
            Ok(Heard::Said(FromWindow::Opened)) => {
                opened = true;
                last_heard_ns = s.clock.now_ns();
            }
            Ok(Heard::Said(FromWindow::Request(r))) => {
                quit |= r == UserRequest::Quit;
                apply(r, s.controls);
            }
            Ok(Heard::Said(FromWindow::Closed {
                frames_drawn,
                adapter,
            })) => closed = Some((frames_drawn, adapter)),
            Ok(Heard::Said(FromWindow::Failed(why))) => failed = Some(why),
            Ok(Heard::Said(FromWindow::CheckIn(answers))) => {
                if let Some(e) = s.end_phase {
                    tracing::info!(?answers, "the patient answered the end screen");
                    *lock(&e.answers) = Some(answers);
                }
            }
            Ok(Heard::Said(FromWindow::MessageShown)) => {
                let at_ms = (s.clock.unix_ns() / 1_000_000).max(1);
                // The first time only (a replacement window shows it again).
                let first = s.controls.message_shown_unix_ms.compare_exchange(
                    0,
                    at_ms,
                    Ordering::AcqRel,
                    Ordering::Acquire,
                );
                if first.is_ok() {
                    tracing::info!(at_ms, "the therapist's message is on the screen");
                }
            }
            // Pulls are answered by the reader thread and reach here as `Pulled`.
            Ok(Heard::Said(FromWindow::Pull)) => {}
            gone @ (Ok(Heard::Gone(_)) | Err(mpsc::RecvTimeoutError::Disconnected)) => {
                let why = match gone {
                    Ok(Heard::Gone(why)) => failed.or(why),
                    _ => failed,
                }
                .unwrap_or_default();
                let ending = if closing_since_ns.is_some() || s.done.load(Ordering::Acquire) {
                    Ending::SessionOver
                } else if quit {
                    Ending::Quit
                } else if opened {
                    Ending::Lost(why)
                } else {
                    Ending::NeverOpened(why)
                };
                return Outcome {
                    ending,
                    opened,
                    closed,
                };
            }
            Err(mpsc::RecvTimeoutError::Timeout) => {}
        }
        if s.done.load(Ordering::Acquire)
            && closing_since_ns.is_none()
            && !end_screen_holds(s, opened, &mut end_since_ns)
        {
            // The session is over: closing our side ends the window's loop.
            let _ = socket.shutdown(std::net::Shutdown::Write);
            closing_since_ns = Some(s.clock.now_ns());
        }
        let ending = match closing_since_ns {
            Some(t) if elapsed(s.clock, t) > CLOSE_TIMEOUT => Ending::SessionOver,
            Some(_) => continue,
            None if !opened && elapsed(s.clock, started_ns) > OPEN_TIMEOUT => Ending::NeverOpened(
                format!("it did not open within {} s", OPEN_TIMEOUT.as_secs()),
            ),
            None if opened && elapsed(s.clock, last_heard_ns) > HANG_TIMEOUT => {
                Ending::Lost(format!(
                    "the patient window stopped answering for {} s",
                    HANG_TIMEOUT.as_secs()
                ))
            }
            None => continue,
        };
        return Outcome {
            ending,
            opened,
            closed,
        };
    }
}

/// After the session: the open window stays up while it asks the end screen's questions,
/// until answered or [`EndPhase::limit`] after the session ended.
fn end_screen_holds(s: &Supervised<'_>, opened: bool, end_since_ns: &mut Option<u64>) -> bool {
    let Some(e) = s.end_phase.filter(|e| opened && e.asking()) else {
        return false;
    };
    let since = *end_since_ns.get_or_insert_with(|| s.clock.now_ns());
    elapsed(s.clock, since) <= e.limit()
}

/// Apply a key the patient pressed in the window to the session.
fn apply(r: UserRequest, controls: &Controls) {
    match r {
        UserRequest::Quit => controls.stop.store(true, Ordering::Relaxed),
        UserRequest::TogglePause => {
            controls.pause.fetch_xor(true, Ordering::Relaxed);
        }
        // The window asks before ending: meanwhile the exercise waits.
        UserRequest::AskEnd => controls.pause.store(true, Ordering::Relaxed),
        // R: a rest now; Space during a break: go on now.
        UserRequest::Rest => controls.rest.store(true, Ordering::Relaxed),
        UserRequest::GoOn => controls.end_break.store(true, Ordering::Relaxed),
        // Seeking and speed are a replay's; a live session has neither.
        _ => {}
    }
}

/// Reap the window process: wait a little if it is closing normally, kill it otherwise (a
/// hung one does not close). Returns how it ended, in words.
fn finish(child: &mut Child, closing: bool, clock: &Clock) -> String {
    if closing {
        let start_ns = clock.now_ns();
        while elapsed(clock, start_ns) < CLOSE_TIMEOUT {
            if let Ok(Some(status)) = child.try_wait() {
                return crate::platform::describe_exit(status);
            }
            std::thread::sleep(WATCH_PERIOD);
        }
    }
    let _ = child.kill();
    match child.wait() {
        Ok(status) => crate::platform::describe_exit(status),
        Err(e) => format!("could not be waited for ({e})"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_wheel_and_gamepad_answer_the_end_screen_only_once_it_is_up_as_keys_in_order() {
        let c = Controls::default();
        c.end_answers.step(1);
        assert!(
            end_answers(&c).is_empty(),
            "not before the end screen is up"
        );
        c.end_screen_up.store(true, Ordering::Release);
        c.end_answers.step(2);
        c.end_answers.step(-1);
        c.end_answers.confirm();
        c.end_answers.skip();
        // The step taken before the end screen was up comes first, then the rest in the
        // order said.
        assert_eq!(
            end_answers(&c),
            [
                UserRequest::SeekForward,
                UserRequest::SeekForward,
                UserRequest::SeekForward,
                UserRequest::SeekBack,
                UserRequest::Confirm,
                UserRequest::Quit
            ]
        );
        assert!(end_answers(&c).is_empty(), "each answer passed on once");
        c.end_answers.step(-3);
        assert_eq!(end_answers(&c), [UserRequest::SeekBack; 3]);
    }
}
