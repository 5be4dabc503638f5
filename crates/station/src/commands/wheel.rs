//! `telerehab wheel`: measure a real force-feedback wheel and write its profile.

use std::path::PathBuf;

/// `telerehab wheel`.
#[derive(Debug, clap::Args)]
pub struct WheelArgs {
    /// What to do with the wheel.
    #[command(subcommand)]
    pub command: WheelCommand,
}

/// `telerehab wheel …`.
#[derive(Debug, clap::Subcommand)]
pub enum WheelCommand {
    /// Measure the connected wheel (angle range, signs, encoder resolution, usable update
    /// rate) with a guided procedure and write a profile file for `[wheel] profile_file`.
    Calibrate(CalibrateArgs),
}

/// `telerehab wheel calibrate`.
#[derive(Debug, clap::Args)]
pub struct CalibrateArgs {
    /// The wheel's device node (default: the first force-feedback wheel found).
    #[arg(long)]
    pub device: Option<PathBuf>,
    /// Where to write the profile (TOML).
    #[arg(long, default_value = "wheel-profile.toml")]
    pub out: PathBuf,
    /// The motor's rated (peak) torque from the maker's sheet, N·m, if known: written into the
    /// profile (otherwise the built-in or assumed figure is kept).
    #[arg(long)]
    pub rated_torque_nm: Option<f64>,
}

/// Run `telerehab wheel …`.
pub fn run(args: &WheelArgs) -> anyhow::Result<()> {
    match &args.command {
        WheelCommand::Calibrate(a) => calibrate(a),
    }
}

fn calibrate(_args: &CalibrateArgs) -> anyhow::Result<()> {
    anyhow::bail!("not yet")
}
