//! TLS configuration from PEM files (rustls with the `ring` provider).
//!
//! Security choice: TLS 1.2/1.3 with rustls' safe defaults, the server authenticated by a
//! certificate chaining to a CA the station is given explicitly (no system roots: a clinic
//! runs its own small CA). Plaintext is allowed only when no TLS configuration is given *and*
//! the address is loopback (see [`crate::station::StationLinkConfig::validate`] and
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
}

/// Hub-side TLS: its certificate chain and private key.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ServerTls {
    /// PEM file with the hub's certificate chain, leaf first.
    pub cert_pem_path: PathBuf,
    /// PEM file with the hub's private key (PKCS#8, PKCS#1 or SEC1).
    pub key_pem_path: PathBuf,
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

impl ClientTls {
    /// Builds the connector, reading the CA file now so errors surface at start-up.
    pub fn connector(
        &self,
    ) -> Result<(tokio_rustls::TlsConnector, ServerName<'static>), NetlinkError> {
        let what = "CA certificates";
        let mut roots = rustls::RootCertStore::empty();
        for cert in load_certs(what, &self.ca_pem_path)? {
            roots
                .add(cert)
                .map_err(|e| pem_error(what, &self.ca_pem_path, e))?;
        }
        let config = rustls::ClientConfig::builder_with_provider(provider())
            .with_safe_default_protocol_versions()?
            .with_root_certificates(roots)
            .with_no_client_auth();
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
        let chain = load_certs("certificate chain", &self.cert_pem_path)?;
        let key = PrivateKeyDer::from_pem_file(&self.key_pem_path)
            .map_err(|e| pem_error("private key", &self.key_pem_path, e))?;
        let config = rustls::ServerConfig::builder_with_provider(provider())
            .with_safe_default_protocol_versions()?
            .with_no_client_auth()
            .with_single_cert(chain, key)?;
        Ok(tokio_rustls::TlsAcceptor::from(Arc::new(config)))
    }
}
