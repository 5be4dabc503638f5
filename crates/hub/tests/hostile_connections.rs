//! Connection budgets against hostile clients (issue 25): half-sent requests and idle
//! connections, from many loopback addresses, cannot take the descriptors or the slots that
//! paired stations and therapists need; the console port's deadlines close what is held.

mod common;

use std::future::Future;
use std::net::{IpAddr, Ipv4Addr, SocketAddr};
use std::path::Path;
use std::sync::Arc;
use std::time::{Duration, Instant};

use axum::http::{Request, StatusCode, header};
use http_body_util::BodyExt;
use hub::bench::BenchStation;
use hub::clinic::{Bound, Clinic, ServeOptions};
use hub::limits::ConnectionBudget;
use hub::web::{self, AppState, WebLimits};
use hub::{Db, Role};
use netlink::therapist::budget::REFUSAL_DETAILS_PER_INTERVAL;
use netlink::{ClientTls, Frame, FrameDecoder, Hello, PROTOCOL_VERSION, Summary, TherapistEvent};
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::{TcpSocket, TcpStream};

const PASSWORD: &str = "correct horse battery staple";
const HALF_SENT_REQUESTS: usize = 5_000;
const IDLE_STATION_CONNECTIONS: usize = 5_000;
/// Junk connections from the paired station's own address (its "NAT"), above the cap.
const JUNK_FROM_STATION_ADDRESS: usize = 40;
/// Generous bound for anything that should be immediate.
const GUARD: Duration = Duration::from_secs(15);

fn now_ms() -> i64 {
    web::system_now_ms()
}

/// A loopback address `127.<a>.<b>.<c>` for the `i`-th junk connection of a `block`, five
/// connections per address.
fn junk_address(block: u8, i: usize) -> IpAddr {
    let n = i / 5 + 1;
    IpAddr::V4(Ipv4Addr::new(
        127,
        block,
        (n / 250) as u8,
        (n % 250 + 2) as u8,
    ))
}

async fn connect_from(source: IpAddr, to: SocketAddr) -> std::io::Result<TcpStream> {
    let socket = TcpSocket::new_v4()?;
    socket.bind(SocketAddr::new(source, 0))?;
    socket.connect(to).await
}

/// Opens `n` connections with `open`, 64 at a time; those that opened (kept open).
async fn open_many<T, F, Fut>(n: usize, open: F) -> Vec<T>
where
    T: Send + 'static,
    F: Fn(usize) -> Fut + Send + Sync + 'static,
    Fut: Future<Output = Option<T>> + Send,
{
    let open = Arc::new(open);
    let workers = 64;
    let mut tasks = Vec::new();
    for w in 0..workers {
        let open = open.clone();
        tasks.push(tokio::spawn(async move {
            let mut held = Vec::new();
            for i in (w..n).step_by(workers) {
                if let Some(x) = open(i).await {
                    held.push(x);
                }
            }
            held
        }));
    }
    let mut all = Vec::with_capacity(n);
    for t in tasks {
        all.extend(t.await.expect("opener"));
    }
    all
}

fn open_fds() -> usize {
    std::fs::read_dir("/proc/self/fd").map_or(0, Iterator::count)
}

/// What the flood test needs from a running hub.
struct RunningHub {
    bound: Bound,
    events: Arc<std::sync::Mutex<Vec<TherapistEvent>>>,
    stop: tokio::sync::oneshot::Sender<()>,
    task: tokio::task::JoinHandle<Result<(), hub::HubError>>,
    station: BenchStation,
    ca_pem: std::path::PathBuf,
    _dir: tempfile::TempDir,
}

async fn start_hub() -> RunningHub {
    let dir = tempfile::tempdir().unwrap();
    let clinic = Clinic::at(dir.path().join("clinic"));
    clinic
        .init(
            "root@clinic.example",
            &["localhost".to_owned()],
            None,
            now_ms(),
        )
        .await
        .unwrap();
    let db = clinic.open_db(None).await.unwrap();
    db.add_therapist("ada@clinic.example", PASSWORD, Role::Therapist, now_ms())
        .await
        .unwrap();
    let stations_dir = dir.path().join("stations");
    let mut provisioned = hub::bench::provision(
        &db,
        &clinic.ca().unwrap(),
        "localhost",
        1,
        &stations_dir,
        now_ms(),
    )
    .await
    .unwrap();
    let options = ServeOptions {
        now_ms: Arc::new(now_ms),
        ..ServeOptions::new(
            "127.0.0.1:0".parse().unwrap(),
            Some("127.0.0.1:0".parse().unwrap()),
        )
    };
    let events = Arc::new(std::sync::Mutex::new(Vec::new()));
    let (bound_tx, bound_rx) = tokio::sync::oneshot::channel();
    let (stop, stopped) = tokio::sync::oneshot::channel::<()>();
    let seen = events.clone();
    let task = tokio::spawn(async move {
        hub::clinic::serve(
            &clinic,
            db,
            options,
            move |b| {
                let _ = bound_tx.send(b);
            },
            move |e| seen.lock().unwrap().push(e.clone()),
            async move {
                let _ = stopped.await;
            },
        )
        .await
    });
    let bound = tokio::time::timeout(GUARD, bound_rx)
        .await
        .expect("hub listening")
        .expect("hub started");
    RunningHub {
        bound,
        events,
        stop,
        task,
        station: provisioned.remove(0),
        ca_pem: stations_dir.join("ca.crt"),
        _dir: dir,
    }
}

/// The paired station connects (from 127.0.0.1), says Hello, sends one summary and waits for
/// its Ack.
async fn station_streams(addr: SocketAddr, st: &BenchStation) -> Result<(), String> {
    let (connector, name) = st.tls.connector().map_err(|e| e.to_string())?;
    let tcp = TcpStream::connect(addr).await.map_err(|e| e.to_string())?;
    let mut tls = connector
        .connect(name, tcp)
        .await
        .map_err(|e| format!("TLS: {e}"))?;
    let session_id = "hostile-s1".to_owned();
    let hello = Frame::Hello(Hello {
        protocol_version: PROTOCOL_VERSION,
        min_protocol_version: None,
        wheel: None,
        station_id: st.station_id.clone(),
        patient_id: st.patient_id.clone(),
        session_id: session_id.clone(),
        exercise: "sine-road".into(),
        started_unix_ms: netlink::frame::unix_ms_now(),
        software_version: "hostile test".into(),
    });
    for frame in [hello, Frame::Summary(Summary::example(&session_id, 0))] {
        let bytes = netlink::encode_to_vec(&frame).map_err(|e| e.to_string())?;
        tls.write_all(&bytes).await.map_err(|e| e.to_string())?;
    }
    let mut decoder = FrameDecoder::new();
    let mut buf = vec![0u8; 4096];
    loop {
        let n = tls.read(&mut buf).await.map_err(|e| e.to_string())?;
        if n == 0 {
            return Err("the hub closed the connection".into());
        }
        decoder.extend(&buf[..n]);
        while let Some(frame) = decoder.next_frame().map_err(|e| e.to_string())? {
            match frame {
                Frame::Ack(ack) if ack.seq == 0 => return Ok(()),
                Frame::Error(e) => return Err(format!("hub error: {}", e.message)),
                _ => {}
            }
        }
    }
}

/// A therapist logs in over HTTPS (from 127.0.0.1); the response status.
async fn login(addr: SocketAddr, ca_pem: &Path) -> Result<StatusCode, String> {
    let tls = ClientTls {
        ca_pem_path: ca_pem.to_owned(),
        server_name: "localhost".into(),
        identity: None,
    };
    let (connector, name) = tls.connector().map_err(|e| e.to_string())?;
    let tcp = TcpStream::connect(addr).await.map_err(|e| e.to_string())?;
    let stream = connector
        .connect(name, tcp)
        .await
        .map_err(|e| format!("TLS: {e}"))?;
    let (mut sender, connection) =
        hyper::client::conn::http1::handshake(hyper_util::rt::TokioIo::new(stream))
            .await
            .map_err(|e| e.to_string())?;
    tokio::spawn(connection);
    let body = serde_json::json!({ "email": "ada@clinic.example", "password": PASSWORD });
    let request = Request::post("/api/login")
        .header(header::HOST, "localhost")
        .header(header::CONTENT_TYPE, "application/json")
        .body(http_body_util::Full::new(axum::body::Bytes::from(
            body.to_string(),
        )))
        .map_err(|e| e.to_string())?;
    let response = sender
        .send_request(request)
        .await
        .map_err(|e| e.to_string())?;
    let status = response.status();
    let _ = response.into_body().collect().await;
    Ok(status)
}

/// A request whose head is complete and whose body (64 bytes announced) never comes.
const HALF_SENT: &[u8] = b"POST /api/login HTTP/1.1\r\nHost: localhost\r\n\
    Content-Type: application/json\r\nContent-Length: 64\r\n\r\n";

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn held_half_sent_requests_and_idle_station_connections_leave_a_station_and_a_login_within_1_s()
 {
    let limit = hub::limits::raise_fd_limit().unwrap().unwrap_or(u64::MAX);
    let budget = ConnectionBudget {
        stations: netlink::therapist::DEFAULT_MAX_CONNECTIONS,
        stations_unauthenticated: netlink::therapist::DEFAULT_MAX_UNAUTHENTICATED,
        web_connections: WebLimits::default().max_connections,
        web_unanswered: WebLimits::default().max_unanswered,
    };
    let clients =
        (HALF_SENT_REQUESTS + IDLE_STATION_CONNECTIONS + JUNK_FROM_STATION_ADDRESS) as u64;
    let needed = clients + budget.descriptors() + 512;
    if limit < needed {
        println!(
            "SKIPPED: the open-file limit is {limit}; holding {clients} hostile connections \
             beside the hub's budget needs {needed}"
        );
        return;
    }
    let hub = start_hub().await;
    let (stations_addr, web_addr) = (hub.bound.stations, hub.bound.web.unwrap());
    assert_eq!(
        hub.bound.budget, budget,
        "the caps fit a {limit} descriptor limit"
    );
    let fds_before = open_fds();
    let t0 = Instant::now();

    // 5 000 idle station-port connections from 1 000 addresses, and more than the per-address
    // cap from the station's own address.
    let mut idle = open_many(IDLE_STATION_CONNECTIONS, move |i| async move {
        connect_from(junk_address(1, i), stations_addr).await.ok()
    })
    .await;
    for _ in 0..JUNK_FROM_STATION_ADDRESS {
        idle.push(TcpStream::connect(stations_addr).await.unwrap());
    }
    // 5 000 half-sent requests over TLS from 1 000 other addresses.
    let ca_pem = hub.ca_pem.clone();
    let half_sent = open_many(HALF_SENT_REQUESTS, move |i| {
        let ca_pem = ca_pem.clone();
        async move {
            let tls = ClientTls {
                ca_pem_path: ca_pem,
                server_name: "localhost".into(),
                identity: None,
            };
            let (connector, name) = tls.connector().ok()?;
            let tcp = connect_from(junk_address(2, i), web_addr).await.ok()?;
            let mut stream = tokio::time::timeout(GUARD, connector.connect(name, tcp))
                .await
                .ok()?
                .ok()?;
            stream.write_all(HALF_SENT).await.ok()?;
            stream.flush().await.ok()?;
            Some(stream)
        }
    })
    .await;
    let opening_s = t0.elapsed().as_secs_f64();
    println!(
        "opened {} idle station connections and {} half-sent requests in {opening_s:.1} s",
        idle.len(),
        half_sent.len()
    );
    assert_eq!(
        idle.len(),
        IDLE_STATION_CONNECTIONS + JUNK_FROM_STATION_ADDRESS
    );
    assert!(
        half_sent.len() >= HALF_SENT_REQUESTS * 9 / 10,
        "only {} half-sent requests got through TLS",
        half_sent.len()
    );
    // The hub holds only its caps' worth of them; the rest it has closed.
    let hub_fds = open_fds().saturating_sub(fds_before + idle.len() + half_sent.len());
    let cap = budget.stations_unauthenticated + budget.web_unanswered + 64;
    assert!(
        hub_fds <= cap,
        "the hub holds {hub_fds} descriptors for hostile connections, more than its caps ({cap})"
    );

    let started = Instant::now();
    tokio::time::timeout(GUARD, station_streams(stations_addr, &hub.station))
        .await
        .expect("the station is answered")
        .expect("the paired station streams");
    let station_ms = started.elapsed().as_millis();
    let started = Instant::now();
    let status = tokio::time::timeout(GUARD, login(web_addr, &hub.ca_pem))
        .await
        .expect("the login is answered")
        .expect("the therapist reaches the console");
    let login_ms = started.elapsed().as_millis();
    println!("under the flood: station Ack in {station_ms} ms, login in {login_ms} ms");
    assert_eq!(status, StatusCode::OK);
    assert!(station_ms < 1000, "the station needed {station_ms} ms");
    assert!(login_ms < 1000, "the login needed {login_ms} ms");

    // 10 000 refused or evicted connections made a bounded number of lines.
    let elapsed_intervals = t0.elapsed().as_secs() / 10 + 2;
    let lines = hub
        .events
        .lock()
        .unwrap()
        .iter()
        .filter(|e| {
            matches!(
                e,
                TherapistEvent::ProtocolError { .. } | TherapistEvent::Refused { .. }
            )
        })
        .count() as u64;
    let bound = elapsed_intervals * (u64::from(REFUSAL_DETAILS_PER_INTERVAL) + 1);
    assert!(lines <= bound, "{lines} refusal lines, more than {bound}");
    drop(idle);
    drop(half_sent);
    hub.stop.send(()).unwrap();
    tokio::time::timeout(GUARD, hub.task)
        .await
        .expect("the hub stops")
        .unwrap()
        .unwrap();
}

/// The console app over plain HTTP on loopback within `limits`.
async fn console(limits: WebLimits) -> (SocketAddr, Db, tempfile::TempDir) {
    let (db, dir) = common::sqlite_db().await;
    let (live, _) = tokio::sync::broadcast::channel(16);
    let state = AppState::new(db.clone(), live);
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
    let addr = listener.local_addr().unwrap();
    tokio::spawn(web::serve_with_limits(
        listener,
        None,
        state,
        limits,
        std::future::pending(),
    ));
    (addr, db, dir)
}

/// Reads until the server closes; what it sent and how long that took.
async fn read_until_closed(stream: &mut TcpStream) -> (String, Duration) {
    let t0 = Instant::now();
    let mut text = Vec::new();
    let mut buf = [0u8; 4096];
    loop {
        match tokio::time::timeout(GUARD, stream.read(&mut buf)).await {
            Ok(Ok(0) | Err(_)) => break,
            Ok(Ok(n)) => text.extend_from_slice(&buf[..n]),
            Err(_) => panic!("the server kept the connection open for {GUARD:?}"),
        }
    }
    (String::from_utf8_lossy(&text).into_owned(), t0.elapsed())
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_half_sent_request_is_refused_at_the_body_deadline_and_an_idle_connection_closed_at_the_header_deadline()
 {
    let limits = WebLimits {
        header_read_timeout_ms: 400,
        body_timeout_ms: 400,
        ..WebLimits::default()
    };
    let (addr, _db, _dir) = console(limits).await;
    // Complete head, no body: answered 400 and closed, not held.
    let mut half = TcpStream::connect(addr).await.unwrap();
    half.write_all(HALF_SENT).await.unwrap();
    let (answer, waited) = read_until_closed(&mut half).await;
    assert!(answer.starts_with("HTTP/1.1 400"), "{answer}");
    assert!(
        waited >= Duration::from_millis(300),
        "closed after {waited:?}"
    );
    // Nothing sent at all: closed at the header deadline.
    let mut silent = TcpStream::connect(addr).await.unwrap();
    let (answer, _) = read_until_closed(&mut silent).await;
    assert!(!answer.contains("200 OK"), "{answer}");
    // An answered request, then idle: the keep-alive connection is closed too.
    let mut idle = TcpStream::connect(addr).await.unwrap();
    idle.write_all(b"GET /api/health HTTP/1.1\r\nHost: localhost\r\n\r\n")
        .await
        .unwrap();
    let (answer, _) = read_until_closed(&mut idle).await;
    assert!(answer.starts_with("HTTP/1.1 200"), "{answer}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn half_sent_requests_over_the_per_address_cap_push_out_the_oldest_not_a_login() {
    let limits = WebLimits {
        max_unanswered_per_address: 3,
        ..WebLimits::default()
    };
    let (addr, db, _dir) = console(limits).await;
    db.add_therapist("ada@clinic.example", PASSWORD, Role::Therapist, now_ms())
        .await
        .unwrap();
    let mut held = Vec::new();
    for _ in 0..3 {
        let mut s = TcpStream::connect(addr).await.unwrap();
        s.write_all(HALF_SENT).await.unwrap();
        held.push(s);
    }
    // A login from the same address: it replaces the oldest half-sent request and is answered
    // long before the 10 s body deadline.
    let body = serde_json::json!({ "email": "ada@clinic.example", "password": PASSWORD });
    let body = body.to_string();
    let mut login = TcpStream::connect(addr).await.unwrap();
    let request = format!(
        "POST /api/login HTTP/1.1\r\nHost: localhost\r\nContent-Type: application/json\r\n\
         Content-Length: {}\r\nConnection: close\r\n\r\n{body}",
        body.len()
    );
    login.write_all(request.as_bytes()).await.unwrap();
    let (answer, waited) = read_until_closed(&mut login).await;
    assert!(answer.starts_with("HTTP/1.1 200"), "{answer}");
    assert!(waited < Duration::from_secs(5), "the login took {waited:?}");
    let (oldest, waited) = read_until_closed(&mut held[0]).await;
    assert!(oldest.is_empty(), "closed without an answer: {oldest}");
    assert!(waited < Duration::from_secs(5), "closed after {waited:?}");
}
