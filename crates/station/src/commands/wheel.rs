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
    /// Seconds given to turn the wheel lock to lock.
    #[arg(long, default_value_t = 15.0)]
    pub turn_seconds: f64,
    /// Replace `--out` if it exists (it is never overwritten otherwise).
    #[arg(long)]
    pub force: bool,
}

/// Run `telerehab wheel …`.
pub fn run(args: &WheelArgs) -> anyhow::Result<()> {
    match &args.command {
        WheelCommand::Calibrate(a) => calibrate(a),
    }
}

/// The person at the wheel, on the terminal.
#[cfg(target_os = "linux")]
struct Terminal;

#[cfg(target_os = "linux")]
impl wheel_devices::evdev_wheel::calibrate::Guide for Terminal {
    fn say(&mut self, text: &str) {
        println!("{text}");
    }
    fn confirm(&mut self, question: &str) -> bool {
        use std::io::Write as _;
        print!("{question} [y/N] ");
        let _ = std::io::stdout().flush();
        let mut answer = String::new();
        std::io::stdin().read_line(&mut answer).is_ok()
            && matches!(answer.trim(), "y" | "Y" | "yes" | "Yes")
    }
}

#[cfg(target_os = "linux")]
fn calibrate(args: &CalibrateArgs) -> anyhow::Result<()> {
    use anyhow::Context;
    use haptic_wheel::Wheel as _;
    use wheel_devices::evdev_wheel::EvdevWheel;
    if let Some(t) = args.rated_torque_nm {
        haptic_wheel::WheelConfig {
            rated_torque_nm: Some(t),
            ..Default::default()
        }
        .validate()?;
    }
    anyhow::ensure!(
        (3.0..=120.0).contains(&args.turn_seconds),
        "--turn-seconds = {}, allowed 3 to 120 s",
        args.turn_seconds
    );
    if args.out.exists() && !args.force {
        anyhow::bail!(
            "{} exists: choose another --out, or add --force to replace it",
            args.out.display()
        );
    }
    // Driven as the station would drive it without a profile file: the built-in profile for
    // its USB id, or an unknown wheel's (capped), at full gain.
    let config = haptic_wheel::WheelConfig::default();
    let clock = clock::Clock::real();
    let mut wheel = match &args.device {
        Some(p) => EvdevWheel::open(p, config, clock),
        None => EvdevWheel::open_first(config, clock),
    }
    .context("no force-feedback wheel to measure (run `telerehab devices`)")?;
    println!("Measuring {}.", wheel.capabilities().name);
    let report = wheel.calibrate(&mut Terminal, args.turn_seconds, args.rated_torque_nm)?;
    drop(wheel);
    let text = toml::to_string(&report.profile).context("profile to TOML")?;
    std::fs::write(&args.out, text)
        .with_context(|| format!("cannot write {}", args.out.display()))?;
    println!(
        "Profile written to {}. Use it with, in the station's configuration:\n[wheel]\nprofile_file = \"{}\"",
        args.out.display(),
        args.out.display()
    );
    println!(
        "{}",
        haptic_wheel::CeilingReport::new(&report.profile, 1.0, None)
    );
    Ok(())
}

#[cfg(not(target_os = "linux"))]
fn calibrate(_args: &CalibrateArgs) -> anyhow::Result<()> {
    anyhow::bail!("measuring a wheel needs the Linux kernel force-feedback API")
}
