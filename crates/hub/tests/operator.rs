//! What a clinic network's operator watches (issue 45): `/metrics` counts a station's session,
//! upload and refused connection by the right amounts on SQLite and PostgreSQL, and Debian's
//! `promtool check metrics` accepts the text; `/readyz` turns 503 naming the database while
//! PostgreSQL cannot be reached and 200 again after, names a recordings directory that takes
//! no file, and says "draining" once shutdown is asked; `/healthz` answers throughout. All over
//! loopback with the real link codec.

mod common;

use std::net::SocketAddr;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use common::PgDb;
use common::link::{
    GUARD, RunningHub, bye, clinic_with_station, clinic_with_station_on, exchange, hello,
    start_hub_with, summary_at, upload,
};
use hub::clinic::{Clinic, ServeOptions};
use netlink::{Frame, Hello};
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::{TcpListener, TcpStream};

/// `GET path` over plain HTTP/1.1: the status and the body.
async fn get(addr: SocketAddr, path: &str) -> (u16, String) {
    let mut tcp = TcpStream::connect(addr).await.unwrap();
    let request = format!("GET {path} HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n\r\n");
    tcp.write_all(request.as_bytes()).await.unwrap();
    let mut response = String::new();
    tokio::time::timeout(GUARD, tcp.read_to_string(&mut response))
        .await
        .expect("an answer")
        .unwrap();
    let status = response
        .split_whitespace()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("no status in {response:?}"));
    let body = response
        .split_once("\r\n\r\n")
        .map_or(String::new(), |(_, b)| b.to_owned());
    (status, body)
}

/// The value of the sample `name` (labels as the text writes them), if present.
fn sample(text: &str, name: &str) -> Option<f64> {
    text.lines()
        .find_map(|l| l.strip_prefix(name)?.strip_prefix(' ')?.parse().ok())
}

/// `name`'s value, 0 when it has no sample yet.
fn value(text: &str, name: &str) -> f64 {
    sample(text, &format!("telerehab_hub_{name}")).unwrap_or(0.0)
}

/// Debian's `promtool check metrics` on `text`: it must accept it with no lint problem.
fn promtool_accepts(text: &str) {
    let promtool = std::path::Path::new("/usr/bin/promtool");
    if !promtool.exists() {
        println!("SKIPPED: promtool is not installed (scripts/setup.sh installs prometheus)");
        return;
    }
    let mut child = std::process::Command::new(promtool)
        .args(["check", "metrics"])
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    std::io::Write::write_all(&mut child.stdin.take().unwrap(), text.as_bytes()).unwrap();
    let out = child.wait_with_output().unwrap();
    let said = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        out.status.success() && said.trim().is_empty(),
        "promtool check metrics: {said}\n{text}"
    );
}

/// A hub of `clinic` serving the operator's listener on a free loopback port.
async fn start_watched(clinic: &Clinic, drain: Duration) -> (RunningHub, SocketAddr) {
    let options = ServeOptions {
        metrics: Some("127.0.0.1:0".parse().unwrap()),
        drain,
        ..ServeOptions::new("127.0.0.1:0".parse().unwrap(), None)
    };
    let hub = start_hub_with(clinic, options).await;
    let metrics = hub.bound.metrics.expect("the operator's listener");
    (hub, metrics)
}

/// Polls `path` until `done(status, body)`, at most [`GUARD`]; the last answer.
async fn until(addr: SocketAddr, path: &str, done: impl Fn(u16, &str) -> bool) -> (u16, String) {
    let began = Instant::now();
    loop {
        let (status, body) = get(addr, path).await;
        if done(status, &body) || began.elapsed() > GUARD {
            return (status, body);
        }
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
}

const SUMMARIES: u64 = 7;
const RECORDING_BYTES: usize = 300_000;

async fn a_session_an_upload_and_a_refusal_move_the_counters_by_their_amounts(
    clinic: Clinic,
    st: hub::bench::BenchStation,
) {
    let (hub, metrics) = start_watched(&clinic, Duration::ZERO).await;
    let (status, before) = get(metrics, "/metrics").await;
    assert_eq!(status, 200);
    assert_eq!(value(&before, "summaries_ingested_total"), 0.0, "{before}");
    let addr = hub.bound.stations;
    let started = netlink::frame::unix_ms_now();
    let mut frames = vec![hello(&st, "s-ops", started)];
    frames.extend((0..SUMMARIES).map(|seq| summary_at("s-ops", seq, seq as f64 * 0.1)));
    frames.push(Frame::Bye(bye("s-ops", Some(SUMMARIES - 1))));
    let answered = exchange(addr, &st, &frames).await;
    assert!(
        answered
            .iter()
            .any(|f| matches!(f, Frame::Ack(a) if a.seq == SUMMARIES - 1)),
        "{answered:?}"
    );
    let until_at = Instant::now() + GUARD;
    let acked = upload(
        addr,
        st.clone(),
        "s-ops".into(),
        started,
        RECORDING_BYTES,
        until_at,
    )
    .await;
    assert_eq!(acked, RECORDING_BYTES as u64);
    // A station speaking for another patient is refused at admission.
    let stranger = Frame::Hello(Hello {
        patient_id: "someone-else".into(),
        ..common::hello(&st.station_id, &st.patient_id, "s-stranger")
    });
    exchange(addr, &st, &[stranger]).await;

    let (_, text) = until(metrics, "/metrics", |_, t| {
        value(t, "uploads_completed_total") >= 1.0
            && value(t, "station_refused_total{reason=\"wrong_patient\"}") >= 1.0
    })
    .await;
    assert_eq!(
        value(&text, "summaries_ingested_total"),
        SUMMARIES as f64,
        "{text}"
    );
    assert_eq!(value(&text, "ack_latency_seconds_count"), SUMMARIES as f64);
    assert_eq!(
        value(&text, "station_admitted_total"),
        2.0,
        "session and upload"
    );
    let refused = "station_refused_total{reason=\"wrong_patient\"}";
    assert_eq!(value(&text, refused), 1.0);
    assert_eq!(value(&text, "uploads_completed_total"), 1.0);
    assert_eq!(value(&text, "upload_bytes_total"), RECORDING_BYTES as f64);
    assert_eq!(value(&text, "uploads_failed_total"), 0.0);
    assert!(value(&text, "db_pool_max_connections") >= 4.0, "{text}");
    assert!(value(&text, "db_pool_connections") >= 1.0);
    assert!(value(&text, "process_start_time_seconds") > 1.7e9);
    // The first scrape is counted once answered: the second shows it.
    let scrapes = "http_requests_total{route=\"metrics\",status=\"2xx\"}";
    assert!(value(&text, scrapes) >= 1.0, "{text}");
    // No pseudonym, station or session id is ever a label.
    for private in [
        st.station_id.as_str(),
        &st.patient_id,
        "s-ops",
        "someone-else",
    ] {
        assert!(!text.contains(private), "{private} in\n{text}");
    }
    promtool_accepts(&text);

    let (status, body) = get(metrics, "/healthz").await;
    assert_eq!((status, body.as_str()), (200, r#"{"status":"alive"}"#));
    let (status, body) = get(metrics, "/readyz").await;
    assert_eq!(status, 200, "{body}");
    assert!(body.contains(r#""status":"ready""#), "{body}");
    hub.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn metrics_count_a_session_an_upload_and_a_refusal_on_sqlite() {
    let dir = tempfile::tempdir().unwrap();
    let (clinic, st) = clinic_with_station(dir.path()).await;
    a_session_an_upload_and_a_refusal_move_the_counters_by_their_amounts(clinic, st).await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn metrics_count_a_session_an_upload_and_a_refusal_on_postgres() {
    let Some(pg) = PgDb::create().await else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let (clinic, st) = clinic_with_station_on(dir.path(), Some(&pg.url)).await;
    a_session_an_upload_and_a_refusal_move_the_counters_by_their_amounts(clinic, st).await;
    pg.drop_db().await;
}

/// A TCP relay to `target` that can be cut (every connection closed, new ones refused) and
/// restored: the database's machine gone and back, as the hub sees it.
struct Relay {
    addr: SocketAddr,
    up: Arc<AtomicBool>,
    cut: tokio::sync::watch::Sender<u64>,
}

impl Relay {
    async fn to(target: SocketAddr) -> Self {
        let listener = TcpListener::bind("127.0.0.1:0").await.unwrap();
        let addr = listener.local_addr().unwrap();
        let up = Arc::new(AtomicBool::new(true));
        let (cut, cuts) = tokio::sync::watch::channel(0u64);
        let accepting = up.clone();
        tokio::spawn(async move {
            while let Ok((mut client, _)) = listener.accept().await {
                if !accepting.load(Ordering::SeqCst) {
                    continue; // dropped: closed at once
                }
                let mut cuts = cuts.clone();
                // Only a cut after this connection began ends it.
                cuts.borrow_and_update();
                tokio::spawn(async move {
                    let Ok(mut server) = TcpStream::connect(target).await else {
                        return;
                    };
                    tokio::select! {
                        _ = tokio::io::copy_bidirectional(&mut client, &mut server) => {}
                        _ = cuts.changed() => {}
                    }
                });
            }
        });
        Self { addr, up, cut }
    }

    fn cut(&self) {
        self.up.store(false, Ordering::SeqCst);
        self.cut.send_modify(|n| *n += 1);
    }

    fn restore(&self) {
        self.up.store(true, Ordering::SeqCst);
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn readyz_is_503_naming_the_database_while_postgres_is_unreachable_and_200_after() {
    let Some(pg) = PgDb::create().await else {
        return;
    };
    let target: SocketAddr = pg
        .url
        .split_once('@')
        .and_then(|(_, rest)| rest.split_once('/'))
        .map(|(hostport, _)| hostport.parse().unwrap())
        .expect("postgres://user@HOST:PORT/db");
    let relay = Relay::to(target).await;
    let relayed = pg.url.replace(&target.to_string(), &relay.addr.to_string());
    let dir = tempfile::tempdir().unwrap();
    let (clinic, _st) = clinic_with_station_on(dir.path(), Some(&relayed)).await;
    let (hub, metrics) = start_watched(&clinic, Duration::ZERO).await;
    let (status, body) = until(metrics, "/readyz", |s, _| s == 200).await;
    assert_eq!(status, 200, "{body}");

    relay.cut();
    let (status, body) = until(metrics, "/readyz", |s, _| s == 503).await;
    assert_eq!(status, 503, "{body}");
    assert!(body.contains("database: "), "{body}");
    assert!(!body.contains("recordings"), "{body}");
    // Liveness is not readiness: the process still answers.
    assert_eq!(get(metrics, "/healthz").await.0, 200);

    relay.restore();
    let (status, body) = until(metrics, "/readyz", |s, _| s == 200).await;
    assert_eq!(status, 200, "{body}");
    hub.stop().await;
    pg.drop_db().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn readyz_names_a_recordings_directory_that_takes_no_file_and_says_draining_at_shutdown() {
    let dir = tempfile::tempdir().unwrap();
    let (clinic, _st) = clinic_with_station(dir.path()).await;
    let (hub, metrics) = start_watched(&clinic, Duration::from_secs(3)).await;
    // A file where the directory should be (root ignores permissions, not this).
    let recordings = clinic.dir().join("recordings");
    let _ = std::fs::remove_dir_all(&recordings);
    std::fs::write(&recordings, b"not a directory").unwrap();
    let (status, body) = until(metrics, "/readyz", |s, _| s == 503).await;
    assert_eq!(status, 503, "{body}");
    assert!(body.contains("recordings: "), "{body}");
    std::fs::remove_file(&recordings).unwrap();
    let (status, body) = until(metrics, "/readyz", |s, _| s == 200).await;
    assert_eq!(status, 200, "{body}");

    let RunningHub { stop, task, .. } = hub;
    let _ = stop.send(());
    let (status, body) = until(metrics, "/readyz", |s, _| s == 503).await;
    assert_eq!(status, 503, "{body}");
    assert!(body.contains("draining"), "{body}");
    assert_eq!(get(metrics, "/healthz").await.0, 200);
    let stopped = tokio::time::timeout(GUARD, task).await;
    assert!(matches!(stopped, Ok(Ok(Ok(())))), "{stopped:?}");
}

/// The metric families the hub exports (every labelled one given a series first), by name.
fn exported_families() -> Vec<String> {
    let telemetry = hub::telemetry::Telemetry::new();
    telemetry.station_refused("revoked");
    telemetry.replay(hub::telemetry::ReplayOutcome::Started);
    telemetry.pain_mail(true);
    telemetry.http_request("health", 200, 0.001);
    telemetry
        .encode(None)
        .lines()
        .filter_map(|l| l.strip_prefix("# TYPE ")?.split(' ').next())
        .map(str::to_owned)
        .collect()
}

#[test]
fn the_operators_guide_explains_every_metric_and_the_shipped_alerts_pass_promtool() {
    let docs = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs");
    let guide = std::fs::read_to_string(docs.join("OPERATING.md")).unwrap();
    let rules_path = docs.join("operating/alerts.yml");
    let rules = std::fs::read_to_string(&rules_path).unwrap();
    let families = exported_families();
    assert!(families.len() >= 20, "{families:?}");
    for family in &families {
        let short = family.strip_prefix("telerehab_hub_").unwrap();
        assert!(
            guide.contains(&format!("| `{short}")),
            "docs/OPERATING.md has no row for {family}"
        );
    }
    // Every metric an alert names is one the hub exports (a renamed metric breaks no alert
    // silently).
    let named = rules
        .split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .filter(|w| w.starts_with("telerehab_hub_"));
    for name in named {
        let family = ["_bucket", "_count", "_sum"]
            .iter()
            .find_map(|s| name.strip_suffix(s))
            .unwrap_or(name);
        assert!(
            families.iter().any(|f| f == family),
            "alerts.yml names {name}, which the hub does not export"
        );
    }
    let promtool = std::path::Path::new("/usr/bin/promtool");
    if !promtool.exists() {
        println!("SKIPPED: promtool is not installed (scripts/setup.sh installs prometheus)");
        return;
    }
    let out = std::process::Command::new(promtool)
        .args(["check", "rules"])
        .arg(&rules_path)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "promtool check rules: {}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}
