//! The patient's wheel, as their stations tell it in each `Hello` (migration 0011): what the
//! prescribe form and the regimen check bound every torque by.

use serde::Serialize;

use super::{Db, col};
use crate::error::HubError;

/// The wheel a station of the patient last told the hub of.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PatientWheel {
    /// The station that told it.
    pub station_id: String,
    /// The wheel's model in words (`unknown wheel (…)` for a model the station has no
    /// profile for).
    pub model: String,
    /// The motor's rated torque, N·m.
    pub rated_torque_nm: f64,
    /// The most torque the station's safety chain lets this wheel give, N·m: the patient's
    /// own bound for every torque of a prescription.
    pub ceiling_nm: f64,
    /// The model is unknown to the station (rating assumed, conservative ceiling).
    pub unknown: bool,
    /// When the station last told it, ms since the Unix epoch.
    pub seen_at_ms: i64,
}

impl Db {
    /// Keeps `wheel` as the wheel station `station_id` told at `now_ms` (checked with
    /// [`netlink::WheelInfo::validate`]: an invalid one is [`HubError::Invalid`]).
    pub async fn note_station_wheel(
        &self,
        station_id: &str,
        wheel: &netlink::WheelInfo,
        now_ms: i64,
    ) -> Result<(), HubError> {
        wheel
            .validate()
            .map_err(|e| HubError::invalid("wheel", e.0))?;
        let done = sqlx::query(
            "UPDATE stations SET wheel_model = $2, wheel_rated_torque_nm = $3, \
             wheel_ceiling_nm = $4, wheel_unknown = $5, wheel_seen_at_ms = $6 \
             WHERE station_id = $1",
        )
        .bind(station_id)
        .bind(&wheel.model)
        .bind(wheel.rated_torque_nm)
        .bind(wheel.ceiling_nm)
        .bind(i64::from(wheel.unknown))
        .bind(now_ms)
        .execute(self.pool())
        .await
        .map_err(HubError::db("keeping a station's wheel"))?;
        if done.rows_affected() == 0 {
            return Err(HubError::not_found("station", station_id));
        }
        Ok(())
    }

    /// The wheel the patient's stations (revoked ones left out) told the hub of last, if any.
    pub async fn wheel_of(&self, patient_id: &str) -> Result<Option<PatientWheel>, HubError> {
        let row = sqlx::query(
            "SELECT station_id, wheel_model, wheel_rated_torque_nm, wheel_ceiling_nm, \
             wheel_unknown, wheel_seen_at_ms FROM stations \
             WHERE patient_id = $1 AND revoked_at_ms IS NULL AND wheel_seen_at_ms IS NOT NULL \
             ORDER BY wheel_seen_at_ms DESC, station_id LIMIT 1",
        )
        .bind(patient_id)
        .fetch_optional(self.pool())
        .await
        .map_err(HubError::db("reading the patient's wheel"))?;
        let Some(row) = row else {
            return Ok(None);
        };
        Ok(Some(PatientWheel {
            station_id: col(&row, "station_id")?,
            model: col(&row, "wheel_model")?,
            rated_torque_nm: col(&row, "wheel_rated_torque_nm")?,
            ceiling_nm: col(&row, "wheel_ceiling_nm")?,
            unknown: col::<i64>(&row, "wheel_unknown")? != 0,
            seen_at_ms: col(&row, "wheel_seen_at_ms")?,
        }))
    }
}
