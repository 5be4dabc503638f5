//! The crate's error type for configuration, TLS and transport failures.

use std::path::PathBuf;

use crate::codec::CodecError;

/// Errors of the transport layer (the codec has its own [`CodecError`]).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum NetlinkError {
    /// A configuration field is out of its allowed range (the message names it).
    #[error("invalid netlink configuration: {0}")]
    Config(String),
    /// A PEM file could not be read or holds no usable item.
    #[error("cannot load {what} from {path}: {reason}")]
    Pem {
        /// What was expected (certificate chain, private key, CA certificates).
        what: &'static str,
        /// The file.
        path: PathBuf,
        /// Why it failed.
        reason: String,
    },
    /// rustls refused the TLS configuration.
    #[error("TLS configuration error: {0}")]
    Tls(#[from] rustls::Error),
    /// A socket or file operation failed.
    #[error("{context}: {source}")]
    Io {
        /// What was being done.
        context: String,
        /// The I/O error.
        source: std::io::Error,
    },
    /// The peer sent bytes that are not a valid frame.
    #[error("protocol error: {0}")]
    Codec(#[from] CodecError),
    /// The peer sent a valid frame that is not allowed at this point of the conversation.
    #[error("protocol violation: {0}")]
    Protocol(String),
    /// The named station is not connected to this hub.
    #[error("station {0:?} is not connected")]
    NotConnected(String),
    /// A bounded queue is full (a peer that does not read); the message says which. Retry later.
    #[error("busy: {0}")]
    Busy(String),
    /// The hub or link has been shut down.
    #[error("the link has been shut down")]
    Closed,
    /// The hub's system of record failed to store what the link received (the station is
    /// told to send it again later).
    #[error("the hub could not store it: {0}")]
    Store(String),
}

impl NetlinkError {
    pub(crate) fn io(context: impl Into<String>, source: std::io::Error) -> Self {
        Self::Io {
            context: context.into(),
            source,
        }
    }
}
