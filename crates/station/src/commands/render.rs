//! `telerehab render`: a simulated session drawn offscreen to PNG frames (the window's drawing
//! code, on Mesa's software Vulkan/GL where there is no GPU).

use super::run::{RunArgs, Speed};
use crate::screen::CourseView;
use record::TickRecord;
use render::ScreenState;
use session::signals::install_stop_flag;
use session::{self, SessionObserver, SessionOptions};
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// `telerehab render`.
#[derive(Debug, clap::Args)]
pub struct RenderArgs {
    /// Exercise to render.
    #[arg(long, default_value = "sine-road", conflicts_with = "regimen")]
    pub exercise: String,
    /// Regimen file to render instead of one exercise.
    #[arg(long)]
    pub regimen: Option<PathBuf>,
    /// Station configuration (TOML).
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// Seed of the simulation.
    #[arg(long, default_value_t = 7)]
    pub seed: u64,
    /// Frames to render.
    #[arg(long, default_value_t = 120)]
    pub frames: usize,
    /// Frames per second of session time.
    #[arg(long, default_value_t = 30.0)]
    pub fps: f64,
    /// Frame size, WIDTHxHEIGHT in pixels.
    #[arg(long, default_value = "1280x720", value_parser = super::parse_size)]
    pub size: (u32, u32),
    /// Output directory for frame_0000.png, frame_0001.png, …
    #[arg(long)]
    pub out: PathBuf,
}

/// Collects the ticks to draw: one every `every` ticks, `frames` of them, then stops the
/// session; each with the patient's own arm lengths once the session has measured them.
struct FrameCollector {
    every: u64,
    frames: usize,
    records: Vec<(TickRecord, Option<[f64; 2]>)>,
    arm_measured_m: Option<[f64; 2]>,
    stop: Arc<AtomicBool>,
}

impl SessionObserver for FrameCollector {
    fn on_tick(&mut self, record: &TickRecord) {
        if self.records.len() < self.frames && record.tick.is_multiple_of(self.every) {
            self.records.push((*record, self.arm_measured_m));
            if self.records.len() == self.frames {
                self.stop.store(true, Ordering::Relaxed);
            }
        }
    }

    fn on_summary(&mut self, summary: &session::LiveSummary) {
        if let Some(lengths) = summary.measured_arm_lengths_m() {
            self.arm_measured_m.get_or_insert(lengths);
        }
    }
}

/// Run `telerehab render`: simulate as fast as possible, then draw the collected ticks.
pub fn run(args: RenderArgs) -> anyhow::Result<()> {
    anyhow::ensure!(args.frames > 0, "--frames must be at least 1");
    anyhow::ensure!(
        args.fps.is_finite() && (1.0..=240.0).contains(&args.fps),
        "--fps must be 1 to 240"
    );
    let run_args = RunArgs {
        config: args.config.clone(),
        exercise: args.regimen.is_none().then(|| args.exercise.clone()),
        regimen: args.regimen.clone(),
        speed: Speed::Max,
        ..RunArgs::simulated(args.frames as f64 / args.fps + 1.0, args.seed)
    };
    let (cfg, regimen) = super::run::plan(&run_args)?;
    let view = CourseView::new(&cfg, regimen.as_ref())?;
    let stop = install_stop_flag()?;
    let every = ((cfg.session.loop_rate_hz / args.fps).round() as u64).max(1);
    let mut frames = FrameCollector {
        every,
        frames: args.frames,
        records: Vec::with_capacity(args.frames),
        arm_measured_m: None,
        stop: stop.clone(),
    };
    let opts = SessionOptions {
        regimen,
        ..SessionOptions::simulated(cfg)
    };
    session::run(&opts, &session::Controls::with_stop(stop), &mut frames)?;
    let scenes = frames
        .records
        .iter()
        .map(|(r, arm)| view.scene_with_arm(r, ScreenState::Running, *arm));
    let (w, h) = args.size;
    let stats = render::headless_frames(scenes, w, h, &args.out)?;
    println!(
        "rendered {} frames of {w}×{h} to {} on {:?}: {:.1} ms mean, p99 {:.1} ms per frame",
        stats.frames,
        args.out.display(),
        stats.adapter,
        stats.mean_ms,
        stats.p99_ms
    );
    Ok(())
}
