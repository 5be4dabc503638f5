//! Client addresses behind the load balancer (issue 45): a hub behind a real HAProxy
//! (Debian's) that passes both ports through as TCP and sends a PROXY protocol v2 header
//! (`send-proxy-v2`), the hub trusting the balancer's address only (`[network]
//! proxy_protocol_from`).
//!
//! Two clients from different loopback addresses (127.0.0.2 and 127.0.0.3) reach the hub
//! through the same balancer: one using up its address's login allowance and its station-port
//! connections does not refuse the other, and the audit log and the hub's lines name the
//! clients, never the balancer. A forged header sent straight to the hub from an address it
//! does not trust is not believed, and a connection from the trusted address without a header
//! is closed with a line naming it.
//!
//! SQLite is enough (one hub); says SKIPPED without haproxy (`scripts/setup.sh` installs it).

use std::fs::File;
use std::io::{Read, Write};
use std::net::{IpAddr, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command};
use std::time::{Duration, Instant};

use telerehab_tests::balancer::Haproxy;
use telerehab_tests::clinic::NewClinic;
use telerehab_tests::console::{Console, connect_from};
use telerehab_tests::telerehab_bin;

/// Longest any step waits.
const GUARD: Duration = Duration::from_secs(30);
/// Unadmitted station connections one address may hold (`--max-connections-per-address`);
/// as many more wait in its line, and past that they are refused at once.
const PER_ADDRESS: usize = 2;
/// The first client, the one that uses up its allowances.
const X: &str = "127.0.0.2";
/// The second client, which must not be refused for the first one's doing.
const Y: &str = "127.0.0.3";
/// A client that sends the hub a forged header directly, claiming to be 10.9.9.9.
const FORGER: &str = "127.0.0.5";

fn ip(s: &str) -> IpAddr {
    s.parse().unwrap()
}

/// Waits until `path` holds a line with `needle`; that line.
fn line_with(path: &Path, needle: &str) -> String {
    let began = Instant::now();
    loop {
        let text = std::fs::read_to_string(path).unwrap_or_default();
        if let Some(line) = text.lines().find(|l| l.contains(needle)) {
            return line.to_owned();
        }
        assert!(
            began.elapsed() < GUARD,
            "no line with {needle:?} in {}:\n{text}",
            path.display()
        );
        std::thread::sleep(Duration::from_millis(25));
    }
}

/// `hub serve` of `data` with its station events (standard output) and log (standard error)
/// in files; its station and console addresses.
struct Hub {
    child: Child,
    out: PathBuf,
    log: PathBuf,
    stations: String,
    web: String,
}

impl Hub {
    fn serve(data: &Path, dir: &Path) -> Self {
        let (out, log) = (dir.join("hub.out"), dir.join("hub.log"));
        let child = Command::new(telerehab_bin())
            .args(["hub", "serve", "--data", data.to_str().unwrap()])
            .args(["--stations", "127.0.0.1:0", "--web", "127.0.0.1:0"])
            .args(["--max-connections-per-address", &PER_ADDRESS.to_string()])
            .stdout(File::create(&out).unwrap())
            .stderr(File::create(&log).unwrap())
            .spawn()
            .unwrap();
        let stations = line_with(&out, "stations listening on ");
        let stations = stations
            .strip_prefix("stations listening on ")
            .and_then(|r| r.split_whitespace().next())
            .unwrap()
            .to_owned();
        let web = line_with(&out, "console API on https://");
        let web = web
            .strip_prefix("console API on https://")
            .and_then(|r| r.strip_suffix("/api/"))
            .unwrap()
            .to_owned();
        Self {
            child,
            out,
            log,
            stations,
            web,
        }
    }
}

impl Drop for Hub {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// The configuration of a HAProxy of the test's own in front of `hub`, sending PROXY protocol v2
/// headers on both ports (what docs/DEPLOY.md shows). The station port's checks (a `LOCAL` header, then the
/// connection closed) each cost the hub a line of its 20 detailed refusals per 10 s, so they
/// run every 2 s as in DEPLOY.md, leaving room for the lines the test reads.
fn balancer_config(stations: u16, console: u16, hub: &Hub) -> String {
    format!(
        "global\n  maxconn 1024\n\
         defaults\n  timeout connect 2s\n  timeout client 1h\n  timeout server 1h\n  \
         timeout check 2s\n  retries 3\n\
         frontend stations\n  mode tcp\n  bind 127.0.0.1:{stations}\n  \
         default_backend hub_stations\n\
         backend hub_stations\n  mode tcp\n  \
         server a {hub_stations} send-proxy-v2 check inter 2s fall 1 rise 1\n\
         frontend console\n  mode tcp\n  bind 127.0.0.1:{console}\n  \
         default_backend hub_console\n\
         backend hub_console\n  mode tcp\n  \
         option httpchk\n  http-check send meth GET uri /readyz\n  \
         http-check expect status 200\n  \
         server a {hub_web} send-proxy-v2 check check-ssl verify none inter 300ms fall 1 rise 1\n",
        hub_stations = hub.stations,
        hub_web = hub.web,
    )
}

/// A failed login (an unknown e-mail of its own, so only the address throttle is shared)
/// through `console`; its status.
fn failed_login(console: &Console, n: usize) -> u16 {
    let body = format!(r#"{{"email": "nobody{n}@clinic.example", "password": "wrong"}}"#);
    console.request("POST", "/api/login", None, &body).status
}

/// Whether the hub closes `tcp` (reading to the end of the stream, past a TLS alert it may
/// send first, or to a reset) within [`GUARD`].
fn closed_by_the_hub(tcp: &mut TcpStream) -> bool {
    tcp.set_read_timeout(Some(GUARD)).unwrap();
    let mut buf = [0u8; 512];
    loop {
        match tcp.read(&mut buf) {
            Ok(0) => return true,
            Ok(_) => {}
            Err(e) => {
                return !matches!(
                    e.kind(),
                    std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
                );
            }
        }
    }
}

#[test]
fn clients_behind_haproxy_are_counted_and_audited_by_their_own_addresses() {
    let tmp = tempfile::tempdir().unwrap();
    let made = NewClinic::make(tmp.path(), None);
    let mut toml = std::fs::OpenOptions::new()
        .append(true)
        .open(made.data.join("hub.toml"))
        .unwrap();
    // The balancer connects to the hub from 127.0.0.1; the clients are other loopback addresses.
    writeln!(
        toml,
        "\n[network]\nproxy_protocol_from = [\"127.0.0.1/32\"]"
    )
    .unwrap();
    drop(toml);
    let hub = Hub::serve(&made.data, tmp.path());
    let Some(balancer) = Haproxy::start(tmp.path(), |st, web| balancer_config(st, web, &hub))
    else {
        return;
    };
    let via_balancer = Console::new(&made.data, &format!("127.0.0.1:{}", balancer.console));
    let began = Instant::now();
    while via_balancer.request("GET", "/readyz", None, "").status != 200 {
        assert!(
            began.elapsed() < GUARD,
            "the console never answered through the balancer"
        );
        std::thread::sleep(Duration::from_millis(100));
    }

    // The login allowance: X's failures are X's alone.
    let x = Console::new(&made.data, &format!("127.0.0.1:{}", balancer.console)).from_source(ip(X));
    let y = Console::new(&made.data, &format!("127.0.0.1:{}", balancer.console)).from_source(ip(Y));
    let mut x_statuses: Vec<u16> = (0..5).map(|n| failed_login(&x, n)).collect();
    assert_eq!(x_statuses, [401; 5], "five free failures");
    // The sixth is evaluated once the first delay (1 s) is over; X must then wait 2 s, and
    // Y's attempt comes within them (had the hub counted both as the balancer, it would be
    // refused as X's next one is).
    let began = Instant::now();
    loop {
        let status = failed_login(&x, x_statuses.len());
        x_statuses.push(status);
        if status == 401 {
            break;
        }
        assert_eq!(status, 429, "{x_statuses:?}");
        assert!(began.elapsed() < GUARD, "{x_statuses:?}");
        std::thread::sleep(Duration::from_millis(200));
    }
    let throttled = failed_login(&x, 99);
    x_statuses.push(throttled);
    assert_eq!(throttled, 429, "X's address is throttled: {x_statuses:?}");
    assert_eq!(
        failed_login(&y, 100),
        401,
        "Y's attempt is evaluated, not throttled for X's failures"
    );

    // The audit log names the clients, not the balancer.
    let admin = Console::new(&made.data, &format!("127.0.0.1:{}", balancer.console))
        .from_source(ip("127.0.0.4"));
    let cookie = admin.login("ana@clinic.example", &made.admin_password);
    let audit = admin.get("/api/audit?limit=200", &cookie);
    assert_eq!(audit.status, 200);
    let audit = String::from_utf8_lossy(&audit.body).into_owned();
    assert!(audit.contains(&format!("from {X}")), "{audit}");
    assert!(audit.contains(&format!("from {Y}")), "{audit}");
    assert!(!audit.contains("from 127.0.0.1"), "{audit}");

    // The station port: X fills its slots and its line with idle connections; its next one
    // is refused at once, while Y's connection is served (its TLS handshake fails on the
    // garbage it sends, and the hub's line names Y).
    let x_idle: Vec<TcpStream> = (0..2 * PER_ADDRESS)
        .map(|_| connect_from(Some(ip(X)), &format!("127.0.0.1:{}", balancer.stations)))
        .collect();
    // Each idle connection is through the balancer and counted before the next test step.
    std::thread::sleep(Duration::from_millis(200));
    let mut x_over = connect_from(Some(ip(X)), &format!("127.0.0.1:{}", balancer.stations));
    assert!(
        closed_by_the_hub(&mut x_over),
        "X's connection past its line was kept"
    );
    let mut y_conn = connect_from(Some(ip(Y)), &format!("127.0.0.1:{}", balancer.stations));
    y_conn.write_all(b"not TLS at all\r\n\r\n").unwrap();
    let line = line_with(&hub.out, &format!("[{Y}:"));
    assert!(line.contains("protocol error"), "{line}");
    drop(x_idle);
    // The balancer's own checks (a `LOCAL` header, then closed) keep the balancer's address.
    let check = line_with(&hub.out, "[127.0.0.1:");
    assert!(check.contains("protocol error"), "{check}");

    // A forged header straight to the hub from an address it does not trust: not believed
    // (the header is not read; its bytes fail the TLS handshake, which names the real peer).
    let mut forged = connect_from(Some(ip(FORGER)), &hub.stations);
    forged
        .write_all(b"PROXY TCP4 10.9.9.9 127.0.0.1 1111 4433\r\nnot TLS either\r\n\r\n")
        .unwrap();
    assert!(closed_by_the_hub(&mut forged));
    let line = line_with(&hub.out, &format!("[{FORGER}:"));
    assert!(line.contains("TLS handshake failed"), "{line}");
    let out = std::fs::read_to_string(&hub.out).unwrap();
    assert!(!out.contains("10.9.9.9"), "{out}");

    // From the trusted address without a header: closed, and the log names it.
    let mut bare = connect_from(None, &hub.web);
    bare.write_all(&[0x16, 0x03, 0x01, 0x00, 0xc8, 0x01, 0x00, 0x00, 0xc4])
        .unwrap();
    assert!(closed_by_the_hub(&mut bare));
    let line = line_with(&hub.log, "did not start with a PROXY protocol header");
    assert!(
        line.contains("127.0.0.1") && line.contains("console port"),
        "{line}"
    );
    println!(
        "x logins {x_statuses:?}; y evaluated; audit names {X} and {Y}; station line: {}",
        line_with(&hub.out, &format!("[{Y}:"))
    );
}
