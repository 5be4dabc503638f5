//! `telerehab`: the patient station and the therapist hub.

use std::process::ExitCode;

fn main() -> ExitCode {
    match station::cli::main() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // `{:#}` prints the whole chain of causes on one line: what failed and why.
            eprintln!("telerehab: error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
