//! A clinic's hub (`hub serve`) and the plain summary hub (`therapist`) stop on SIGINT and
//! SIGTERM within 5 s whatever they are doing — under a flood of connections, mid-upload,
//! mid-pairing — and what they acknowledged is still there when they come back.

use std::io::{Read, Write};
use std::net::TcpStream;
use std::path::Path;
use std::process::{Command, Stdio};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use telerehab_tests::clinic::{Hub, clinic, ok, produced, run_session, show, show_json, telerehab};
use telerehab_tests::{TherapistHub, stored_seqs};

/// What the issue asks of every stop.
const STOP_LIMIT: Duration = Duration::from_secs(5);

/// Connections opened and written to as fast as one thread can, each held until the flood
/// ends: a client that never finishes what it starts.
struct Flood {
    stop: Arc<AtomicBool>,
    threads: Vec<std::thread::JoinHandle<usize>>,
}

impl Flood {
    /// `threads` threads flooding each of `addrs` (`host:port`).
    fn start(addrs: &[String], threads: usize) -> Self {
        let stop = Arc::new(AtomicBool::new(false));
        let threads = addrs
            .iter()
            .flat_map(|a| std::iter::repeat_n(a.clone(), threads))
            .map(|addr| {
                let stop = stop.clone();
                std::thread::spawn(move || {
                    let mut held = Vec::new();
                    let mut opened = 0;
                    while !stop.load(Ordering::Relaxed) {
                        if let Ok(mut c) = TcpStream::connect(&addr) {
                            // Half a TLS record header, half an HTTP request line.
                            let _ = c.write_all(b"\x16\x03\x01\x02GET /api/health HT");
                            opened += 1;
                            if held.len() < 200 {
                                held.push(c);
                            }
                        } else {
                            std::thread::sleep(Duration::from_millis(5));
                        }
                    }
                    opened
                })
            })
            .collect();
        std::thread::sleep(Duration::from_millis(500));
        Self { stop, threads }
    }

    /// Ends the flood; connections opened.
    fn end(self) -> usize {
        self.stop.store(true, Ordering::Relaxed);
        self.threads.into_iter().map(|t| t.join().unwrap()).sum()
    }
}

#[test]
fn hub_serve_stops_within_5_s_of_sigint_under_a_flood_and_keeps_what_it_acknowledged() {
    let tmp = tempfile::tempdir().unwrap();
    let (data, code) = clinic(tmp.path());
    let mut hub = Hub::serve_with(&data, "127.0.0.1:0", &["--web", "127.0.0.1:0"]);
    let home = tmp.path().join("station");
    ok(
        &["pair", "--hub", &hub.stations, "--code", &code],
        Some(&home),
    );
    let n = produced(&run_session(&home, "3"));
    let station_port = hub.stations_port();
    let web = hub.web.clone().unwrap();
    let flood = Flood::start(&[format!("127.0.0.1:{station_port}"), web], 2);
    let took = hub.signal_and_wait("INT", STOP_LIMIT);
    let opened = flood.end();
    assert!(took.is_some(), "still running {STOP_LIMIT:?} after SIGINT");
    assert!(opened > 100, "the flood opened only {opened} connections");
    // Back up: every summary the station was acknowledged is stored, once.
    let again = Hub::serve(&data, &format!("127.0.0.1:{station_port}"));
    assert_eq!(show(&data).0, vec![n]);
    again.stop();
}

#[test]
fn therapist_stops_within_5_s_of_sigint_under_a_flood_and_keeps_what_it_acknowledged() {
    let tmp = tempfile::tempdir().unwrap();
    let store = tmp.path().join("store");
    let hub = TherapistHub::start(&store);
    let run = telerehab(
        &[
            "run",
            "--sim",
            "--headless",
            "--speed",
            "max",
            "--duration",
            "3",
            "--therapist",
            &hub.addr,
        ],
        Some(&tmp.path().join("home")),
    );
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let stored_before = stored_seqs(&store, "station-1");
    assert!(!stored_before.is_empty());
    let mut hub = hub;
    let flood = Flood::start(std::slice::from_ref(&hub.addr), 4);
    let took = hub.signal_and_wait("INT", STOP_LIMIT);
    let opened = flood.end();
    assert!(took.is_some(), "still running {STOP_LIMIT:?} after SIGINT");
    assert!(opened > 100, "the flood opened only {opened} connections");
    assert_eq!(stored_seqs(&store, "station-1"), stored_before);
}

#[test]
fn hub_serve_stops_within_5_s_of_sigterm_mid_upload_and_the_upload_resumes() {
    let tmp = tempfile::tempdir().unwrap();
    let (data, code) = clinic(tmp.path());
    let hub = Hub::serve(&data, "127.0.0.1:0");
    let port = hub.stations_port();
    let home = tmp.path().join("station");
    ok(
        &["pair", "--hub", &hub.stations, "--code", &code],
        Some(&home),
    );
    hub.stop();
    // A session while the hub is down: its recording (about 2 MB, 2 s at the station's
    // 1 MB/s) waits for `sync`.
    let n = produced(&run_session(&home, "20"));

    let mut hub = Hub::serve(&data, &format!("127.0.0.1:{port}"));
    let mut sync = Command::new(telerehab_tests::telerehab_bin())
        .arg("sync")
        .env("TELEREHAB_HOME", &home)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let recordings = data.join("recordings");
    let deadline = Instant::now() + Duration::from_secs(30);
    while !has_file(&recordings, "part") {
        assert!(Instant::now() < deadline, "no upload began within 30 s");
        std::thread::sleep(Duration::from_millis(10));
    }
    let took = hub.signal_and_wait("TERM", STOP_LIMIT);
    assert!(
        took.is_some(),
        "still running {STOP_LIMIT:?} after SIGTERM mid-upload"
    );
    let _ = sync.wait();

    let hub = Hub::serve(&data, &format!("127.0.0.1:{port}"));
    let synced = ok(&["sync"], Some(&home));
    assert!(synced.contains("0 summaries still queued"), "{synced}");
    assert_eq!(show(&data).0, vec![n]);
    let recording = &show_json(&data)["sessions"][0]["recording"];
    assert_eq!(recording["complete"], true, "{recording}");
    assert!(
        !has_file(&recordings, "part"),
        "the partial copy became the recording"
    );
    hub.stop();
}

#[test]
fn hub_serve_stops_within_5_s_of_sigint_mid_pairing_and_the_code_still_pairs() {
    let tmp = tempfile::tempdir().unwrap();
    let (data, code) = clinic(tmp.path());
    let mut hub = Hub::serve(&data, "127.0.0.1:0");
    let port = hub.stations_port();
    // A station that starts pairing and goes quiet: TLS, PairStart, the hub's challenge, and
    // no PairFinish (the hub waits for it).
    let mut client = Command::new("openssl")
        .args([
            "s_client",
            "-quiet",
            "-connect",
            &format!("127.0.0.1:{port}"),
        ])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("openssl (scripts/setup.sh installs it)");
    let start = pair_start(&code);
    client.stdin.as_mut().unwrap().write_all(&start).unwrap();
    let mut challenge = [0u8; 8];
    client
        .stdout
        .as_mut()
        .unwrap()
        .read_exact(&mut challenge)
        .unwrap();

    let took = hub.signal_and_wait("INT", STOP_LIMIT);
    let _ = client.kill();
    let _ = client.wait();
    assert!(
        took.is_some(),
        "still running {STOP_LIMIT:?} after SIGINT mid-pairing"
    );

    // The interrupted attempt did not burn the code: after its wait, it pairs.
    let hub = Hub::serve(&data, &format!("127.0.0.1:{port}"));
    let wait_ms = u64::try_from(::hub::db::MIN_ATTEMPT_WAIT_MS).unwrap() + 100;
    std::thread::sleep(Duration::from_millis(wait_ms));
    let home = tmp.path().join("station");
    let paired = ok(
        &["pair", "--hub", &hub.stations, "--code", &code],
        Some(&home),
    );
    assert!(
        paired.starts_with("paired: this station is st-"),
        "{paired}"
    );
    hub.stop();
}

/// A `PairStart` frame for `code` with a real SPAKE2 message, as a station's first bytes.
fn pair_start(code: &str) -> Vec<u8> {
    use spake2::{Ed25519Group, Identity, Password, Spake2};
    let code = netlink::pairing::PairingCode::parse(code).unwrap();
    let (_, message) = Spake2::<Ed25519Group>::start_a(
        &Password::new(code.secret().as_bytes()),
        &Identity::new(b"telerehab station"),
        &Identity::new(b"telerehab hub"),
    );
    let hex: String = message.iter().map(|b| format!("{b:02x}")).collect();
    netlink::encode_to_vec(&netlink::frame::Frame::PairStart(
        netlink::frame::PairStart {
            code_id: code.code_id().to_owned(),
            pake: hex,
        },
    ))
    .unwrap()
}

/// Whether a file ending in `.ext` is anywhere under `dir` (one level of subdirectories).
fn has_file(dir: &Path, ext: &str) -> bool {
    std::fs::read_dir(dir)
        .into_iter()
        .flatten()
        .flatten()
        .flat_map(|e| std::fs::read_dir(e.path()).into_iter().flatten().flatten())
        .any(|e| e.path().extension().is_some_and(|x| x == ext))
}
