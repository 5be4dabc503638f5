//! Command-line interface.

use clap::{Parser, Subcommand};

use crate::commands::vehicle::VehicleArgs;

/// telerehab: home upper-limb rehabilitation with a force-feedback wheel.
#[derive(Debug, Parser)]
#[command(name = "telerehab", version, about)]
pub struct Cli {
    /// What to run.
    #[command(subcommand)]
    pub command: Option<Command>,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Run the vehicle model offline on a CSV of driver inputs.
    Vehicle(VehicleArgs),
}

/// Parse the command line and run it.
pub fn main() -> anyhow::Result<()> {
    let cli = Cli::parse();
    match cli.command {
        Some(Command::Vehicle(args)) => crate::commands::vehicle::run(args),
        None => Ok(()),
    }
}
