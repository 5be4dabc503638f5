//! The TCP balancer `hub bench --hubs N` puts in front of its hubs: Debian's HAProxy in
//! `mode tcp` (mutual TLS stays end to end, as docs/DEPLOY.md configures the station port),
//! `balance leastconn`, a TCP check of each hub's station port. It runs as a child process in
//! the foreground (`-db`) with its configuration in a temporary directory, and stops with the
//! bench.

use std::net::SocketAddr;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use anyhow::{Context, bail};

/// How long HAProxy may take to listen after its start.
const LISTEN_WITHIN: Duration = Duration::from_secs(10);

/// A running HAProxy in front of the hubs.
#[derive(Debug)]
pub struct Balancer {
    child: tokio::process::Child,
    /// The address stations connect to.
    pub addr: SocketAddr,
    _dir: tempfile::TempDir,
}

/// HAProxy's binary: on the PATH, else Debian's `/usr/sbin/haproxy`.
fn haproxy_binary() -> PathBuf {
    let debian = PathBuf::from("/usr/sbin/haproxy");
    if debian.exists() {
        debian
    } else {
        PathBuf::from("haproxy")
    }
}

/// The configuration: one TCP frontend on `port`, every hub of `hubs` a server, room for
/// `connections` at once (each takes two descriptors in HAProxy: client and server side).
pub fn config(port: u16, hubs: &[SocketAddr], connections: usize) -> String {
    let mut c = format!(
        "global\n  maxconn {max}\n\ndefaults\n  mode tcp\n  timeout connect 5s\n  \
         timeout client 1h\n  timeout server 1h\n\nfrontend stations\n  \
         bind 127.0.0.1:{port}\n  maxconn {max}\n  default_backend hubs\n\nbackend hubs\n  \
         balance leastconn\n",
        max = connections + 64,
    );
    for (i, hub) in hubs.iter().enumerate() {
        c.push_str(&format!("  server hub{i} {hub} check inter 1s\n"));
    }
    c
}

impl Balancer {
    /// Starts HAProxy before `hubs` for `connections` stations and waits until it listens.
    pub async fn start(hubs: &[SocketAddr], connections: usize) -> anyhow::Result<Self> {
        let dir = tempfile::tempdir().context("cannot make the balancer's directory")?;
        let port = std::net::TcpListener::bind("127.0.0.1:0")
            .and_then(|l| l.local_addr())
            .context("cannot find a free port for the balancer")?
            .port();
        let cfg = dir.path().join("haproxy.cfg");
        std::fs::write(&cfg, config(port, hubs, connections))
            .context("cannot write the balancer's configuration")?;
        let binary = haproxy_binary();
        let mut child = tokio::process::Command::new(&binary)
            .arg("-db")
            .arg("-f")
            .arg(&cfg)
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .kill_on_drop(true)
            .spawn()
            .with_context(|| {
                format!(
                    "cannot start HAProxy ({}): hub bench --hubs needs it (Debian: apt install haproxy)",
                    binary.display()
                )
            })?;
        let addr = SocketAddr::from(([127, 0, 0, 1], port));
        let t0 = Instant::now();
        loop {
            if let Some(status) = child.try_wait()? {
                bail!(
                    "HAProxy exited at its start ({status}); its configuration: {}",
                    cfg.display()
                );
            }
            if tokio::net::TcpStream::connect(addr).await.is_ok() {
                break;
            }
            if t0.elapsed() > LISTEN_WITHIN {
                bail!("HAProxy did not listen on {addr} within {LISTEN_WITHIN:?}");
            }
            tokio::time::sleep(Duration::from_millis(50)).await;
        }
        Ok(Self {
            child,
            addr,
            _dir: dir,
        })
    }

    /// The balancer's process id (its CPU is counted beside the hubs').
    pub fn pid(&self) -> Option<u32> {
        self.child.id()
    }

    /// Stops it.
    pub async fn stop(mut self) {
        let _ = self.child.kill().await;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_hub_is_a_checked_server_and_the_frontend_has_room_for_every_station() {
        let hubs: Vec<SocketAddr> = vec![
            "127.0.0.1:7001".parse().unwrap(),
            "127.0.0.1:7002".parse().unwrap(),
        ];
        let c = config(9000, &hubs, 3000);
        assert!(c.contains("bind 127.0.0.1:9000"), "{c}");
        assert!(c.contains("server hub0 127.0.0.1:7001 check"), "{c}");
        assert!(c.contains("server hub1 127.0.0.1:7002 check"), "{c}");
        assert!(
            c.contains("mode tcp") && c.contains("balance leastconn"),
            "{c}"
        );
        assert_eq!(c.matches("maxconn 3064").count(), 2, "{c}");
    }
}
