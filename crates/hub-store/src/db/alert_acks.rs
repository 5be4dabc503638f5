//! Acknowledged and snoozed alerts (migration 0020): a therapist's word that they have seen
//! an alert of a patient, with a note, and until when it may stay quiet.

use std::collections::BTreeMap;

use serde::Serialize;

use super::{Db, col, new_id};
use crate::error::HubError;
use crate::refusal::{Code, Why};

/// Longest alert key, characters (`decline:dial+road:wheel_rom_deg` and the like).
pub const MAX_ALERT_KEY_CHARS: usize = 128;

/// The newest acknowledgement or snooze of one alert of a patient.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct AlertAck {
    /// The alert's key (`hub_care::attention::Alert::key`).
    pub alert_key: String,
    /// The evidence it was given for (`hub_care::attention::Alert::fingerprint`): the alert
    /// stays quiet only while that is unchanged.
    pub fingerprint: String,
    /// A snooze's end, ms since the Unix epoch; `None` for an acknowledgement (quiet until
    /// something new happens).
    pub until_ms: Option<i64>,
    /// The therapist's note.
    pub note: String,
    /// Who, by e-mail (`None` if the account is gone).
    pub by_email: Option<String>,
    /// When, ms since the Unix epoch.
    pub at_ms: i64,
}

/// What an acknowledgement records.
#[derive(Debug, Clone, Copy)]
pub struct NewAck<'a> {
    /// The patient.
    pub patient_id: &'a str,
    /// The alert's key.
    pub alert_key: &'a str,
    /// The alert's evidence as the therapist saw it.
    pub fingerprint: &'a str,
    /// A snooze's end, ms since the Unix epoch (`None`: acknowledged).
    pub until_ms: Option<i64>,
    /// The note (checked with [`super::check_note_text`]).
    pub note: &'a str,
    /// The therapist.
    pub therapist_id: &'a str,
}

impl Db {
    /// Records `ack` at `now_ms`; a note that is empty, too long or holds control
    /// characters, or a snooze that ends in the past, is [`HubError::Invalid`].
    pub async fn put_alert_ack(&self, ack: &NewAck<'_>, now_ms: i64) -> Result<(), HubError> {
        super::check_note_text(ack.note).map_err(|e| {
            let why = crate::refusal::of_text("note", ack.note, super::MAX_NOTE_CHARS);
            HubError::refused("note", e, why)
        })?;
        if ack.alert_key.is_empty() || ack.alert_key.chars().count() > MAX_ALERT_KEY_CHARS {
            return Err(HubError::invalid(
                "key",
                format!("an alert key has 1 to {MAX_ALERT_KEY_CHARS} characters"),
            ));
        }
        if ack.until_ms.is_some_and(|u| u <= now_ms) {
            return Err(HubError::refused(
                "snooze_until_ms",
                "a snooze ends in the future: choose a later date",
                Why::new(Code::SnoozePast),
            ));
        }
        sqlx::query(
            "INSERT INTO alert_acks (id, patient_id, alert_key, fingerprint, until_ms, note, \
             therapist_id, at_ms) VALUES ($1, $2, $3, $4, $5, $6, $7, $8)",
        )
        .bind(new_id("ack-")?)
        .bind(ack.patient_id)
        .bind(ack.alert_key)
        .bind(ack.fingerprint)
        .bind(ack.until_ms)
        .bind(ack.note)
        .bind(ack.therapist_id)
        .bind(now_ms)
        .execute(self.pool())
        .await
        .map_err(HubError::db("acknowledging an alert"))?;
        Ok(())
    }

    /// The newest acknowledgement or snooze of each of patient `patient_id`'s alerts, by key.
    pub async fn alert_acks_of(
        &self,
        patient_id: &str,
    ) -> Result<BTreeMap<String, AlertAck>, HubError> {
        let rows = sqlx::query(
            "SELECT a.alert_key, a.fingerprint, a.until_ms, a.note, a.at_ms, t.email \
             FROM alert_acks a LEFT JOIN therapists t ON t.id = a.therapist_id \
             WHERE a.patient_id = $1 ORDER BY a.at_ms, a.id",
        )
        .bind(patient_id)
        .fetch_all(self.pool())
        .await
        .map_err(HubError::db("reading acknowledged alerts"))?;
        let mut out = BTreeMap::new();
        for r in &rows {
            let ack = AlertAck {
                alert_key: col(r, "alert_key")?,
                fingerprint: col(r, "fingerprint")?,
                until_ms: col(r, "until_ms")?,
                note: col(r, "note")?,
                by_email: col(r, "email")?,
                at_ms: col(r, "at_ms")?,
            };
            // Oldest first: the newest of each key stays.
            out.insert(ack.alert_key.clone(), ack);
        }
        Ok(out)
    }
}
