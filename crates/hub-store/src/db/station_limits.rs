//! What the hub counts to hold a paired station to its prescription: the sessions it starts a
//! day, the recording bytes it uploads a day (kept across restarts), the time of a session's
//! last summary, and which sessions count as training.

use super::{DAY_MS, Db, to_i64};
use crate::error::HubError;

/// Sessions one station may start on one UTC day (by the session's start): three times what
/// the densest regimen prescribes, `regimen::MAX_SESSIONS_PER_WEEK` (28) a week, i.e. 4 a day;
/// the rest is room for sessions stopped and started again. Beyond it a station's `Hello` for
/// a new session is refused (the station keeps it and tries again later).
pub const MAX_SESSIONS_PER_STATION_DAY: i64 = 12;

/// The SQL condition (on a `sessions` row named `s`) of a session that counts as training: at
/// least one summary stored, or movement measures reported at its end (its `Bye`). A `Hello`
/// alone opens a session row, kept for the record, but is no training: the caseload's counts
/// and the session lists leave it out.
pub const TRAINING_SESSION_SQL: &str = "(s.last_seq IS NOT NULL OR EXISTS (SELECT 1 FROM \
    session_metrics tm WHERE tm.session_id = s.session_id))";

impl Db {
    /// Sessions of `station_id` whose start falls on the UTC day of `started_unix_ms`.
    pub async fn sessions_started_on_day(
        &self,
        station_id: &str,
        started_unix_ms: i64,
    ) -> Result<i64, HubError> {
        let day_start = started_unix_ms.div_euclid(DAY_MS) * DAY_MS;
        sqlx::query_scalar(
            "SELECT COUNT(*) FROM sessions WHERE station_id = $1 AND started_unix_ms >= $2 \
             AND started_unix_ms < $3",
        )
        .bind(station_id)
        .bind(day_start)
        .bind(day_start.saturating_add(DAY_MS))
        .fetch_one(self.pool())
        .await
        .map_err(HubError::db("counting a station's sessions of the day"))
    }

    /// The time (`t_s`, s) of the last summary stored in `session_id`, if any.
    pub async fn last_t_s(&self, session_id: &str) -> Result<Option<f64>, HubError> {
        sqlx::query_scalar(
            "SELECT m.t_s FROM summaries m JOIN sessions s ON s.session_id = m.session_id \
             AND m.seq = s.last_seq WHERE s.session_id = $1",
        )
        .bind(session_id)
        .fetch_optional(self.pool())
        .await
        .map_err(HubError::db("reading a session's last summary time"))
    }

    /// Recording bytes taken from `station_id` on UTC day `day` (days since the Unix epoch).
    pub async fn upload_bytes_on(&self, station_id: &str, day: u64) -> Result<u64, HubError> {
        let bytes: Option<i64> = sqlx::query_scalar(
            "SELECT bytes FROM station_upload_days WHERE station_id = $1 AND day = $2",
        )
        .bind(station_id)
        .bind(to_i64("day", day)?)
        .fetch_optional(self.pool())
        .await
        .map_err(HubError::db("reading a station's upload bytes of the day"))?;
        Ok(bytes.map_or(0, |b| u64::try_from(b).unwrap_or(0)))
    }

    /// Adds `bytes` taken from `station_id` on UTC day `day` to the day's count, in one
    /// statement (hubs adding at once on one database both count), and answers the count after.
    pub async fn add_upload_bytes(
        &self,
        station_id: &str,
        day: u64,
        bytes: u64,
    ) -> Result<u64, HubError> {
        let total: i64 = sqlx::query_scalar(
            "INSERT INTO station_upload_days (station_id, day, bytes) VALUES ($1, $2, $3) \
             ON CONFLICT (station_id, day) DO UPDATE SET \
             bytes = station_upload_days.bytes + excluded.bytes RETURNING bytes",
        )
        .bind(station_id)
        .bind(to_i64("day", day)?)
        .bind(to_i64("bytes", bytes)?)
        .fetch_one(self.pool())
        .await
        .map_err(HubError::db(
            "adding to a station's upload bytes of the day",
        ))?;
        Ok(u64::try_from(total).unwrap_or(0))
    }
}
