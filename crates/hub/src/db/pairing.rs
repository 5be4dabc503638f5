//! One-time pairing codes: the clinic gives a patient `XXXX-XXXX`, their station redeems it
//! once to be paired. Only the SHA-256 of the normalised code is stored.

use super::{Db, check_id, col, random_bytes, sha256_hex};
use crate::error::{HubError, PairRefusal};

/// Alphabet of pairing codes: Crockford's base 32 (no I, L, O, U). On input `O` reads as
/// `0` and `I`/`L` as `1`, so the look-alikes cannot be mistyped.
pub const CODE_ALPHABET: &[u8; 32] = b"0123456789ABCDEFGHJKMNPQRSTVWXYZ";

/// Random bits in a pairing code (8 characters of 5 bits).
pub const CODE_BITS: u32 = 40;

/// The canonical form of a typed code: upper case, separators and spaces removed,
/// look-alikes mapped (`O`→`0`, `I`/`L`→`1`); `None` if it cannot be a code.
pub fn normalise_code(code: &str) -> Option<String> {
    let mut out = String::with_capacity(8);
    for c in code.chars() {
        let c = match c.to_ascii_uppercase() {
            '-' | ' ' => continue,
            'O' => '0',
            'I' | 'L' => '1',
            c => c,
        };
        if !c.is_ascii() || !CODE_ALPHABET.contains(&(c as u8)) || out.len() == 8 {
            return None;
        }
        out.push(c);
    }
    (out.len() == 8).then_some(out)
}

/// A new random code, `XXXX-XXXX` ([`CODE_BITS`] bits from the OS CSPRNG).
fn new_code() -> Result<String, HubError> {
    let bytes = random_bytes::<5>()?;
    let bits = bytes.iter().fold(0u64, |acc, &b| (acc << 8) | u64::from(b));
    let mut code = String::with_capacity(9);
    for i in 0..8 {
        if i == 4 {
            code.push('-');
        }
        let index = (bits >> (35 - 5 * i)) & 0x1f;
        code.push(char::from(CODE_ALPHABET[index as usize]));
    }
    Ok(code)
}

impl Db {
    /// Issues a single-use pairing code for `patient_id`, valid for `ttl_ms` after `now_ms`.
    /// Returns the code to show (`XXXX-XXXX`); only its hash is stored.
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
        let code = new_code()?;
        let canonical = normalise_code(&code)
            .ok_or_else(|| HubError::Corrupt(format!("generated code {code} is malformed")))?;
        sqlx::query(
            "INSERT INTO pairing_codes (code_hash, patient_id, created_at_ms, expires_at_ms, \
             failed_attempts) VALUES ($1, $2, $3, $4, 0)",
        )
        .bind(sha256_hex(canonical.as_bytes()))
        .bind(patient_id)
        .bind(now_ms)
        .bind(now_ms.saturating_add(ttl_ms))
        .execute(self.pool())
        .await
        .map_err(HubError::db("storing a pairing code"))?;
        Ok(code)
    }

    /// Redeems a pairing code once, atomically: returns the patient id it was issued for, or
    /// [`HubError::Pair`] saying whether it is unknown, expired or already used (a refused
    /// attempt on a known code is counted in `failed_attempts`).
    pub async fn redeem_pairing_code(&self, code: &str, now_ms: i64) -> Result<String, HubError> {
        let Some(canonical) = normalise_code(code) else {
            return Err(HubError::Pair(PairRefusal::Unknown));
        };
        let hash = sha256_hex(canonical.as_bytes());
        let redeemed: Option<String> = sqlx::query_scalar(
            "UPDATE pairing_codes SET used_at_ms = $2 \
             WHERE code_hash = $1 AND used_at_ms IS NULL AND expires_at_ms > $2 \
             RETURNING patient_id",
        )
        .bind(&hash)
        .bind(now_ms)
        .fetch_optional(self.pool())
        .await
        .map_err(HubError::db("redeeming a pairing code"))?;
        if let Some(patient_id) = redeemed {
            return Ok(patient_id);
        }
        let row = sqlx::query(
            "UPDATE pairing_codes SET failed_attempts = failed_attempts + 1 \
             WHERE code_hash = $1 RETURNING used_at_ms",
        )
        .bind(&hash)
        .fetch_optional(self.pool())
        .await
        .map_err(HubError::db("counting a refused pairing code"))?;
        let refusal = match row {
            None => PairRefusal::Unknown,
            Some(row) if col::<Option<i64>>(&row, "used_at_ms")?.is_some() => PairRefusal::Used,
            Some(_) => PairRefusal::Expired,
        };
        Err(HubError::Pair(refusal))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn generated_codes_have_the_format_and_normalise() {
        for _ in 0..100 {
            let code = new_code().unwrap();
            assert_eq!(code.len(), 9);
            assert_eq!(&code[4..5], "-");
            assert_eq!(normalise_code(&code).unwrap(), code.replace('-', ""));
        }
    }

    #[test]
    fn look_alikes_and_case_are_forgiven_but_wrong_lengths_are_not() {
        assert_eq!(normalise_code("o1il-abcd").as_deref(), Some("0111ABCD"));
        assert_eq!(normalise_code(" 7K3M Q9XD ").as_deref(), Some("7K3MQ9XD"));
        assert_eq!(normalise_code("7K3M-Q9X"), None);
        assert_eq!(normalise_code("7K3M-Q9XDD"), None);
        assert_eq!(normalise_code("7K3M-Q9XU"), None);
        assert_eq!(normalise_code("'; DROP TABLE"), None);
    }
}
