//! Why a recording could not be read: the one error of every reader of the crate.

use super::blocks::BlockError;
use super::types::MetadataError;

/// Why a recording could not be read.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReadError {
    /// The file or stream could not be read.
    #[error("cannot read the recording{path}: {source}")]
    Io {
        /// `" <path>"` when read from a file, empty otherwise.
        path: String,
        /// Why.
        source: std::io::Error,
    },
    /// Not an MCAP file, or a damaged one (a killed session's file: run `telerehab recover`).
    #[error("not a readable MCAP recording: {0}")]
    Mcap(#[from] mcap::McapError),
    /// A message is not what its channel's schema says.
    #[error("message {index} of channel {topic} does not decode: {source}")]
    Decode {
        /// The channel's topic.
        topic: &'static str,
        /// The sample's position within its channel, from 0.
        index: usize,
        /// What serde found.
        source: serde_json::Error,
    },
    /// A block message of a high-rate channel does not decode.
    #[error("the block of channel {topic} from sample {index} does not decode: {source}")]
    Block {
        /// The channel's topic.
        topic: &'static str,
        /// The position of the block's first sample within its channel, from 0
        /// (`usize::MAX`: the channel's layout).
        index: usize,
        /// What the block decoder found.
        source: BlockError,
    },
    /// A record, chunk or message claims more bytes than the readers accept
    /// ([`super::walk::MAX_RECORD_BYTES`], [`super::walk::StreamLimits`]): refused before any
    /// of it is allocated.
    #[error(
        "{what} claims {claimed_bytes} bytes, more than the {limit_bytes} this reader accepts \
         (a damaged or hostile recording)"
    )]
    TooLarge {
        /// What, and where (e.g. `the uncompressed data of chunk 3`).
        what: String,
        /// The length the file claims, bytes.
        claimed_bytes: u64,
        /// The limit, bytes.
        limit_bytes: u64,
    },
    /// A chunk's data is not what its header declares (it decompresses to more or fewer bytes,
    /// or a record inside overruns it).
    #[error("chunk {chunk} {reason} (a damaged or hostile recording)")]
    BadChunk {
        /// The chunk's position in the file, from 1.
        chunk: u64,
        /// What is wrong.
        reason: String,
    },
    /// A record's fields overrun the record.
    #[error("a damaged record (in chunk {chunk}; 0: outside chunks): {reason}")]
    Damaged {
        /// The chunk holding it, from 1 (0: outside chunks).
        chunk: u64,
        /// What is wrong.
        reason: String,
    },
    /// The reading was stopped before the end by its [`super::walk::Check`] (the reader
    /// went away, or the work's budget was spent), for the reason given.
    #[error("reading stopped: {0}")]
    Stopped(String),
    /// The session metadata record is missing.
    #[error("the recording has no `session` metadata record")]
    NoMetadata,
    /// The session metadata record is incomplete or malformed.
    #[error(transparent)]
    Metadata(#[from] MetadataError),
    /// A channel asked for ([`super::select::Selection`]) that the recording does not have.
    #[error("the recording has no channel {topic} (it has {})", present.join(", "))]
    NoSuchChannel {
        /// The topic asked for.
        topic: String,
        /// The topics it has, readable ones only.
        present: Vec<String>,
    },
    /// A selection that cannot be read ([`super::select::Selection`]): a start after the
    /// end, a time that is not a number, no channel named.
    #[error("cannot read that part of the recording: {0}")]
    BadSelection(String),
}
