//! The TCP balancer `hub bench --hubs N` puts in front of its hubs: Debian's HAProxy in
//! `mode tcp` (mutual TLS stays end to end, as docs/DEPLOY.md configures the station port),
//! `balance leastconn`, a TCP check of each hub's station port (or, for the chaos day,
//! [`Balancer::start_ready`], an HTTPS `GET /readyz` of each hub's console, so a hub that lost
//! its database or store gets no new stations). It runs as a child process in the foreground
//! (`-db`) with its configuration in a temporary directory, and stops with its user.

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

/// [`config`] with each hub `(stations, console)` checked by an HTTPS `GET /readyz` of its
/// console (docs/DEPLOY.md's check) every 500 ms, out after one failure, back after two
/// passes; a connection a hub refuses is tried on another (`option redispatch`).
pub fn config_ready(port: u16, hubs: &[(SocketAddr, SocketAddr)], connections: usize) -> String {
    let mut c = config(port, &[], connections).replace(
        "  timeout server 1h\n",
        "  timeout server 1h\n  timeout check 2s\n  retries 3\n  option redispatch\n",
    );
    c.push_str(
        "  option httpchk\n  http-check send meth GET uri /readyz\n  http-check expect status 200\n",
    );
    for (i, (st, web)) in hubs.iter().enumerate() {
        c.push_str(&format!(
            "  server hub{i} {st} check port {} check-ssl verify none inter 500ms fall 1 rise 2\n",
            web.port()
        ));
    }
    c
}

impl Balancer {
    /// Starts HAProxy before `hubs` for `connections` stations and waits until it listens.
    pub async fn start(hubs: &[SocketAddr], connections: usize) -> anyhow::Result<Self> {
        Self::launch(|port| config(port, hubs, connections)).await
    }

    /// Starts HAProxy before `hubs` (station port, console) with [`config_ready`]'s checks.
    pub async fn start_ready(
        hubs: &[(SocketAddr, SocketAddr)],
        connections: usize,
    ) -> anyhow::Result<Self> {
        Self::launch(|port| config_ready(port, hubs, connections)).await
    }

    async fn launch(config: impl FnOnce(u16) -> String) -> anyhow::Result<Self> {
        let dir = tempfile::tempdir().context("cannot make the balancer's directory")?;
        let port = std::net::TcpListener::bind("127.0.0.1:0")
            .and_then(|l| l.local_addr())
            .context("cannot find a free port for the balancer")?
            .port();
        let cfg = dir.path().join("haproxy.cfg");
        std::fs::write(&cfg, config(port)).context("cannot write the balancer's configuration")?;
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
                    "cannot start HAProxy ({}): several hubs need it (Debian: apt install haproxy)",
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

    #[test]
    fn the_chaos_days_balancer_checks_each_hubs_readiness_on_its_console() {
        let hubs: Vec<(SocketAddr, SocketAddr)> = vec![
            (
                "127.0.0.1:7001".parse().unwrap(),
                "127.0.0.1:8001".parse().unwrap(),
            ),
            (
                "127.0.0.1:7002".parse().unwrap(),
                "127.0.0.1:8002".parse().unwrap(),
            ),
        ];
        let c = config_ready(9000, &hubs, 10);
        assert!(c.contains("http-check send meth GET uri /readyz"), "{c}");
        assert!(
            c.contains("server hub1 127.0.0.1:7002 check port 8002 check-ssl"),
            "{c}"
        );
        assert!(c.contains("option redispatch"), "{c}");
    }
}
