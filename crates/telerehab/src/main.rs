//! `telerehab`: the patient station and the therapist hub.

use std::process::ExitCode;
use telerehab::cli::{Cli, dispatch};

fn main() -> ExitCode {
    let cli = Cli::from_env();
    station::logging::init(cli.log.as_deref(), cli.log_format);
    if let Some(Err(e)) = cli.language.as_deref().map(session::language::force) {
        eprintln!("telerehab: error: {e}");
        return ExitCode::FAILURE;
    }
    match dispatch(cli.command) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // `{:#}` prints the whole chain of causes on one line: what failed and why.
            eprintln!("telerehab: error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
