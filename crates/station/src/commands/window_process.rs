//! `telerehab window-process`: the patient window's own process, started by `telerehab run`
//! with a socket as its standard input (not for people to run; hidden from `--help`). It opens
//! the window, asks the station for the newest tick about 120 times a second, draws it, and
//! passes the patient's keys back. It shares no memory with the station, so a graphics driver
//! that crashes or hangs takes only this process down; the station notices, pauses the
//! exercise and starts a new one ([`session::window::supervisor`]).

use crate::checkin::CheckInFlow;
use crate::screen::{CourseView, WindowState, live_screen_state};
use anyhow::Context;
use record::TickRecord;
use regimen::Regimen;
use render::ScreenState;
use render::window::{UserRequest, WindowOptions};
use session::config::StationConfig;
use session::window::channel::{self, WindowSocket};
use session::window::wire::{self, EndScreen, FromWindow, Hello, ToWindow};
use session::{BreakKind, BreakNow};
use std::io::Write;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

/// Below the session's threads ([`session::haptic::WINDOW_NICE`]) when the station asked for it.
fn lower_priority_if_asked(hello: &Hello) {
    if hello.background_priority {
        let idle = session::haptic::request_background_priority();
        tracing::debug!(idle, "patient window below the session's threads (nice 10)");
    }
}

/// What a key means during the session: Esc once asks (the exercise waits) and again ends;
/// Space or R after Esc goes on; Space during a break ends it; R asks for a rest.
fn session_request(r: UserRequest, confirming: &AtomicBool, in_break: bool) -> UserRequest {
    let asking = confirming.load(Ordering::Relaxed);
    match r {
        UserRequest::AskEnd if asking => UserRequest::Quit,
        UserRequest::AskEnd => {
            confirming.store(true, Ordering::Relaxed);
            UserRequest::AskEnd
        }
        UserRequest::TogglePause | UserRequest::Typed('r' | 'R') if asking => {
            confirming.store(false, Ordering::Relaxed);
            UserRequest::TogglePause
        }
        UserRequest::TogglePause if in_break => UserRequest::GoOn,
        UserRequest::Typed('r' | 'R') => UserRequest::Rest,
        other => other,
    }
}

/// What the reader thread last heard from the station.
#[derive(Default)]
struct Latest {
    record: Option<TickRecord>,
    /// The break in progress.
    brk: BreakNow,
    /// The patient's own arm lengths once the session has measured them.
    arm_measured_m: Option<[f64; 2]>,
    /// The station closed the socket: the session is over.
    ended: bool,
    /// The session is over and the station asked for the end screen (taken when shown).
    end_screen: Option<EndScreen>,
    /// Answers to the end screen given with the wheel or a gamepad, not yet applied.
    end_input: Vec<UserRequest>,
}

/// No arguments: everything comes over the socket.
#[derive(Debug, clap::Args)]
pub struct WindowProcessArgs {}

/// Serve the station that started this process on its standard input.
pub fn run(_args: &WindowProcessArgs) -> anyhow::Result<()> {
    serve(channel::connect_to_station().context("the station's socket")?)
}

/// Serve the station on `socket`: read its [`Hello`], open the window and draw until the
/// station closes the socket or the patient closes the window.
fn serve(socket: WindowSocket) -> anyhow::Result<()> {
    let mut reader = socket.try_clone().context("the station's socket")?;
    let writer = Mutex::new(socket);
    let hello: Hello = match wire::recv(&mut reader).context("the station's first message")? {
        Some(ToWindow::Hello(hello)) => *hello,
        Some(other) => anyhow::bail!("the station's first message is not a hello: {other:?}"),
        None => return Ok(()), // the station went away before saying anything
    };
    let tell = |message: &FromWindow| -> bool {
        let mut w = writer
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        wire::send(&mut *w, message)
            .and_then(|()| w.flush())
            .is_ok()
    };
    let view = match course_view(&hello) {
        Ok(v) => v,
        Err(e) => {
            tell(&FromWindow::Failed(format!("{e:#}")));
            return Err(e);
        }
    };
    lower_priority_if_asked(&hello);
    let latest = Mutex::new(Latest::default());
    let draw = Arc::new(AtomicBool::new(true));
    let opened = Arc::new(AtomicBool::new(false));
    // The end screen, once the station asks for it: it takes the keys, and Esc skips a
    // question instead of closing the window.
    let flow: Mutex<Option<CheckInFlow>> = Mutex::new(None);
    let esc_keeps_open = Arc::new(AtomicBool::new(false));
    let options = WindowOptions {
        size: hello.size,
        fullscreen: hello.fullscreen,
        max_fps: hello.max_fps,
        draw_gate: hello.gated.then(|| draw.clone()),
        opened: Some(opened.clone()),
        esc_keeps_open: Some(esc_keeps_open.clone()),
        confirm_end: true,
        ..WindowOptions::new(&hello.title)
    };
    // Esc was pressed once: the next Esc ends, Space goes on.
    let confirming = AtomicBool::new(false);
    let in_break = AtomicBool::new(false);
    let shown_at = std::time::Instant::now();
    std::thread::scope(|scope| {
        scope.spawn(|| read_frames(&mut reader, &latest, &draw));
        let mut told_opened = false;
        let mut message = MessageShown::default();
        let mut explain_pause = hello.replaces_a_lost_window;
        let source = || {
            if !told_opened && opened.load(Ordering::Acquire) {
                told_opened = tell(&FromWindow::Opened);
            }
            message.before_next_frame(&tell);
            // Ask for the next frame now; this one shows the newest the station sent.
            let asked = tell(&FromWindow::Pull);
            let mut l = latest
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner);
            let rec = l.record.unwrap_or_default();
            let mut f = flow
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner);
            if let Some(end) = l.end_screen.take() {
                tracing::info!("end screen: the session's results and the check-in");
                esc_keeps_open.store(true, Ordering::Release);
                *f = Some(end_flow(end));
            }
            if let Some(flow) = f.as_mut() {
                let (input, keeps_open) = (std::mem::take(&mut l.end_input), &esc_keeps_open);
                return end_screen_scene(flow, input, &view, &rec, &tell, keeps_open);
            }
            if l.ended || !asked {
                return None;
            }
            in_break.store(l.brk.kind != BreakKind::None, Ordering::Relaxed);
            let state = WindowState {
                brk: l.brk,
                confirming_end: confirming.load(Ordering::Relaxed),
                anim_s: shown_at.elapsed().as_secs_f64(),
            };
            let screen = screen_now(&view, &rec, &state, &mut explain_pause);
            crate::speech::speak_page(&screen);
            message.drawing(&screen);
            let mut scene = view.scene_with_arm(&rec, screen, l.arm_measured_m);
            // The gentle cue to sit up is said as it appears, over the running exercise.
            let notice = (scene.screen == ScreenState::Running)
                .then_some(scene.hud.notice.as_deref())
                .flatten();
            crate::speech::speak_notice(notice);
            if hello.practice {
                session::wheel_cards::mark_practice(&mut scene);
            }
            Some(scene)
        };
        let on_request = |r: UserRequest| {
            let mut f = flow
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner);
            if let Some(flow) = f.as_mut() {
                // The end screen takes the keys; there Esc skips a question.
                let r = if r == UserRequest::AskEnd {
                    UserRequest::Quit
                } else {
                    r
                };
                flow.apply(r, std::time::Instant::now());
                return;
            }
            let r = session_request(r, &confirming, in_break.load(Ordering::Relaxed));
            tell(&FromWindow::Request(r));
        };
        let result = render::window::run_with(&options, source, on_request);
        let last = match &result {
            Ok(stats) => FromWindow::Closed {
                frames_drawn: stats.frames_drawn,
                adapter: stats.adapter.clone(),
            },
            Err(e) => FromWindow::Failed(e.to_string()),
        };
        tell(&last);
        // The reader thread ends when the station closes its side, which it does on our
        // last message; shutting ours down ends it in any case.
        if let Ok(w) = writer.lock() {
            let _ = w.shutdown(std::net::Shutdown::Both);
        }
        result.map(|_| ()).map_err(anyhow::Error::from)
    })
}

/// The end screen's pages from the station's request.
fn end_flow(end: EndScreen) -> CheckInFlow {
    CheckInFlow::new(
        end.lines,
        std::time::Duration::from_secs(end.question_timeout_s),
        std::time::Instant::now(),
    )
    .with_care(end.pain_threshold_0_10, end.clinic_phone)
    .stopped_early(end.stopped_early)
}

/// The end screen's page now, after the wheel's and a gamepad's `input`, or `None` once it
/// is over (its answers sent to the station, and the window closes).
fn end_screen_scene(
    flow: &mut CheckInFlow,
    input: Vec<UserRequest>,
    view: &CourseView,
    rec: &TickRecord,
    tell: &dyn Fn(&FromWindow) -> bool,
    esc_keeps_open: &AtomicBool,
) -> Option<render::Scene> {
    for r in input {
        flow.apply(r, std::time::Instant::now());
    }
    flow.tick(std::time::Instant::now());
    if flow.is_done() {
        tracing::info!(answers = ?flow.answers(), "end screen closed");
        tell(&FromWindow::CheckIn(flow.answers().clone()));
        esc_keeps_open.store(false, Ordering::Release);
        return None;
    }
    Some(view.scene(rec, ScreenState::CheckIn(flow.page())))
}

/// What the window shows for the tick `rec`: the view's screen, except that until the
/// patient resumes a window that replaces a lost one (`explain_pause`) says why the exercise
/// paused by itself.
fn screen_now(
    view: &CourseView,
    rec: &TickRecord,
    state: &WindowState,
    explain_pause: &mut bool,
) -> ScreenState {
    match view.screen_state(rec, state) {
        ScreenState::Welcome(page)
            if *explain_pause
                && page.id == "paused"
                && live_screen_state(rec) == ScreenState::Paused =>
        {
            lost_window_card(page)
        }
        ScreenState::Running => {
            *explain_pause = false;
            ScreenState::Running
        }
        other => other,
    }
}

/// The pause page of a window that replaces a lost one: first why it paused by itself, then
/// its choices as ever.
fn lost_window_card(mut page: render::Welcome) -> ScreenState {
    page.lines.insert(
        0,
        render::StatusLine {
            ok: None,
            text: i18n::tr!("pause-screen-restarted"),
        },
    );
    ScreenState::Welcome(page)
}

/// Says once that the start card with the therapist's message was presented: it was handed to
/// the window to draw, and the window has asked for the frame after it.
#[derive(Default)]
struct MessageShown {
    drawn: bool,
    told: bool,
}

impl MessageShown {
    /// Before the next frame: tell the station if the message's frame was presented.
    fn before_next_frame(&mut self, tell: &dyn Fn(&FromWindow) -> bool) {
        if self.drawn && !self.told {
            self.told = tell(&FromWindow::MessageShown);
        }
    }

    /// The window is handed `screen` to draw.
    fn drawing(&mut self, screen: &ScreenState) {
        self.drawn |= matches!(screen, ScreenState::Next(c) if c.message.is_some());
    }
}

/// The view of the course from the session's configuration and regimen, with the
/// therapist's message for the start card.
fn course_view(hello: &Hello) -> anyhow::Result<CourseView> {
    let cfg: StationConfig =
        toml::from_str(&hello.config_toml).context("the session's configuration")?;
    let regimen: Option<Regimen> = hello
        .regimen_toml
        .as_deref()
        .map(toml::from_str)
        .transpose()
        .context("the session's regimen")?;
    // The patient's voice and neglected side, from the prescription.
    crate::speech::for_patient(regimen.as_ref().and_then(|r| r.patient.as_ref()));
    let mut view = CourseView::new(&cfg, regimen.as_ref())?;
    view.set_message(hello.message.clone());
    Ok(view)
}

/// Keep `latest` up to date with the station's frames until it closes the socket.
fn read_frames(reader: &mut WindowSocket, latest: &Mutex<Latest>, draw: &AtomicBool) {
    loop {
        let frame = wire::recv::<ToWindow>(reader);
        let mut l = latest
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        match frame {
            Ok(Some(ToWindow::Frame {
                record,
                draw: d,
                brk,
                arm_measured_m,
            })) => {
                l.record = Some(*record);
                l.brk = brk;
                l.arm_measured_m = arm_measured_m;
                draw.store(d, Ordering::Relaxed);
            }
            Ok(Some(ToWindow::EndScreen(end))) => l.end_screen = Some(*end),
            Ok(Some(ToWindow::EndInput(input))) => l.end_input.extend(input),
            Ok(Some(ToWindow::Hello(_))) => {
                tracing::warn!("the station said hello twice; ignored");
            }
            Ok(None) => {
                l.ended = true;
                return;
            }
            Err(e) => {
                tracing::warn!("the station's socket: {e}; closing the window");
                l.ended = true;
                return;
            }
        }
    }
}
