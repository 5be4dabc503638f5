//! `telerehab recover`: turn the recording of a killed session into a finished MCAP file
//! (the copy itself is [`crate::record::recover`]).

use crate::record::recover::{Recovered, recover as recover_bytes};
use anyhow::Context;
use std::io::{BufWriter, Write};
use std::path::Path;

/// Copy the readable part of `input` into a finished MCAP file `output`.
pub fn recover(input: &Path, output: &Path) -> anyhow::Result<Recovered> {
    let bytes = std::fs::read(input).with_context(|| format!("cannot read {}", input.display()))?;
    let file = std::fs::File::create(output)
        .with_context(|| format!("cannot create {}", output.display()))?;
    let (copied, mut sink) = recover_bytes(&bytes, BufWriter::new(file))
        .with_context(|| format!("cannot recover {}", input.display()))?;
    sink.flush()
        .with_context(|| format!("cannot write {}", output.display()))?;
    Ok(copied)
}
