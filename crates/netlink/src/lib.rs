//! The station–therapist link: a versioned, length-prefixed frame codec and its tokio
//! transport (TCP, optionally TLS) with store-and-forward of session summaries.
//!
//! - [`codec`] and [`frame`]: the wire format, pure (no I/O); normative text in `PROTOCOL.md`.
//! - [`station`]: [`StationLink`] — the station's non-blocking, store-and-forward sender.
//! - [`therapist`]: [`TherapistServer`] — the hub that stores and acknowledges summaries.
//! - [`store`]: the hub's on-disk layout, `DIR/<station_id>/<session_id>.jsonl`.
//! - [`tls`]: rustls configuration from PEM files.
//! - [`pairing`]: a one-time code becomes a station's credential (SPAKE2, both sides);
//!   [`pki`]: the clinic's own certificate authority; [`upload`]: the station's side of a
//!   recording upload.
//! - [`proxy_protocol`]: the client's address behind a load balancer (PROXY protocol headers
//!   read from trusted peers only), on the station port and the console's.
//! - Private: `transport` (the byte-stream plumbing both sides share) and `error`
//!   ([`NetlinkError`]).
//!
//! Safety invariant 4 of DESIGN.md ("a dropped network link resumes without losing or
//! duplicating a summary") rests on three rules: the station forgets a summary only when a
//! cumulative `Ack` covers it, it resends everything unacknowledged after a reconnect, and the
//! hub stores a summary only if its sequence number is above the last one stored.
//!
//! # Station side
//!
//! ```no_run
//! use std::time::Duration;
//! use netlink::{Hello, PROTOCOL_VERSION, StationLink, StationLinkConfig};
//!
//! # fn summary(seq: u64) -> netlink::Summary {
//! #     netlink::Summary {
//! #         session_id: "2026-11-21T09-30-00Z".into(), seq, t_s: seq as f64 * 0.1,
//! #         exercise: "sine-road".into(), speed_m_s: 12.0, lateral_m: 0.1,
//! #         rms_lateral_m: 0.2, max_lateral_m: 0.5, pct_in_lane: 99.0,
//! #         max_abs_torque_nm: 1.1, loop_p99_us: 40.0, ticks: seq * 100,
//! #         dropped_records: 0, extra: Default::default(),
//! #     }
//! # }
//! let runtime = tokio::runtime::Runtime::new()?;
//! let hello = Hello {
//!     protocol_version: PROTOCOL_VERSION,
//!     station_id: "station-01".into(),
//!     patient_id: "p-0042".into(),
//!     session_id: "2026-11-21T09-30-00Z".into(),
//!     exercise: "sine-road".into(),
//!     started_unix_ms: 1_795_253_400_000,
//!     software_version: "telerehab 0.1.0".into(),
//!     min_protocol_version: None,
//!     wheel: None,
//! };
//! let config = StationLinkConfig::new("localhost:7878", None, hello); // resolved on each attempt
//! let (sender, mut link) = StationLink::spawn(runtime.handle(), config)?;
//! for seq in 0..600 {
//!     // From the recorder thread, every 100 ms: never blocks.
//!     if let Err(e) = sender.send(summary(seq)) {
//!         eprintln!("summary {seq} not queued: {e}");
//!     }
//!     if let Some(regimen) = link.try_recv_regimen() {
//!         // Validate against the safety bounds before anything reaches the haptic thread.
//!     }
//! }
//! let stats = link.finish_blocking(runtime.handle(), Duration::from_secs(5));
//! println!("sent {} acknowledged {} NOT delivered {}", stats.sent, stats.acked, stats.pending);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # Therapist side
//!
//! ```no_run
//! use netlink::{TherapistConfig, TherapistServer};
//!
//! # async fn hub() -> Result<(), netlink::NetlinkError> {
//! let config = TherapistConfig::new("127.0.0.1:7878".parse().unwrap(), "store", None);
//! let (server, mut events) = TherapistServer::bind(config).await?;
//! while let Some(event) = events.recv().await {
//!     println!("{event}"); // one line per event
//! }
//! server.shutdown(std::time::Duration::from_secs(5)).await;
//! # Ok(())
//! # }
//! ```

pub mod address;
mod answer;
pub mod codec;
mod error;
pub mod frame;
pub mod ndjson;
pub mod pairing;
pub mod pki;
pub mod proxy_protocol;
pub mod server_stop;
pub mod station;
pub mod store;
pub mod therapist;
pub mod tls;
mod transport;
pub mod upload;

pub use codec::{CodecError, FrameDecoder, decode, encode, encode_to_vec};
pub use error::NetlinkError;
pub use frame::{
    Ack, AssessmentTag, Bye, CARE_VERSION, CHECK_NEWS_VERSION, Care, CheckIn, DifficultyChange,
    DifficultyWhy, ErrorFrame, ExerciseResult, Frame, FrameKind, Hello, MAX_MESSAGE_TEXT_CHARS,
    MESSAGES_VERSION, Message, MessageSeen, PROTOCOL_VERSION, Regimen, Summary, WheelInfo,
    check_message_text,
};
pub use station::{
    Backoff, HubAddress, LinkStats, SendError, StationLink, StationLinkConfig, SummarySender,
};
pub use therapist::{
    BoxFuture, CheckNews, FileStore, HubStore, Peer, Refusal, SessionStore, TherapistConfig,
    TherapistEvent, TherapistServer,
};
pub use tls::{ClientTls, Identity, ServerTls};
