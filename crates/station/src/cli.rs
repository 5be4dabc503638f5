//! Command-line interface.

use clap::Parser;

/// telerehab: home upper-limb rehabilitation with a force-feedback wheel.
#[derive(Debug, Parser)]
#[command(name = "telerehab", version, about)]
pub struct Cli {}

/// Parse the command line and run it.
pub fn main() -> anyhow::Result<()> {
    let _cli = Cli::parse();
    Ok(())
}
