//! Frames queued for a station: encoded once, an error frame kept printable and short, a
//! frame the station does not read dropped and counted (the outbox's). Used by the frame loop
//! ([`super::connection`]) and by pairing ([`super::pairing`]).

use crate::codec::encode_to_vec;
use crate::frame::{ErrorFrame, Frame, MAX_MESSAGE_LEN, printable};
use crate::transport::{Outbox, Outgoing};

/// `message` as an `Error` frame without a code.
pub(super) fn error_outgoing(message: &str) -> Option<Outgoing> {
    coded_error_outgoing(message, None)
}

/// `message` as an `Error` frame with `code` (a machine-readable one, e.g. an update required).
pub(super) fn coded_error_outgoing(message: &str, code: Option<&str>) -> Option<Outgoing> {
    let message = printable(message, MAX_MESSAGE_LEN);
    encode_to_vec(&Frame::Error(ErrorFrame {
        message,
        code: code.map(str::to_owned),
    }))
    .ok()
    .map(|b| Outgoing::new(b.into()))
}

/// `frame` encoded for the outbox; one that cannot be encoded is logged, not sent.
pub(super) fn frame_outgoing(frame: &Frame) -> Option<Outgoing> {
    match encode_to_vec(frame) {
        Ok(b) => Some(Outgoing::new(b.into())),
        Err(e) => {
            tracing::error!(error = %e, "therapist hub: cannot encode {}", frame.kind());
            None
        }
    }
}

/// Queues `frame` for the station; a closed writer is noticed by the frame loop, a full outbox
/// (a station that does not read) drops the frame, counted in the hub's outbox stats.
pub(super) fn send(out: &Outbox, frame: Option<Outgoing>) {
    if let Some(o) = frame {
        out.send(o);
    }
}
