//! End-to-end tests of the station link against the therapist hub on loopback.
//!
//! Every wait is a bounded loop or a timeout used as a liveness guard (a hung test fails
//! instead of hanging CI); no test asserts on speed.

use std::net::SocketAddr;
use std::path::Path;
use std::time::Duration;

use netlink::store::read_session;
use netlink::{
    Backoff, ClientTls, Frame, FrameDecoder, Hello, Identity, LinkStats, PROTOCOL_VERSION, Regimen,
    SendError, ServerTls, StationLink, StationLinkConfig, Summary, SummarySender, TherapistConfig,
    TherapistEvent, TherapistServer, encode_to_vec,
};
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::{TcpListener, TcpStream};
use tokio::sync::mpsc;

const GUARD: Duration = Duration::from_secs(30);

fn hello(station: &str, session: &str) -> Hello {
    Hello {
        protocol_version: PROTOCOL_VERSION,
        station_id: station.into(),
        patient_id: format!("patient-of-{station}"),
        session_id: session.into(),
        exercise: "sine-road".into(),
        started_unix_ms: 1_795_253_400_000,
        software_version: "telerehab-test".into(),
        min_protocol_version: None,
        wheel: None,
    }
}

fn summary(session: &str, seq: u64) -> Summary {
    Summary::example(session, seq)
}

fn fast_config(addr: SocketAddr, tls: Option<ClientTls>, hello: Hello) -> StationLinkConfig {
    let mut config = StationLinkConfig::new(addr, tls, hello);
    config.reconnect = Backoff {
        initial_ms: 20,
        max_ms: 200,
    };
    config.connect_timeout_ms = 2_000;
    config
}

async fn start_hub(
    store: &Path,
    tls: Option<ServerTls>,
) -> (TherapistServer, mpsc::Receiver<TherapistEvent>) {
    let listen: SocketAddr = "127.0.0.1:0".parse().unwrap();
    TherapistServer::bind(TherapistConfig::new(listen, store, tls))
        .await
        .unwrap()
}

/// Polls `cond` every 20 ms for at most [`GUARD`].
async fn wait_until(what: &str, mut cond: impl FnMut() -> bool) {
    let tries = GUARD.as_millis() / 20;
    for _ in 0..tries {
        if cond() {
            return;
        }
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
    panic!("timed out waiting for {what}");
}

async fn next_event(events: &mut mpsc::Receiver<TherapistEvent>) -> TherapistEvent {
    tokio::time::timeout(GUARD, events.recv())
        .await
        .expect("no hub event within the guard time")
        .expect("hub event channel closed")
}

fn stored_seqs(store: &Path, station: &str, session: &str) -> Vec<u64> {
    read_session(store, station, session)
        .unwrap()
        .iter()
        .map(|s| s.seq)
        .collect()
}

fn send_range(sender: &SummarySender, session: &str, seqs: std::ops::Range<u64>) {
    for seq in seqs {
        sender.send(summary(session, seq)).unwrap();
    }
}

fn assert_all_delivered(stats: &LinkStats, n: u64) {
    assert_eq!(stats.acked, n, "{stats:?}");
    assert_eq!(stats.pending, 0, "{stats:?}");
    assert_eq!(stats.dropped, 0, "{stats:?}");
    assert!(stats.bye_acknowledged, "{stats:?}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn plaintext_session_is_stored_once_and_reported_as_events() {
    let store = tempfile::tempdir().unwrap();
    let (hub, mut events) = start_hub(store.path(), None).await;
    let (sender, link) = StationLink::spawn(
        &tokio::runtime::Handle::current(),
        fast_config(hub.local_addr(), None, hello("st-a", "sess-1")),
    )
    .unwrap();
    send_range(&sender, "sess-1", 0..50);
    let stats = link.finish(GUARD).await;
    assert_all_delivered(&stats, 50);
    assert_eq!(stats.sent, 50);
    assert_eq!(stats.resent, 0);
    assert_eq!(
        stored_seqs(store.path(), "st-a", "sess-1"),
        (0..50).collect::<Vec<_>>()
    );
    let hello_back: Hello = serde_json::from_slice(
        &std::fs::read(store.path().join("st-a/sess-1.hello.json")).unwrap(),
    )
    .unwrap();
    // The link announces the range of versions it speaks.
    let mut expected = hello("st-a", "sess-1");
    expected.min_protocol_version = Some(netlink::frame::MIN_PROTOCOL_VERSION);
    assert_eq!(hello_back, expected);

    match next_event(&mut events).await {
        TherapistEvent::Connected { hello: h, .. } => assert_eq!(h.station_id, "st-a"),
        other => panic!("expected Connected, got {other:?}"),
    }
    for seq in 0..50 {
        match next_event(&mut events).await {
            TherapistEvent::Summary {
                station_id,
                summary,
                ..
            } => {
                assert_eq!((station_id.as_str(), summary.seq), ("st-a", seq));
            }
            other => panic!("expected Summary {seq}, got {other:?}"),
        }
    }
    match next_event(&mut events).await {
        TherapistEvent::Disconnected { reason, .. } => {
            assert_eq!(reason, "bye: session complete")
        }
        other => panic!("expected Disconnected, got {other:?}"),
    }
    hub.shutdown(GUARD).await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_sessions_measures_travel_in_its_bye_and_invalid_ones_are_kept_back() {
    let store = tempfile::tempdir().unwrap();
    let (hub, _events) = start_hub(store.path(), None).await;
    let spawn = |session: &str| {
        StationLink::spawn(
            &tokio::runtime::Handle::current(),
            fast_config(hub.local_addr(), None, hello("st-m", session)),
        )
        .unwrap()
    };
    let measures = std::collections::BTreeMap::from([
        ("sparc_median".to_owned(), -1.62),
        ("wheel_rom_deg".to_owned(), 48.5),
    ]);
    let (sender, link) = spawn("sess-m");
    send_range(&sender, "sess-m", 0..5);
    let stats = link
        .finish_with_measures("session complete", measures.clone(), GUARD)
        .await;
    assert_all_delivered(&stats, 5);
    let kept: std::collections::BTreeMap<String, f64> = serde_json::from_slice(
        &std::fs::read(store.path().join("st-m/sess-m.measures.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(kept, measures);

    // A NaN would make the whole Bye unencodable: the measures stay home, the session still
    // ends in order, and the station is told why.
    let (sender, link) = spawn("sess-nan");
    send_range(&sender, "sess-nan", 0..3);
    let bad = std::collections::BTreeMap::from([("sparc_median".to_owned(), f64::NAN)]);
    let stats = link
        .finish_with_measures("session complete", bad, GUARD)
        .await;
    assert_all_delivered(&stats, 3);
    assert!(
        stats
            .last_error
            .as_deref()
            .is_some_and(|e| e.contains("measures not sent") && e.contains("sparc_median")),
        "{:?}",
        stats.last_error
    );
    assert!(!store.path().join("st-m/sess-nan.measures.json").exists());
    hub.shutdown(GUARD).await;
}

struct Pki {
    _dir: tempfile::TempDir,
    server: ServerTls,
    client: ClientTls,
    /// A certificate for station `st-cert` signed by the same CA, for mutual TLS.
    station: Identity,
}

/// A CA, a `localhost` hub leaf and a station leaf signed by it, generated now.
fn pki() -> Pki {
    use rcgen::{
        BasicConstraints, CertificateParams, CertifiedIssuer, IsCa, KeyPair, KeyUsagePurpose,
    };
    let dir = tempfile::tempdir().unwrap();
    let mut ca_params = CertificateParams::new(Vec::<String>::new()).unwrap();
    ca_params.is_ca = IsCa::Ca(BasicConstraints::Unconstrained);
    ca_params.key_usages = vec![KeyUsagePurpose::KeyCertSign, KeyUsagePurpose::CrlSign];
    let ca = CertifiedIssuer::self_signed(ca_params, KeyPair::generate().unwrap()).unwrap();
    let leaf_key = KeyPair::generate().unwrap();
    let leaf = CertificateParams::new(vec!["localhost".to_owned()])
        .unwrap()
        .signed_by(&leaf_key, &ca)
        .unwrap();
    let write = |name: &str, text: String| {
        let path = dir.path().join(name);
        std::fs::write(&path, text).unwrap();
        path
    };
    let station_key = KeyPair::generate().unwrap();
    let station_cert = CertificateParams::new(vec!["st-cert".to_owned()])
        .unwrap()
        .signed_by(&station_key, &ca)
        .unwrap();
    let server = ServerTls {
        cert_pem_path: write("hub.crt", leaf.pem()),
        key_pem_path: write("hub.key", leaf_key.serialize_pem()),
        client_ca_pem_path: None,
    };
    let client = ClientTls {
        ca_pem_path: write("ca.crt", ca.pem()),
        server_name: "localhost".into(),
        identity: None,
    };
    let station = Identity {
        cert_pem_path: write("station.crt", station_cert.pem()),
        key_pem_path: write("station.key", station_key.serialize_pem()),
    };
    Pki {
        _dir: dir,
        server,
        client,
        station,
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn tls_round_trip_with_generated_certificates() {
    let pki = pki();
    let store = tempfile::tempdir().unwrap();
    let (hub, _events) = start_hub(store.path(), Some(pki.server.clone())).await;
    let (sender, link) = StationLink::spawn(
        &tokio::runtime::Handle::current(),
        fast_config(
            hub.local_addr(),
            Some(pki.client.clone()),
            hello("st-tls", "s1"),
        ),
    )
    .unwrap();
    send_range(&sender, "s1", 1..21);
    let stats = link.finish(GUARD).await;
    assert_all_delivered(&stats, 20);
    assert_eq!(
        stored_seqs(store.path(), "st-tls", "s1"),
        (1..21).collect::<Vec<_>>()
    );
    hub.shutdown(GUARD).await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn tls_station_refuses_a_hub_signed_by_another_ca() {
    let hub_pki = pki();
    let other_pki = pki();
    let store = tempfile::tempdir().unwrap();
    let (hub, mut events) = start_hub(store.path(), Some(hub_pki.server.clone())).await;
    let (sender, link) = StationLink::spawn(
        &tokio::runtime::Handle::current(),
        fast_config(
            hub.local_addr(),
            Some(other_pki.client.clone()),
            hello("st-x", "s1"),
        ),
    )
    .unwrap();
    send_range(&sender, "s1", 0..5);
    wait_until("a failed handshake", || link.stats().connect_failures >= 1).await;
    let stats = link.finish(Duration::from_millis(300)).await;
    assert_eq!(stats.acked, 0);
    assert_eq!(stats.pending, 5);
    assert!(!stats.bye_acknowledged);
    let error = stats.last_error.unwrap();
    assert!(error.contains("TLS handshake"), "{error}");
    match next_event(&mut events).await {
        TherapistEvent::ProtocolError { error, .. } => assert!(error.contains("TLS"), "{error}"),
        other => panic!("expected ProtocolError, got {other:?}"),
    }
    hub.shutdown(GUARD).await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn several_stations_at_once_each_get_their_own_session_file() {
    let store = tempfile::tempdir().unwrap();
    let (hub, _events) = start_hub(store.path(), None).await;
    let handle = tokio::runtime::Handle::current();
    let mut links = Vec::new();
    for i in 0..5 {
        let station = format!("st-{i}");
        let (sender, link) = StationLink::spawn(
            &handle,
            fast_config(hub.local_addr(), None, hello(&station, "morning")),
        )
        .unwrap();
        links.push((station, sender, link));
    }
    // Interleave the stations' summaries so their connections are busy at the same time.
    for seq in 0..40 {
        for (_, sender, _) in &links {
            sender.send(summary("morning", seq)).unwrap();
        }
        if seq % 10 == 0 {
            tokio::time::sleep(Duration::from_millis(5)).await;
        }
    }
    wait_until("all stations connected", || {
        hub.connected_stations().len() == 5
    })
    .await;
    let finishes = links
        .into_iter()
        .map(|(station, _sender, link)| async move { (station, link.finish(GUARD).await) });
    for (station, stats) in futures_join_all(finishes).await {
        assert_all_delivered(&stats, 40);
        assert_eq!(
            stored_seqs(store.path(), &station, "morning"),
            (0..40).collect::<Vec<_>>()
        );
    }
    hub.shutdown(GUARD).await;
}

/// Joins futures concurrently by spawning them (keeps the dev-dependencies small).
async fn futures_join_all<F>(futures: impl IntoIterator<Item = F>) -> Vec<F::Output>
where
    F: Future + Send + 'static,
    F::Output: Send + 'static,
{
    let handles: Vec<_> = futures.into_iter().map(tokio::spawn).collect();
    let mut out = Vec::new();
    for h in handles {
        out.push(h.await.unwrap());
    }
    out
}

/// A hub on its own runtime, so "killing" it (dropping the runtime) closes every socket
/// abruptly, with no Bye and no flush, as a crashed process would.
struct KillableHub {
    runtime: tokio::runtime::Runtime,
    server: Option<TherapistServer>,
}

impl KillableHub {
    fn start(listen: SocketAddr, store: &Path) -> Self {
        let runtime = tokio::runtime::Builder::new_multi_thread()
            .worker_threads(1)
            .enable_all()
            .build()
            .unwrap();
        let config = TherapistConfig::new(listen, store, None);
        // Rebinding the port a killed hub used can briefly fail on some kernels; retry.
        let mut result = None;
        for _ in 0..100 {
            match runtime.block_on(TherapistServer::bind(config.clone())) {
                Ok((server, _events)) => {
                    result = Some(server);
                    break;
                }
                Err(_) => std::thread::sleep(Duration::from_millis(50)),
            }
        }
        Self {
            runtime,
            server: Some(result.expect("could not bind the hub")),
        }
    }

    fn addr(&self) -> SocketAddr {
        self.server.as_ref().unwrap().local_addr()
    }

    fn kill(mut self) {
        self.server.take();
        self.runtime.shutdown_background();
    }
}

#[test]
fn therapist_killed_mid_session_and_restarted_stores_every_summary_exactly_once() {
    let store = tempfile::tempdir().unwrap();
    let station_rt = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(1)
        .enable_all()
        .build()
        .unwrap();
    let hub = KillableHub::start("127.0.0.1:0".parse().unwrap(), store.path());
    let addr = hub.addr();
    let (sender, link) = StationLink::spawn(
        station_rt.handle(),
        fast_config(addr, None, hello("st-k", "s1")),
    )
    .unwrap();

    send_range(&sender, "s1", 0..30);
    station_rt.block_on(wait_until("first 30 acknowledged", || {
        link.stats().acked == 30
    }));
    // Kill while a second batch is in flight.
    send_range(&sender, "s1", 30..60);
    hub.kill();
    station_rt.block_on(wait_until("the station to notice", || {
        !link.stats().connected
    }));
    send_range(&sender, "s1", 60..90);
    station_rt.block_on(wait_until("reconnect attempts to fail", || {
        link.stats().connect_failures >= 2
    }));
    let stats = link.stats();
    assert!(stats.pending > 0 && stats.acked < 90, "{stats:?}");

    let hub = KillableHub::start(addr, store.path());
    send_range(&sender, "s1", 90..100);
    let stats = link.finish_blocking(station_rt.handle(), GUARD);
    assert_all_delivered(&stats, 100);
    assert!(stats.connections >= 2, "{stats:?}");
    assert_eq!(
        stored_seqs(store.path(), "st-k", "s1"),
        (0..100).collect::<Vec<_>>()
    );
    hub.kill();
}

#[test]
fn restarted_station_replaying_a_stored_session_adds_only_new_summaries() {
    let store = tempfile::tempdir().unwrap();
    let rt = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(1)
        .enable_all()
        .build()
        .unwrap();
    let hub = KillableHub::start("127.0.0.1:0".parse().unwrap(), store.path());
    // A first station process stores 0..10, then "crashes" (its link is dropped unfinished).
    let (sender, link) = StationLink::spawn(
        rt.handle(),
        fast_config(hub.addr(), None, hello("st-r", "s1")),
    )
    .unwrap();
    send_range(&sender, "s1", 0..10);
    rt.block_on(wait_until("10 acknowledged", || link.stats().acked == 10));
    drop(link);
    hub.kill();
    // A restarted station replays the same session from its recording: 0..15.
    let hub = KillableHub::start("127.0.0.1:0".parse().unwrap(), store.path());
    let (sender, link) = StationLink::spawn(
        rt.handle(),
        fast_config(hub.addr(), None, hello("st-r", "s1")),
    )
    .unwrap();
    send_range(&sender, "s1", 0..15);
    let stats = link.finish_blocking(rt.handle(), GUARD);
    assert_all_delivered(&stats, 15);
    assert_eq!(
        stored_seqs(store.path(), "st-r", "s1"),
        (0..15).collect::<Vec<_>>()
    );
    hub.kill();
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn therapist_absent_for_the_whole_session_finish_reports_everything_undelivered() {
    // Bind and release a port so that nothing listens on it.
    let addr = TcpListener::bind("127.0.0.1:0")
        .await
        .unwrap()
        .local_addr()
        .unwrap();
    let (sender, link) = StationLink::spawn(
        &tokio::runtime::Handle::current(),
        fast_config(addr, None, hello("st-alone", "s1")),
    )
    .unwrap();
    send_range(&sender, "s1", 0..30);
    wait_until("a refused connection", || {
        link.stats().connect_failures >= 1
    })
    .await;
    let stats = tokio::time::timeout(GUARD, link.finish(Duration::from_millis(300)))
        .await
        .expect("finish blocked past its timeout");
    assert_eq!(stats.pending, 30);
    assert_eq!((stats.acked, stats.sent, stats.dropped), (0, 0, 0));
    assert!(!stats.connected && !stats.bye_acknowledged);
    assert!(
        stats
            .last_error
            .unwrap()
            .contains("30 summaries not delivered")
    );
    // After finish the sender reports the link closed instead of pretending.
    assert_eq!(sender.send(summary("s1", 30)), Err(SendError::Closed));
    assert_eq!(sender.stats().dropped, 1);
}

/// Reads frames from a raw socket until it closes (bounded by the guard).
async fn read_frames_until_close(stream: &mut TcpStream) -> Vec<Frame> {
    let mut decoder = FrameDecoder::new();
    let mut frames = Vec::new();
    let mut buf = [0u8; 4096];
    loop {
        let n = tokio::time::timeout(GUARD, stream.read(&mut buf))
            .await
            .expect("hub kept the bad connection open")
            .unwrap_or(0);
        if n == 0 {
            return frames;
        }
        decoder.extend(&buf[..n]);
        while let Some(f) = decoder.next_frame().unwrap() {
            frames.push(f);
        }
    }
}

async fn raw_exchange(addr: SocketAddr, bytes: &[u8]) -> Vec<Frame> {
    let mut stream = TcpStream::connect(addr).await.unwrap();
    stream.write_all(bytes).await.unwrap();
    read_frames_until_close(&mut stream).await
}

fn single_error(frames: &[Frame]) -> &str {
    match frames {
        [Frame::Error(e)] => &e.message,
        other => panic!("expected one Error frame, got {other:?}"),
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn malformed_frames_are_rejected_with_a_clear_error_and_the_hub_keeps_serving() {
    let store = tempfile::tempdir().unwrap();
    let (hub, mut events) = start_hub(store.path(), None).await;
    let addr = hub.local_addr();

    let frames = raw_exchange(addr, b"GET / HTTP/1.1\r\nHost: x\r\n\r\n").await;
    assert!(single_error(&frames).contains("bad magic"));
    match next_event(&mut events).await {
        TherapistEvent::ProtocolError { error, .. } => assert!(error.contains("bad magic")),
        other => panic!("expected ProtocolError, got {other:?}"),
    }

    let mut oversize = b"TRHB\x00\x01\x01\x00".to_vec();
    oversize.extend_from_slice(&u32::MAX.to_be_bytes());
    let frames = raw_exchange(addr, &oversize).await;
    assert!(single_error(&frames).contains("exceeds the maximum"));

    let mut bad_version = encode_to_vec(&Frame::Hello(hello("st", "s"))).unwrap();
    bad_version[5] = 9;
    let frames = raw_exchange(addr, &bad_version).await;
    assert!(single_error(&frames).contains("unsupported protocol version 9"));

    let first_summary = encode_to_vec(&Frame::Summary(summary("s", 0))).unwrap();
    let frames = raw_exchange(addr, &first_summary).await;
    assert!(single_error(&frames).contains("expected Hello first"));

    // A hostile station id that would escape the store directory.
    let payload = serde_json::to_vec(&serde_json::json!({
        "protocol_version": 1, "station_id": "../../etc", "patient_id": "p",
        "session_id": "s", "exercise": "e", "started_unix_ms": 0, "software_version": "v"
    }))
    .unwrap();
    let mut traversal = b"TRHB\x00\x01\x01\x00".to_vec();
    traversal.extend_from_slice(&(payload.len() as u32).to_be_bytes());
    traversal.extend_from_slice(&payload);
    let frames = raw_exchange(addr, &traversal).await;
    assert!(single_error(&frames).contains("station_id"));
    assert!(!store.path().join("../../etc").join("s.jsonl").exists());

    // Valid Hello, then garbage mid-session: Error frame, connection closed, nothing stored
    // from the garbage, the good summary kept.
    let mut bytes = encode_to_vec(&Frame::Hello(hello("st-ok", "s"))).unwrap();
    bytes.extend(encode_to_vec(&Frame::Summary(summary("s", 0))).unwrap());
    bytes.extend_from_slice(b"TRHB\x00\x01\x02\x00\x00\x00\x00\x02{]");
    let frames = raw_exchange(addr, &bytes).await;
    assert_ack_0_then_error(&frames, "bad JSON in Summary");
    assert_eq!(stored_seqs(store.path(), "st-ok", "s"), vec![0]);

    // The hub still serves a well-behaved station.
    let (sender, link) = StationLink::spawn(
        &tokio::runtime::Handle::current(),
        fast_config(addr, None, hello("st-good", "s2")),
    )
    .unwrap();
    send_range(&sender, "s2", 0..3);
    assert_all_delivered(&link.finish(GUARD).await, 3);
    hub.shutdown(GUARD).await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn station_rejects_a_garbage_speaking_server_and_keeps_the_summaries() {
    let listener = TcpListener::bind("127.0.0.1:0").await.unwrap();
    let addr = listener.local_addr().unwrap();
    let server = tokio::spawn(async move {
        let (mut s, _) = listener.accept().await.unwrap();
        s.write_all(b"SSH-2.0-OpenSSH_9.2\r\n").await.unwrap();
        let mut sink = Vec::new();
        let _ = tokio::time::timeout(GUARD, s.read_to_end(&mut sink)).await;
    });
    // No retry during the test, so the protocol error stays the last error.
    let mut config = fast_config(addr, None, hello("st-g", "s1"));
    config.reconnect.initial_ms = 60_000;
    config.reconnect.max_ms = 60_000;
    let (sender, link) = StationLink::spawn(&tokio::runtime::Handle::current(), config).unwrap();
    send_range(&sender, "s1", 0..4);
    wait_until("the bad server to be rejected", || {
        link.stats()
            .last_error
            .is_some_and(|e| e.contains("bad magic"))
    })
    .await;
    let stats = link.finish(Duration::from_millis(200)).await;
    assert_eq!((stats.pending, stats.acked), (4, 0));
    server.await.unwrap();
}

#[test]
fn blocked_therapist_never_blocks_summary_sender() {
    let rt = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(1)
        .enable_all()
        .build()
        .unwrap();
    // A "therapist" that accepts and then never reads: the station's socket buffers fill up.
    let listener = rt.block_on(TcpListener::bind("127.0.0.1:0")).unwrap();
    let addr = listener.local_addr().unwrap();
    let (held_tx, held_rx) = std::sync::mpsc::channel();
    rt.spawn(async move {
        let (socket, _) = listener.accept().await.unwrap();
        let _ = held_tx.send(());
        tokio::time::sleep(GUARD * 2).await;
        drop(socket);
    });
    let (sender, link) =
        StationLink::spawn(rt.handle(), fast_config(addr, None, hello("st-b", "s1"))).unwrap();
    held_rx
        .recv_timeout(GUARD)
        .expect("station never connected");
    // 2 000 summaries of about 2 KB (4 MB) overflow any loopback socket buffer; the channel
    // (4 096) is larger than the burst, so no send may fail either.
    let n = 2_000u64;
    let (done_tx, done_rx) = std::sync::mpsc::channel();
    let sending = std::thread::spawn(move || {
        let mut results = Vec::new();
        for seq in 0..n {
            let mut s = summary("s1", seq);
            for k in 0..60 {
                s.extra
                    .insert(format!("joint_angle_{k:02}_rad"), k as f64 * 0.01);
            }
            results.push(sender.send(s));
        }
        let _ = done_tx.send(());
        (sender, results)
    });
    done_rx
        .recv_timeout(GUARD)
        .expect("SummarySender::send blocked on a stalled therapist");
    let (sender, results) = sending.join().unwrap();
    assert!(results.iter().all(Result::is_ok));
    rt.block_on(wait_until("all summaries queued", || {
        link.stats().pending == n
    }));
    let stats = sender.stats();
    assert_eq!((stats.dropped, stats.acked), (0, 0), "{stats:?}");
    assert!(stats.connected, "{stats:?}");
    let stats = link.finish_blocking(rt.handle(), Duration::from_millis(300));
    assert_eq!(stats.pending, n);
    assert!(!stats.bye_acknowledged);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn regimen_from_the_therapist_reaches_the_station_poll() {
    let store = tempfile::tempdir().unwrap();
    let (hub, mut events) = start_hub(store.path(), None).await;
    let (sender, mut link) = StationLink::spawn(
        &tokio::runtime::Handle::current(),
        fast_config(hub.local_addr(), None, hello("st-reg", "s1")),
    )
    .unwrap();
    sender.send(summary("s1", 0)).unwrap();
    assert!(matches!(
        next_event(&mut events).await,
        TherapistEvent::Connected { .. }
    ));
    let err = hub
        .send_regimen(
            "nobody",
            Regimen {
                id: "r0".into(),
                toml: String::new(),
                prescribed_by: None,
            },
        )
        .unwrap_err();
    assert!(err.to_string().contains("not connected"));
    let regimen = Regimen {
        id: "reg-7".into(),
        toml: "[assist]\nlevel = 0.4\n".into(),
        prescribed_by: Some("ana@clinic.example".into()),
    };
    hub.send_regimen("st-reg", regimen.clone()).unwrap();
    let mut got = None;
    wait_until("the regimen", || {
        got = link.try_recv_regimen();
        got.is_some()
    })
    .await;
    assert_eq!(got, Some(regimen));
    let stats = link.finish(GUARD).await;
    assert_eq!(stats.regimens_received, 1);
    assert_all_delivered(&stats, 1);
    hub.shutdown(GUARD).await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn hub_shutdown_says_bye_and_the_station_resumes_with_a_new_hub() {
    let store = tempfile::tempdir().unwrap();
    let (hub, _events) = start_hub(store.path(), None).await;
    let addr = hub.local_addr();
    // A slow first retry, so the hub's Bye stays the last error while the test reads it.
    let mut config = fast_config(addr, None, hello("st-s", "s1"));
    config.reconnect.initial_ms = 1_000;
    config.reconnect.max_ms = 1_000;
    let (sender, link) = StationLink::spawn(&tokio::runtime::Handle::current(), config).unwrap();
    send_range(&sender, "s1", 0..10);
    wait_until("10 acknowledged", || link.stats().acked == 10).await;
    hub.shutdown(GUARD).await;
    wait_until("the station to notice", || !link.stats().connected).await;
    let error = link.stats().last_error.unwrap();
    assert!(error.contains("shutting down"), "{error}");
    send_range(&sender, "s1", 10..20);
    let (hub, _events) = TherapistServer::bind(TherapistConfig::new(addr, store.path(), None))
        .await
        .unwrap();
    let stats = link.finish(GUARD).await;
    assert_all_delivered(&stats, 20);
    assert_eq!(
        stored_seqs(store.path(), "st-s", "s1"),
        (0..20).collect::<Vec<_>>()
    );
    hub.shutdown(GUARD).await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn sender_refuses_other_sessions_repeated_seqs_and_invalid_values() {
    let addr: SocketAddr = "127.0.0.1:9".parse().unwrap();
    let (sender, link) = StationLink::spawn(
        &tokio::runtime::Handle::current(),
        fast_config(addr, None, hello("st", "s1")),
    )
    .unwrap();
    assert!(matches!(
        sender.send(summary("other", 0)),
        Err(SendError::WrongSession { .. })
    ));
    sender.send(summary("s1", 5)).unwrap();
    assert_eq!(
        sender.send(summary("s1", 5)),
        Err(SendError::SeqNotIncreasing {
            seq: 5,
            previous: 5
        })
    );
    let mut bad = summary("s1", 6);
    bad.lateral_m = f64::NAN;
    match sender.send(bad) {
        Err(SendError::Invalid(m)) => assert!(m.contains("lateral_m"), "{m}"),
        other => panic!("expected Invalid, got {other:?}"),
    }
    assert_eq!(sender.stats().rejected, 3);
    link.finish(Duration::from_millis(100)).await;
}

#[test]
fn plaintext_to_a_remote_address_is_refused() {
    let rt = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .unwrap();
    let remote: SocketAddr = "192.0.2.10:7878".parse().unwrap();
    let err = StationLink::spawn(
        rt.handle(),
        StationLinkConfig::new(remote, None, hello("st", "s")),
    )
    .err()
    .unwrap()
    .to_string();
    assert!(err.contains("plaintext"), "{err}");
    let err = TherapistConfig::new("0.0.0.0:7878".parse().unwrap(), "/tmp/x", None)
        .validate()
        .unwrap_err()
        .to_string();
    assert!(err.contains("plaintext"), "{err}");
}

#[test]
fn out_of_range_config_fields_are_named() {
    let addr: SocketAddr = "127.0.0.1:7878".parse().unwrap();
    let mut c = StationLinkConfig::new(addr, None, hello("st", "s"));
    c.max_pending = 0;
    assert!(
        c.validate()
            .unwrap_err()
            .to_string()
            .contains("max_pending")
    );
    let mut c = StationLinkConfig::new(addr, None, hello("st", "s"));
    c.reconnect = Backoff {
        initial_ms: 500,
        max_ms: 100,
    };
    assert!(
        c.validate()
            .unwrap_err()
            .to_string()
            .contains("reconnect.max_ms")
    );
    let mut c = StationLinkConfig::new(addr, None, hello("st", "s"));
    c.hello.station_id = "a/b".into();
    assert!(c.validate().unwrap_err().to_string().contains("station_id"));
    let mut t = TherapistConfig::new(addr, "/tmp/x", None);
    t.idle_timeout_ms = 10;
    assert!(
        t.validate()
            .unwrap_err()
            .to_string()
            .contains("idle_timeout_ms")
    );
    let bad: Result<TherapistConfig, _> =
        serde_json::from_str(r#"{"listen":"127.0.0.1:1","store_dir":"d","colour":"red"}"#);
    assert!(bad.unwrap_err().to_string().contains("colour"));
}

#[test]
fn missing_pem_files_are_reported_with_their_path() {
    let rt = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .unwrap();
    let addr: SocketAddr = "127.0.0.1:7878".parse().unwrap();
    let tls = ClientTls {
        ca_pem_path: "/nonexistent/ca.pem".into(),
        server_name: "localhost".into(),
        identity: None,
    };
    let err = StationLink::spawn(
        rt.handle(),
        StationLinkConfig::new(addr, Some(tls), hello("st", "s")),
    )
    .err()
    .unwrap()
    .to_string();
    assert!(err.contains("/nonexistent/ca.pem"), "{err}");
}

/// A TCP proxy in front of the hub. On its first connection it forwards station → hub but
/// swallows every hub → station byte (the Acks are "lost") until told to cut the connection;
/// later connections are forwarded both ways.
async fn lossy_proxy(hub: SocketAddr) -> (SocketAddr, tokio::sync::oneshot::Sender<()>) {
    let listener = TcpListener::bind("127.0.0.1:0").await.unwrap();
    let addr = listener.local_addr().unwrap();
    let (cut_tx, cut_rx) = tokio::sync::oneshot::channel::<()>();
    tokio::spawn(async move {
        let mut cut = Some(cut_rx);
        loop {
            let Ok((station, _)) = listener.accept().await else {
                return;
            };
            let upstream = TcpStream::connect(hub).await.unwrap();
            let (mut s_rd, mut s_wr) = station.into_split();
            let (mut h_rd, mut h_wr) = upstream.into_split();
            match cut.take() {
                Some(cut_rx) => {
                    tokio::spawn(async move {
                        let up = tokio::io::copy(&mut s_rd, &mut h_wr);
                        let mut lost = tokio::io::sink();
                        let swallow = tokio::io::copy(&mut h_rd, &mut lost);
                        tokio::select! {
                            _ = up => {}
                            _ = swallow => {}
                            _ = cut_rx => {}
                        }
                        // Dropping every half closes both connections abruptly.
                        drop((s_wr, h_wr));
                    });
                }
                None => {
                    tokio::spawn(async move {
                        let _ = tokio::io::copy(&mut s_rd, &mut h_wr).await;
                        let _ = h_wr.shutdown().await;
                    });
                    tokio::spawn(async move {
                        let _ = tokio::io::copy(&mut h_rd, &mut s_wr).await;
                        let _ = s_wr.shutdown().await;
                    });
                }
            }
        }
    });
    (addr, cut_tx)
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn lost_acks_cause_a_full_resend_that_the_hub_stores_only_once() {
    let store = tempfile::tempdir().unwrap();
    let (hub, _events) = start_hub(store.path(), None).await;
    let (proxy, cut) = lossy_proxy(hub.local_addr()).await;
    let (sender, link) = StationLink::spawn(
        &tokio::runtime::Handle::current(),
        fast_config(proxy, None, hello("st-l", "s1")),
    )
    .unwrap();
    send_range(&sender, "s1", 0..25);
    // The hub stores all 25 but none of its Acks reach the station.
    wait_until("the hub to store 25", || {
        read_session(store.path(), "st-l", "s1").is_ok_and(|s| s.len() == 25)
    })
    .await;
    let stats = link.stats();
    assert_eq!(
        (stats.sent, stats.acked, stats.pending),
        (25, 0, 25),
        "{stats:?}"
    );
    cut.send(()).unwrap();
    let stats = link.finish(GUARD).await;
    assert_all_delivered(&stats, 25);
    assert_eq!(stats.connections, 2, "{stats:?}");
    // The station queues its whole backlog right after Hello, before it can read the hub's
    // Hello-time Ack, so all 25 go out again and the hub must drop every one of them.
    assert_eq!(stats.resent, 25, "{stats:?}");
    assert_eq!(
        stored_seqs(store.path(), "st-l", "s1"),
        (0..25).collect::<Vec<_>>()
    );
    hub.shutdown(GUARD).await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn mutual_tls_hub_stores_only_stations_with_a_certificate() {
    let pki = pki();
    let store = tempfile::tempdir().unwrap();
    let mut server_tls = pki.server.clone();
    server_tls.client_ca_pem_path = Some(pki.client.ca_pem_path.clone());
    let (hub, mut events) = start_hub(store.path(), Some(server_tls)).await;
    let handle = tokio::runtime::Handle::current();

    let mut with_cert = pki.client.clone();
    with_cert.identity = Some(pki.station.clone());
    let (sender, link) = StationLink::spawn(
        &handle,
        fast_config(hub.local_addr(), Some(with_cert), hello("st-cert", "s1")),
    )
    .unwrap();
    send_range(&sender, "s1", 0..10);
    assert_all_delivered(&link.finish(GUARD).await, 10);
    assert_eq!(
        stored_seqs(store.path(), "st-cert", "s1"),
        (0..10).collect::<Vec<_>>()
    );

    let (sender, link) = StationLink::spawn(
        &handle,
        fast_config(
            hub.local_addr(),
            Some(pki.client.clone()),
            hello("st-anon", "s1"),
        ),
    )
    .unwrap();
    send_range(&sender, "s1", 0..10);
    let refused = loop {
        match next_event(&mut events).await {
            TherapistEvent::ProtocolError { error, .. } => break error,
            TherapistEvent::Connected { hello, .. } => {
                assert_eq!(hello.station_id, "st-cert", "anonymous station admitted")
            }
            _ => {}
        }
    };
    // The handshake admits a station without a certificate (it may be pairing); its Hello is
    // refused before anything is stored.
    assert!(
        refused.contains("no client certificate presented"),
        "{refused}"
    );
    let stats = link.finish(Duration::from_millis(300)).await;
    assert_eq!((stats.acked, stats.pending), (0, 10), "{stats:?}");
    assert!(!store.path().join("st-anon").exists());

    // A valid clinic certificate does not let one station speak for another.
    let mut borrowed = pki.client.clone();
    borrowed.identity = Some(pki.station.clone());
    let (sender, link) = StationLink::spawn(
        &handle,
        fast_config(hub.local_addr(), Some(borrowed), hello("st-impostor", "s1")),
    )
    .unwrap();
    send_range(&sender, "s1", 0..3);
    let refused = loop {
        match next_event(&mut events).await {
            // Left over from the anonymous station's retries.
            TherapistEvent::ProtocolError { error, .. }
                if error.contains("no client certificate") => {}
            TherapistEvent::ProtocolError { error, .. } => break error,
            TherapistEvent::Connected { hello, .. } => {
                assert_ne!(hello.station_id, "st-impostor", "impostor admitted")
            }
            _ => {}
        }
    };
    assert!(
        refused.contains("does not name station \"st-impostor\""),
        "{refused}"
    );
    let stats = link.finish(Duration::from_millis(300)).await;
    assert_eq!((stats.acked, stats.pending), (0, 3), "{stats:?}");
    assert!(!store.path().join("st-impostor").exists());
    hub.shutdown(GUARD).await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn hub_that_reads_but_never_acknowledges_is_abandoned_and_reconnected() {
    // A hung hub: accepts and drains every connection, never answers.
    let listener = TcpListener::bind("127.0.0.1:0").await.unwrap();
    let addr = listener.local_addr().unwrap();
    let hung = tokio::spawn(async move {
        loop {
            let (mut s, _) = listener.accept().await.unwrap();
            tokio::spawn(async move {
                let mut sink = Vec::new();
                let _ = tokio::time::timeout(GUARD, s.read_to_end(&mut sink)).await;
            });
        }
    });
    let mut config = fast_config(addr, None, hello("st-h", "s1"));
    config.ack_timeout_ms = 1_000;
    let (sender, link) = StationLink::spawn(&tokio::runtime::Handle::current(), config).unwrap();
    send_range(&sender, "s1", 0..5);
    wait_until(
        "the backlog resent on a new connection after the ack timeout",
        || link.stats().resent >= 5,
    )
    .await;
    let stats = link.finish(Duration::from_millis(200)).await;
    assert!(
        stats
            .last_error
            .as_deref()
            .is_some_and(|e| e.contains("no acknowledgement")),
        "{stats:?}"
    );
    assert!(stats.connections >= 2, "{stats:?}");
    assert_eq!((stats.acked, stats.pending), (0, 5), "{stats:?}");
    hung.abort();
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn summary_jumping_to_u64_max_is_refused_and_the_session_stays_alive() {
    let store = tempfile::tempdir().unwrap();
    let (hub, _events) = start_hub(store.path(), None).await;
    let addr = hub.local_addr();
    // A hostile or buggy peer stores seq 0, then tries to jump to the end of the sequence space.
    let mut bytes = encode_to_vec(&Frame::Hello(hello("st-j", "s1"))).unwrap();
    bytes.extend(encode_to_vec(&Frame::Summary(summary("s1", 0))).unwrap());
    bytes.extend(encode_to_vec(&Frame::Summary(summary("s1", u64::MAX))).unwrap());
    let frames = raw_exchange(addr, &bytes).await;
    assert_ack_0_then_error(&frames, "jumps too far ahead");
    assert_eq!(stored_seqs(store.path(), "st-j", "s1"), vec![0]);
    // The genuine station's next summaries are still stored: the session was not silenced.
    let (sender, link) = StationLink::spawn(
        &tokio::runtime::Handle::current(),
        fast_config(addr, None, hello("st-j", "s1")),
    )
    .unwrap();
    send_range(&sender, "s1", 1..6);
    // The station itself refuses such a jump before it reaches the wire.
    assert!(matches!(
        sender.send(summary("s1", u64::MAX)),
        Err(SendError::SeqJump {
            seq: u64::MAX,
            previous: Some(5),
            ..
        })
    ));
    assert_all_delivered(&link.finish(GUARD).await, 5);
    assert_eq!(
        stored_seqs(store.path(), "st-j", "s1"),
        (0..6).collect::<Vec<_>>()
    );
    hub.shutdown(GUARD).await;
}

/// A TCP proxy in front of the hub whose first connection is a liar: it answers the station
/// with an Ack for `bogus_seq` at once and forwards nothing to the hub. Later connections are
/// forwarded both ways.
async fn lying_ack_proxy(hub: SocketAddr, session: &str, bogus_seq: u64) -> SocketAddr {
    let listener = TcpListener::bind("127.0.0.1:0").await.unwrap();
    let addr = listener.local_addr().unwrap();
    let bogus = encode_to_vec(&Frame::Ack(netlink::Ack {
        session_id: session.into(),
        seq: bogus_seq,
    }))
    .unwrap();
    tokio::spawn(async move {
        let mut first = true;
        loop {
            let Ok((mut station, _)) = listener.accept().await else {
                return;
            };
            if std::mem::take(&mut first) {
                let bogus = bogus.clone();
                tokio::spawn(async move {
                    let _ = station.write_all(&bogus).await;
                    let mut sink = Vec::new();
                    let _ = tokio::time::timeout(GUARD, station.read_to_end(&mut sink)).await;
                });
                continue;
            }
            let upstream = TcpStream::connect(hub).await.unwrap();
            let (mut s_rd, mut s_wr) = station.into_split();
            let (mut h_rd, mut h_wr) = upstream.into_split();
            tokio::spawn(async move {
                let _ = tokio::io::copy(&mut s_rd, &mut h_wr).await;
                let _ = h_wr.shutdown().await;
            });
            tokio::spawn(async move {
                let _ = tokio::io::copy(&mut h_rd, &mut s_wr).await;
                let _ = s_wr.shutdown().await;
            });
        }
    });
    addr
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn ack_above_what_the_station_produced_is_a_protocol_error_and_nothing_is_lost() {
    let store = tempfile::tempdir().unwrap();
    let (hub, _events) = start_hub(store.path(), None).await;
    let proxy = lying_ack_proxy(hub.local_addr(), "s1", 1_000).await;
    let (sender, link) = StationLink::spawn(
        &tokio::runtime::Handle::current(),
        fast_config(proxy, None, hello("st-lie", "s1")),
    )
    .unwrap();
    send_range(&sender, "s1", 0..5);
    wait_until("a second connection", || link.stats().connections >= 2).await;
    let error = link.stats().last_error.unwrap_or_default();
    assert!(error.contains("impossible Ack"), "{error}");
    assert!(error.contains("1000"), "{error}");
    let stats = link.finish(GUARD).await;
    assert_all_delivered(&stats, 5);
    assert_eq!(
        stored_seqs(store.path(), "st-lie", "s1"),
        (0..5).collect::<Vec<_>>()
    );
    hub.shutdown(GUARD).await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_station_that_floods_and_never_reads_keeps_the_hubs_queue_bounded() {
    let store = tempfile::tempdir().unwrap();
    let (hub, _events) = start_hub(store.path(), None).await;
    let addr = hub.local_addr();
    // The flooder: Hello, one summary, then duplicates as fast as the hub takes them for 3 s,
    // never reading a byte of the hub's answers.
    let flood = tokio::spawn(async move {
        let mut stream = TcpStream::connect(addr).await.unwrap();
        let mut first = encode_to_vec(&Frame::Hello(hello("st-flood", "s1"))).unwrap();
        first.extend(encode_to_vec(&Frame::Summary(summary("s1", 0))).unwrap());
        stream.write_all(&first).await.unwrap();
        let dup = encode_to_vec(&Frame::Summary(summary("s1", 0))).unwrap();
        let burst: Vec<u8> = dup.iter().copied().cycle().take(dup.len() * 100).collect();
        let until = tokio::time::Instant::now() + Duration::from_secs(3);
        let mut bursts = 0u64;
        while tokio::time::Instant::now() < until {
            match tokio::time::timeout_at(until, stream.write_all(&burst)).await {
                Ok(Ok(())) => bursts += 1,
                Ok(Err(e)) => panic!("hub closed the flooding connection: {e}"),
                Err(_) => break,
            }
        }
        (stream, bursts)
    });
    wait_until("the flooder connected", || {
        hub.connected_stations() == ["st-flood"]
    })
    .await;
    // Regimens of 32 KB pile up behind the flooder's full socket buffers: the outbox fills and
    // further regimens are refused instead of queued.
    let big = Regimen {
        id: "big".into(),
        toml: format!("# {}\n", "x".repeat(32 * 1024)),
        prescribed_by: None,
    };
    let mut busy = 0;
    for _ in 0..2_000 {
        match hub.send_regimen("st-flood", big.clone()) {
            Ok(()) => {}
            Err(netlink::NetlinkError::Busy(m)) => {
                assert!(m.contains("st-flood"), "{m}");
                busy += 1;
            }
            Err(e) => panic!("unexpected error {e}"),
        }
    }
    assert!(
        busy > 0,
        "2 000 regimens of 32 KB all queued for a peer that never reads"
    );
    // Meanwhile another station is served normally.
    let (sender, link) = StationLink::spawn(
        &tokio::runtime::Handle::current(),
        fast_config(addr, None, hello("st-good", "s1")),
    )
    .unwrap();
    send_range(&sender, "s1", 0..20);
    assert_all_delivered(&link.finish(GUARD).await, 20);
    let (_stream, bursts) = flood.await.unwrap();
    assert!(bursts > 0);
    let high = hub.outgoing_high_water();
    assert!(
        high <= TherapistServer::OUTBOX_CAPACITY + 1,
        "{high} frames queued for one connection"
    );
    assert_eq!(stored_seqs(store.path(), "st-flood", "s1"), vec![0]);
    hub.shutdown(GUARD).await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn idle_connections_from_a_stations_address_are_capped_and_cannot_lock_it_out() {
    let store = tempfile::tempdir().unwrap();
    let listen: SocketAddr = "127.0.0.1:0".parse().unwrap();
    let mut config = TherapistConfig::new(listen, store.path(), None);
    assert_eq!(config.max_connections_per_address, 16);
    config.max_connections_per_address = 2;
    let (hub, _events) = TherapistServer::bind(config).await.unwrap();
    let addr = hub.local_addr();
    // Admitted stations do not count against their address: three behind one "NAT" (one
    // after the other: a third still in its handshake would push out the first).
    let mut held = Vec::new();
    for (i, station) in ["st-1", "st-2", "st-3"].into_iter().enumerate() {
        let mut s = TcpStream::connect(addr).await.unwrap();
        s.write_all(&encode_to_vec(&Frame::Hello(hello(station, "s1"))).unwrap())
            .await
            .unwrap();
        held.push(s);
        wait_until("the station connected", || {
            hub.connected_stations().len() == i + 1
        })
        .await;
    }
    // Idle connections from that address: two hold its slots, two wait in its line, the
    // fifth is closed at once; the oldest are closed once they have stalled for a grace.
    let mut idle = Vec::new();
    for _ in 0..5 {
        idle.push(TcpStream::connect(addr).await.unwrap());
    }
    wait_until("two idle connections kept and two in line", || {
        hub.unauthenticated_connections() == 4
    })
    .await;
    assert!(
        read_frames_until_close(&mut idle[4]).await.is_empty(),
        "the one beyond the line is closed without a word"
    );
    assert!(
        read_frames_until_close(&mut idle[0]).await.is_empty(),
        "the oldest idle connection is closed without a word"
    );
    // A fourth station from the same address still gets in, and delivers.
    let (sender, link) = StationLink::spawn(
        &tokio::runtime::Handle::current(),
        fast_config(addr, None, hello("st-4", "s1")),
    )
    .unwrap();
    send_range(&sender, "s1", 0..3);
    assert_all_delivered(&link.finish(GUARD).await, 3);
    assert!(hub.unauthenticated_connections() <= 4);
    hub.shutdown(GUARD).await;
}

/// A session file whose reading never ends (a FIFO: the hub's own handle keeps it open for
/// writing, so a read waits forever) stands for a very slow disk. Opening it must stall only
/// that station, never the hub's other stations.
#[cfg(unix)]
#[test]
fn a_session_file_that_never_finishes_reading_stalls_only_its_own_station() {
    let store = tempfile::tempdir().unwrap();
    let slow = store.path().join("st-slow");
    std::fs::create_dir_all(&slow).unwrap();
    let fifo = slow.join("s1.jsonl");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    if !made.is_ok_and(|s| s.success()) {
        println!("SKIPPED: mkfifo is not available, so no never-ending session file can be made");
        return;
    }
    let rt = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .unwrap();
    let (hub, _events) = rt.block_on(start_hub(store.path(), None));
    let addr = hub.local_addr();
    let (slow_sender, _slow_link) =
        StationLink::spawn(rt.handle(), fast_config(addr, None, hello("st-slow", "s1"))).unwrap();
    send_range(&slow_sender, "s1", 0..3);
    // Give the slow station's connection time to start reading its file.
    std::thread::sleep(Duration::from_millis(300));
    // Checked from another thread: a hub stalled on its worker threads may stall timers too.
    let (done_tx, done_rx) = std::sync::mpsc::channel();
    let handle = rt.handle().clone();
    std::thread::spawn(move || {
        let stats = handle.block_on(async {
            let (sender, link) = StationLink::spawn(
                &tokio::runtime::Handle::current(),
                fast_config(addr, None, hello("st-ok", "s1")),
            )
            .unwrap();
            send_range(&sender, "s1", 0..10);
            link.finish(GUARD).await
        });
        let _ = done_tx.send(stats);
    });
    let Ok(stats) = done_rx.recv_timeout(Duration::from_secs(10)) else {
        // Dropping a runtime waits for its blocked threads: leave them behind instead.
        rt.shutdown_background();
        panic!("the hub stalled behind one station's session file");
    };
    assert_all_delivered(&stats, 10);
    assert_eq!(
        stored_seqs(store.path(), "st-ok", "s1"),
        (0..10).collect::<Vec<_>>()
    );
    // The blocked read cannot be cancelled; leave it behind with the runtime.
    drop(hub);
    rt.shutdown_background();
}

#[test]
fn two_stations_reconnecting_at_once_store_every_summary_exactly_once() {
    let store = tempfile::tempdir().unwrap();
    let rt = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .unwrap();
    let hub = KillableHub::start("127.0.0.1:0".parse().unwrap(), store.path());
    let addr = hub.addr();
    let links: Vec<_> = ["st-c1", "st-c2"]
        .into_iter()
        .map(|station| {
            let (sender, link) =
                StationLink::spawn(rt.handle(), fast_config(addr, None, hello(station, "s1")))
                    .unwrap();
            send_range(&sender, "s1", 0..30);
            (station, sender, link)
        })
        .collect();
    for (_, _, link) in &links {
        rt.block_on(wait_until("30 acknowledged", || link.stats().acked == 30));
    }
    hub.kill();
    for (_, sender, link) in &links {
        rt.block_on(wait_until("the station to notice", || {
            !link.stats().connected
        }));
        send_range(sender, "s1", 30..60);
    }
    // Both reconnect to the restarted hub at the same time and resend their backlog.
    let hub = KillableHub::start(addr, store.path());
    for (station, _sender, link) in links {
        let stats = link.finish_blocking(rt.handle(), GUARD);
        assert_all_delivered(&stats, 60);
        assert_eq!(
            stored_seqs(store.path(), station, "s1"),
            (0..60).collect::<Vec<_>>()
        );
    }
    hub.kill();
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_hub_name_that_does_not_resolve_never_blocks_the_station() {
    let pki = pki();
    let started = std::time::Instant::now();
    let mut config = fast_config(
        "127.0.0.1:1".parse().unwrap(),
        Some(pki.client.clone()),
        hello("st-dns", "s1"),
    );
    config.addr = "no-such-host.invalid:7878".into();
    assert!(matches!(config.addr, netlink::HubAddress::Name(_)));
    let (sender, link) = StationLink::spawn(&tokio::runtime::Handle::current(), config).unwrap();
    for seq in 0..10 {
        sender.send(summary("s1", seq)).unwrap();
    }
    assert!(
        started.elapsed() < Duration::from_secs(2),
        "creating the link and queuing took {:?}",
        started.elapsed()
    );
    // Each failed resolution is one failed attempt, retried with backoff.
    wait_until("two failed attempts", || link.stats().connect_failures >= 2).await;
    let stats = tokio::time::timeout(GUARD, link.finish(Duration::from_millis(300)))
        .await
        .expect("finish blocked");
    assert_eq!((stats.pending, stats.acked), (10, 0), "{stats:?}");
    let error = stats.last_error.unwrap();
    assert!(error.contains("no-such-host.invalid"), "{error}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_hub_given_by_name_is_resolved_and_reached() {
    let store = tempfile::tempdir().unwrap();
    let (hub, _events) = start_hub(store.path(), None).await;
    let name = format!("localhost:{}", hub.local_addr().port());
    // Plaintext by name is allowed only for localhost.
    let remote = StationLinkConfig::new("hub.clinic.example:7878", None, hello("st", "s"));
    assert!(
        remote
            .validate()
            .unwrap_err()
            .to_string()
            .contains("plaintext")
    );
    let mut config = fast_config(hub.local_addr(), None, hello("st-name", "s1"));
    config.addr = name.as_str().into();
    let (sender, link) = StationLink::spawn(&tokio::runtime::Handle::current(), config).unwrap();
    send_range(&sender, "s1", 0..5);
    assert_all_delivered(&link.finish(GUARD).await, 5);
    assert_eq!(
        stored_seqs(store.path(), "st-name", "s1"),
        (0..5).collect::<Vec<_>>()
    );
    hub.shutdown(GUARD).await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn hub_answers_a_station_it_cannot_serve_with_update_required() {
    let store = tempfile::tempdir().unwrap();
    let (hub, _events) = start_hub(store.path(), None).await;
    // A future station speaking only versions above this hub's (its Hello still framed as
    // version 1).
    let mut future = hello("st-future", "s1");
    future.protocol_version = PROTOCOL_VERSION + 2;
    future.min_protocol_version = Some(PROTOCOL_VERSION + 1);
    let mut bytes = encode_to_vec(&Frame::Hello(future)).unwrap();
    bytes.extend(encode_to_vec(&Frame::Summary(summary("s1", 0))).unwrap());
    let frames = raw_exchange(hub.local_addr(), &bytes).await;
    match frames.as_slice() {
        [Frame::Error(e)] => {
            assert_eq!(
                e.code.as_deref(),
                Some(netlink::frame::UPDATE_REQUIRED),
                "{e:?}"
            );
            assert!(
                e.message.contains(&format!(
                    "this station needs link protocol ≥ {}, the hub speaks at most {}",
                    PROTOCOL_VERSION + 1,
                    PROTOCOL_VERSION
                )),
                "{}",
                e.message
            );
        }
        other => panic!("expected one Error frame, got {other:?}"),
    }
    assert!(!store.path().join("st-future").exists());
    // A station from before version ranges (no min_protocol_version) is still served.
    let mut old = encode_to_vec(&Frame::Hello(hello("st-old", "s1"))).unwrap();
    old.extend(encode_to_vec(&Frame::Summary(summary("s1", 0))).unwrap());
    let mut stream = TcpStream::connect(hub.local_addr()).await.unwrap();
    stream.write_all(&old).await.unwrap();
    wait_until("the old station's summary", || {
        read_session(store.path(), "st-old", "s1").is_ok_and(|s| s.len() == 1)
    })
    .await;
    drop(stream);
    hub.shutdown(GUARD).await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn station_told_update_required_stops_retrying_and_says_so() {
    let listener = TcpListener::bind("127.0.0.1:0").await.unwrap();
    let addr = listener.local_addr().unwrap();
    let accepted = std::sync::Arc::new(std::sync::atomic::AtomicU64::new(0));
    let count = accepted.clone();
    let refusal = encode_to_vec(&Frame::Error(netlink::ErrorFrame {
        message: "update required: the station speaks protocol versions 1..=1, the hub 2..=2"
            .into(),
        code: Some(netlink::frame::UPDATE_REQUIRED.into()),
    }))
    .unwrap();
    let server = tokio::spawn(async move {
        loop {
            let (mut s, _) = listener.accept().await.unwrap();
            count.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
            let refusal = refusal.clone();
            tokio::spawn(async move {
                let mut buf = [0u8; 1024];
                let _ = s.read(&mut buf).await;
                let _ = s.write_all(&refusal).await;
                let _ = s.shutdown().await;
                // Read until the station hangs up: a socket closed with unread data sends a
                // reset, which can reach the station before the refusal it should read.
                while matches!(s.read(&mut buf).await, Ok(n) if n > 0) {}
            });
        }
    });
    let (sender, link) = StationLink::spawn(
        &tokio::runtime::Handle::current(),
        fast_config(addr, None, hello("st-upd", "s1")),
    )
    .unwrap();
    send_range(&sender, "s1", 0..5);
    wait_until("the update-required status", || {
        link.stats().update_required.is_some()
    })
    .await;
    let status = link.stats().update_required.unwrap();
    assert!(status.contains("update required"), "{status}");
    // Backoff is 20..200 ms: a retrying station would have reconnected many times by now.
    tokio::time::sleep(Duration::from_millis(1_000)).await;
    assert_eq!(accepted.load(std::sync::atomic::Ordering::SeqCst), 1);
    // The exercise goes on: summaries are still accepted, and reported undelivered.
    send_range(&sender, "s1", 5..8);
    let stats = link.finish(Duration::from_millis(300)).await;
    assert_eq!(
        (stats.pending, stats.acked, stats.connections),
        (8, 0, 1),
        "{stats:?}"
    );
    assert!(stats.update_required.is_some());
    server.abort();
}

/// The hub acknowledged seq 0, then refused the rest with an Error frame saying `why`.
fn assert_ack_0_then_error(frames: &[Frame], why: &str) {
    match frames {
        [Frame::Ack(a), Frame::Error(e)] => {
            assert_eq!(a.seq, 0);
            assert!(e.message.contains(why), "{}", e.message);
        }
        other => panic!("expected Ack then Error, got {other:?}"),
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_message_reaches_a_version_2_station_its_seen_reaches_the_hub_and_a_version_1_station_gets_none()
 {
    let store = tempfile::tempdir().unwrap();
    let (hub, mut events) = start_hub(store.path(), None).await;
    let (sender, mut link) = StationLink::spawn(
        &tokio::runtime::Handle::current(),
        fast_config(hub.local_addr(), None, hello("st-msg", "s1")),
    )
    .unwrap();
    sender.send(summary("s1", 0)).unwrap();
    assert!(matches!(
        next_event(&mut events).await,
        TherapistEvent::Connected { .. }
    ));
    let message = netlink::Message {
        id: "m-1".into(),
        text: "Well done — see you Thursday".into(),
        sent_unix_ms: 1_795_253_400_000,
    };
    assert!(hub.send_message("st-msg", message.clone()).unwrap());
    let mut got = None;
    wait_until("the message", || {
        got = link.try_recv_message();
        got.is_some()
    })
    .await;
    assert_eq!(got, Some(message.clone()));
    link.report_seen(netlink::MessageSeen {
        id: "m-1".into(),
        seen_unix_ms: 1_795_253_401_000,
    });
    let seen = loop {
        if let TherapistEvent::MessageSeen { seen, .. } = next_event(&mut events).await {
            break seen;
        }
    };
    assert_eq!(
        (seen.id.as_str(), seen.seen_unix_ms),
        ("m-1", 1_795_253_401_000)
    );
    assert_all_delivered(&link.finish(GUARD).await, 1);

    // A station that speaks only version 1 is never sent the frame (it would not know it).
    let old = Hello {
        protocol_version: 1,
        min_protocol_version: Some(1),
        ..hello("st-old", "s2")
    };
    let (sender, link) = StationLink::spawn(
        &tokio::runtime::Handle::current(),
        fast_config(hub.local_addr(), None, old),
    )
    .unwrap();
    sender.send(summary("s2", 0)).unwrap();
    loop {
        if let TherapistEvent::Connected { .. } = next_event(&mut events).await {
            break;
        }
    }
    assert!(
        !hub.send_message("st-old", message).unwrap(),
        "a version-1 station"
    );
    let stats = link.finish(GUARD).await;
    assert_all_delivered(&stats, 1);
    assert_eq!(stats.last_error, None, "{stats:?}");
    hub.shutdown(GUARD).await;
}

/// A queued session resent (as `telerehab sync` does) to a hub that already stores its first
/// 40 summaries: the hub's Ack of seq 39 arrives when the station has handed over only
/// seqs 0–2 of the 100. Once that was an "impossible Ack": Error frame, a reconnect, and on a
/// real queue a 15 s wait for an acknowledgement, per queued session.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_resent_queued_session_takes_the_hubs_ack_of_what_it_holds_without_reconnecting() {
    let store = tempfile::tempdir().unwrap();
    let (hub, _events) = start_hub(store.path(), None).await;
    let addr = hub.local_addr();
    let handle = tokio::runtime::Handle::current();
    // The first run got 0..40 to the hub before the station stopped.
    let (sender, link) =
        StationLink::spawn(&handle, fast_config(addr, None, hello("st-q", "s1"))).unwrap();
    send_range(&sender, "s1", 0..40);
    wait_until("the first run acknowledged", || link.stats().acked == 40).await;
    drop(sender);
    drop(link);
    // The resend of the whole queued session, whose last seq the station knows.
    let mut config = fast_config(addr, None, hello("st-q", "s1"));
    config.replay_last_seq = Some(99);
    let (sender, link) = StationLink::spawn(&handle, config).unwrap();
    send_range(&sender, "s1", 0..3);
    wait_until("the hub's Ack taken or refused", || {
        let s = link.stats();
        s.acked >= 3 || s.connections >= 2
    })
    .await;
    send_range(&sender, "s1", 3..100);
    let stats = link.finish(GUARD).await;
    assert_eq!(stats.connections, 1, "{stats:?}");
    assert_eq!(stats.last_error, None, "{stats:?}");
    assert_eq!(stats.resent, 0, "{stats:?}");
    assert_all_delivered(&stats, 100);
    assert_eq!(
        stored_seqs(store.path(), "st-q", "s1"),
        (0..100).collect::<Vec<_>>()
    );
    hub.shutdown(GUARD).await;
}

/// The known last seq of a resent session bounds what the hub may acknowledge: an Ack one
/// above it is still impossible (a broken hub must not make the station forget summaries it
/// never stored), and everything is resent on the next connection.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_ack_above_a_resent_sessions_last_seq_is_still_a_protocol_error_and_nothing_is_lost() {
    let store = tempfile::tempdir().unwrap();
    let (hub, _events) = start_hub(store.path(), None).await;
    let proxy = lying_ack_proxy(hub.local_addr(), "s1", 5).await;
    let mut config = fast_config(proxy, None, hello("st-lie-q", "s1"));
    config.replay_last_seq = Some(4);
    let (sender, link) = StationLink::spawn(&tokio::runtime::Handle::current(), config).unwrap();
    send_range(&sender, "s1", 0..5);
    wait_until("a second connection", || link.stats().connections >= 2).await;
    let error = link.stats().last_error.unwrap_or_default();
    assert!(error.contains("impossible Ack"), "{error}");
    assert!(error.contains("seq 5 "), "{error}");
    let stats = link.finish(GUARD).await;
    assert_all_delivered(&stats, 5);
    assert_eq!(
        stored_seqs(store.path(), "st-lie-q", "s1"),
        (0..5).collect::<Vec<_>>()
    );
    hub.shutdown(GUARD).await;
}
