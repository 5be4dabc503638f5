//! A patient's home network for the end-to-end tests: a network namespace "home" joined to the
//! root namespace (where the hub runs) by a veth pair, whose link the test degrades as home
//! internet does — down and up (an outage, a flapping link), packet loss (nftables' `numgen
//! random` in the namespace), a slow uplink (`tc tbf`), and a round-trip delay: `tc netem` when
//! the kernel has it, otherwise Toxiproxy (Shopify's TCP fault proxy, which `scripts/setup.sh`
//! builds into `~/.local/bin/toxiproxy-server`) between the station and the hub. Needs root and
//! `ip`; [`Home::make`] says why not otherwise, for the caller to print `SKIPPED`.

use std::io::{Read, Write};
use std::net::TcpStream;
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicU32, Ordering};
use std::time::{Duration, Instant};

/// Homes made by this process so far (each gets its own names and addresses).
static MADE: AtomicU32 = AtomicU32::new(0);

/// Longest Toxiproxy may take to answer on its API port.
const LISTEN_WITHIN: Duration = Duration::from_secs(20);

/// `program args`, which must succeed; its standard error otherwise.
fn sh(program: &str, args: &[&str]) -> Result<(), String> {
    let out = Command::new(program)
        .args(args)
        .stdin(Stdio::null())
        .output()
        .map_err(|e| format!("{program}: {e}"))?;
    if out.status.success() {
        Ok(())
    } else {
        Err(format!(
            "{program} {}: {}",
            args.join(" "),
            String::from_utf8_lossy(&out.stderr).trim()
        ))
    }
}

/// [`sh`] that must succeed (the namespace exists, so a failure is the test's).
fn must(program: &str, args: &[&str]) {
    if let Err(e) = sh(program, args) {
        panic!("{e}");
    }
}

/// A network namespace with a veth link to the root namespace; deleted when dropped (also
/// when a test panics).
pub struct Home {
    /// The namespace's name.
    pub ns: String,
    /// The veth end in the root namespace (the hub's side).
    veth_hub: String,
    /// The veth end in the namespace (the station's side).
    veth_home: String,
    /// The hub side's address (reach the hub here from the namespace).
    pub hub_ip: String,
    /// The station side's address.
    pub home_ip: String,
}

impl Home {
    /// A new namespace joined by a /30 veth link; `Err(why)` when this machine cannot (not
    /// root, no `ip`).
    pub fn make() -> Result<Self, String> {
        let n = MADE.fetch_add(1, Ordering::Relaxed);
        let pid = std::process::id();
        // A /30 of 10.203.0.0/16 per home of any process (16 384 of them).
        let block = ((pid % 4096) * 4 + n % 4) * 4;
        let (hi, lo) = (block >> 8, block & 255);
        let home = Self {
            ns: format!("telerehab-home-{pid}-{n}"),
            veth_hub: format!("trh{}h{n}", pid % 100_000),
            veth_home: format!("trh{}s{n}", pid % 100_000),
            hub_ip: format!("10.203.{hi}.{}", lo + 1),
            home_ip: format!("10.203.{hi}.{}", lo + 2),
        };
        sh("ip", &["netns", "add", &home.ns])?;
        // From here on, Drop cleans up whatever was made.
        let (ns, hub, sta) = (&home.ns, &home.veth_hub, &home.veth_home);
        sh(
            "ip",
            &["link", "add", hub, "type", "veth", "peer", "name", sta],
        )?;
        sh("ip", &["link", "set", sta, "netns", ns])?;
        sh(
            "ip",
            &["addr", "add", &format!("{}/30", home.hub_ip), "dev", hub],
        )?;
        sh("ip", &["link", "set", hub, "up"])?;
        sh(
            "ip",
            &[
                "-n",
                ns,
                "addr",
                "add",
                &format!("{}/30", home.home_ip),
                "dev",
                sta,
            ],
        )?;
        sh("ip", &["-n", ns, "link", "set", sta, "up"])?;
        sh("ip", &["-n", ns, "link", "set", "lo", "up"])?;
        Ok(home)
    }

    /// `program` run inside the namespace (`ip netns exec`), the environment inherited.
    pub fn command(&self, program: impl Into<PathBuf>) -> Command {
        let mut cmd = Command::new("ip");
        cmd.args(["netns", "exec", &self.ns]).arg(program.into());
        cmd
    }

    /// The link goes down (both ends lose carrier: packets go nowhere, connections stall).
    pub fn down(&self) {
        must("ip", &["link", "set", &self.veth_hub, "down"]);
    }

    /// The link comes back.
    pub fn up(&self) {
        must("ip", &["link", "set", &self.veth_hub, "up"]);
    }

    /// Drops `percent` % of the packets in each direction at random in the namespace
    /// (nftables: `numgen random mod 100 < percent drop` on input and output); `Err(why)`
    /// without `nft`.
    pub fn loss(&self, percent: u32) -> Result<(), String> {
        let rules = format!(
            "table inet telerehab_loss {{\n\
             chain inbound {{ type filter hook input priority 0; policy accept; \
             iifname \"{v}\" numgen random mod 100 < {percent} drop; }}\n\
             chain outbound {{ type filter hook output priority 0; policy accept; \
             oifname \"{v}\" numgen random mod 100 < {percent} drop; }}\n}}\n",
            v = self.veth_home
        );
        let path = std::env::temp_dir().join(format!("{}.nft", self.ns));
        std::fs::write(&path, rules).unwrap();
        let done = sh(
            "ip",
            &[
                "netns",
                "exec",
                &self.ns,
                "nft",
                "-f",
                path.to_str().unwrap(),
            ],
        );
        let _ = std::fs::remove_file(&path);
        done
    }

    /// Caps the station's uplink (its side's egress) at `kbit_per_s` kbit/s (`tc tbf`).
    pub fn uplink_kbit(&self, kbit_per_s: u32) {
        must(
            "ip",
            &[
                "netns",
                "exec",
                &self.ns,
                "tc",
                "qdisc",
                "replace",
                "dev",
                &self.veth_home,
                "root",
                "tbf",
                "rate",
                &format!("{kbit_per_s}kbit"),
                "burst",
                "16kb",
                "latency",
                "400ms",
            ],
        );
    }

    /// `delay_ms` added each way (so twice that to the round trip) and `loss_percent` % lost
    /// each way with `tc netem` on both ends; `false` when the kernel has no netem
    /// ("Specified qdisc kind is unknown"), nothing changed then.
    pub fn netem(&self, delay_ms: u32, loss_percent: u32) -> bool {
        let args = |dev: &str| {
            [
                "qdisc",
                "replace",
                "dev",
                dev,
                "root",
                "netem",
                "delay",
                &format!("{delay_ms}ms"),
                "loss",
                &format!("{loss_percent}%"),
            ]
            .map(str::to_owned)
        };
        let home: Vec<String> = ["netns", "exec", &self.ns, "tc"]
            .iter()
            .map(|s| (*s).to_owned())
            .chain(args(&self.veth_home))
            .collect();
        let home: Vec<&str> = home.iter().map(String::as_str).collect();
        if sh("ip", &home).is_err() {
            return false;
        }
        let hub = args(&self.veth_hub);
        let hub: Vec<&str> = hub.iter().map(String::as_str).collect();
        must("tc", &hub);
        true
    }
}

impl Drop for Home {
    fn drop(&mut self) {
        // Deleting the namespace deletes its veth end, and so the pair; the root end is
        // deleted too in case the pair was only half made.
        let _ = sh("ip", &["netns", "del", &self.ns]);
        let _ = sh("ip", &["link", "del", &self.veth_hub]);
    }
}

/// Toxiproxy's server, `$TELEREHAB_TOXIPROXY` or `~/.local/bin/toxiproxy-server` (where
/// `scripts/setup.sh` builds it) or on `PATH`.
fn toxiproxy_bin() -> PathBuf {
    if let Ok(p) = std::env::var("TELEREHAB_TOXIPROXY") {
        return PathBuf::from(p);
    }
    let local = std::env::var("HOME")
        .map(|h| PathBuf::from(h).join(".local/bin/toxiproxy-server"))
        .unwrap_or_default();
    if local.is_file() {
        local
    } else {
        PathBuf::from("toxiproxy-server")
    }
}

/// A Toxiproxy server of a test's own with one proxy, `listen` → `upstream`; killed when
/// dropped.
pub struct Toxiproxy {
    child: Child,
    api: u16,
    /// Where the proxy listens (`ip:port`).
    pub listen: String,
}

impl Toxiproxy {
    /// Starts `toxiproxy-server` (its API on a free loopback port) with a proxy named `hub`
    /// from a free port on `ip` to `upstream`; `Err(why)` when it is not installed.
    pub fn start(ip: &str, upstream: &str) -> Result<Self, String> {
        let api = crate::balancer::free_port();
        let port = std::net::TcpListener::bind((ip, 0))
            .and_then(|l| l.local_addr())
            .map_err(|e| format!("no free port on {ip}: {e}"))?
            .port();
        let bin = toxiproxy_bin();
        let child = Command::new(&bin)
            .args(["-host", "127.0.0.1", "-port", &api.to_string()])
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .map_err(|e| {
                format!(
                    "cannot start {} ({e}); scripts/setup.sh builds it",
                    bin.display()
                )
            })?;
        let proxy = Self {
            child,
            api,
            listen: format!("{ip}:{port}"),
        };
        let began = Instant::now();
        while TcpStream::connect(("127.0.0.1", api)).is_err() {
            assert!(began.elapsed() < LISTEN_WITHIN, "toxiproxy did not listen");
            std::thread::sleep(Duration::from_millis(50));
        }
        let body = serde_json::json!({
            "name": "hub", "listen": proxy.listen, "upstream": upstream, "enabled": true,
        });
        proxy.call("POST", "/proxies", &body.to_string());
        Ok(proxy)
    }

    /// Adds `latency_ms` each way (a `latency` toxic on both streams).
    pub fn latency(&self, latency_ms: u32) {
        for stream in ["upstream", "downstream"] {
            let body = serde_json::json!({
                "name": format!("latency-{stream}"), "type": "latency", "stream": stream,
                "toxicity": 1.0, "attributes": { "latency": latency_ms, "jitter": 0 },
            });
            self.call("POST", "/proxies/hub/toxics", &body.to_string());
        }
    }

    /// Removes the latency again.
    pub fn no_latency(&self) {
        for stream in ["upstream", "downstream"] {
            self.call(
                "DELETE",
                &format!("/proxies/hub/toxics/latency-{stream}"),
                "",
            );
        }
    }

    /// One request to the API, which must answer 2xx.
    fn call(&self, method: &str, path: &str, body: &str) {
        let mut tcp = TcpStream::connect(("127.0.0.1", self.api)).unwrap();
        write!(
            tcp,
            "{method} {path} HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n\
             Content-Length: {}\r\nConnection: close\r\n\r\n{body}",
            body.len()
        )
        .unwrap();
        let mut answer = String::new();
        tcp.read_to_string(&mut answer).unwrap();
        let status = answer.split_whitespace().nth(1).unwrap_or("");
        assert!(
            status.starts_with('2'),
            "toxiproxy {method} {path}: {answer}"
        );
    }
}

impl Drop for Toxiproxy {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}
