//! Sessions, their summaries (stored exactly once), movement metrics and MCAP recordings.

use std::collections::BTreeMap;

use netlink::{Bye, Hello};
use serde::Serialize;
use sqlx::any::AnyRow;

use super::{Db, check_id, col, to_i64};
use crate::error::HubError;

/// A session as the hub records it.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct SessionRow {
    /// Identifier (from the station's `Hello`).
    pub session_id: String,
    /// The station that runs it.
    pub station_id: String,
    /// The patient exercising.
    pub patient_id: String,
    /// Exercise name, e.g. `sine-road`.
    pub exercise: String,
    /// Session start (station clock), ms since the Unix epoch.
    pub started_unix_ms: i64,
    /// Station software version.
    pub software_version: String,
    /// When the hub first heard of it, ms since the Unix epoch.
    pub opened_at_ms: i64,
    /// When the station said `Bye`, ms since the Unix epoch.
    pub closed_at_ms: Option<i64>,
    /// The station's reason for ending.
    pub end_reason: Option<String>,
    /// Last sequence number the station produced (from its `Bye`).
    pub final_seq: Option<i64>,
    /// Highest sequence number stored.
    pub last_seq: Option<i64>,
}

impl SessionRow {
    fn from_row(row: &AnyRow) -> Result<Self, HubError> {
        Ok(Self {
            session_id: col(row, "session_id")?,
            station_id: col(row, "station_id")?,
            patient_id: col(row, "patient_id")?,
            exercise: col(row, "exercise")?,
            started_unix_ms: col(row, "started_unix_ms")?,
            software_version: col(row, "software_version")?,
            opened_at_ms: col(row, "opened_at_ms")?,
            closed_at_ms: col(row, "closed_at_ms")?,
            end_reason: col(row, "end_reason")?,
            final_seq: col(row, "final_seq")?,
            last_seq: col(row, "last_seq")?,
        })
    }
}

/// Upload state of a session's MCAP recording.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Recording {
    /// The session recorded.
    pub session_id: String,
    /// Expected lowercase hex SHA-256 of the whole file.
    pub sha256: String,
    /// Expected size, bytes.
    pub size_bytes: i64,
    /// Bytes received so far.
    pub received_bytes: i64,
    /// Where the hub stores the file.
    pub path: String,
    /// True once every byte arrived and the hash matched.
    pub complete: bool,
    /// While not complete: when the hub last noted a part of it arriving, ms since the Unix
    /// epoch ([`Db::note_recording_progress`]); `None` when never noted.
    pub last_part_ms: Option<i64>,
}

const SESSION_COLUMNS: &str = "session_id, station_id, patient_id, exercise, started_unix_ms, \
    software_version, opened_at_ms, closed_at_ms, end_reason, final_seq, last_seq";

fn last_seq_u64(last: Option<i64>) -> Result<Option<u64>, HubError> {
    last.map(|l| u64::try_from(l).map_err(|_| HubError::Corrupt(format!("last_seq {l} < 0"))))
        .transpose()
}

impl Db {
    /// Records the session a station announces (once; a reconnect finds it) and returns the
    /// highest sequence number already stored, to resume from. Refused: an invalid `Hello`, an
    /// unknown or revoked station, a patient other than the station's, and a session id that
    /// belongs to another station.
    pub async fn open_session(&self, hello: &Hello, now_ms: i64) -> Result<Option<u64>, HubError> {
        hello
            .validate()
            .map_err(|reason| HubError::invalid("hello", reason))?;
        let station = self
            .station(&hello.station_id)
            .await?
            .ok_or_else(|| HubError::not_found("station", &hello.station_id))?;
        if station.is_revoked() {
            return Err(HubError::StationRevoked(station.station_id));
        }
        if station.patient_id != hello.patient_id {
            return Err(HubError::Conflict(format!(
                "station {:?} is paired with patient {:?}, not {:?}",
                station.station_id, station.patient_id, hello.patient_id
            )));
        }
        sqlx::query(
            "INSERT INTO sessions (session_id, station_id, patient_id, exercise, \
             started_unix_ms, software_version, opened_at_ms) \
             VALUES ($1, $2, $3, $4, $5, $6, $7) ON CONFLICT (session_id) DO NOTHING",
        )
        .bind(&hello.session_id)
        .bind(&hello.station_id)
        .bind(&hello.patient_id)
        .bind(&hello.exercise)
        .bind(to_i64("started_unix_ms", hello.started_unix_ms)?)
        .bind(&hello.software_version)
        .bind(now_ms)
        .execute(self.pool())
        .await
        .map_err(HubError::db("opening a session"))?;
        let session = self
            .session(&hello.session_id)
            .await?
            .ok_or_else(|| HubError::not_found("session", &hello.session_id))?;
        if session.station_id != hello.station_id || session.patient_id != hello.patient_id {
            return Err(HubError::Conflict(format!(
                "session {:?} belongs to another station",
                hello.session_id
            )));
        }
        last_seq_u64(session.last_seq)
    }

    /// Records the end of a session from the station's `Bye`, with the movement measures it
    /// carries ([`Self::put_metrics`]); returns the highest sequence number stored (for the
    /// hub's `Bye` reply). A repeated `Bye` (a station that did not hear the reply) records
    /// the same again.
    pub async fn close_session(&self, bye: &Bye, now_ms: i64) -> Result<Option<u64>, HubError> {
        check_id("session_id", &bye.session_id)?;
        let final_seq = bye.final_seq.map(|s| to_i64("final_seq", s)).transpose()?;
        let reason: String = bye.reason.chars().take(256).collect();
        let done = sqlx::query(
            "UPDATE sessions SET closed_at_ms = $2, end_reason = $3, final_seq = $4 \
             WHERE session_id = $1",
        )
        .bind(&bye.session_id)
        .bind(now_ms)
        .bind(reason)
        .bind(final_seq)
        .execute(self.pool())
        .await
        .map_err(HubError::db("closing a session"))?;
        if done.rows_affected() == 0 {
            return Err(HubError::not_found("session", &bye.session_id));
        }
        if !bye.measures.is_empty() {
            self.put_metrics(&bye.session_id, &bye.measures).await?;
        }
        if let Some(checkin) = &bye.checkin {
            self.put_checkin(&bye.session_id, checkin, now_ms).await?;
        }
        if let Some(d) = &bye.difficulty {
            self.put_difficulty(&bye.session_id, d, now_ms).await?;
        }
        if !bye.exercises.is_empty() {
            self.put_exercises(&bye.session_id, &bye.exercises).await?;
        }
        let session = self
            .session(&bye.session_id)
            .await?
            .ok_or_else(|| HubError::not_found("session", &bye.session_id))?;
        last_seq_u64(session.last_seq)
    }

    /// The session with this id, if any.
    pub async fn session(&self, session_id: &str) -> Result<Option<SessionRow>, HubError> {
        let sql = sqlx::AssertSqlSafe(format!(
            "SELECT {SESSION_COLUMNS} FROM sessions WHERE session_id = $1"
        ));
        let row = sqlx::query(sql)
            .bind(session_id)
            .fetch_optional(self.pool())
            .await
            .map_err(HubError::db("reading a session"))?;
        row.as_ref().map(SessionRow::from_row).transpose()
    }

    /// A patient's sessions, newest first.
    pub async fn sessions_of(&self, patient_id: &str) -> Result<Vec<SessionRow>, HubError> {
        self.sessions_of_where(patient_id, "TRUE").await
    }

    /// A patient's sessions that count as training (a summary stored or measures reported;
    /// see [`super::TRAINING_SESSION_SQL`]), newest first: what the console lists.
    pub async fn training_sessions_of(
        &self,
        patient_id: &str,
    ) -> Result<Vec<SessionRow>, HubError> {
        self.sessions_of_where(patient_id, super::TRAINING_SESSION_SQL)
            .await
    }

    /// A patient's sessions (the row named `s`) meeting the SQL condition `condition`, newest
    /// first.
    async fn sessions_of_where(
        &self,
        patient_id: &str,
        condition: &str,
    ) -> Result<Vec<SessionRow>, HubError> {
        let sql = sqlx::AssertSqlSafe(format!(
            "SELECT {SESSION_COLUMNS} FROM sessions s WHERE s.patient_id = $1 AND {condition} \
             ORDER BY s.started_unix_ms DESC, s.session_id"
        ));
        let rows = sqlx::query(sql)
            .bind(patient_id)
            .fetch_all(self.pool())
            .await
            .map_err(HubError::db("listing sessions"))?;
        rows.iter().map(SessionRow::from_row).collect()
    }

    /// Sets movement metrics of a session (name → value; replaces values of the same name).
    pub async fn put_metrics(
        &self,
        session_id: &str,
        metrics: &BTreeMap<String, f64>,
    ) -> Result<(), HubError> {
        for (name, value) in metrics {
            if name.is_empty() || name.len() > 64 || name.chars().any(char::is_control) {
                return Err(HubError::invalid(
                    "metric name",
                    format!("{name:?} must have 1 to 64 bytes and no control characters"),
                ));
            }
            if !value.is_finite() {
                return Err(HubError::invalid(
                    "metric value",
                    format!("{name} is {value}, must be finite"),
                ));
            }
        }
        let mut tx = self
            .pool()
            .begin()
            .await
            .map_err(HubError::db("starting a transaction"))?;
        for (name, value) in metrics {
            sqlx::query(
                "INSERT INTO session_metrics (session_id, name, value) VALUES ($1, $2, $3) \
                 ON CONFLICT (session_id, name) DO UPDATE SET value = excluded.value",
            )
            .bind(session_id)
            .bind(name)
            .bind(*value)
            .execute(&mut *tx)
            .await
            .map_err(HubError::db("storing metrics"))?;
        }
        tx.commit()
            .await
            .map_err(HubError::db("committing metrics"))
    }

    /// A session's movement metrics, name → value.
    pub async fn metrics_of(&self, session_id: &str) -> Result<BTreeMap<String, f64>, HubError> {
        let rows = sqlx::query("SELECT name, value FROM session_metrics WHERE session_id = $1")
            .bind(session_id)
            .fetch_all(self.pool())
            .await
            .map_err(HubError::db("reading metrics"))?;
        rows.iter()
            .map(|row| Ok((col(row, "name")?, col(row, "value")?)))
            .collect()
    }

    /// Creates or updates the upload state of a session's recording.
    pub async fn put_recording(&self, recording: &Recording) -> Result<(), HubError> {
        sqlx::query(
            "INSERT INTO recordings (session_id, sha256, size_bytes, received_bytes, path, \
             complete) VALUES ($1, $2, $3, $4, $5, $6) ON CONFLICT (session_id) DO UPDATE SET \
             sha256 = excluded.sha256, size_bytes = excluded.size_bytes, \
             received_bytes = excluded.received_bytes, path = excluded.path, \
             complete = excluded.complete",
        )
        .bind(&recording.session_id)
        .bind(&recording.sha256)
        .bind(recording.size_bytes)
        .bind(recording.received_bytes)
        .bind(&recording.path)
        .bind(i64::from(recording.complete))
        .execute(self.pool())
        .await
        .map_err(HubError::db("storing a recording's state"))?;
        Ok(())
    }

    /// Notes how much of a session's recording an upload holds (`recording.complete` false):
    /// a row for a recording on its way. A recording already stored whole is left as it is
    /// (a late note from a slower hub never makes it partial again). `recording.last_part_ms`
    /// says when (the console says a recording noted longer than
    /// [`RECORDING_STALLED_AFTER_MS`] ago stopped arriving).
    ///
    /// [`RECORDING_STALLED_AFTER_MS`]: crate::db::RECORDING_STALLED_AFTER_MS
    pub async fn note_recording_progress(&self, recording: &Recording) -> Result<(), HubError> {
        sqlx::query(
            "INSERT INTO recordings (session_id, sha256, size_bytes, received_bytes, path, \
             complete, last_part_ms) VALUES ($1, $2, $3, $4, $5, 0, $6) \
             ON CONFLICT (session_id) DO UPDATE SET \
             sha256 = excluded.sha256, size_bytes = excluded.size_bytes, \
             received_bytes = excluded.received_bytes, path = excluded.path, \
             last_part_ms = excluded.last_part_ms WHERE recordings.complete = 0",
        )
        .bind(&recording.session_id)
        .bind(&recording.sha256)
        .bind(recording.size_bytes)
        .bind(recording.received_bytes)
        .bind(&recording.path)
        .bind(recording.last_part_ms)
        .execute(self.pool())
        .await
        .map_err(HubError::db("noting an upload's progress"))?;
        Ok(())
    }

    /// The upload state of a session's recording, if any.
    pub async fn recording(&self, session_id: &str) -> Result<Option<Recording>, HubError> {
        let row = sqlx::query(
            "SELECT session_id, sha256, size_bytes, received_bytes, path, complete, \
             last_part_ms FROM recordings WHERE session_id = $1",
        )
        .bind(session_id)
        .fetch_optional(self.pool())
        .await
        .map_err(HubError::db("reading a recording's state"))?;
        row.map(|row| {
            Ok(Recording {
                session_id: col(&row, "session_id")?,
                sha256: col(&row, "sha256")?,
                size_bytes: col(&row, "size_bytes")?,
                received_bytes: col(&row, "received_bytes")?,
                path: col(&row, "path")?,
                complete: col::<i64>(&row, "complete")? != 0,
                last_part_ms: col(&row, "last_part_ms")?,
            })
        })
        .transpose()
    }
}
