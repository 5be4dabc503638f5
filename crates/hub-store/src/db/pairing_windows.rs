//! The pairing attempts each client address began in the last minute and failed in the last
//! hour, counted in the database (migration 0026) so that every hub behind a balancer sees
//! the same counts: an address spreading its attempts over several hubs gets no more than it
//! would from one.
//!
//! Each count is a fixed window that starts at its first event; an event after the window has
//! passed starts a new one. An event is counted by one conditional upsert that returns the
//! count after it, so parallel attempts on several hubs cannot all pass a check made before
//! the count moved.

use super::Db;
use crate::error::HubError;

/// What is counted per address, and over how long.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PairingEvent {
    /// A pairing attempt begun (counted over a minute).
    Begun,
    /// A pairing attempt that failed (counted over an hour).
    Failed,
}

impl PairingEvent {
    fn kind(self) -> &'static str {
        match self {
            Self::Begun => "begun",
            Self::Failed => "failed",
        }
    }

    /// The length of this event's window, ms.
    pub fn window_ms(self) -> i64 {
        match self {
            Self::Begun => 60_000,
            Self::Failed => 3_600_000,
        }
    }
}

impl Db {
    /// Counts one `event` from `address` (an address key: the IPv4 address, or the IPv6 /64) at
    /// `now_ms`; the count in its window after it.
    pub async fn count_pairing_event(
        &self,
        event: PairingEvent,
        address: &str,
        now_ms: i64,
    ) -> Result<u32, HubError> {
        // Both backends evaluate every SET expression over the row as it was before the
        // update, so the window test reads the old start in both columns.
        let events: i64 = sqlx::query_scalar(
            "INSERT INTO pairing_address_windows (kind, address, window_start_ms, events) \
             VALUES ($1, $2, $3, 1) \
             ON CONFLICT (kind, address) DO UPDATE SET \
             events = CASE WHEN pairing_address_windows.window_start_ms <= $4 THEN 1 \
                      ELSE pairing_address_windows.events + 1 END, \
             window_start_ms = CASE WHEN pairing_address_windows.window_start_ms <= $4 THEN $3 \
                      ELSE pairing_address_windows.window_start_ms END \
             RETURNING events",
        )
        .bind(event.kind())
        .bind(address)
        .bind(now_ms)
        .bind(now_ms.saturating_sub(event.window_ms()))
        .fetch_one(self.pool())
        .await
        .map_err(HubError::db("counting a pairing attempt of an address"))?;
        Ok(u32::try_from(events).unwrap_or(u32::MAX))
    }

    /// The `event`s from `address` in the window running at `now_ms` (0 if none).
    pub async fn pairing_events(
        &self,
        event: PairingEvent,
        address: &str,
        now_ms: i64,
    ) -> Result<u32, HubError> {
        let events: Option<i64> = sqlx::query_scalar(
            "SELECT events FROM pairing_address_windows \
             WHERE kind = $1 AND address = $2 AND window_start_ms > $3",
        )
        .bind(event.kind())
        .bind(address)
        .bind(now_ms.saturating_sub(event.window_ms()))
        .fetch_optional(self.pool())
        .await
        .map_err(HubError::db("reading the pairing attempts of an address"))?;
        Ok(events.map_or(0, |n| u32::try_from(n).unwrap_or(u32::MAX)))
    }

    /// Forgets the windows that have passed at `now_ms` (housekeeping: an attack from many
    /// addresses must not grow the table).
    pub async fn purge_pairing_windows(&self, now_ms: i64) -> Result<(), HubError> {
        sqlx::query("DELETE FROM pairing_address_windows WHERE window_start_ms <= $1")
            .bind(now_ms.saturating_sub(PairingEvent::Failed.window_ms()))
            .execute(self.pool())
            .await
            .map_err(HubError::db("purging pairing attempt counts"))?;
        Ok(())
    }
}
