//! What a station is told of its patient, read from the database: the clinic's pain settings
//! with the patient's clearance, the therapist's unseen messages and the current regimen.
//! A session's connection is pushed them when it connects (`clinic`); a station's check
//! (today's page, `doctor --hub`) is answered with them ([`for_check`], protocol version 4), so
//! a plan prescribed while today's page is open shows within its next check.

use netlink::CheckNews;

use crate::care::CareConfig;
use hub_store::db::{Db, RegimenVersion};

/// The clinic's pain settings in force, with the patient's clearance after a pain stop.
pub async fn care_frame(db: &Db, care: &CareConfig, patient_id: &str) -> netlink::Care {
    let cleared = match db.pain_cleared_at(patient_id).await {
        Ok(at) => at.and_then(|ms| u64::try_from(ms).ok()),
        Err(e) => {
            tracing::warn!(patient = %patient_id, "cannot read the pain clearance: {e}");
            None
        }
    };
    let threshold = care.pain_threshold_in(db).await;
    care.care_frame(threshold, cleared)
}

/// The patient's messages not yet seen, oldest first, as frames (none if the database does
/// not answer: logged).
pub async fn unseen_messages(db: &Db, patient_id: &str) -> Vec<netlink::Message> {
    match db.unseen_messages(patient_id).await {
        Ok(messages) => messages
            .into_iter()
            .map(|m| netlink::Message {
                sent_unix_ms: u64::try_from(m.created_at_ms).unwrap_or(0),
                id: m.id,
                text: m.text,
            })
            .collect(),
        Err(e) => {
            tracing::warn!(patient = %patient_id, "cannot read unseen messages: {e}");
            Vec::new()
        }
    }
}

/// `regimen` as the station receives it, its id `PATIENT-vN` and its prescriber named by the
/// clinic's words for them (their e-mail), never the internal therapist id.
pub async fn regimen_frame(db: &Db, regimen: &RegimenVersion) -> netlink::Regimen {
    let prescribed_by = match db.therapist(&regimen.prescribed_by).await {
        Ok(Some(t)) => Some(t.email),
        _ => None,
    };
    netlink::Regimen {
        id: format!("{}-v{}", regimen.patient_id, regimen.version),
        toml: regimen.toml.clone(),
        prescribed_by,
    }
}

/// The answer to a station's check for `patient_id` at `now_ms`: its care (when the hub has
/// care settings), unseen messages (noted delivered) and current regimen.
pub async fn for_check(
    db: &Db,
    care: Option<&CareConfig>,
    patient_id: &str,
    now_ms: i64,
) -> CheckNews {
    let care = match care {
        Some(c) => Some(care_frame(db, c, patient_id).await),
        None => None,
    };
    let messages = unseen_messages(db, patient_id).await;
    for m in &messages {
        if let Err(e) = db.message_delivered(&m.id, now_ms).await {
            tracing::warn!("cannot note message {} delivered: {e}", m.id);
        }
    }
    let regimen = match db.latest_regimen(patient_id).await {
        Ok(Some(r)) => Some(regimen_frame(db, &r).await),
        Ok(None) => None,
        Err(e) => {
            tracing::warn!(patient = %patient_id, "cannot read the current regimen: {e}");
            None
        }
    };
    CheckNews {
        care,
        messages,
        regimen,
    }
}
