//! The patient's end-of-session check-in (pain, tiredness, how hard it felt), from the
//! station's `Bye`, and the caseload alert it raises.

use netlink::CheckIn;
use serde::Serialize;

use super::{Db, col};
use crate::error::HubError;

/// Pain (0–10) at or above which the caseload raises an alert whatever the patient's usual.
pub const PAIN_ALERT_AT: i64 = 7;

/// Points above the patient's usual pain (the median of their earlier answers) that raise
/// an alert.
pub const PAIN_RISE_ALERT: i64 = 2;

/// One session's check-in as the hub stores it.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct SessionCheckIn {
    /// The session it followed.
    pub session_id: String,
    /// The session's start (station clock), ms since the Unix epoch.
    pub started_unix_ms: i64,
    /// Pain now, 0–10, if answered.
    pub pain_0_10: Option<i64>,
    /// Tiredness now, 0–10, if answered.
    pub tiredness_0_10: Option<i64>,
    /// `too_easy`, `about_right` or `too_hard`, if answered.
    pub difficulty: Option<String>,
    /// When the hub received it, ms since the Unix epoch.
    pub received_at_ms: i64,
}

/// The alert of the newest pain answer against the earlier ones (`newest_first`), if any:
/// pain of [`PAIN_ALERT_AT`] or more, or [`PAIN_RISE_ALERT`] points above the median of the
/// earlier answers.
pub fn pain_alert(newest_first: &[i64]) -> Option<String> {
    let (&last, earlier) = newest_first.split_first()?;
    if last >= PAIN_ALERT_AT {
        return Some(format!("pain {last}/10 after the last session"));
    }
    let mut earlier = earlier.to_vec();
    if earlier.is_empty() {
        return None;
    }
    earlier.sort_unstable();
    let n = earlier.len();
    // The median, rounded up for an even count (the alert errs on the quiet side).
    let usual = if n % 2 == 1 {
        earlier[n / 2]
    } else {
        (earlier[n / 2 - 1] + earlier[n / 2] + 1) / 2
    };
    (last >= usual + PAIN_RISE_ALERT)
        .then(|| format!("pain {last}/10 after the last session (usually {usual}/10)"))
}

impl Db {
    /// Stores the check-in of session `session_id` (a repeated `Bye` stores it again).
    pub async fn put_checkin(
        &self,
        session_id: &str,
        checkin: &CheckIn,
        now_ms: i64,
    ) -> Result<(), HubError> {
        checkin
            .validate()
            .map_err(|e| HubError::invalid("checkin", e.0))?;
        let session = self
            .session(session_id)
            .await?
            .ok_or_else(|| HubError::not_found("session", session_id))?;
        let mut tx = self
            .pool()
            .begin()
            .await
            .map_err(HubError::db("storing a check-in"))?;
        sqlx::query("DELETE FROM session_checkins WHERE session_id = $1")
            .bind(session_id)
            .execute(&mut *tx)
            .await
            .map_err(HubError::db("storing a check-in"))?;
        sqlx::query(
            "INSERT INTO session_checkins (session_id, patient_id, started_unix_ms, pain_0_10, \
             tiredness_0_10, difficulty, received_at_ms) VALUES ($1, $2, $3, $4, $5, $6, $7)",
        )
        .bind(session_id)
        .bind(&session.patient_id)
        .bind(session.started_unix_ms)
        .bind(checkin.pain_0_10.map(i64::from))
        .bind(checkin.tiredness_0_10.map(i64::from))
        .bind(checkin.difficulty.as_deref())
        .bind(now_ms)
        .execute(&mut *tx)
        .await
        .map_err(HubError::db("storing a check-in"))?;
        tx.commit()
            .await
            .map_err(HubError::db("storing a check-in"))
    }

    /// A patient's check-ins, newest session first.
    pub async fn checkins_of(&self, patient_id: &str) -> Result<Vec<SessionCheckIn>, HubError> {
        let rows = sqlx::query(
            "SELECT session_id, started_unix_ms, pain_0_10, tiredness_0_10, difficulty, \
             received_at_ms FROM session_checkins WHERE patient_id = $1 \
             ORDER BY started_unix_ms DESC, session_id",
        )
        .bind(patient_id)
        .fetch_all(self.pool())
        .await
        .map_err(HubError::db("reading check-ins"))?;
        rows.iter()
            .map(|row| {
                Ok(SessionCheckIn {
                    session_id: col(row, "session_id")?,
                    started_unix_ms: col(row, "started_unix_ms")?,
                    pain_0_10: col(row, "pain_0_10")?,
                    tiredness_0_10: col(row, "tiredness_0_10")?,
                    difficulty: col(row, "difficulty")?,
                    received_at_ms: col(row, "received_at_ms")?,
                })
            })
            .collect()
    }

    /// The caseload's pain alert for a patient ([`pain_alert`] over their last 50 answers).
    pub(crate) async fn pain_alert_of(&self, patient_id: &str) -> Result<Option<String>, HubError> {
        let rows = sqlx::query(
            "SELECT pain_0_10, started_unix_ms FROM session_checkins WHERE patient_id = $1 \
             AND pain_0_10 IS NOT NULL ORDER BY started_unix_ms DESC, session_id LIMIT 50",
        )
        .bind(patient_id)
        .fetch_all(self.pool())
        .await
        .map_err(HubError::db("reading pain answers"))?;
        let pains = rows
            .iter()
            .map(|row| col(row, "pain_0_10"))
            .collect::<Result<Vec<i64>, HubError>>()?;
        let Some(alert) = pain_alert(&pains) else {
            return Ok(None);
        };
        // Later sessions without a pain answer: the pain was not after the last session.
        let reported: i64 = col(&rows[0], "started_unix_ms")?;
        let later = self
            .training_sessions_of(patient_id)
            .await?
            .iter()
            .any(|s| s.started_unix_ms > reported);
        Ok(Some(if later {
            let day = &super::day_of(reported);
            alert.replace(
                "after the last session",
                &format!("after the session of {day}"),
            )
        } else {
            alert
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::pain_alert;

    #[test]
    fn pain_alerts_at_seven_or_two_above_the_median_of_earlier_answers() {
        assert_eq!(pain_alert(&[]), None);
        assert_eq!(pain_alert(&[6]), None, "no usual yet, under 7");
        assert!(pain_alert(&[7]).unwrap().contains("pain 7/10"));
        assert_eq!(pain_alert(&[3, 2, 2, 1]), None, "one above the usual 2");
        let rise = pain_alert(&[4, 2, 2, 1]).unwrap();
        assert!(rise.contains("usually 2/10"), "{rise}");
        // Even count: median of 1 and 3 is 2.
        assert!(pain_alert(&[4, 1, 3]).is_some());
        assert_eq!(
            pain_alert(&[2, 0, 0, 9]),
            Some("pain 2/10 after the last session (usually 0/10)".into())
        );
    }
}
