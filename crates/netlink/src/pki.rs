//! The clinic's own small certificate authority (rcgen): the CA, the hub's certificate and
//! the stations' certificates, signed from their requests at pairing.

use rcgen::{
    BasicConstraints, CertificateParams, CertificateSigningRequestParams, DistinguishedName,
    DnType, ExtendedKeyUsagePurpose, IsCa, Issuer, KeyPair, KeyUsagePurpose, SanType,
};

/// A certificate and its private key, PEM.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CertAndKey {
    /// The certificate, PEM.
    pub cert_pem: String,
    /// The private key, PKCS#8 PEM.
    pub key_pem: String,
}

/// The clinic's CA: signs the hub's certificate and every paired station's.
pub struct ClinicCa {
    pem: CertAndKey,
    issuer: Issuer<'static, KeyPair>,
    /// Where "now" comes from for the validity of what it signs (the real clock unless a
    /// test injects a mock: [`ClinicCa::with_clock`]).
    clock: clock::Clock,
}

impl std::fmt::Debug for ClinicCa {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ClinicCa").finish_non_exhaustive()
    }
}

/// What went wrong making, signing or reading a certificate; the message names the step.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PkiError {
    /// A step of rcgen failed: generating a key, signing, or reading a key, the CA or a
    /// station's certificate request.
    #[error("{step}: {source}")]
    Certificate {
        /// The step, e.g. `signing the station certificate`.
        step: &'static str,
        /// rcgen's reason.
        source: rcgen::Error,
    },
    /// A PEM text with no certificate in it.
    #[error("no CERTIFICATE in the PEM text")]
    NoCertificate,
    /// A certificate's PEM that does not decode.
    #[error("certificate PEM: {0}")]
    Pem(rustls::pki_types::pem::Error),
}

fn err(step: &'static str) -> impl Fn(rcgen::Error) -> PkiError {
    move |source| PkiError::Certificate { step, source }
}

/// Days a station's certificate is valid (revocation is immediate at the hub regardless).
pub const STATION_CERT_DAYS: i64 = 5 * 365;

/// Valid from a day ago (clocks differ) for `days` days.
fn valid_for_days(params: &mut CertificateParams, days: i64, clock: &clock::Clock) {
    let now = time::OffsetDateTime::from_unix_timestamp_nanos(i128::from(clock.unix_ns()))
        .unwrap_or(time::OffsetDateTime::UNIX_EPOCH);
    params.not_before = now - time::Duration::days(1);
    params.not_after = now + time::Duration::days(days);
}

impl ClinicCa {
    /// A new CA named `name` (e.g. the clinic), ECDSA P-256, valid 20 years from now.
    pub fn create(name: &str) -> Result<Self, PkiError> {
        Self::create_with_clock(name, clock::Clock::real())
    }

    /// [`ClinicCa::create`] with "now" read from `clock` (for this CA and all it signs).
    pub fn create_with_clock(name: &str, clock: clock::Clock) -> Result<Self, PkiError> {
        let key = KeyPair::generate().map_err(err("generating the CA key"))?;
        let mut params = CertificateParams::new(Vec::<String>::new()).map_err(err("CA"))?;
        params.is_ca = IsCa::Ca(BasicConstraints::Constrained(0));
        params.key_usages = vec![KeyUsagePurpose::KeyCertSign, KeyUsagePurpose::CrlSign];
        let mut dn = DistinguishedName::new();
        dn.push(DnType::CommonName, format!("{name} telerehab CA"));
        params.distinguished_name = dn;
        valid_for_days(&mut params, 20 * 365, &clock);
        let cert = params.self_signed(&key).map_err(err("signing the CA"))?;
        let pem = CertAndKey {
            cert_pem: cert.pem(),
            key_pem: key.serialize_pem(),
        };
        Ok(Self {
            issuer: Issuer::new(params, key),
            pem,
            clock,
        })
    }

    /// The CA from its PEM certificate and key (as [`Self::pem`] gave them).
    pub fn load(pem: CertAndKey) -> Result<Self, PkiError> {
        let key = KeyPair::from_pem(&pem.key_pem).map_err(err("reading the CA key"))?;
        let issuer = Issuer::from_ca_cert_pem(&pem.cert_pem, key).map_err(err("reading the CA"))?;
        Ok(Self {
            pem,
            issuer,
            clock: clock::Clock::real(),
        })
    }

    /// The same CA signing with "now" read from `clock`.
    pub fn with_clock(mut self, clock: clock::Clock) -> Self {
        self.clock = clock;
        self
    }

    /// The CA's certificate and key, PEM (store the key 0600).
    pub fn pem(&self) -> &CertAndKey {
        &self.pem
    }

    /// A server certificate for the hub, naming `names` (DNS names or IP literals).
    pub fn issue_server(&self, names: &[String]) -> Result<CertAndKey, PkiError> {
        let key = KeyPair::generate().map_err(err("generating the hub key"))?;
        let mut params = CertificateParams::new(names.to_vec()).map_err(err("hub names"))?;
        params.extended_key_usages = vec![ExtendedKeyUsagePurpose::ServerAuth];
        valid_for_days(&mut params, 2 * 365, &self.clock);
        let cert = params
            .signed_by(&key, &self.issuer)
            .map_err(err("signing the hub certificate"))?;
        Ok(CertAndKey {
            cert_pem: cert.pem(),
            key_pem: key.serialize_pem(),
        })
    }

    /// Signs a station's request: whatever names it asked for, the certificate names exactly
    /// `station_id` (DNS subjectAltName) and serves only client authentication.
    pub fn sign_station(&self, csr_pem: &str, station_id: &str) -> Result<String, PkiError> {
        let mut csr = CertificateSigningRequestParams::from_pem(csr_pem)
            .map_err(err("the station's certificate request"))?;
        let name = station_id
            .to_owned()
            .try_into()
            .map_err(err("station id as a DNS name"))?;
        let mut params = CertificateParams::default();
        params.subject_alt_names = vec![SanType::DnsName(name)];
        params.extended_key_usages = vec![ExtendedKeyUsagePurpose::ClientAuth];
        let mut dn = DistinguishedName::new();
        dn.push(DnType::CommonName, station_id);
        params.distinguished_name = dn;
        valid_for_days(&mut params, STATION_CERT_DAYS, &self.clock);
        csr.params = params;
        let cert = csr
            .signed_by(&self.issuer)
            .map_err(err("signing the station certificate"))?;
        Ok(cert.pem())
    }
}

/// SHA-256 of a certificate's DER, lowercase hex: how the hub names a station's credential.
pub fn certificate_sha256_hex(der: &[u8]) -> String {
    crate::pairing::to_hex(ring::digest::digest(&ring::digest::SHA256, der).as_ref())
}

/// The DER of the first certificate in a PEM text.
pub fn first_certificate_der(pem: &str) -> Result<Vec<u8>, PkiError> {
    use rustls::pki_types::CertificateDer;
    use rustls::pki_types::pem::PemObject;
    CertificateDer::pem_slice_iter(pem.as_bytes())
        .next()
        .ok_or(PkiError::NoCertificate)?
        .map(|c| c.to_vec())
        .map_err(PkiError::Pem)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The validity window of a PEM certificate, Unix seconds.
    fn validity_unix_s(pem: &str) -> (i64, i64) {
        let der = first_certificate_der(pem).unwrap();
        let (_, cert) = x509_parser::parse_x509_certificate(&der).unwrap();
        let v = cert.validity();
        (v.not_before.timestamp(), v.not_after.timestamp())
    }

    #[test]
    fn certificates_are_valid_from_the_injected_clocks_day_before() {
        let (clock, mock) = clock::Clock::mock();
        mock.advance_ns(3_600 * 1_000_000_000);
        let ca = ClinicCa::create_with_clock("Clinic", clock.clone()).unwrap();
        let unix_s = i64::try_from(clock.unix_ns() / 1_000_000_000).unwrap();
        let day = 86_400;
        assert_eq!(
            validity_unix_s(&ca.pem().cert_pem),
            (unix_s - day, unix_s + 20 * 365 * day),
            "from a day before the mock's now"
        );
        let server = ca.issue_server(&["hub.example".into()]).unwrap();
        assert_eq!(
            validity_unix_s(&server.cert_pem),
            (unix_s - day, unix_s + 2 * 365 * day)
        );
    }

    #[test]
    fn a_bad_certificate_request_or_pem_is_refused_naming_what_is_wrong() {
        let ca = ClinicCa::create("Test clinic").unwrap();
        match ca.sign_station("not a request", "st-1") {
            Err(e @ PkiError::Certificate { step, .. }) => {
                assert_eq!(step, "the station's certificate request");
                assert!(
                    e.to_string()
                        .starts_with("the station's certificate request: "),
                    "{e}"
                );
            }
            other => panic!("{other:?}"),
        }
        assert!(matches!(
            first_certificate_der("no pem here"),
            Err(PkiError::NoCertificate)
        ));
        let garbled = "-----BEGIN CERTIFICATE-----\n!!!\n-----END CERTIFICATE-----\n";
        let e = first_certificate_der(garbled).unwrap_err();
        assert!(matches!(e, PkiError::Pem(_)), "{e:?}");
        let cert = ca.issue_server(&["localhost".to_owned()]).unwrap();
        assert!(!first_certificate_der(&cert.cert_pem).unwrap().is_empty());
    }
}
