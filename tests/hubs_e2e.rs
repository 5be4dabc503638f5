//! Several hubs, no shared disk (issue 45): two `hub serve` processes, each with a data
//! directory of its own (a copy of the clinic's configuration and keys; no recordings), sharing
//! only PostgreSQL and a real S3 store (SeaweedFS), behind a real HAProxy (Debian's) that
//! passes the station port through as TCP (mutual TLS stays end to end) and checks the
//! console's `/readyz`, both with PROXY protocol v2 headers naming the client (`send-proxy-v2`;
//! the balancer connects from 127.0.0.2, the one address the hubs trust with
//! `[network] proxy_protocol_from`; the test's own direct connections come from 127.0.0.1).
//!
//! One day of it: a station pairs and exercises through the balancer (on hub A); a therapist
//! logged in on hub B watches its summaries live; hub A is SIGKILLed mid-session and the
//! station finishes on hub B with every summary stored exactly once and its recording in the
//! store; hub A comes back, the station's next session lands on it, and a revocation on hub B
//! drops it within a measured bound; failed logins spread over both hubs get one address's
//! allowance, not two.
//!
//! Needs PostgreSQL (`bash scripts/with-postgres.sh cargo test -p telerehab-tests --test
//! hubs_e2e`) and haproxy (`scripts/setup.sh`); says SKIPPED without either.

#[path = "../crates/hub/tests/common/s3.rs"]
mod s3;

use std::io::Write;
use std::path::Path;
use std::process::{Child, Command};
use std::sync::mpsc::Receiver;
use std::time::{Duration, Instant};

use telerehab_tests::balancer::Haproxy;
use telerehab_tests::clinic::{Hub, NewClinic, fresh_postgres_database, show, show_json};
use telerehab_tests::console::Console;
use telerehab_tests::spawn_real_time_session;

/// Longest any step waits.
const GUARD: Duration = Duration::from_secs(30);

/// How long after a revocation on one hub its station's connection to another hub must have
/// ended: the hubs re-read the revoked stations every second (`REVOCATION_POLL`), and the
/// next summary (10 a second) of the revoked station ends its connection; the margin is a
/// loaded 2-core machine's.
const REVOKED_WITHIN: Duration = Duration::from_secs(3);

fn port_of(addr: &str) -> &str {
    addr.rsplit(':').next().unwrap()
}

/// The balancer's configuration in front of hubs `a` and `b`: what docs/DEPLOY.md shows, on
/// these ports.
fn balancer_config(stations: u16, console: u16, a: &Hub, b: &Hub) -> String {
    let (a_st, b_st) = (a.stations_port(), b.stations_port());
    let (a_web, b_web) = (port_of(a.web()), port_of(b.web()));
    format!(
        "global\n  maxconn 1024\n\
         defaults\n  timeout connect 2s\n  timeout client 1h\n  timeout server 1h\n  \
         timeout check 2s\n  retries 3\n  option redispatch\n\
         frontend stations\n  mode tcp\n  bind 127.0.0.1:{stations}\n  \
         default_backend hub_stations\n\
         backend hub_stations\n  mode tcp\n  balance first\n  \
         server a 127.0.0.1:{a_st} source 127.0.0.2 send-proxy-v2 check inter 300ms fall 1 rise 2\n  \
         server b 127.0.0.1:{b_st} source 127.0.0.2 send-proxy-v2 check inter 300ms fall 1 rise 2\n\
         frontend console\n  mode tcp\n  bind 127.0.0.1:{console}\n  \
         default_backend hub_console\n\
         backend hub_console\n  mode tcp\n  balance roundrobin\n  \
         option httpchk\n  http-check send meth GET uri /readyz\n  \
         http-check expect status 200\n  \
         server a 127.0.0.1:{a_web} source 127.0.0.2 send-proxy-v2 check check-ssl verify none inter 300ms fall 1 rise 2\n  \
         server b 127.0.0.1:{b_web} source 127.0.0.2 send-proxy-v2 check check-ssl verify none inter 300ms fall 1 rise 2\n"
    )
}

/// Copies the clinic's directory `from` to `to`: a second hub machine's own disk, with the
/// same configuration and keys.
fn copy_dir(from: &Path, to: &Path) {
    let status = Command::new("cp")
        .arg("-a")
        .arg(from)
        .arg(to)
        .status()
        .unwrap();
    assert!(status.success());
}

/// Puts the clinic's recordings in the S3 store `s3` (`hub.toml`'s `[recordings]`), and has
/// the hub read the balancer's PROXY headers (`[network]`, as docs/DEPLOY.md configures it).
fn recordings_in(data: &Path, s3: &s3::SeaweedS3) {
    let config = s3.config();
    let credentials = config.credentials_file.unwrap();
    let mut toml = std::fs::OpenOptions::new()
        .append(true)
        .open(data.join("hub.toml"))
        .unwrap();
    write!(
        toml,
        "\n[recordings]\nstore = \"s3\"\nbucket = \"{}\"\nendpoint = \"{}\"\n\
         allow_http = true\ncredentials_file = \"{}\"\n\
         \n[network]\nproxy_protocol_from = [\"127.0.0.2/32\"]\n",
        s3::BUCKET,
        s3.endpoint,
        credentials.display()
    )
    .unwrap();
}

/// `hub serve` of `data` on `stations` (and the console on `web`), with `/metrics`.
fn serve(data: &Path, stations: &str, web: &str) -> Hub {
    Hub::serve_with(
        data,
        stations,
        &["--web", web, "--metrics-listen", "127.0.0.1:0"],
    )
}

/// The stations connected to `hub` and admitted, from its `/metrics`.
fn connected_stations(hub: &Hub) -> u64 {
    let Ok(mut tcp) = std::net::TcpStream::connect(hub.metrics.as_deref().unwrap()) else {
        return 0;
    };
    let _ = tcp.set_read_timeout(Some(Duration::from_secs(2)));
    let _ = tcp.write_all(b"GET /metrics HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n");
    let mut text = String::new();
    let _ = std::io::Read::read_to_string(&mut tcp, &mut text);
    text.lines()
        .find_map(|l| l.strip_prefix("telerehab_hub_station_connections "))
        .and_then(|v| v.trim().parse::<f64>().ok())
        .map_or(0, |v| v as u64)
}

/// Waits until `hub` has `n` stations connected; how long that took.
fn until_connected(hub: &Hub, n: u64) -> Duration {
    let began = Instant::now();
    while connected_stations(hub) != n {
        assert!(
            began.elapsed() < GUARD,
            "hub never had {n} stations connected"
        );
        std::thread::sleep(Duration::from_millis(25));
    }
    began.elapsed()
}

/// The next live summary of session `session` (any session when `None`) on `events`: its
/// session and sequence number.
fn next_summary(events: &Receiver<(String, String)>, session: Option<&str>) -> (String, u64) {
    let began = Instant::now();
    loop {
        let left = GUARD.saturating_sub(began.elapsed());
        let (event, data) = events.recv_timeout(left).expect("a live summary");
        if event != "summary" {
            continue;
        }
        let v: serde_json::Value = serde_json::from_str(&data).unwrap();
        let id = v["session_id"].as_str().unwrap().to_owned();
        if session.is_none_or(|s| s == id) {
            return (id, v["summary"]["seq"].as_u64().unwrap());
        }
    }
}

/// A finished `telerehab run`'s report (standard output and error).
fn report_of(child: Child) -> String {
    let out = child.wait_with_output().unwrap();
    format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    )
}

/// Waits until the console answers `/readyz` with 200 (through the balancer: a hub passed
/// its checks).
fn until_ready(console: &Console) {
    let began = Instant::now();
    while console.request("GET", "/readyz", None, "").status != 200 {
        assert!(began.elapsed() < GUARD, "no ready hub");
        std::thread::sleep(Duration::from_millis(100));
    }
}

/// `telerehab pair` of the station in `home` through `hub` with `code`; the station's id.
fn pair_through(hub: &str, code: &str, home: &Path) -> String {
    let paired = telerehab_tests::clinic::ok(&["pair", "--hub", hub, "--code", code], Some(home));
    assert!(
        paired.starts_with("paired: this station is st-"),
        "{paired}"
    );
    telerehab_tests::clinic::after(&paired, "this station is ")
        .trim_end_matches(',')
        .to_owned()
}

/// The run that `report` ends delivered every summary, stored exactly once by the clinic of
/// `data`, and uploaded its recording, which is complete in the S3 store (not on a hub's disk).
fn assert_delivered_once_into_the_store(report: &str, data: &Path) {
    let n = telerehab_tests::clinic::produced(report);
    assert!(
        report.contains(&format!("{n} sent, {n} acknowledged, 0 NOT delivered")),
        "{report}"
    );
    assert!(
        report.contains("recording upload    1 uploaded"),
        "{report}"
    );
    let (stored, _) = show(data);
    assert_eq!(stored, vec![n], "summaries stored exactly once");
    let recording = &show_json(data)["sessions"][0]["recording"];
    assert_eq!(recording["complete"], true, "{recording}");
    assert!(
        recording["path"].as_str().unwrap().starts_with("s3://"),
        "{recording}"
    );
}

/// `n` logins with a wrong password for the clinic's admin, sent at once, in turn to each of
/// `consoles`; their statuses.
fn failed_logins_at_once(consoles: &[Console], n: usize) -> Vec<u16> {
    std::thread::scope(|scope| {
        let tries: Vec<_> = (0..n)
            .map(|i| {
                let console = &consoles[i % consoles.len()];
                scope.spawn(move || {
                    let body = r#"{"email": "ana@clinic.example", "password": "not the password"}"#;
                    console.request("POST", "/api/login", None, body).status
                })
            })
            .collect();
        tries.into_iter().map(|t| t.join().unwrap()).collect()
    })
}

#[test]
fn two_hubs_behind_haproxy_share_live_data_revocation_throttles_and_lose_nothing_to_a_kill() {
    let test_began = Instant::now();
    let Some(url) = fresh_postgres_database() else {
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .unwrap();
    let s3 = runtime.block_on(s3::SeaweedS3::start());
    let made = NewClinic::make(tmp.path(), Some(&url));
    let (data_a, data_b) = (made.data.clone(), tmp.path().join("clinic-b"));
    copy_dir(&data_a, &data_b);
    recordings_in(&data_a, &s3);
    recordings_in(&data_b, &s3);
    let mut a = serve(&data_a, "127.0.0.1:0", "127.0.0.1:0");
    let b = serve(&data_b, "127.0.0.1:0", "127.0.0.1:0");
    let (a_stations, a_web) = (
        format!("127.0.0.1:{}", a.stations_port()),
        a.web().to_owned(),
    );
    let Some(balancer) = Haproxy::start(tmp.path(), |st, web| balancer_config(st, web, &a, &b))
    else {
        return;
    };
    let through = format!("localhost:{}", balancer.stations);

    // The console through the balancer: both hubs pass their readiness checks and answer.
    until_ready(&Console::new(
        &data_a,
        &format!("127.0.0.1:{}", balancer.console),
    ));

    // Pairing and the first session through the balancer (hub A, the first server).
    let home = tmp.path().join("station");
    let station_id = pair_through(&through, &made.code, &home);
    let patient_id = show_json(&data_b)["patient"]["id"]
        .as_str()
        .unwrap()
        .to_owned();

    // A therapist on hub B watches the patient live.
    let console_b = Console::new(&data_b, b.web());
    let cookie = console_b.login("ana@clinic.example", &made.admin_password);
    let live = console_b.events(&format!("/api/patients/{patient_id}/live"), &cookie);
    let session = spawn_real_time_session("8", |c| c.env("TELEREHAB_HOME", &home));
    until_connected(&a, 1);
    let (session_1, first_seq) = next_summary(&live, None);
    println!("hub B shows session {session_1} live from seq {first_seq} (station on hub A)");

    // Hub A dies mid-session: the station reconnects through the balancer to hub B.
    std::thread::sleep(Duration::from_secs(2));
    a.child.kill().unwrap();
    a.child.wait().unwrap();
    let killed = Instant::now();
    until_connected(&b, 1);
    println!(
        "the station reached hub B {:.1} s after hub A was killed",
        killed.elapsed().as_secs_f64()
    );
    // Live data keeps coming, now from hub B itself.
    next_summary(&live, Some(&session_1));
    assert_delivered_once_into_the_store(&report_of(session), &data_b);

    // Hub A comes back on its ports; the next session lands on it (the balancer's first).
    let a = serve(&data_a, &a_stations, &a_web);
    // The balancer sees it up again after two good checks (300 ms apart).
    std::thread::sleep(Duration::from_millis(1500));
    let session = spawn_real_time_session("8", |c| c.env("TELEREHAB_HOME", &home));
    until_connected(&a, 1);
    // (Session 1's last summaries may still be queued on the stream.)
    let session_2 = loop {
        let (id, _) = next_summary(&live, None);
        if id != session_1 {
            break id;
        }
    };
    println!("hub B shows session {session_2} live (station on hub A again)");
    // Revoked from hub B's console: hub A drops the station.
    let revoked = console_b.request(
        "POST",
        &format!("/api/stations/{station_id}/revoke"),
        Some(&cookie),
        "{}",
    );
    assert_eq!(revoked.status, 200, "{:?}", revoked.body);
    let dropped_after = until_connected(&a, 0);
    println!(
        "a revocation on hub B dropped the station from hub A after {:.2} s",
        dropped_after.as_secs_f64()
    );
    assert!(dropped_after < REVOKED_WITHIN, "{dropped_after:?}");
    let report = report_of(session);
    assert!(
        report.contains("has been revoked by the clinic"),
        "{report}"
    );
    assert_eq!(connected_stations(&b), 0, "nor did it get in on hub B");

    // Failed logins from one address, sent at once and spread over both hubs: one address's
    // free allowance is evaluated in all, not one per hub.
    let answers = failed_logins_at_once(&[Console::new(&data_a, a.web()), console_b], 12);
    // Each attempt must win a place on the address's count and on the account's (here: its
    // familiar place's) at once, so of parallel attempts at most the free allowance is
    // evaluated; counted per hub, each would evaluate at least 4 of its 6.
    let evaluated = answers.iter().filter(|s| **s == 401).count();
    let throttled = answers.iter().filter(|s| **s == 429).count();
    let free = usize::try_from(hub::db::ADDRESS_FREE_FAILURES).unwrap();
    assert!(
        (1..=free).contains(&evaluated) && evaluated + throttled == answers.len(),
        "{answers:?}"
    );
    println!(
        "12 failed logins at once over two hubs: {evaluated} evaluated, {throttled} throttled"
    );

    drop(balancer);
    a.stop();
    b.stop();
    println!(
        "several hubs end to end: {:.1} s",
        test_began.elapsed().as_secs_f64()
    );
}
