//! Chosen channels of a recording over a span of session time, read without decoding the rest:
//! what Python's `telerehab.session.read(path, channels=…, start_s=…, end_s=…)` uses, and
//! what a report or replay of part of a session can use.
//!
//! A finished recording ends with a summary (MCAP's summary section: the channels, and one
//! chunk index per chunk naming the time range of its messages and where each channel's
//! message index is). [`read_selected`] reads that summary (`summary`), picks the chunks that
//! hold messages of the chosen channels stamped in the window (`plan`: chunk indexes first,
//! then the chosen channels' message indexes of the chunks at the window's edges),
//! decompresses only those (mcap's indexed reader), and decodes only the chosen channels'
//! messages among them, keeping the samples in the window ([`super::columns`]).
//!
//! A recording without a summary (cut short, or of another writer without indexes) is read by
//! the front-to-back walk of [`super::columns`] instead, with the same result: the chosen
//! channels, their samples in the window.
//!
//! What the indexed path relies on, as the station's writer ([`super::RecordWriter`]) records
//! it: a message's log time is its first sample's session time plus one offset for the whole
//! file (the session's start; a block message is stamped with its first sample), and each
//! channel's samples are in time order. The offset is taken from the earliest message stamp
//! (the session's first tick is at 0 s) and checked against every message decoded; a file that
//! disagrees is read again with the offset it shows, and then front to back.
//!
//! The untrusted-input limits of the walk ([`super::walk`]) hold here too: every record of the
//! summary, every message index, chunk and message within [`super::MAX_RECORD_BYTES`] and the
//! [`StreamLimits`], every length inside a record checked before mcap parses it, and the
//! chunks decompressed within the same zstd window ([`super::walk::ZSTD_WINDOW_LOG_MAX`]).

mod decompress;
pub mod info;
mod plan;
mod summary;

use super::columns::{self, RecordingColumns};
use super::error::ReadError;
use super::walk::StreamLimits;
use std::io::{Read, Seek};
use std::path::Path;

pub use super::selection::Selection;
pub use info::{ChannelInfo, RecordingInfo, recording_info, recording_info_path};

/// How a selection was read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Route {
    /// Through the summary's indexes: only the chunks holding what was asked for.
    Indexed,
    /// Front to back (no usable summary, or one the messages disagree with).
    Linear,
}

/// A selection read: the columns, and what reading them cost.
#[derive(Clone, Debug, PartialEq)]
pub struct Selected {
    /// The chosen channels' columns and messages, their samples in the window, and the
    /// session metadata.
    pub columns: RecordingColumns,
    /// How it was read.
    pub route: Route,
    /// Chunks decompressed.
    pub chunks_read: u64,
    /// Chunks in the file (from its summary; on the linear route, those walked).
    pub chunks_in_file: u64,
}

/// Reads `selection` of the recording at `path` ([`read_selected`]).
pub fn read_selected_path(
    path: &Path,
    limits: StreamLimits,
    selection: &Selection,
) -> Result<Selected, ReadError> {
    let file = std::fs::File::open(path).map_err(|source| ReadError::Io {
        path: format!(" {}", path.display()),
        source,
    })?;
    read_selected(std::io::BufReader::new(file), limits, selection)
}

/// Reads the channels and window of `selection` from a recording, within `limits`: through
/// its summary when it has a usable one, front to back otherwise (the module's documentation
/// says how). The columns are those [`super::read_columns`] gives for the whole file, with the
/// channels not chosen left out and each channel's samples outside `[start_s, end_s)` (by
/// their `t_s`) dropped.
///
/// Fails as [`super::read_columns`] does, and with [`ReadError::BadSelection`] for a
/// selection that cannot be read and [`ReadError::NoSuchChannel`] for a topic the recording
/// has no readable channel of.
pub fn read_selected<R: Read + Seek>(
    mut input: R,
    limits: StreamLimits,
    selection: &Selection,
) -> Result<Selected, ReadError> {
    let picked = selection.checked()?;
    if let Some(selected) = plan::read_indexed(&mut input, limits, &picked)? {
        return Ok(selected);
    }
    input.rewind().map_err(|source| ReadError::Io {
        path: String::new(),
        source,
    })?;
    let (columns, chunks) = columns::read_picked(input, limits, &picked)?;
    Ok(Selected {
        columns,
        route: Route::Linear,
        chunks_read: chunks,
        chunks_in_file: chunks,
    })
}

#[cfg(test)]
mod tests;
