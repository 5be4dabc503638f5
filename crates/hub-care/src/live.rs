//! What reaches the console's live views of a running session ([`LiveEvent`], broadcast by the
//! ingest in-process and carried between hubs by [`crate::fanout`]), and the wall-clock
//! milliseconds the hub stamps what it stores and sends with ([`unix_ms`], [`system_now_ms`]).
//! Below the console's API (`hub::web`, which streams the events and re-exports these), so the
//! ingest, the fan-out and the pain mail use them without depending on the web.

use netlink::Summary;
use serde::{Deserialize, Serialize};

/// One summary of a running session, as broadcast by the ingest to the console's live views.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LiveEvent {
    /// The patient exercising.
    pub patient_id: String,
    /// Their session.
    pub session_id: String,
    /// The summary just stored.
    pub summary: Summary,
}

/// The system clock, ms since the Unix epoch (the real [`clock::Clock`]).
pub fn system_now_ms() -> i64 {
    unix_ms(&clock::Clock::real())
}

/// `clock`'s wall-clock time, ms since the Unix epoch.
pub fn unix_ms(clock: &clock::Clock) -> i64 {
    i64::try_from(clock.unix_ns() / 1_000_000).unwrap_or(i64::MAX)
}
