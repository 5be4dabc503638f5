//! The `telerehab` command line: the clap tree and the dispatch, nothing else. Each
//! subcommand's arguments and `run()` live in the library that does the work: the station's
//! in `station::commands`, the clinic hub's in `hub::cli`, the measurements and drills in
//! `tools`.

use crate::docs;
use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};
use station::commands::{
    devices, doctor, pair, recover, render, replay, report, run, start, sync, therapist, vehicle,
    wheel, window_process,
};
use station::version::version;
use tools::bench;

/// telerehab: home upper-limb rehabilitation with a force-feedback steering wheel.
#[derive(Debug, Parser)]
#[command(name = "telerehab", version, about, long_about = None)]
pub struct Cli {
    /// Log filter (e.g. `info`, `debug`, `station=trace`); overrides RUST_LOG.
    #[arg(long, global = true)]
    pub log: Option<String>,
    /// Log lines on stderr as text (default) or one JSON object a line (for a log collector).
    #[arg(
        long,
        global = true,
        value_enum,
        env = "TELEREHAB_LOG_FORMAT",
        default_value_t
    )]
    pub log_format: station::logging::LogFormat,
    /// The language of the patient's screens (`en`, `de`, `es`, `zh`, or the pseudo-locale
    /// `en-XA` for layout checks), over the prescription's and the first-run choice.
    #[arg(long, global = true, env = session::language::ENV, value_name = "TAG")]
    pub language: Option<String>,
    /// What to do; none opens the patient's window (the first-run pages, then the session).
    #[command(subcommand)]
    pub command: Option<Command>,
}

impl Cli {
    /// The command line of this process, `--version` naming the formats it speaks.
    pub fn from_env() -> Self {
        let matches = Self::with_version().get_matches();
        Self::from_arg_matches(&matches).unwrap_or_else(|e| e.exit())
    }

    /// The clap command tree with `--version` naming the formats it speaks (for parsing, man
    /// pages and completions).
    pub fn with_version() -> clap::Command {
        // Built once or twice per process; clap takes a `'static` version text.
        let version: &'static str = Box::leak(version().into_boxed_str());
        Self::command().version(version)
    }
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Run a patient session.
    Run(run::RunArgs),
    /// Run the therapist hub: receive live summaries from stations and store them.
    Therapist(therapist::TherapistArgs),
    /// List wheels, pedals, gamepads and IMUs, with each wheel's torque ceiling.
    Devices(devices::DevicesArgs),
    /// Is this station ready for a session? One line per check with what to do; exit status
    /// 0 ready, 1 not ready, 2 could not check.
    Doctor(doctor::DoctorArgs),
    /// Render a simulated session offscreen to PNG frames (the window's drawing code, on
    /// Mesa's software Vulkan/GL where there is no GPU).
    Render(render::RenderArgs),
    /// Finish the MCAP recording of a killed session into a complete file.
    Recover(recover::RecoverArgs),
    /// Re-run a recorded simulated session and say whether it is reproduced bit for bit.
    Replay(replay::ReplayArgs),
    /// Write an HTML report of recorded sessions: measures, charts and progress.
    Report(report::ReportArgs),
    /// Run the vehicle model offline on a CSV of driver inputs.
    Vehicle(vehicle::VehicleArgs),
    /// Measure the whole station (for BENCHMARKS.md).
    Bench(bench::BenchArgs),
    /// Measure a real force-feedback wheel and write its profile (`wheel calibrate`).
    Wheel(wheel::WheelArgs),
    /// The clinic's hub: init, serve stations and the console, patients, stations, therapists.
    /// (Linux only: the hub is a clinic's server.)
    #[cfg(unix)]
    Hub(HubArgs),
    /// Pair this station with a clinic's hub using the code the clinic gave.
    Pair(pair::PairArgs),
    /// Deliver the summaries earlier sessions could not (they are also sent at the next run).
    Sync(sync::SyncArgs),
    /// The patient window's own process, started by `run` (not for people to run).
    #[command(hide = true)]
    WindowProcess(window_process::WindowProcessArgs),
    /// Write the man pages and shell completions (for packaging).
    #[command(hide = true)]
    Docs(docs::DocsArgs),
}

/// Run one subcommand; none opens the patient's window ([`start`]).
pub fn dispatch(command: Option<Command>) -> anyhow::Result<()> {
    let Some(command) = command else {
        return start::run();
    };
    match command {
        Command::Run(args) => run::run(args),
        Command::Therapist(args) => therapist::run(args),
        Command::Devices(args) => devices::run(&args),
        Command::Doctor(args) => doctor::run(&args),
        Command::Render(args) => render::run(args),
        Command::Recover(args) => recover::run(&args),
        Command::Replay(args) => replay::run(&args),
        Command::Report(args) => report::run(&args),
        Command::Vehicle(args) => vehicle::run(args),
        Command::Bench(args) => bench::run(args),
        Command::Wheel(args) => wheel::run(&args),
        #[cfg(unix)]
        Command::Hub(args) => match args.command {
            HubCommand::Clinic(command) => hub::cli::run(hub::cli::HubArgs { command }),
            HubCommand::Chaos(args) => on_runtime(tools::chaos::run(args)),
            HubCommand::Cohort(args) => on_runtime(tools::cohort::run(args)),
        },
        Command::Pair(args) => pair::run(&args),
        Command::Sync(args) => sync::run(&args),
        Command::WindowProcess(args) => window_process::run(&args),
        Command::Docs(args) => docs::run(&args, Cli::with_version()),
    }
}

/// `telerehab hub`: the hub's own commands, and the drills that run whole hubs and stations.
#[cfg(unix)]
#[derive(Debug, clap::Args)]
pub struct HubArgs {
    /// What to do.
    #[command(subcommand)]
    pub command: HubCommand,
}

/// `telerehab hub …`.
#[cfg(unix)]
#[derive(Debug, Subcommand)]
pub enum HubCommand {
    /// The clinic's system of record (`hub::cli`).
    #[command(flatten)]
    Clinic(hub::cli::HubCommand),
    /// A compressed clinic day on two hubs sharing one PostgreSQL (its own throwaway
    /// server), with hubs, stations and the database killed at random and restarted; fails
    /// unless every summary is stored exactly once, every recording verified, no station stuck
    /// and the audit log complete.
    Chaos(tools::chaos::ChaosArgs),
    /// The standard assessment's measurement noise: two simulated cohorts of unchanged
    /// patients assessed weekly through real stations and a hub; prints every measure's
    /// ICC(2,1), SEM and MDC95 and the false better/worse rate on the held-out cohort, and
    /// writes the noise table and the reliability page (docs/RELIABILITY.md).
    Cohort(tools::cohort::CohortArgs),
}

/// Runs a drill on the hub's runtime, stopping at SIGINT or SIGTERM as the hub does.
#[cfg(unix)]
fn on_runtime(drill: impl Future<Output = anyhow::Result<()>>) -> anyhow::Result<()> {
    netlink::server_stop::run_to_stop(hub::cli::runtime()?, drill)
}
