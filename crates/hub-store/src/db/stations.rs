//! Paired stations, identified by the SHA-256 fingerprint of their client certificate.

use serde::Serialize;
use sqlx::any::AnyRow;

use super::{Db, check_id, col};
use crate::error::HubError;

/// A station paired with a patient.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Station {
    /// The station's identifier (as in its certificate and `Hello`).
    pub station_id: String,
    /// The patient it is paired with.
    pub patient_id: String,
    /// Lowercase hex SHA-256 of the DER client certificate (64 digits).
    pub cert_fingerprint: String,
    /// Pairing time, ms since the Unix epoch.
    pub paired_at_ms: i64,
    /// Last contact, ms since the Unix epoch.
    pub last_seen_ms: Option<i64>,
    /// When the clinic revoked it, ms since the Unix epoch; a revoked station is refused.
    pub revoked_at_ms: Option<i64>,
}

impl Station {
    /// True if the clinic has revoked this station.
    pub fn is_revoked(&self) -> bool {
        self.revoked_at_ms.is_some()
    }

    fn from_row(row: &AnyRow) -> Result<Self, HubError> {
        Ok(Self {
            station_id: col(row, "station_id")?,
            patient_id: col(row, "patient_id")?,
            cert_fingerprint: col(row, "cert_fingerprint")?,
            paired_at_ms: col(row, "paired_at_ms")?,
            last_seen_ms: col(row, "last_seen_ms")?,
            revoked_at_ms: col(row, "revoked_at_ms")?,
        })
    }
}

pub(super) fn check_fingerprint(fingerprint: &str) -> Result<(), HubError> {
    if fingerprint.len() == 64
        && fingerprint
            .bytes()
            .all(|b| b.is_ascii_digit() || (b'a'..=b'f').contains(&b))
    {
        Ok(())
    } else {
        Err(HubError::invalid(
            "cert_fingerprint",
            "must be the SHA-256 of the DER certificate as 64 lowercase hex digits",
        ))
    }
}

const COLUMNS: &str =
    "station_id, patient_id, cert_fingerprint, paired_at_ms, last_seen_ms, revoked_at_ms";

impl Db {
    /// Records a newly paired station (the station id and fingerprint must be new).
    pub async fn add_station(
        &self,
        station_id: &str,
        patient_id: &str,
        cert_fingerprint: &str,
        now_ms: i64,
    ) -> Result<Station, HubError> {
        check_id("station_id", station_id)?;
        check_id("patient_id", patient_id)?;
        check_fingerprint(cert_fingerprint)?;
        if self.patient(patient_id).await?.is_none() {
            return Err(HubError::not_found("patient", patient_id));
        }
        sqlx::query(
            "INSERT INTO stations (station_id, patient_id, cert_fingerprint, paired_at_ms) \
             VALUES ($1, $2, $3, $4)",
        )
        .bind(station_id)
        .bind(patient_id)
        .bind(cert_fingerprint)
        .bind(now_ms)
        .execute(self.pool())
        .await
        .map_err(HubError::inserting(
            "station or certificate",
            station_id,
            "adding a station",
        ))?;
        Ok(Station {
            station_id: station_id.to_owned(),
            patient_id: patient_id.to_owned(),
            cert_fingerprint: cert_fingerprint.to_owned(),
            paired_at_ms: now_ms,
            last_seen_ms: None,
            revoked_at_ms: None,
        })
    }

    /// The station with this id, if any (revoked ones included: check
    /// [`Station::is_revoked`]).
    pub async fn station(&self, station_id: &str) -> Result<Option<Station>, HubError> {
        let sql = sqlx::AssertSqlSafe(format!(
            "SELECT {COLUMNS} FROM stations WHERE station_id = $1"
        ));
        let row = sqlx::query(sql)
            .bind(station_id)
            .fetch_optional(self.pool())
            .await
            .map_err(HubError::db("reading a station"))?;
        row.as_ref().map(Station::from_row).transpose()
    }

    /// The station whose client certificate has this fingerprint, if any.
    pub async fn station_by_fingerprint(
        &self,
        cert_fingerprint: &str,
    ) -> Result<Option<Station>, HubError> {
        let sql = sqlx::AssertSqlSafe(format!(
            "SELECT {COLUMNS} FROM stations WHERE cert_fingerprint = $1"
        ));
        let row = sqlx::query(sql)
            .bind(cert_fingerprint)
            .fetch_optional(self.pool())
            .await
            .map_err(HubError::db("reading a station"))?;
        row.as_ref().map(Station::from_row).transpose()
    }

    /// Stations paired with a patient, newest first.
    pub async fn stations_of(&self, patient_id: &str) -> Result<Vec<Station>, HubError> {
        let sql = sqlx::AssertSqlSafe(format!(
            "SELECT {COLUMNS} FROM stations WHERE patient_id = $1 ORDER BY paired_at_ms DESC"
        ));
        let rows = sqlx::query(sql)
            .bind(patient_id)
            .fetch_all(self.pool())
            .await
            .map_err(HubError::db("listing stations"))?;
        rows.iter().map(Station::from_row).collect()
    }

    /// Revokes a station from `now_ms` on (idempotent: the first revocation time stays).
    pub async fn revoke_station(&self, station_id: &str, now_ms: i64) -> Result<(), HubError> {
        let done = sqlx::query(
            "UPDATE stations SET revoked_at_ms = COALESCE(revoked_at_ms, $2) \
             WHERE station_id = $1",
        )
        .bind(station_id)
        .bind(now_ms)
        .execute(self.pool())
        .await
        .map_err(HubError::db("revoking a station"))?;
        if done.rows_affected() == 0 {
            return Err(HubError::not_found("station", station_id));
        }
        Ok(())
    }

    /// Records contact from a station at `now_ms`.
    pub async fn touch_station(&self, station_id: &str, now_ms: i64) -> Result<(), HubError> {
        let done = sqlx::query("UPDATE stations SET last_seen_ms = $2 WHERE station_id = $1")
            .bind(station_id)
            .bind(now_ms)
            .execute(self.pool())
            .await
            .map_err(HubError::db("recording station contact"))?;
        if done.rows_affected() == 0 {
            return Err(HubError::not_found("station", station_id));
        }
        Ok(())
    }
}
