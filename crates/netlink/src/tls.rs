//! TLS configuration from PEM files (rustls with the `ring` provider).
//!
//! Security choice: TLS 1.2/1.3 with rustls' safe defaults, the server authenticated by a
//! certificate chaining to a CA the station is given explicitly (no system roots: a clinic
//! runs its own small CA). Stations can be authenticated too (mutual TLS): the hub then
//! requires a client certificate chaining to `ServerTls::client_ca_pem_path`. Plaintext is
//! allowed only when no TLS configuration is given *and* the address is loopback (see
//! [`crate::station::StationLinkConfig::validate`] and
//! [`crate::therapist::TherapistConfig::validate`]).

use std::path::{Path, PathBuf};
use std::sync::Arc;

use rustls::pki_types::pem::PemObject;
use rustls::pki_types::{CertificateDer, PrivateKeyDer, ServerName};
use serde::{Deserialize, Serialize};

use crate::error::NetlinkError;

/// Station-side TLS: whom to trust and which name to expect.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ClientTls {
    /// PEM file with the CA certificate(s) that signed the hub's certificate.
    pub ca_pem_path: PathBuf,
    /// DNS name (or IP literal) the hub's certificate must carry.
    pub server_name: String,
    /// The station's own certificate and key, for hubs that require client authentication.
    #[serde(default)]
    pub identity: Option<Identity>,
}

/// A certificate chain and its private key, as PEM files.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Identity {
    /// PEM file with the certificate chain, leaf first.
    pub cert_pem_path: PathBuf,
    /// PEM file with the private key (PKCS#8, PKCS#1 or SEC1).
    pub key_pem_path: PathBuf,
}

/// Hub-side TLS: its certificate chain and private key.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ServerTls {
    /// PEM file with the hub's certificate chain, leaf first.
    pub cert_pem_path: PathBuf,
    /// PEM file with the hub's private key (PKCS#8, PKCS#1 or SEC1).
    pub key_pem_path: PathBuf,
    /// If set, stations must present a certificate chaining to a CA in this PEM file (mutual
    /// TLS), and that certificate must carry the station's `station_id` as a DNS
    /// subjectAltName (see [`certificate_names_station`]); other connections are refused.
    #[serde(default)]
    pub client_ca_pem_path: Option<PathBuf>,
}

fn provider() -> Arc<rustls::crypto::CryptoProvider> {
    Arc::new(rustls::crypto::ring::default_provider())
}

fn pem_error(what: &'static str, path: &Path, reason: impl ToString) -> NetlinkError {
    NetlinkError::Pem {
        what,
        path: path.to_owned(),
        reason: reason.to_string(),
    }
}

fn load_certs(
    what: &'static str,
    path: &Path,
) -> Result<Vec<CertificateDer<'static>>, NetlinkError> {
    let certs = CertificateDer::pem_file_iter(path)
        .map_err(|e| pem_error(what, path, e))?
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| pem_error(what, path, e))?;
    if certs.is_empty() {
        return Err(pem_error(what, path, "no CERTIFICATE section found"));
    }
    Ok(certs)
}

fn load_roots(what: &'static str, path: &Path) -> Result<rustls::RootCertStore, NetlinkError> {
    let mut roots = rustls::RootCertStore::empty();
    for cert in load_certs(what, path)? {
        roots.add(cert).map_err(|e| pem_error(what, path, e))?;
    }
    Ok(roots)
}

type ChainAndKey = (Vec<CertificateDer<'static>>, PrivateKeyDer<'static>);

fn load_chain_and_key(
    cert_pem_path: &Path,
    key_pem_path: &Path,
) -> Result<ChainAndKey, NetlinkError> {
    let chain = load_certs("certificate chain", cert_pem_path)?;
    let key = PrivateKeyDer::from_pem_file(key_pem_path)
        .map_err(|e| pem_error("private key", key_pem_path, e))?;
    Ok((chain, key))
}

impl ClientTls {
    /// Builds the connector, reading the CA file now so errors surface at start-up.
    pub fn connector(
        &self,
    ) -> Result<(tokio_rustls::TlsConnector, ServerName<'static>), NetlinkError> {
        let roots = load_roots("CA certificates", &self.ca_pem_path)?;
        let builder = rustls::ClientConfig::builder_with_provider(provider())
            .with_safe_default_protocol_versions()?
            .with_root_certificates(roots);
        let config = match &self.identity {
            None => builder.with_no_client_auth(),
            Some(identity) => {
                let (chain, key) =
                    load_chain_and_key(&identity.cert_pem_path, &identity.key_pem_path)?;
                builder.with_client_auth_cert(chain, key)?
            }
        };
        let name = ServerName::try_from(self.server_name.clone()).map_err(|e| {
            NetlinkError::Config(format!(
                "tls.server_name {:?} is not a DNS name or IP address: {e}",
                self.server_name
            ))
        })?;
        Ok((tokio_rustls::TlsConnector::from(Arc::new(config)), name))
    }
}

impl ServerTls {
    /// Builds the acceptor, reading both files now so errors surface at start-up.
    pub fn acceptor(&self) -> Result<tokio_rustls::TlsAcceptor, NetlinkError> {
        let (chain, key) = load_chain_and_key(&self.cert_pem_path, &self.key_pem_path)?;
        let builder = rustls::ServerConfig::builder_with_provider(provider())
            .with_safe_default_protocol_versions()?;
        let builder = match &self.client_ca_pem_path {
            None => builder.with_no_client_auth(),
            Some(path) => {
                let roots = load_roots("client CA certificates", path)?;
                let verifier = rustls::server::WebPkiClientVerifier::builder_with_provider(
                    Arc::new(roots),
                    provider(),
                )
                // A station being paired has no certificate yet; every Hello still needs one
                // (checked by the hub before anything is stored).
                .allow_unauthenticated()
                .build()
                .map_err(|e| pem_error("client CA certificates", path, e))?;
                builder.with_client_cert_verifier(verifier)
            }
        };
        let config = builder.with_single_cert(chain, key)?;
        Ok(tokio_rustls::TlsAcceptor::from(Arc::new(config)))
    }
}

impl ServerTls {
    /// SHA-256 of the hub's own (leaf) certificate, DER: what pairing binds to.
    pub fn leaf_sha256(&self) -> Result<[u8; 32], NetlinkError> {
        let chain = load_certs("certificate chain", &self.cert_pem_path)?;
        let digest = ring::digest::digest(&ring::digest::SHA256, &chain[0]);
        let mut out = [0u8; 32];
        out.copy_from_slice(digest.as_ref());
        Ok(out)
    }
}

/// Why a client certificate cannot speak for the station it says it is.
#[derive(Debug, thiserror::Error)]
pub enum StationNameError {
    /// The station id cannot be a certificate's DNS name.
    #[error("station_id {0:?} is not a DNS name, so no certificate can name it")]
    NotADnsName(String),
    /// The certificate is not X.509 that webpki reads.
    #[error("client certificate cannot be parsed: {0}")]
    Unreadable(webpki::Error),
    /// The certificate names other stations.
    #[error("client certificate does not name station {0:?} (DNS subjectAltName)")]
    OtherStation(String),
}

/// Checks that a station's client certificate carries `station_id` as a DNS subjectAltName,
/// so a station holding a valid clinic certificate cannot speak for another station.
pub fn certificate_names_station(
    cert: &CertificateDer<'_>,
    station_id: &str,
) -> Result<(), StationNameError> {
    let name = ServerName::try_from(station_id)
        .map_err(|_| StationNameError::NotADnsName(station_id.to_owned()))?;
    let cert = webpki::EndEntityCert::try_from(cert).map_err(StationNameError::Unreadable)?;
    cert.verify_is_valid_for_subject_name(&name)
        .map_err(|_| StationNameError::OtherStation(station_id.to_owned()))
}
