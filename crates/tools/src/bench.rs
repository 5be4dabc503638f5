//! `telerehab bench`: measurements that need the whole station, not a micro-benchmark. Each
//! compares two things in one run, so that the noise of a shared machine hits both alike.

#[cfg(target_os = "linux")]
mod loop_;
mod recording;
mod soak;
mod window;

#[cfg(target_os = "linux")]
pub use loop_::BenchLoopArgs;
pub use recording::BenchRecordingArgs;
pub use soak::BenchSoakArgs;
pub use window::RenderImpact;

/// `telerehab bench`.
#[derive(Debug, clap::Args)]
pub struct BenchArgs {
    /// What to measure.
    #[command(subcommand)]
    pub what: BenchCommand,
}

/// The benchmarks.
#[derive(Debug, clap::Subcommand)]
pub enum BenchCommand {
    /// The window's effect on the haptic loop: drawing on and off in alternating phases of one
    /// real-time session (needs a display; use `xvfb-run -a` on a machine without one).
    Window(BenchWindowArgs),
    /// The recording's bytes and the recorder's CPU: the compact encoding against the
    /// all-JSON one it replaced, on the same ticks of a simulated session.
    Recording(BenchRecordingArgs),
    /// A long simulated, recorded session (1 h at `--speed max` by default) watched for
    /// growing memory or descriptors, a recording that does not grow linearly and late ticks.
    Soak(BenchSoakArgs),
    /// The haptic loop's wake-up lateness against the platform's floor: the station's
    /// real-time session, a minimal SCHED_FIFO `clock_nanosleep` loop on the same core and
    /// `cyclictest` (when installed), back to back, and their ratios. (Linux: its reference is
    /// the Linux real-time floor.)
    #[cfg(target_os = "linux")]
    Loop(BenchLoopArgs),
}

/// `telerehab bench window`.
#[derive(Debug, clap::Args)]
pub struct BenchWindowArgs {
    /// Session length, s (the first two phases are warm-up and not counted).
    #[arg(long, default_value_t = 40.0)]
    pub duration: f64,
    /// Length of each drawing-on and drawing-off phase, s.
    #[arg(long, default_value_t = 2.0)]
    pub phase: f64,
    /// Exercise to run.
    #[arg(long, default_value = "sine-road")]
    pub exercise: String,
    /// Seed of the simulation.
    #[arg(long, default_value_t = 7)]
    pub seed: u64,
    /// Most frames per second the window draws (default: the window's own choice).
    #[arg(long)]
    pub max_fps: Option<f64>,
    /// Window size, WIDTHxHEIGHT in pixels.
    #[arg(long, default_value = "1280x720", value_parser = station::commands::parse_size)]
    pub size: (u32, u32),
    /// Leave the window at normal scheduling priority (the station puts it below the session's
    /// threads, nice 10); for comparing the two.
    #[arg(long)]
    pub normal_priority: bool,
    /// Sessions to run one after the other; with more than one, the median of what drawing
    /// added to the p99 period error is printed last.
    #[arg(long, default_value_t = 1)]
    pub runs: usize,
}

/// Run `telerehab bench …`.
pub fn run(args: BenchArgs) -> anyhow::Result<()> {
    match args.what {
        BenchCommand::Window(a) => window::window(a),
        BenchCommand::Recording(a) => recording::recording(a),
        BenchCommand::Soak(a) => soak::soak(a),
        #[cfg(target_os = "linux")]
        BenchCommand::Loop(a) => loop_::bench_loop(a),
    }
}
