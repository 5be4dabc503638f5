//! Pairing a station with a clinic's hub: a one-time code becomes the station's own credential.
//!
//! The clinic prints a code `XXXX-XXXX` (`telerehab hub patient add`). Its first half names the
//! code; its second half is the password of a SPAKE2 exchange (RustCrypto's `spake2`, Ed25519
//! group) and never crosses the wire, so an eavesdropper or a fake hub learns nothing it could
//! guess offline, and each online guess makes the code wait longer before the next. The exchanged
//! key authenticates the rest both ways:
//!
//! 1. station → hub `PairStart { code_id, pake }` (over TLS whose certificate the station cannot
//!    check yet; it remembers it);
//! 2. hub → station `PairChallenge { pake }`;
//! 3. station → hub `PairFinish { csr_pem, mac }`: a certificate request for a key generated on
//!    the station (it never leaves), MAC'd together with the hub certificate the station saw —
//!    a relay in the middle presents another certificate, so its MAC fails at the hub;
//! 4. hub → station `Paired { station_id, patient_id, ca_pem, cert_pem, server_name, mac,
//!    patient_pseudonym }` (the pseudonym optional, outside the MAC):
//!    the station checks the MAC and that the certificate it saw chains to `ca_pem` for
//!    `server_name`, then trusts only that CA from now on (mutual TLS with its certificate).
//!
//! [`PairingAuthority`] is the hub's side of the policy (codes, rate limits, issuing
//! certificates); the hub crate implements it over its database and CA.

mod crypto;
mod station;

use std::net::SocketAddr;

pub use crypto::{CODE_ALPHABET, PairingCode, PairingCodeError};
pub(crate) use crypto::{HubExchange, MacLabel, mac_hex, verify_mac};
pub use station::{Credential, PairError, pair};

use crate::answer::{BoxFuture, Refusal};

/// The one answer to every pairing attempt that fails at the hub, whatever the reason
/// (mistyped, unknown, expired, used, or the code waiting after an earlier attempt): a station
/// cannot tell which, so codes cannot be enumerated. Plain words for the patient.
pub const CODE_NOT_ACCEPTED: &str = "this pairing code was not accepted: it may be mistyped, \
    expired or already used. Check it and try again in a minute; if it still fails, ask the \
    clinic for a new code";

/// A live pairing code, as the hub's authority found it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Ticket {
    /// The secret half of the code (the SPAKE2 password).
    pub secret: String,
    /// The patient the code pairs a station for.
    pub patient_id: String,
}

/// What the hub issues to a paired station.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Issued {
    /// The station's new identity (its certificate names it as a DNS subjectAltName).
    pub station_id: String,
    /// The patient it speaks for.
    pub patient_id: String,
    /// The clinic's CA certificate, PEM.
    pub ca_pem: String,
    /// The station's certificate, PEM.
    pub cert_pem: String,
    /// The name on the hub's certificate.
    pub server_name: String,
    /// The patient's pseudonym as the clinic knows it, if the hub says it.
    pub patient_pseudonym: Option<String>,
}

/// The hub's pairing policy: which codes are live, how many guesses they allow, and how a
/// station's certificate is issued.
pub trait PairingAuthority: Send + Sync + 'static {
    /// The live code named `code_id`, or why not (unknown, expired, used, too many attempts
    /// from `peer`).
    fn begin<'a>(
        &'a self,
        code_id: &'a str,
        peer: SocketAddr,
    ) -> BoxFuture<'a, Result<Ticket, Refusal>>;

    /// The station proved a wrong secret for `code_id` (counts toward the code's limit).
    fn failed<'a>(&'a self, code_id: &'a str, peer: SocketAddr) -> BoxFuture<'a, ()>;

    /// Uses up the code (single use, atomically) and issues a certificate for the request.
    fn complete<'a>(
        &'a self,
        code_id: &'a str,
        csr_pem: &'a str,
    ) -> BoxFuture<'a, Result<Issued, Refusal>>;
}

/// The Paired frame's MAC parts, in order.
pub(crate) fn paired_parts(p: &crate::frame::Paired) -> [&[u8]; 5] {
    [
        p.station_id.as_bytes(),
        p.patient_id.as_bytes(),
        p.ca_pem.as_bytes(),
        p.cert_pem.as_bytes(),
        p.server_name.as_bytes(),
    ]
}

/// Hex of `bytes`, lowercase.
pub(crate) fn to_hex(bytes: &[u8]) -> String {
    use std::fmt::Write;
    bytes
        .iter()
        .fold(String::with_capacity(2 * bytes.len()), |mut s, b| {
            let _ = write!(s, "{b:02x}");
            s
        })
}

/// Bytes of a hex string (the codec has checked the digits and length).
pub(crate) fn from_hex(hex: &str) -> Option<Vec<u8>> {
    (0..hex.len())
        .step_by(2)
        .map(|i| {
            hex.get(i..i + 2)
                .and_then(|d| u8::from_str_radix(d, 16).ok())
        })
        .collect()
}
