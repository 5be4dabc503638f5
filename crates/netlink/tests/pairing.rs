//! Pairing end to end on loopback: a code becomes a credential the station then uses for
//! mutual TLS; wrong, used and unknown codes are refused with a reason.

use std::net::SocketAddr;
use std::path::Path;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use netlink::pairing::{Issued, PairError, PairingAuthority, PairingCode, Ticket, pair};
use netlink::pki::ClinicCa;
use netlink::{
    BoxFuture, ClientTls, FileStore, Hello, HubStore, Identity, PROTOCOL_VERSION, Refusal,
    ServerTls, SessionStore, StationLink, StationLinkConfig, Summary, TherapistConfig,
    TherapistServer,
};

const GUARD: Duration = Duration::from_secs(20);

/// One live code, in memory; the hub crate keeps codes in its database.
struct OneCode {
    ca: ClinicCa,
    code: PairingCode,
    used: Mutex<bool>,
    failures: Mutex<u32>,
}

impl PairingAuthority for OneCode {
    fn begin<'a>(
        &'a self,
        code_id: &'a str,
        _peer: SocketAddr,
    ) -> BoxFuture<'a, Result<Ticket, Refusal>> {
        Box::pin(async move {
            if code_id != self.code.code_id() || *self.used.lock().unwrap() {
                return Err(Refusal::new(format!(
                    "pairing code {code_id}-… is unknown or used"
                )));
            }
            Ok(Ticket {
                secret: self.code.secret().to_owned(),
                patient_id: "p-0042".into(),
            })
        })
    }

    fn failed<'a>(&'a self, _code_id: &'a str, _peer: SocketAddr) -> BoxFuture<'a, ()> {
        Box::pin(async move { *self.failures.lock().unwrap() += 1 })
    }

    fn complete<'a>(
        &'a self,
        _code_id: &'a str,
        csr_pem: &'a str,
    ) -> BoxFuture<'a, Result<Issued, Refusal>> {
        Box::pin(async move {
            *self.used.lock().unwrap() = true;
            let cert_pem = self
                .ca
                .sign_station(csr_pem, "st-paired")
                .map_err(|e| Refusal::new(e.to_string()))?;
            Ok(Issued {
                station_id: "st-paired".into(),
                patient_id: "p-0042".into(),
                ca_pem: self.ca.pem().cert_pem.clone(),
                cert_pem,
                server_name: "localhost".into(),
                patient_pseudonym: Some("P-0042".into()),
            })
        })
    }
}

struct PairingFiles {
    files: FileStore,
    authority: Arc<OneCode>,
}

impl HubStore for PairingFiles {
    fn open_session<'a>(
        &'a self,
        hello: &'a Hello,
    ) -> BoxFuture<'a, Result<Box<dyn SessionStore>, Refusal>> {
        self.files.open_session(hello)
    }

    fn pairing(&self) -> Option<Arc<dyn PairingAuthority>> {
        Some(self.authority.clone())
    }
}

fn write(dir: &Path, name: &str, text: &str) -> std::path::PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

async fn start_pairing_hub(dir: &Path, code: &PairingCode) -> (TherapistServer, Arc<OneCode>) {
    let ca = ClinicCa::create("Test clinic").unwrap();
    let hub_cert = ca.issue_server(&["localhost".to_owned()]).unwrap();
    let tls = ServerTls {
        cert_pem_path: write(dir, "hub.crt", &hub_cert.cert_pem),
        key_pem_path: write(dir, "hub.key", &hub_cert.key_pem),
        client_ca_pem_path: Some(write(dir, "ca.crt", &ca.pem().cert_pem)),
    };
    let authority = Arc::new(OneCode {
        ca,
        code: code.clone(),
        used: Mutex::new(false),
        failures: Mutex::new(0),
    });
    let store = Arc::new(PairingFiles {
        files: FileStore::new(dir.join("store")),
        authority: authority.clone(),
    });
    let config = TherapistConfig::new("127.0.0.1:0".parse().unwrap(), dir.join("store"), Some(tls));
    let (hub, _events) = TherapistServer::bind_with_store(config, store)
        .await
        .unwrap();
    (hub, authority)
}

fn summary(seq: u64) -> Summary {
    Summary::example("s1", seq)
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_paired_station_speaks_over_mutual_tls_with_the_credential_it_received() {
    let dir = tempfile::tempdir().unwrap();
    let code = PairingCode::generate().unwrap();
    let (hub, authority) = start_pairing_hub(dir.path(), &code).await;
    let addr = format!("localhost:{}", hub.local_addr().port());

    let cred = pair(&addr, &code.to_string().to_lowercase(), GUARD)
        .await
        .unwrap();
    assert_eq!(
        (cred.station_id.as_str(), cred.patient_id.as_str()),
        ("st-paired", "p-0042")
    );
    assert_eq!(
        cred.patient_pseudonym.as_deref(),
        Some("P-0042"),
        "the clinic's pseudonym reaches the station"
    );
    assert_eq!(*authority.failures.lock().unwrap(), 0);

    let home = tempfile::tempdir().unwrap();
    let tls = ClientTls {
        ca_pem_path: write(home.path(), "ca.crt", &cred.ca_pem),
        server_name: cred.server_name.clone(),
        identity: Some(Identity {
            cert_pem_path: write(home.path(), "station.crt", &cred.cert_pem),
            key_pem_path: write(home.path(), "station.key", &cred.key_pem),
        }),
    };
    let hello = Hello {
        protocol_version: PROTOCOL_VERSION,
        station_id: cred.station_id.clone(),
        patient_id: cred.patient_id.clone(),
        session_id: "s1".into(),
        exercise: "sine-road".into(),
        started_unix_ms: 1_795_253_400_000,
        software_version: "telerehab-test".into(),
        min_protocol_version: None,
        wheel: None,
    };
    let config = StationLinkConfig::new(addr.as_str(), Some(tls), hello);
    let handle = tokio::runtime::Handle::current();
    let (sender, link) = StationLink::spawn(&handle, config).unwrap();
    for seq in 0..5 {
        sender.send(summary(seq)).unwrap();
    }
    let stats = link.finish(GUARD).await;
    assert_eq!((stats.acked, stats.pending), (5, 0), "{stats:?}");
    assert!(dir.path().join("store/st-paired/s1.jsonl").exists());

    // Single use: the same code again is refused with the authority's reason.
    match pair(&addr, &code.to_string(), GUARD).await {
        Err(PairError::Refused(why)) => assert!(why.contains("unknown or used"), "{why}"),
        other => panic!("expected a refusal, got {other:?}"),
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_wrong_secret_is_refused_counted_and_stores_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let code = PairingCode::parse("7KQ2-M9XD").unwrap();
    let (hub, authority) = start_pairing_hub(dir.path(), &code).await;
    let addr = format!("localhost:{}", hub.local_addr().port());
    match pair(&addr, "7KQ2-M9XE", GUARD).await {
        Err(PairError::Refused(why)) => assert_eq!(why, netlink::pairing::CODE_NOT_ACCEPTED),
        other => panic!("expected a refusal, got {other:?}"),
    }
    assert_eq!(*authority.failures.lock().unwrap(), 1);
    assert!(
        !*authority.used.lock().unwrap(),
        "a failed guess does not use the code"
    );
    match pair(&addr, "ZZZZ-M9XD", GUARD).await {
        Err(PairError::Refused(why)) => assert!(why.contains("unknown"), "{why}"),
        other => panic!("expected a refusal, got {other:?}"),
    }
    match pair(&addr, "7KQ2-M9X", GUARD).await {
        Err(PairError::BadCode(why)) => assert!(why.contains("8 letters"), "{why}"),
        other => panic!("expected a bad code, got {other:?}"),
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_plain_summary_store_does_not_pair() {
    let dir = tempfile::tempdir().unwrap();
    let ca = ClinicCa::create("Test clinic").unwrap();
    let hub_cert = ca.issue_server(&["localhost".to_owned()]).unwrap();
    let tls = ServerTls {
        cert_pem_path: write(dir.path(), "hub.crt", &hub_cert.cert_pem),
        key_pem_path: write(dir.path(), "hub.key", &hub_cert.key_pem),
        client_ca_pem_path: None,
    };
    let config = TherapistConfig::new(
        "127.0.0.1:0".parse().unwrap(),
        dir.path().join("s"),
        Some(tls),
    );
    let (hub, _events) = TherapistServer::bind(config).await.unwrap();
    let addr = format!("localhost:{}", hub.local_addr().port());
    match pair(&addr, "7KQ2-M9XD", GUARD).await {
        Err(PairError::Refused(why)) => assert!(why.contains("does not pair"), "{why}"),
        other => panic!("expected a refusal, got {other:?}"),
    }
}
