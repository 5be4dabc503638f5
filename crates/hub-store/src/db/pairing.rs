//! One-time pairing codes: the clinic gives a patient `XXXX-XXXX` ([`PairingCode`]); their
//! station pairs with it once. The public half names the code; the secret half is the
//! password of the SPAKE2 exchange of `netlink::pairing`, which the hub needs in clear.

use netlink::pairing::PairingCode;

use super::{Db, check_id, col};
use crate::error::{HubError, PairRefusal};

/// Shortest wait after an attempt before the code takes the next from the same address, ms.
/// Every attempt is counted when it begins (before the SPAKE2 exchange), so parallel guesses
/// from one address get one real try per wait.
pub const MIN_ATTEMPT_WAIT_MS: i64 = 5_000;

/// Longest wait between two attempts at one code, ms (1 h).
pub const MAX_ATTEMPT_WAIT_MS: i64 = 3_600_000;

/// Attempts a code takes with the shortest wait before the waits double.
pub const ATTEMPTS_BEFORE_BACKOFF: i64 = 3;

/// How long a code refuses another attempt from an address after that address's `n`-th
/// (1-based), ms:
/// [`MIN_ATTEMPT_WAIT_MS`] for the first [`ATTEMPTS_BEFORE_BACKOFF`], then doubling up to
/// [`MAX_ATTEMPT_WAIT_MS`].
///
/// A wrong guess never kills a code (anyone who knew its public half could otherwise burn a
/// patient's code with three tries); it slows the next one instead. Over a 72 h code this
/// allows at most 82 online guesses of the 20-bit secret per address (success ≤ 82 / 2²⁰ ≈
/// 8·10⁻⁵), and the per-address limits of the ingest bound what one address can try. The
/// waits are per address (issue 44) so that a guesser cannot hold the code waiting for the
/// patient's own station; more addresses buy a guesser more tries, no more than they would
/// against the ingest's per-address limits.
pub fn attempt_wait_ms(n: i64) -> i64 {
    let doublings = (n - ATTEMPTS_BEFORE_BACKOFF).clamp(0, 20);
    MIN_ATTEMPT_WAIT_MS
        .saturating_mul(1_i64 << doublings)
        .min(MAX_ATTEMPT_WAIT_MS)
}

/// A live code's secret and patient.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PairingTicket {
    /// The secret half (SPAKE2 password).
    pub secret: String,
    /// The patient the code pairs a station for.
    pub patient_id: String,
}

impl Db {
    /// Issues a single-use pairing code for `patient_id`, valid for `ttl_ms` after `now_ms`.
    /// Returns the code to show (`XXXX-XXXX`).
    pub async fn create_pairing_code(
        &self,
        patient_id: &str,
        now_ms: i64,
        ttl_ms: i64,
    ) -> Result<String, HubError> {
        check_id("patient_id", patient_id)?;
        if ttl_ms <= 0 {
            return Err(HubError::invalid("ttl_ms", format!("{ttl_ms} must be > 0")));
        }
        if self.patient(patient_id).await?.is_none() {
            return Err(HubError::not_found("patient", patient_id));
        }
        // The per-address waits of codes that can no longer pair are of no use: forgotten, so
        // the table holds only live codes' waits however many addresses tried them.
        sqlx::query(
            "DELETE FROM pairing_attempt_waits WHERE code_id IN (SELECT code_id FROM \
             pairing_codes WHERE used_at_ms IS NOT NULL OR expires_at_ms <= $1)",
        )
        .bind(now_ms)
        .execute(self.pool())
        .await
        .map_err(HubError::db("forgetting the waits of spent pairing codes"))?;
        // The public half must be unique among stored codes: retry on the rare collision.
        for _ in 0..8 {
            let code = PairingCode::generate().map_err(|e| HubError::Corrupt(e.to_string()))?;
            let inserted = sqlx::query(
                "INSERT INTO pairing_codes (code_id, secret, patient_id, created_at_ms, \
                 expires_at_ms, failed_attempts) VALUES ($1, $2, $3, $4, $5, 0) \
                 ON CONFLICT (code_id) DO NOTHING",
            )
            .bind(code.code_id())
            .bind(code.secret())
            .bind(patient_id)
            .bind(now_ms)
            .bind(now_ms.saturating_add(ttl_ms))
            .execute(self.pool())
            .await
            .map_err(HubError::db("storing a pairing code"))?;
            if inserted.rows_affected() == 1 {
                return Ok(code.to_string());
            }
        }
        Err(HubError::Corrupt(
            "no free pairing code after 8 tries (remove expired codes)".into(),
        ))
    }

    /// The live code named `code_id` (its public half), or why it cannot pair.
    pub async fn pairing_ticket(
        &self,
        code_id: &str,
        now_ms: i64,
    ) -> Result<PairingTicket, HubError> {
        let row = sqlx::query(
            "SELECT secret, patient_id, expires_at_ms, used_at_ms, failed_attempts \
             FROM pairing_codes WHERE code_id = $1",
        )
        .bind(code_id)
        .fetch_optional(self.pool())
        .await
        .map_err(HubError::db("reading a pairing code"))?;
        let Some(row) = row else {
            return Err(HubError::Pair(PairRefusal::Unknown));
        };
        let refusal = if col::<Option<i64>>(&row, "used_at_ms")?.is_some() {
            Some(PairRefusal::Used)
        } else if col::<i64>(&row, "expires_at_ms")? <= now_ms {
            Some(PairRefusal::Expired)
        } else {
            None
        };
        match refusal {
            Some(r) => Err(HubError::Pair(r)),
            None => Ok(PairingTicket {
                secret: col(&row, "secret")?,
                patient_id: col(&row, "patient_id")?,
            }),
        }
    }

    /// Begins one attempt at the code named `code_id` from `address` (`db::address_key` of the
    /// client), atomically: counts it and sets when that address may try this code again
    /// ([`attempt_wait_ms`] of its own attempts), and returns the code's ticket; `None` when
    /// the code is unknown, expired or used, or this address still waits after an earlier
    /// attempt. Waits are per code and address (issue 44): attempts from one address never
    /// make the code wait for another. The caller then runs the exchange with a decoy secret,
    /// so a station cannot tell these apart from a wrong secret (nothing to enumerate).
    pub async fn begin_pairing_attempt(
        &self,
        code_id: &str,
        address: &str,
        now_ms: i64,
    ) -> Result<Option<PairingTicket>, HubError> {
        let live = sqlx::query(
            "SELECT secret, patient_id FROM pairing_codes \
             WHERE code_id = $1 AND used_at_ms IS NULL AND expires_at_ms > $2",
        )
        .bind(code_id)
        .bind(now_ms)
        .fetch_optional(self.pool())
        .await
        .map_err(HubError::db("reading a pairing code"))?;
        let Some(live) = live else {
            return Ok(None);
        };
        // One statement takes the address's attempt and closes the code to it for the
        // shortest wait, so parallel attempts from one address cannot both pass.
        let attempts: Option<i64> = sqlx::query_scalar(
            "INSERT INTO pairing_attempt_waits (code_id, address, attempts, next_attempt_at_ms) \
             VALUES ($1, $2, 1, $4) \
             ON CONFLICT (code_id, address) DO UPDATE \
             SET attempts = pairing_attempt_waits.attempts + 1, next_attempt_at_ms = $4 \
             WHERE pairing_attempt_waits.next_attempt_at_ms <= $3 \
             RETURNING attempts",
        )
        .bind(code_id)
        .bind(address)
        .bind(now_ms)
        .bind(now_ms.saturating_add(MIN_ATTEMPT_WAIT_MS))
        .fetch_optional(self.pool())
        .await
        .map_err(HubError::db("beginning a pairing attempt"))?;
        let Some(attempts) = attempts else {
            return Ok(None);
        };
        sqlx::query(
            "UPDATE pairing_attempt_waits SET next_attempt_at_ms = $3 \
             WHERE code_id = $1 AND address = $2",
        )
        .bind(code_id)
        .bind(address)
        .bind(now_ms.saturating_add(attempt_wait_ms(attempts)))
        .execute(self.pool())
        .await
        .map_err(HubError::db("delaying the next pairing attempt"))?;
        sqlx::query(
            "UPDATE pairing_codes SET failed_attempts = failed_attempts + 1 WHERE code_id = $1",
        )
        .bind(code_id)
        .execute(self.pool())
        .await
        .map_err(HubError::db("counting a pairing attempt"))?;
        Ok(Some(PairingTicket {
            secret: col(&live, "secret")?,
            patient_id: col(&live, "patient_id")?,
        }))
    }

    /// Pairs a station with the code named `code_id`, in one transaction: uses up the code,
    /// adds the station (`station_id`, its certificate's SHA-256 `fingerprint`) for the
    /// code's patient and audits it; the patient id, or why not. A failure leaves the code
    /// live and nothing stored (it once burned the code and left no audit entry).
    pub async fn pair_station(
        &self,
        code_id: &str,
        station_id: &str,
        fingerprint: &str,
        now_ms: i64,
    ) -> Result<String, HubError> {
        check_id("station_id", station_id)?;
        super::stations::check_fingerprint(fingerprint)?;
        let mut tx = self
            .pool()
            .begin()
            .await
            .map_err(HubError::db("starting a transaction"))?;
        let redeemed: Option<String> = sqlx::query_scalar(
            "UPDATE pairing_codes SET used_at_ms = $2 \
             WHERE code_id = $1 AND used_at_ms IS NULL AND expires_at_ms > $2 \
             RETURNING patient_id",
        )
        .bind(code_id)
        .bind(now_ms)
        .fetch_optional(&mut *tx)
        .await
        .map_err(HubError::db("redeeming a pairing code"))?;
        let Some(patient_id) = redeemed else {
            drop(tx);
            return Err(self
                .pairing_ticket(code_id, now_ms)
                .await
                .err()
                .unwrap_or(HubError::Pair(PairRefusal::Used)));
        };
        sqlx::query(
            "INSERT INTO stations (station_id, patient_id, cert_fingerprint, paired_at_ms) \
             VALUES ($1, $2, $3, $4)",
        )
        .bind(station_id)
        .bind(&patient_id)
        .bind(fingerprint)
        .bind(now_ms)
        .execute(&mut *tx)
        .await
        .map_err(HubError::db("adding a station"))?;
        sqlx::query("DELETE FROM pairing_attempt_waits WHERE code_id = $1")
            .bind(code_id)
            .execute(&mut *tx)
            .await
            .map_err(HubError::db("forgetting a used code's waits"))?;
        super::audit::audit_on(
            &mut *tx,
            "station:pairing",
            "station_paired",
            station_id,
            &patient_id,
            now_ms,
        )
        .await?;
        tx.commit()
            .await
            .map_err(HubError::db("committing a pairing"))?;
        Ok(patient_id)
    }
}
