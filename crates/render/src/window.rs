//! The patient's window: winit 0.30 event loop, wgpu surface, the shared draw path.
//!
//! The loop pulls the newest [`Scene`] from the caller's closure about 120 times a second
//! (the closure reads a lock-free snapshot, so the haptic thread is never waited on) and
//! presents with vsync, so drawing runs at the display rate. A minimised or hidden window keeps
//! pulling scenes (to notice the end of the session) but skips drawing. Keys: Space asks to
//! pause or resume, F11 toggles full screen, Esc or closing the window ends the session; the
//! arrows and Home are passed on for a replay's seek and speed; typed characters, Backspace,
//! Enter, Tab and F2 for the first-run screens.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use winit::application::ApplicationHandler;
use winit::dpi::LogicalSize;
use winit::event::{ElementState, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{Key, NamedKey};
use winit::window::{Fullscreen, Window, WindowId};

use super::gpu::{Renderer, instance_descriptor, request_adapter};
use super::{AdapterSummary, RenderError, Scene};

/// How often the loop asks for a new scene when nothing else wakes it.
const PULL_PERIOD: Duration = Duration::from_micros(8_333);

/// Frame-rate cap on a software rasteriser when the caller sets none: it has no display rate
/// to wait for, and every frame it does not draw is CPU time the rest of the station keeps.
pub const SOFTWARE_MAX_FPS: f64 = 30.0;

/// A request from the patient's keyboard, passed to the caller's callback.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[non_exhaustive]
pub enum UserRequest {
    /// Space: pause a running exercise, or start / resume it.
    TogglePause,
    /// Esc or the window's close button: end the session.
    Quit,
    /// Esc in a window that asks before ending ([`WindowOptions::confirm_end`]).
    AskEnd,
    /// A rest now (the session window's R, or a wheel button).
    Rest,
    /// End the break in progress and go on now (Space during a rest).
    GoOn,
    /// ←: seek back (replay).
    SeekBack,
    /// →: seek forward (replay).
    SeekForward,
    /// ↑: play faster (replay).
    Faster,
    /// ↓: play slower (replay).
    Slower,
    /// Home: back to the start (replay).
    Restart,
    /// A printable character was typed (first-run screens: the pairing code).
    Typed(char),
    /// Backspace: erase the last character typed.
    Erase,
    /// Enter: confirm what was typed.
    Confirm,
    /// Tab: the next field.
    NextField,
    /// F2: a short simulated try-out (first-run screen).
    TryOut,
}

/// Window settings.
#[derive(Debug, Clone)]
pub struct WindowOptions {
    /// Window title.
    pub title: String,
    /// Initial inner size in logical pixels.
    pub size: (u32, u32),
    /// Start in borderless full screen.
    pub fullscreen: bool,
    /// Allow the event loop on a thread other than the main one (Linux only; for tests).
    pub any_thread: bool,
    /// Most frames drawn per second; `None` draws at the display rate (vsync) on a GPU and
    /// at [`SOFTWARE_MAX_FPS`] on a software rasteriser.
    pub max_fps: Option<f64>,
    /// Draw only while this flag is set (the loop still pulls scenes and handles keys);
    /// `None` always draws. For measuring what drawing costs the rest of the machine.
    pub draw_gate: Option<Arc<AtomicBool>>,
    /// Set once the window is open and can draw (for a caller on another thread, or in
    /// another process, that must tell a window that never opened from one that died).
    pub opened: Option<Arc<AtomicBool>>,
    /// While this flag is set, Esc is only reported (the end screen's "skip this question")
    /// and does not close the window; `None` or unset: Esc closes it.
    pub esc_keeps_open: Option<Arc<AtomicBool>>,
    /// Esc asks before ending ([`UserRequest::AskEnd`], the window stays open); the close
    /// button still ends at once.
    pub confirm_end: bool,
}

impl WindowOptions {
    /// A 1280×720 window with `title`.
    pub fn new(title: &str) -> Self {
        WindowOptions {
            title: title.into(),
            size: (1280, 720),
            fullscreen: false,
            any_thread: false,
            max_fps: None,
            draw_gate: None,
            opened: None,
            esc_keeps_open: None,
            confirm_end: false,
        }
    }
}

/// Opens the window and draws scenes from `scene_source` until it returns `None` (session
/// over), Esc is pressed or the window is closed. Space and Esc/close are reported to
/// `on_request`. Must be called on the main thread.
pub fn run(
    title: &str,
    scene_source: impl FnMut() -> Option<Scene>,
    on_request: impl FnMut(UserRequest),
) -> Result<(), RenderError> {
    run_with(&WindowOptions::new(title), scene_source, on_request).map(|_| ())
}

/// What a window session did.
#[derive(Debug, Clone, PartialEq)]
pub struct WindowStats {
    /// The adapter that drew the frames (None if the window never opened).
    pub adapter: Option<AdapterSummary>,
    /// Frames drawn and presented.
    pub frames_drawn: u64,
}

/// [`run`] with explicit [`WindowOptions`], returning what was drawn.
pub fn run_with(
    options: &WindowOptions,
    scene_source: impl FnMut() -> Option<Scene>,
    on_request: impl FnMut(UserRequest),
) -> Result<WindowStats, RenderError> {
    let mut builder = EventLoop::builder();
    #[cfg(target_os = "linux")]
    if options.any_thread {
        use winit::platform::x11::EventLoopBuilderExtX11;
        builder.with_any_thread(true);
    }
    let event_loop = builder
        .build()
        .map_err(|e| RenderError::Window(format!("cannot open a display: {e}")))?;
    let instance = wgpu::Instance::new(instance_descriptor(Some(Box::new(
        event_loop.owned_display_handle(),
    ))));
    let mut app = App {
        options: options.clone(),
        instance,
        gfx: None,
        scene_source,
        on_request,
        scene: None,
        next_pull: Instant::now(),
        next_draw: Instant::now(),
        error: None,
        frames_drawn: 0,
        adapter: None,
    };
    event_loop
        .run_app(&mut app)
        .map_err(|e| RenderError::Window(format!("event loop: {e}")))?;
    match app.error {
        Some(e) => Err(e),
        None => Ok(WindowStats {
            adapter: app.adapter,
            frames_drawn: app.frames_drawn,
        }),
    }
}

/// Window, surface and renderer, created on `resumed`.
struct Gfx {
    // Field order matters: the surface must drop before the window it draws into.
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    renderer: Renderer,
    window: Arc<Window>,
    /// The frame-rate cap in force.
    max_fps: Option<f64>,
}

struct App<F, G> {
    options: WindowOptions,
    instance: wgpu::Instance,
    gfx: Option<Gfx>,
    scene_source: F,
    on_request: G,
    scene: Option<Scene>,
    next_pull: Instant,
    /// Earliest time of the next frame under `max_fps`.
    next_draw: Instant,
    error: Option<RenderError>,
    frames_drawn: u64,
    /// The adapter that drew (kept once the window is closed).
    adapter: Option<AdapterSummary>,
}

impl<F: FnMut() -> Option<Scene>, G: FnMut(UserRequest)> App<F, G> {
    fn fail(&mut self, event_loop: &ActiveEventLoop, e: RenderError) {
        self.error.get_or_insert(e);
        self.close(event_loop);
    }

    /// Closes the window while the loop still runs (so the display hears of it: a process
    /// that goes on after the window, like the first-run pages before a session, leaves no
    /// dead window on the screen), then ends the loop.
    fn close(&mut self, event_loop: &ActiveEventLoop) {
        self.gfx = None;
        event_loop.exit();
    }

    fn create_gfx(&self, event_loop: &ActiveEventLoop) -> Result<Gfx, RenderError> {
        let (w, h) = self.options.size;
        let mut attrs = Window::default_attributes()
            .with_title(self.options.title.clone())
            .with_inner_size(LogicalSize::new(w, h))
            .with_min_inner_size(LogicalSize::new(320, 180));
        if self.options.fullscreen {
            attrs = attrs.with_fullscreen(Some(Fullscreen::Borderless(None)));
        }
        let window = Arc::new(
            event_loop
                .create_window(attrs)
                .map_err(|e| RenderError::Window(format!("creating the window: {e}")))?,
        );
        let surface = self
            .instance
            .create_surface(window.clone())
            .map_err(|e| RenderError::Window(format!("creating the surface: {e}")))?;
        let adapter = request_adapter(&self.instance, Some(&surface))?;
        let caps = surface.get_capabilities(&adapter);
        // egui and our colours are in display space: prefer a non-sRGB surface format.
        let format = caps
            .formats
            .iter()
            .copied()
            .find(|f| !f.is_srgb())
            .or_else(|| caps.formats.first().copied())
            .ok_or_else(|| RenderError::Window("the surface supports no format".into()))?;
        let size = window.inner_size();
        let (pw, ph) = (size.width.max(1), size.height.max(1));
        let renderer = Renderer::with_adapter(&adapter, format, pw, ph)?;
        let software = adapter.get_info().device_type == wgpu::DeviceType::Cpu;
        let max_fps = self
            .options
            .max_fps
            .or(software.then_some(SOFTWARE_MAX_FPS));
        println!(
            "render: adapter {}, surface format {format:?}, {}",
            renderer.adapter(),
            max_fps.map_or("frames at the display rate".into(), |f| format!(
                "at most {f} frames/s"
            ))
        );
        let mut config = surface
            .get_default_config(&adapter, pw, ph)
            .ok_or_else(|| RenderError::Window("surface is not supported by the adapter".into()))?;
        config.format = format;
        config.present_mode = wgpu::PresentMode::AutoVsync;
        surface.configure(renderer.device(), &config);
        Ok(Gfx {
            surface,
            config,
            renderer,
            window,
            max_fps,
        })
    }

    fn resize(&mut self, width: u32, height: u32) -> Result<(), RenderError> {
        let Some(g) = &mut self.gfx else {
            return Ok(());
        };
        if width == 0 || height == 0 {
            return Ok(()); // minimised: keep the old size, draw nothing
        }
        g.renderer.resize(width, height)?;
        g.config.width = width;
        g.config.height = height;
        g.surface.configure(g.renderer.device(), &g.config);
        Ok(())
    }

    fn redraw(&mut self) -> Result<(), RenderError> {
        let (Some(g), Some(scene)) = (&mut self.gfx, &self.scene) else {
            return Ok(());
        };
        let size = g.window.inner_size();
        if size.width == 0 || size.height == 0 {
            return Ok(());
        }
        let frame = match g.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(f)
            | wgpu::CurrentSurfaceTexture::Suboptimal(f) => f,
            wgpu::CurrentSurfaceTexture::Timeout | wgpu::CurrentSurfaceTexture::Occluded => {
                return Ok(());
            }
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                g.surface.configure(g.renderer.device(), &g.config);
                return Ok(());
            }
            wgpu::CurrentSurfaceTexture::Validation => {
                return Err(RenderError::Window("surface validation error".into()));
            }
        };
        let view = frame
            .texture
            .create_view(&wgpu::TextureViewDescriptor::default());
        g.renderer.draw(scene, &view)?;
        g.renderer.queue().present(frame);
        self.frames_drawn += 1;
        Ok(())
    }

    fn toggle_fullscreen(&self) {
        if let Some(g) = &self.gfx {
            let next = match g.window.fullscreen() {
                Some(_) => None,
                None => Some(Fullscreen::Borderless(None)),
            };
            g.window.set_fullscreen(next);
        }
    }
}

impl<F: FnMut() -> Option<Scene>, G: FnMut(UserRequest)> ApplicationHandler for App<F, G> {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.gfx.is_some() {
            return;
        }
        match self.create_gfx(event_loop) {
            Ok(g) => {
                self.adapter = Some(g.renderer.adapter().clone());
                self.gfx = Some(g);
                if let Some(opened) = &self.options.opened {
                    opened.store(true, Ordering::Release);
                }
            }
            Err(e) => self.fail(event_loop, e),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        match event {
            WindowEvent::CloseRequested => {
                (self.on_request)(UserRequest::Quit);
                self.close(event_loop);
            }
            WindowEvent::Resized(size) => {
                if let Err(e) = self.resize(size.width, size.height) {
                    self.fail(event_loop, e);
                }
            }
            WindowEvent::KeyboardInput { event, .. } if event.state == ElementState::Pressed => {
                match event.logical_key {
                    Key::Named(NamedKey::Escape) if self.options.confirm_end => {
                        if !event.repeat {
                            (self.on_request)(UserRequest::AskEnd);
                        }
                    }
                    Key::Named(NamedKey::Escape) => {
                        (self.on_request)(UserRequest::Quit);
                        let keep = self.options.esc_keeps_open.as_ref();
                        if !keep.is_some_and(|k| k.load(Ordering::Acquire)) {
                            self.close(event_loop);
                        }
                    }
                    Key::Named(NamedKey::F11) if !event.repeat => self.toggle_fullscreen(),
                    Key::Named(NamedKey::Space) if !event.repeat => {
                        (self.on_request)(UserRequest::TogglePause);
                    }
                    Key::Named(NamedKey::ArrowLeft) => (self.on_request)(UserRequest::SeekBack),
                    Key::Named(NamedKey::ArrowRight) => {
                        (self.on_request)(UserRequest::SeekForward);
                    }
                    Key::Named(NamedKey::ArrowUp) if !event.repeat => {
                        (self.on_request)(UserRequest::Faster);
                    }
                    Key::Named(NamedKey::ArrowDown) if !event.repeat => {
                        (self.on_request)(UserRequest::Slower);
                    }
                    Key::Named(NamedKey::Home) if !event.repeat => {
                        (self.on_request)(UserRequest::Restart);
                    }
                    Key::Named(NamedKey::Enter) if !event.repeat => {
                        (self.on_request)(UserRequest::Confirm);
                    }
                    Key::Named(NamedKey::Tab) if !event.repeat => {
                        (self.on_request)(UserRequest::NextField);
                    }
                    Key::Named(NamedKey::F2) if !event.repeat => {
                        (self.on_request)(UserRequest::TryOut);
                    }
                    Key::Named(NamedKey::Backspace) => (self.on_request)(UserRequest::Erase),
                    _ => {
                        let typed = event.text.as_deref().unwrap_or_default();
                        for c in typed
                            .chars()
                            .filter(|c| !c.is_control() && !c.is_whitespace())
                        {
                            (self.on_request)(UserRequest::Typed(c));
                        }
                    }
                }
            }
            WindowEvent::RedrawRequested => {
                if let Err(e) = self.redraw() {
                    self.fail(event_loop, e);
                }
            }
            _ => {}
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        let now = Instant::now();
        if now >= self.next_pull {
            match (self.scene_source)() {
                Some(scene) => self.scene = Some(scene),
                None => {
                    self.close(event_loop);
                    return;
                }
            }
            self.next_pull = now + PULL_PERIOD;
            let gate_open = self
                .options
                .draw_gate
                .as_ref()
                .is_none_or(|g| g.load(Ordering::Relaxed));
            if let Some(g) = &self.gfx
                && gate_open
                && now >= self.next_draw
            {
                if let Some(fps) = g.max_fps {
                    self.next_draw = now + Duration::from_secs_f64(1.0 / fps);
                }
                g.window.request_redraw();
            }
        }
        event_loop.set_control_flow(ControlFlow::WaitUntil(self.next_pull));
    }
}
