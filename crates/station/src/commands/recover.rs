//! `telerehab recover`: turn the recording of a killed session into a finished MCAP file
//! (the copy itself is [`crate::record::recover`]).

use crate::record::recover::{Recovered, recover as recover_bytes};
use anyhow::Context;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// `telerehab recover`.
#[derive(Debug, clap::Args)]
pub struct RecoverArgs {
    /// The recording left by the killed session.
    pub input: PathBuf,
    /// Where to write the finished file (a new file: never the input, never over another).
    #[arg(long)]
    pub out: PathBuf,
}

/// Recover `args.input` into `args.out` and say what was copied.
pub fn run(args: &RecoverArgs) -> anyhow::Result<()> {
    let r = recover(&args.input, &args.out)?;
    println!(
        "recovered {} messages on {} channels into {}{}",
        r.messages,
        r.channels,
        args.out.display(),
        r.stopped_at
            .map(|e| format!(" (the truncated tail was dropped: {e})"))
            .unwrap_or_default()
    );
    Ok(())
}

/// Copy the readable part of `input` into a finished MCAP file `output`.
pub fn recover(input: &Path, output: &Path) -> anyhow::Result<Recovered> {
    let bytes = std::fs::read(input).with_context(|| format!("cannot read {}", input.display()))?;
    // Never over an existing file: above all not over the input, the only copy of the session.
    let file = std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(output)
        .with_context(|| {
            format!(
                "cannot create {} (recover never writes over an existing file, its input least \
                 of all)",
                output.display()
            )
        })?;
    let (copied, mut sink) = recover_bytes(&bytes, BufWriter::new(file))
        .with_context(|| format!("cannot recover {}", input.display()))?;
    sink.flush()
        .with_context(|| format!("cannot write {}", output.display()))?;
    Ok(copied)
}
