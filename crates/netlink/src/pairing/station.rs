//! The station's side of pairing: [`pair`] turns a code into a [`Credential`].

use std::sync::{Arc, Mutex};
use std::time::Duration;

use rustls::client::danger::{HandshakeSignatureValid, ServerCertVerified, ServerCertVerifier};
use rustls::crypto::CryptoProvider;
use rustls::pki_types::{CertificateDer, ServerName, UnixTime};
use rustls::{DigitallySignedStruct, SignatureScheme};
use tokio::io::AsyncWriteExt;
use tokio::net::TcpStream;

use super::crypto::StationExchange;
use super::{MacLabel, PairingCode, from_hex, mac_hex, paired_parts, to_hex, verify_mac};
use crate::codec::encode_to_vec;
use crate::frame::{Frame, PairFinish, PairStart, Paired};
use crate::transport::{BoxStream, FrameReader};

/// What a paired station keeps (the key never left it).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Credential {
    /// The station's identity at the hub.
    pub station_id: String,
    /// The patient it speaks for.
    pub patient_id: String,
    /// The clinic's CA, PEM: the only root trusted for this hub.
    pub ca_pem: String,
    /// The station's certificate, PEM.
    pub cert_pem: String,
    /// The station's private key, PKCS#8 PEM (store it 0600).
    pub key_pem: String,
    /// The name to check on the hub's certificate.
    pub server_name: String,
    /// The patient's pseudonym as the clinic knows it (`None` from hubs that do not say it).
    pub patient_pseudonym: Option<String>,
}

/// Why pairing failed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PairError {
    /// The code is not well formed (the message says how).
    #[error("{0}")]
    BadCode(String),
    /// The hub could not be reached or the connection broke.
    #[error("cannot reach the hub at {addr}: {reason}")]
    Unreachable {
        /// The address asked for.
        addr: String,
        /// Why.
        reason: String,
    },
    /// The hub refused (its message says why: unknown, expired or used code, too many tries).
    #[error("the hub refused pairing: {0}")]
    Refused(String),
    /// The hub's answer did not prove the code, or its certificate is not the one it vouched
    /// for: someone may be in the middle. Nothing was stored.
    #[error(
        "the hub's answer is not authentic ({0}); nothing was stored — check the address and the code"
    )]
    NotAuthentic(String),
    /// This station could not make its key or certificate request (nothing was sent).
    #[error("cannot make this station's key and certificate request: {0}")]
    Key(#[from] rcgen::Error),
}

/// Accepts any certificate during the handshake (the station has no CA yet) but checks the
/// server holds its key, and remembers the certificate so pairing can bind to it.
#[derive(Debug)]
struct RememberCertificate {
    provider: Arc<CryptoProvider>,
    seen: Mutex<Option<CertificateDer<'static>>>,
}

impl ServerCertVerifier for RememberCertificate {
    fn verify_server_cert(
        &self,
        end_entity: &CertificateDer<'_>,
        _intermediates: &[CertificateDer<'_>],
        _server_name: &ServerName<'_>,
        _ocsp: &[u8],
        _now: UnixTime,
    ) -> Result<ServerCertVerified, rustls::Error> {
        *self
            .seen
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner) =
            Some(end_entity.clone().into_owned());
        Ok(ServerCertVerified::assertion())
    }

    fn verify_tls12_signature(
        &self,
        message: &[u8],
        cert: &CertificateDer<'_>,
        dss: &DigitallySignedStruct,
    ) -> Result<HandshakeSignatureValid, rustls::Error> {
        rustls::crypto::verify_tls12_signature(
            message,
            cert,
            dss,
            &self.provider.signature_verification_algorithms,
        )
    }

    fn verify_tls13_signature(
        &self,
        message: &[u8],
        cert: &CertificateDer<'_>,
        dss: &DigitallySignedStruct,
    ) -> Result<HandshakeSignatureValid, rustls::Error> {
        rustls::crypto::verify_tls13_signature(
            message,
            cert,
            dss,
            &self.provider.signature_verification_algorithms,
        )
    }

    fn supported_verify_schemes(&self) -> Vec<SignatureScheme> {
        self.provider
            .signature_verification_algorithms
            .supported_schemes()
    }
}

/// The host part of `host:port` (brackets of an IPv6 literal removed).
fn host_of(addr: &str) -> &str {
    let host = addr.rsplit_once(':').map_or(addr, |(h, _)| h);
    host.trim_start_matches('[').trim_end_matches(']')
}

/// Pairs with the hub at `addr` (`host:port`) using `code`, within `timeout`. On success the
/// caller stores the credential; nothing is stored by this function.
pub async fn pair(addr: &str, code: &str, timeout: Duration) -> Result<Credential, PairError> {
    let code = PairingCode::parse(code).map_err(|e| PairError::BadCode(e.to_string()))?;
    match tokio::time::timeout(timeout, pair_inner(addr, &code)).await {
        Ok(r) => r,
        Err(_) => Err(PairError::Unreachable {
            addr: addr.to_owned(),
            reason: format!("no answer within {} s", timeout.as_secs_f64()),
        }),
    }
}

async fn pair_inner(addr: &str, code: &PairingCode) -> Result<Credential, PairError> {
    let unreachable = |reason: String| PairError::Unreachable {
        addr: addr.to_owned(),
        reason,
    };
    let provider = Arc::new(rustls::crypto::ring::default_provider());
    let verifier = Arc::new(RememberCertificate {
        provider: provider.clone(),
        seen: Mutex::new(None),
    });
    let config = rustls::ClientConfig::builder_with_provider(provider.clone())
        .with_safe_default_protocol_versions()
        .map_err(|e| unreachable(e.to_string()))?
        .dangerous()
        .with_custom_certificate_verifier(verifier.clone())
        .with_no_client_auth();
    let sni = ServerName::try_from(host_of(addr).to_owned())
        .map_err(|e| unreachable(format!("{:?} is not a host name: {e}", host_of(addr))))?;
    let tcp = TcpStream::connect(addr)
        .await
        .map_err(|e| unreachable(e.to_string()))?;
    let tls = tokio_rustls::TlsConnector::from(Arc::new(config))
        .connect(sni, tcp)
        .await
        .map_err(|e| unreachable(format!("TLS handshake: {e}")))?;
    let seen = verifier
        .seen
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
        .clone()
        .ok_or_else(|| unreachable("the hub presented no certificate".into()))?;
    let (rd, mut wr) = tokio::io::split(Box::new(tls) as BoxStream);
    let mut reader = FrameReader::new(rd);
    let mut send = async |frame: Frame| -> Result<(), PairError> {
        let bytes = encode_to_vec(&frame).map_err(|e| unreachable(e.to_string()))?;
        wr.write_all(&bytes)
            .await
            .map_err(|e| unreachable(e.to_string()))
    };

    let (exchange, station_msg) = StationExchange::start(code);
    send(Frame::PairStart(PairStart {
        code_id: code.code_id().to_owned(),
        pake: to_hex(&station_msg),
    }))
    .await?;
    let hub_msg = match next(&mut reader, addr).await? {
        Frame::PairChallenge(c) => from_hex(&c.pake).unwrap_or_default(),
        other => return Err(unexpected(other)),
    };
    let key = exchange
        .finish(&hub_msg)
        .map_err(|e| PairError::NotAuthentic(e.to_string()))?;

    let (csr_pem, key_pem) = certificate_request()?;
    let seen_sha256 = ring::digest::digest(&ring::digest::SHA256, &seen);
    let transcript: [&[u8]; 4] = [
        &station_msg,
        &hub_msg,
        csr_pem.as_bytes(),
        seen_sha256.as_ref(),
    ];
    let mac = mac_hex(&key, MacLabel::StationFinish, &transcript);
    send(Frame::PairFinish(PairFinish {
        csr_pem: csr_pem.clone(),
        mac,
    }))
    .await?;
    let paired = match next(&mut reader, addr).await? {
        Frame::Paired(p) => p,
        other => return Err(unexpected(other)),
    };
    let mut parts: Vec<&[u8]> = vec![&station_msg, &hub_msg];
    parts.extend(paired_parts(&paired));
    if !verify_mac(&key, MacLabel::HubPaired, &parts, &paired.mac) {
        return Err(PairError::NotAuthentic(
            "the credential's MAC is wrong".into(),
        ));
    }
    check_seen_certificate(&paired, &seen, &provider)?;
    let _ = wr.shutdown().await;
    Ok(Credential {
        station_id: paired.station_id,
        patient_id: paired.patient_id,
        ca_pem: paired.ca_pem,
        cert_pem: paired.cert_pem,
        key_pem,
        server_name: paired.server_name,
        patient_pseudonym: paired.patient_pseudonym,
    })
}

/// The next frame; an `Error` frame is the hub's refusal.
async fn next(reader: &mut FrameReader, addr: &str) -> Result<Frame, PairError> {
    match reader.next_frame().await {
        Ok(Some(Frame::Error(e))) => Err(PairError::Refused(e.message)),
        Ok(Some(frame)) => Ok(frame),
        Ok(None) => Err(PairError::Unreachable {
            addr: addr.to_owned(),
            reason: "the hub closed the connection".into(),
        }),
        Err(e) => Err(PairError::Unreachable {
            addr: addr.to_owned(),
            reason: e.to_string(),
        }),
    }
}

fn unexpected(frame: Frame) -> PairError {
    PairError::NotAuthentic(format!("unexpected {} frame during pairing", frame.kind()))
}

/// A new key pair (ECDSA P-256) and a certificate request for it: (CSR PEM, key PEM).
fn certificate_request() -> Result<(String, String), rcgen::Error> {
    let key = rcgen::KeyPair::generate()?;
    let csr = rcgen::CertificateParams::new(Vec::<String>::new())
        .and_then(|p| p.serialize_request(&key))
        .and_then(|csr| csr.pem())?;
    Ok((csr, key.serialize_pem()))
}

/// The certificate the hub presented must chain to the CA it sent, for the name it gave.
fn check_seen_certificate(
    paired: &Paired,
    seen: &CertificateDer<'static>,
    provider: &Arc<CryptoProvider>,
) -> Result<(), PairError> {
    let bad = |why: String| PairError::NotAuthentic(why);
    let mut roots = rustls::RootCertStore::empty();
    for cert in rustls::pki_types::pem::PemObject::pem_slice_iter(paired.ca_pem.as_bytes()) {
        let cert: CertificateDer<'static> = cert.map_err(|e| bad(format!("CA PEM: {e}")))?;
        roots
            .add(cert)
            .map_err(|e| bad(format!("CA certificate: {e}")))?;
    }
    let verifier = rustls::client::WebPkiServerVerifier::builder_with_provider(
        Arc::new(roots),
        provider.clone(),
    )
    .build()
    .map_err(|e| bad(format!("CA: {e}")))?;
    let name = ServerName::try_from(paired.server_name.clone())
        .map_err(|e| bad(format!("server name {:?}: {e}", paired.server_name)))?;
    verifier
        .verify_server_cert(seen, &[], &name, &[], UnixTime::now())
        .map(drop)
        .map_err(|e| {
            bad(format!(
                "the hub's certificate does not chain to its CA: {e}"
            ))
        })
}
