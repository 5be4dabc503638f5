//! The station–therapist link: a versioned, length-prefixed frame codec and its tokio
//! transport (TCP, optionally TLS) with store-and-forward of session summaries.
//!
//! - [`codec`] and [`frame`]: the wire format, pure (no I/O); normative text in `PROTOCOL.md`.
//! - [`station`]: [`StationLink`] — the station's non-blocking, store-and-forward sender.
//! - [`therapist`]: [`TherapistServer`] — the hub that stores and acknowledges summaries.
//! - [`store`]: the hub's on-disk layout, `DIR/<station_id>/<session_id>.jsonl`.
//! - [`tls`]: rustls configuration from PEM files.
//!
//! Safety invariant 4 of DESIGN.md ("a dropped network link resumes without losing or
//! duplicating a summary") rests on three rules: the station forgets a summary only when a
//! cumulative `Ack` covers it, it resends everything unacknowledged after a reconnect, and the
//! hub stores a summary only if its sequence number is above the last one stored.

pub mod codec;
mod error;
pub mod frame;
pub mod station;
pub mod store;
pub mod therapist;
pub mod tls;
mod transport;

pub use codec::{CodecError, FrameDecoder, decode, encode, encode_to_vec};
pub use error::NetlinkError;
pub use frame::{
    Ack, Bye, ErrorFrame, Frame, FrameKind, Hello, PROTOCOL_VERSION, Regimen, Summary,
};
pub use station::{Backoff, LinkStats, SendError, StationLink, StationLinkConfig, SummarySender};
pub use therapist::{TherapistConfig, TherapistEvent, TherapistServer};
pub use tls::{ClientTls, ServerTls};
