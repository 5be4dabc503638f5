//! The pairing code, the SPAKE2 exchange and the MACs that bind the rest of pairing to it.

use std::fmt;

use ring::hmac;
use ring::rand::{SecureRandom, SystemRandom};
use spake2::{Ed25519Group, Identity, Password, Spake2};

/// Letters and digits of a pairing code: Crockford's base 32 (no I, L, O, U); on input `O`
/// reads as `0` and `I`/`L` as `1`, so look-alikes cannot be mistyped from paper.
pub const CODE_ALPHABET: &[u8; 32] = b"0123456789ABCDEFGHJKMNPQRSTVWXYZ";
/// Characters in each half of a code.
const HALF: usize = 4;

const STATION_ID: &[u8] = b"telerehab station";
const HUB_ID: &[u8] = b"telerehab hub";

/// Why a pairing code could not be read or made.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum PairingCodeError {
    /// Not 8 letters and digits (spaces and dashes aside).
    #[error(
        "a pairing code has {letters} letters and digits (like 7KQ2-M9XD); {text:?} has {found}",
        letters = 2 * HALF
    )]
    Length {
        /// The code as typed.
        text: String,
        /// Letters and digits found in it.
        found: usize,
    },
    /// A character outside [`CODE_ALPHABET`] (after the look-alikes are mapped).
    #[error(
        "a pairing code never contains {0:?} (it uses {alphabet})",
        alphabet = String::from_utf8_lossy(CODE_ALPHABET)
    )]
    Character(char),
    /// The operating system's random generator failed (making a code).
    #[error("the operating system's random generator failed")]
    Random,
}

/// The SPAKE2 exchange failed: the peer's message was malformed.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("the pairing exchange failed: {0}")]
pub(crate) struct ExchangeError(String);

/// A pairing code `XXXX-XXXX` (40 bits): the first half names the code (public), the second
/// is the SPAKE2 password (secret, 2²⁰ values; the hub allows a few guesses per code).
#[derive(Clone, PartialEq, Eq)]
pub struct PairingCode {
    code_id: String,
    secret: String,
}

impl fmt::Debug for PairingCode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "PairingCode({}-****)", self.code_id)
    }
}

impl fmt::Display for PairingCode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}-{}", self.code_id, self.secret)
    }
}

impl PairingCode {
    /// Reads a code as a person types it: case, spaces and dashes do not matter, and the
    /// look-alikes `O`, `I`, `L` read as `0`, `1`, `1`.
    pub fn parse(text: &str) -> Result<Self, PairingCodeError> {
        let chars: String = text
            .chars()
            .filter(|c| !c.is_whitespace() && *c != '-')
            .map(|c| match c.to_ascii_uppercase() {
                'O' => '0',
                'I' | 'L' => '1',
                c => c,
            })
            .collect();
        if chars.len() != 2 * HALF {
            return Err(PairingCodeError::Length {
                text: text.to_owned(),
                found: chars.chars().count(),
            });
        }
        if let Some(bad) = chars.bytes().find(|b| !CODE_ALPHABET.contains(b)) {
            return Err(PairingCodeError::Character(bad as char));
        }
        Ok(Self {
            code_id: chars[..HALF].to_owned(),
            secret: chars[HALF..].to_owned(),
        })
    }

    /// A new random code from the operating system's CSPRNG (5 random bits a character).
    pub fn generate() -> Result<Self, PairingCodeError> {
        let mut bytes = [0u8; 2 * HALF];
        SystemRandom::new()
            .fill(&mut bytes)
            .map_err(|_| PairingCodeError::Random)?;
        let code: String = bytes
            .iter()
            .map(|b| CODE_ALPHABET[usize::from(b & 0x1f)] as char)
            .collect();
        Self::parse(&code)
    }

    /// The public half, e.g. `7KQ2`.
    pub fn code_id(&self) -> &str {
        &self.code_id
    }

    /// The secret half, e.g. `M9XD`.
    pub fn secret(&self) -> &str {
        &self.secret
    }
}

/// The key both sides derive from the exchange.
pub(crate) struct SharedKey(hmac::Key);

/// What a MAC covers; the label keeps a station's tag from being replayed as the hub's.
#[derive(Debug, Clone, Copy)]
pub(crate) enum MacLabel {
    /// `PairFinish`: the request, the exchange, the hub certificate the station saw.
    StationFinish,
    /// `Paired`: the credential and the exchange.
    HubPaired,
}

fn finish(state: Spake2<Ed25519Group>, theirs: &[u8]) -> Result<SharedKey, ExchangeError> {
    let key = state
        .finish(theirs)
        .map_err(|e| ExchangeError(format!("{e:?}")))?;
    Ok(SharedKey(hmac::Key::new(hmac::HMAC_SHA256, &key)))
}

/// The station's half of the exchange.
pub(crate) struct StationExchange(Spake2<Ed25519Group>);

impl StationExchange {
    /// Starts with the code's secret; the message to send.
    pub(crate) fn start(code: &PairingCode) -> (Self, Vec<u8>) {
        let (state, msg) = Spake2::<Ed25519Group>::start_a(
            &Password::new(code.secret.as_bytes()),
            &Identity::new(STATION_ID),
            &Identity::new(HUB_ID),
        );
        (Self(state), msg)
    }

    /// The key, from the hub's message.
    pub(crate) fn finish(self, hub_msg: &[u8]) -> Result<SharedKey, ExchangeError> {
        finish(self.0, hub_msg)
    }
}

/// The hub's half of the exchange.
pub(crate) struct HubExchange;

impl HubExchange {
    /// Answers the station's message with the code's secret: the message to send and the key.
    pub(crate) fn respond(
        secret: &str,
        station_msg: &[u8],
    ) -> Result<(Vec<u8>, SharedKey), ExchangeError> {
        let (state, msg) = Spake2::<Ed25519Group>::start_b(
            &Password::new(secret.as_bytes()),
            &Identity::new(STATION_ID),
            &Identity::new(HUB_ID),
        );
        Ok((msg, finish(state, station_msg)?))
    }
}

/// The bytes a MAC covers: the label, then each part length-prefixed (so parts cannot be
/// shifted between fields).
fn transcript(label: MacLabel, parts: &[&[u8]]) -> Vec<u8> {
    let mut msg = format!("{label:?}").into_bytes();
    for part in parts {
        msg.extend_from_slice(&(part.len() as u64).to_be_bytes());
        msg.extend_from_slice(part);
    }
    msg
}

/// HMAC-SHA-256 of `parts` under the exchanged key, lowercase hex.
pub(crate) fn mac_hex(key: &SharedKey, label: MacLabel, parts: &[&[u8]]) -> String {
    super::to_hex(hmac::sign(&key.0, &transcript(label, parts)).as_ref())
}

/// Whether `mac` (hex) is the tag of `parts` (compared in constant time).
pub(crate) fn verify_mac(key: &SharedKey, label: MacLabel, parts: &[&[u8]], mac: &str) -> bool {
    super::from_hex(mac)
        .is_some_and(|mac| hmac::verify(&key.0, &transcript(label, parts), &mac).is_ok())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_code_reads_back_whatever_the_case_spaces_and_dashes() {
        let code = PairingCode::parse(" 7kq2-m9xd ").unwrap();
        assert_eq!((code.code_id(), code.secret()), ("7KQ2", "M9XD"));
        assert_eq!(code.to_string(), "7KQ2-M9XD");
        let short = PairingCode::parse("7KQ2-M9X").unwrap_err();
        assert!(
            matches!(short, PairingCodeError::Length { found: 7, .. }),
            "{short:?}"
        );
        assert!(short.to_string().contains("has 7"), "{short}");
        let u = PairingCode::parse("7KQ2-M9XU").unwrap_err();
        assert_eq!(u, PairingCodeError::Character('U'));
        assert!(u.to_string().contains("'U'") && u.to_string().contains("0123456789ABC"));
        let read = PairingCode::parse("o1il-abcd").unwrap();
        assert_eq!(read.to_string(), "0111-ABCD", "look-alikes read as digits");
        assert!(PairingCode::parse("'; DROP TABLE").is_err());
    }

    #[test]
    fn generated_codes_use_the_alphabet_and_differ() {
        let a = PairingCode::generate().unwrap();
        let b = PairingCode::generate().unwrap();
        assert_ne!(a, b, "two codes from the CSPRNG (1 in 8.5e11 to collide)");
        assert!(
            a.to_string()
                .bytes()
                .all(|c| c == b'-' || CODE_ALPHABET.contains(&c))
        );
        assert!(
            !format!("{a:?}").contains(a.secret()),
            "Debug hides the secret"
        );
    }

    #[test]
    fn the_same_secret_gives_the_same_key_and_another_secret_a_different_one() {
        let code = PairingCode::parse("7KQ2-M9XD").unwrap();
        let (station, msg_a) = StationExchange::start(&code);
        let (msg_b, hub_key) = HubExchange::respond("M9XD", &msg_a).unwrap();
        let station_key = station.finish(&msg_b).unwrap();
        let parts: [&[u8]; 2] = [b"csr", b"cert"];
        let mac = mac_hex(&station_key, MacLabel::StationFinish, &parts);
        assert!(verify_mac(&hub_key, MacLabel::StationFinish, &parts, &mac));
        assert!(
            !verify_mac(&hub_key, MacLabel::HubPaired, &parts, &mac),
            "label binds"
        );
        assert!(!verify_mac(
            &hub_key,
            MacLabel::StationFinish,
            &[b"csr", b"other"],
            &mac
        ));

        let (station, msg_a) = StationExchange::start(&code);
        let (msg_b, wrong_key) = HubExchange::respond("M9XE", &msg_a).unwrap();
        let station_key = station.finish(&msg_b).unwrap();
        let mac = mac_hex(&station_key, MacLabel::StationFinish, &parts);
        assert!(!verify_mac(
            &wrong_key,
            MacLabel::StationFinish,
            &parts,
            &mac
        ));
    }
}
