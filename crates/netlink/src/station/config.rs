//! The link's configuration: where the hub is, how to reconnect, how much to queue.

use std::net::SocketAddr;

use serde::{Deserialize, Serialize};

use crate::error::NetlinkError;
use crate::frame::Hello;
use crate::tls::ClientTls;

/// Reconnection backoff: the delay starts at `initial_ms` and doubles after each failed
/// attempt up to `max_ms`; it resets once a connection gets an acknowledgement.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Backoff {
    /// First delay, ms, in [1, 60 000].
    pub initial_ms: u64,
    /// Largest delay, ms, in [`initial_ms`, 600 000].
    pub max_ms: u64,
}

impl Default for Backoff {
    fn default() -> Self {
        Self {
            initial_ms: 200,
            max_ms: 5_000,
        }
    }
}

/// Where the therapist hub is: a socket address, or a `host:port` name resolved afresh on
/// every connection attempt (a name that does not resolve — home internet down — is just a
/// failed attempt, retried with backoff; it never blocks the station).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum HubAddress {
    /// An address used as is.
    Socket(SocketAddr),
    /// `host:port` (IPv6 literals in brackets), resolved on each connection attempt.
    Name(String),
}

impl HubAddress {
    /// The host part of a name (brackets removed), `None` for a socket address.
    pub fn host(&self) -> Option<&str> {
        match self {
            Self::Socket(_) => None,
            Self::Name(n) => Some(
                n.rsplit_once(':')
                    .map_or(n.as_str(), |(h, _)| h)
                    .trim_matches(['[', ']']),
            ),
        }
    }

    /// True if every address this can stand for is loopback (`localhost` counts).
    pub fn is_loopback(&self) -> bool {
        match self {
            Self::Socket(a) => a.ip().is_loopback(),
            Self::Name(_) => self
                .host()
                .is_some_and(|h| h.eq_ignore_ascii_case("localhost")),
        }
    }
}

impl From<SocketAddr> for HubAddress {
    fn from(addr: SocketAddr) -> Self {
        Self::Socket(addr)
    }
}

impl From<&str> for HubAddress {
    /// A socket address if `text` parses as one, otherwise a name.
    fn from(text: &str) -> Self {
        text.parse()
            .map_or_else(|_| Self::Name(text.to_owned()), Self::Socket)
    }
}

impl From<String> for HubAddress {
    fn from(text: String) -> Self {
        Self::from(text.as_str())
    }
}

impl std::fmt::Display for HubAddress {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Socket(a) => write!(f, "{a}"),
            Self::Name(n) => f.write_str(n),
        }
    }
}

/// Configuration of a [`StationLink`](super::StationLink).
#[derive(Debug, Clone, PartialEq)]
pub struct StationLinkConfig {
    /// The therapist hub's address; a name is resolved on every connection attempt.
    pub addr: HubAddress,
    /// TLS settings; `None` means plaintext, allowed only to a loopback address.
    pub tls: Option<ClientTls>,
    /// Sent first on every connection; its `session_id` is the session of every summary.
    pub hello: Hello,
    /// Most unacknowledged summaries kept, in [1, 10 000 000]; beyond it new ones are dropped
    /// and counted. Default 100 000 (2.8 h at 10 Hz, about 40 MB).
    pub max_pending: usize,
    /// Capacity of the channel from [`SummarySender`](super::SummarySender) to the link task, in [1, 1 000 000].
    /// Default 4 096 (almost 7 minutes at 10 Hz, should the task ever be starved).
    pub channel_capacity: usize,
    /// Reconnection backoff.
    pub reconnect: Backoff,
    /// Limit on a TCP connect plus TLS handshake, ms, in [100, 60 000]. Default 5 000.
    pub connect_timeout_ms: u64,
    /// A connection with unacknowledged summaries and nothing heard from the hub for this
    /// long is considered dead and re-established, ms, in [1 000, 600 000]. Default 15 000.
    pub ack_timeout_ms: u64,
    /// The last `seq` of the summaries this link will be given, when it is known before they
    /// are handed over: a queued session being resent (`telerehab sync`, a later run's
    /// delivery). The hub may already hold part of such a session and acknowledge it as soon
    /// as the Hello arrives, before the replay has produced that far; an Ack up to this `seq`
    /// is then legitimate (it drops the summaries it covers, even those handed over later,
    /// so they are never sent), and only one above it is impossible. `None` (default, a live
    /// session): only an Ack up to the last summary handed over is possible.
    pub replay_last_seq: Option<u64>,
}

impl StationLinkConfig {
    /// A configuration with the documented defaults. `addr` is a [`SocketAddr`] or a
    /// `host:port` string (never resolved here: see [`HubAddress`]).
    pub fn new(addr: impl Into<HubAddress>, tls: Option<ClientTls>, hello: Hello) -> Self {
        Self {
            addr: addr.into(),
            tls,
            hello,
            max_pending: 100_000,
            channel_capacity: 4_096,
            reconnect: Backoff::default(),
            connect_timeout_ms: 5_000,
            ack_timeout_ms: 15_000,
            replay_last_seq: None,
        }
    }

    /// Checks every field; the error names the field and its allowed range.
    ///
    /// Plaintext (no `tls`) is refused unless `addr` is a loopback address: summaries are
    /// health data and must be encrypted in transit.
    pub fn validate(&self) -> Result<(), NetlinkError> {
        let err = |m: String| Err(NetlinkError::Config(m));
        self.hello
            .validate()
            .map_err(|m| NetlinkError::Config(format!("hello: {m}")))?;
        self.hello
            .negotiate()
            .map_err(|m| NetlinkError::Config(format!("hello: {m}")))?;
        if let HubAddress::Name(name) = &self.addr {
            let port_ok = name
                .rsplit_once(':')
                .is_some_and(|(h, p)| !h.is_empty() && p.parse::<u16>().is_ok());
            if !port_ok {
                return err(format!(
                    "addr {name:?} is not host:port (e.g. hub.clinic.example:7878)"
                ));
            }
        }
        if self.tls.is_none() && !self.addr.is_loopback() {
            return err(format!(
                "addr {} is not loopback and no tls is configured; plaintext is allowed only to \
                 127.0.0.1/::1/localhost",
                self.addr
            ));
        }
        if !(1..=10_000_000).contains(&self.max_pending) {
            return err(format!(
                "max_pending is {}, allowed [1, 10000000]",
                self.max_pending
            ));
        }
        if !(1..=1_000_000).contains(&self.channel_capacity) {
            return err(format!(
                "channel_capacity is {}, allowed [1, 1000000]",
                self.channel_capacity
            ));
        }
        let b = self.reconnect;
        if !(1..=60_000).contains(&b.initial_ms) {
            return err(format!(
                "reconnect.initial_ms is {}, allowed [1, 60000]",
                b.initial_ms
            ));
        }
        if !(b.initial_ms..=600_000).contains(&b.max_ms) {
            return err(format!(
                "reconnect.max_ms is {}, allowed [reconnect.initial_ms = {}, 600000]",
                b.max_ms, b.initial_ms
            ));
        }
        if !(100..=60_000).contains(&self.connect_timeout_ms) {
            return err(format!(
                "connect_timeout_ms is {}, allowed [100, 60000]",
                self.connect_timeout_ms
            ));
        }
        if !(1_000..=600_000).contains(&self.ack_timeout_ms) {
            return err(format!(
                "ack_timeout_ms is {}, allowed [1000, 600000]",
                self.ack_timeout_ms
            ));
        }
        Ok(())
    }
}
