//! What happens at the hub, reported to the CLI.

use std::fmt;
use std::net::SocketAddr;

use crate::frame::{Hello, MessageSeen, Summary};

/// Something that happened at the hub, for the CLI to print.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum TherapistEvent {
    /// A station connected and said Hello.
    Connected {
        /// Its address.
        peer: SocketAddr,
        /// Its Hello.
        hello: Hello,
    },
    /// A new (not duplicate) summary was stored.
    Summary {
        /// The station it came from.
        station_id: String,
        /// The patient the station speaks for.
        patient_id: String,
        /// The summary.
        summary: Summary,
    },
    /// A station's connection ended.
    Disconnected {
        /// The station.
        station_id: String,
        /// Its session.
        session_id: String,
        /// Why, for humans (`bye: …` for an orderly end).
        reason: String,
    },
    /// A station asked to be paired; how it ended.
    Pairing {
        /// Its address.
        peer: SocketAddr,
        /// `paired station … for patient …`, or why it was refused.
        outcome: String,
    },
    /// A peer broke the protocol (or the TLS handshake); its connection was closed.
    ProtocolError {
        /// Its address.
        peer: SocketAddr,
        /// What was wrong.
        error: String,
    },
    /// Connections refused or dropped before admission that were not reported one by one
    /// (over a connection cap, or past the per-interval budget of [`Self::ProtocolError`]
    /// lines): one summary per interval at most, however many there were.
    Refused {
        /// How many.
        count: u64,
        /// Over how long, s.
        interval_s: u64,
        /// How many for each reason.
        reasons: String,
    },
    /// A station showed a therapist's message to its patient (and the store recorded it).
    MessageSeen {
        /// The station.
        station_id: String,
        /// The patient the station speaks for.
        patient_id: String,
        /// Which message, and when it was shown (station clock).
        seen: MessageSeen,
    },
}

impl fmt::Display for TherapistEvent {
    /// One line per event, for a live console.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Connected { peer, hello } => write!(
                f,
                "[{}] connected from {peer}: patient {} session {} exercise {} ({})",
                hello.station_id,
                hello.patient_id,
                hello.session_id,
                hello.exercise,
                hello.software_version
            ),
            Self::Summary {
                station_id,
                summary: s,
                ..
            } => write!(
                f,
                "[{station_id}] t={:7.1} s seq={:<6} speed={:5.2} m/s lateral={:+.3} m \
                 rms={:.3} m max={:.3} m in-lane={:5.1} % |torque|max={:.2} N·m p99={:.0} µs",
                s.t_s,
                s.seq,
                s.speed_m_s,
                s.lateral_m,
                s.rms_lateral_m,
                s.max_lateral_m,
                s.pct_in_lane,
                s.max_abs_torque_nm,
                s.loop_p99_us
            ),
            Self::Disconnected {
                station_id,
                session_id,
                reason,
            } => write!(
                f,
                "[{station_id}] session {session_id} disconnected: {reason}"
            ),
            Self::Pairing { peer, outcome } => write!(f, "[{peer}] pairing: {outcome}"),
            Self::ProtocolError { peer, error } => write!(f, "[{peer}] protocol error: {error}"),
            Self::Refused {
                count,
                interval_s,
                reasons,
            } => write!(
                f,
                "refused {count} connections in the last {interval_s} s ({reasons})"
            ),
            Self::MessageSeen {
                station_id,
                patient_id,
                seen,
            } => write!(
                f,
                "[{station_id}] patient {patient_id} was shown message {} at {} ms",
                seen.id, seen.seen_unix_ms
            ),
        }
    }
}
