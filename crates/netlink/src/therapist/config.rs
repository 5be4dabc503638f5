//! The hub's configuration: where it listens, where it stores, how many stations it takes.

use std::net::SocketAddr;
use std::path::PathBuf;

use serde::{Deserialize, Serialize};

use crate::error::NetlinkError;
use crate::proxy_protocol::TrustedProxies;
use crate::tls::ServerTls;

/// Configuration of a [`TherapistServer`](super::TherapistServer).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TherapistConfig {
    /// Address to listen on.
    pub listen: SocketAddr,
    /// Root of the store: `DIR/<station_id>/<session_id>.jsonl` and `.hello.json`.
    pub store_dir: PathBuf,
    /// TLS settings; `None` means plaintext, allowed only on a loopback address.
    #[serde(default)]
    pub tls: Option<ServerTls>,
    /// Most stations connected at once (their Hello admitted by the store), in
    /// [1, 100 000]. Default 2 048. A station over it is told so (`Error`) and retries later.
    #[serde(default = "default_max_connections")]
    pub max_connections: usize,
    /// Most simultaneous connections from one remote IP address that are not admitted yet
    /// (TLS handshake, waiting for the Hello, pairing), in [1, 10 000]. Default 16. Admitted
    /// stations do not count, so any number of stations may share one address (a NAT). A new
    /// connection over it replaces that address's oldest one still waiting for its first
    /// frame.
    #[serde(default = "default_max_connections_per_address")]
    pub max_connections_per_address: usize,
    /// Most simultaneous connections not admitted yet, from all addresses, in [1, 100 000].
    /// Default 1 024. A new connection over it replaces the oldest one still waiting for its
    /// first frame, so idle connections cannot lock stations out.
    #[serde(default = "default_max_unauthenticated")]
    pub max_unauthenticated: usize,
    /// Time allowed for the TLS handshake and the station's Hello, ms, in [100, 600 000].
    /// Default 10 000.
    #[serde(default = "default_hello_timeout_ms")]
    pub hello_timeout_ms: u64,
    /// A connection silent for this long is closed, ms, in [1 000, 3 600 000]. Default 60 000
    /// (stations send a summary every 100 ms).
    #[serde(default = "default_idle_timeout_ms")]
    pub idle_timeout_ms: u64,
    /// The load balancers whose connections start with a PROXY protocol header naming the
    /// station's address ([`crate::proxy_protocol`]); read within `hello_timeout_ms`. Default
    /// none: every connection's address is its peer's.
    #[serde(default)]
    pub proxy_protocol_from: TrustedProxies,
    /// Largest recording taken for one session, bytes, in [1 MiB, 16 GiB]. Default 2 GiB
    /// (an hour at 1 kHz with raw inputs is about 420 MB).
    #[serde(default = "default_max_upload_bytes_per_session")]
    pub max_upload_bytes_per_session: u64,
    /// Most recording bytes taken from one station in a UTC day, in [1 MiB, 1 TiB]. Default
    /// 4 GiB.
    #[serde(default = "default_max_upload_bytes_per_station_day")]
    pub max_upload_bytes_per_station_day: u64,
    /// Fastest one upload is taken, bytes/s, in [16 KiB, 1 GiB]. Default 4 MB/s (stations
    /// send at most 1 MB/s).
    #[serde(default = "default_max_upload_bytes_per_s")]
    pub max_upload_bytes_per_s: u64,
    /// Summaries taken from one station per second of the hub's clock, over all its
    /// connections, in [1, 10 000]. Default
    /// [`SUMMARY_PACE_PER_S`](super::station_limits::SUMMARY_PACE_PER_S) (200: the backlog of an
    /// hour offline drains in 3 minutes). Not read from a configuration file; tests lower it to
    /// show the pacing against a flood a debug build can send.
    #[serde(skip, default = "default_summary_pace_per_s")]
    pub summary_pace_per_s: u32,
    /// The oldest link protocol version this hub serves. Always
    /// [`crate::frame::MIN_PROTOCOL_VERSION`] in the product (not read from a configuration
    /// file); tests raise it to play a hub newer than the station under test.
    #[serde(skip, default = "default_min_protocol_version")]
    pub min_protocol_version: u16,
}

fn default_summary_pace_per_s() -> u32 {
    super::station_limits::SUMMARY_PACE_PER_S as u32
}

fn default_min_protocol_version() -> u16 {
    crate::frame::MIN_PROTOCOL_VERSION
}

fn default_max_upload_bytes_per_session() -> u64 {
    2 << 30
}
fn default_max_upload_bytes_per_station_day() -> u64 {
    4 << 30
}
fn default_max_upload_bytes_per_s() -> u64 {
    4_000_000
}

/// Default [`TherapistConfig::max_connections`] (also `telerehab hub serve`'s).
pub const DEFAULT_MAX_CONNECTIONS: usize = 2_048;
/// Default [`TherapistConfig::max_connections_per_address`].
pub const DEFAULT_MAX_CONNECTIONS_PER_ADDRESS: usize = 16;
/// Default [`TherapistConfig::max_unauthenticated`].
pub const DEFAULT_MAX_UNAUTHENTICATED: usize = 1_024;

fn default_max_connections() -> usize {
    DEFAULT_MAX_CONNECTIONS
}
fn default_max_connections_per_address() -> usize {
    DEFAULT_MAX_CONNECTIONS_PER_ADDRESS
}
fn default_max_unauthenticated() -> usize {
    DEFAULT_MAX_UNAUTHENTICATED
}
fn default_hello_timeout_ms() -> u64 {
    10_000
}
fn default_idle_timeout_ms() -> u64 {
    60_000
}

impl TherapistConfig {
    /// A configuration with the documented defaults.
    pub fn new(listen: SocketAddr, store_dir: impl Into<PathBuf>, tls: Option<ServerTls>) -> Self {
        Self {
            listen,
            store_dir: store_dir.into(),
            tls,
            max_connections: default_max_connections(),
            max_connections_per_address: default_max_connections_per_address(),
            max_unauthenticated: default_max_unauthenticated(),
            hello_timeout_ms: default_hello_timeout_ms(),
            idle_timeout_ms: default_idle_timeout_ms(),
            proxy_protocol_from: TrustedProxies::default(),
            max_upload_bytes_per_session: default_max_upload_bytes_per_session(),
            max_upload_bytes_per_station_day: default_max_upload_bytes_per_station_day(),
            max_upload_bytes_per_s: default_max_upload_bytes_per_s(),
            summary_pace_per_s: default_summary_pace_per_s(),
            min_protocol_version: default_min_protocol_version(),
        }
    }

    /// Checks every field; the error names the field and its allowed range.
    ///
    /// Plaintext (no `tls`) is refused unless `listen` is a loopback address.
    pub fn validate(&self) -> Result<(), NetlinkError> {
        let err = |m: String| Err(NetlinkError::Config(m));
        if self.tls.is_none() && !self.listen.ip().is_loopback() {
            return err(format!(
                "listen {} is not loopback and no tls is configured; plaintext is allowed only on \
                 127.0.0.1/::1",
                self.listen
            ));
        }
        if !(1..=100_000).contains(&self.max_connections) {
            return err(format!(
                "max_connections is {}, allowed [1, 100000]",
                self.max_connections
            ));
        }
        if !(1..=100_000).contains(&self.max_unauthenticated) {
            return err(format!(
                "max_unauthenticated is {}, allowed [1, 100000]",
                self.max_unauthenticated
            ));
        }
        if !(1..=10_000).contains(&self.max_connections_per_address) {
            return err(format!(
                "max_connections_per_address is {}, allowed [1, 10000]",
                self.max_connections_per_address
            ));
        }
        if !(1..=10_000).contains(&self.summary_pace_per_s) {
            return err(format!(
                "summary_pace_per_s is {}, allowed [1, 10000]",
                self.summary_pace_per_s
            ));
        }
        if !(100..=600_000).contains(&self.hello_timeout_ms) {
            return err(format!(
                "hello_timeout_ms is {}, allowed [100, 600000]",
                self.hello_timeout_ms
            ));
        }
        if !(1_000..=3_600_000).contains(&self.idle_timeout_ms) {
            return err(format!(
                "idle_timeout_ms is {}, allowed [1000, 3600000]",
                self.idle_timeout_ms
            ));
        }
        let uploads = [
            (
                "max_upload_bytes_per_session",
                self.max_upload_bytes_per_session,
                1 << 20,
                crate::frame::MAX_RECORDING_BYTES,
            ),
            (
                "max_upload_bytes_per_station_day",
                self.max_upload_bytes_per_station_day,
                1 << 20,
                1 << 40,
            ),
            (
                "max_upload_bytes_per_s",
                self.max_upload_bytes_per_s,
                16 << 10,
                1 << 30,
            ),
        ];
        for (name, value, min, max) in uploads {
            if !(min..=max).contains(&value) {
                return err(format!("{name} is {value}, allowed [{min}, {max}]"));
            }
        }
        if self.store_dir.as_os_str().is_empty() {
            return err("store_dir is empty".into());
        }
        Ok(())
    }
}
