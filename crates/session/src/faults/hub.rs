//! The `hub-down` fault: a relay between the station's link and its hub that cuts and
//! refuses connections while the hub is down.

use crate::config::faults::{FaultKind, FaultSpec, windows};

/// The therapist link's seam for `hub-down`: a relay on loopback between the station's link
/// and its hub, on the link's runtime. In a hub-down window (session time, told by
/// [`HubSwitch::at`] with each summary) it cuts the connections it carries and refuses new
/// ones (accepted and closed at once, as a hub that went away answers); otherwise it passes
/// bytes through untouched (TLS included: it sees only ciphertext).
pub struct HubSwitch {
    windows: Vec<(u64, u64)>,
    down: tokio::sync::watch::Sender<bool>,
    local: std::net::SocketAddr,
}

impl HubSwitch {
    /// A relay to `hub` (`host:port`, resolved on each connection) on `runtime`, when `faults`
    /// take the hub down; `None` otherwise.
    pub fn start(
        runtime: &tokio::runtime::Handle,
        hub: &str,
        faults: &[FaultSpec],
    ) -> std::io::Result<Option<Self>> {
        let windows: Vec<(u64, u64)> = windows(faults)
            .into_iter()
            .filter(|(k, _, _)| *k == FaultKind::HubDown)
            .map(|(_, start, end)| (start, end))
            .collect();
        if windows.is_empty() {
            return Ok(None);
        }
        let std_listener = std::net::TcpListener::bind((std::net::Ipv4Addr::LOCALHOST, 0))?;
        std_listener.set_nonblocking(true)?;
        let local = std_listener.local_addr()?;
        let listener = {
            let _in_runtime = runtime.enter();
            tokio::net::TcpListener::from_std(std_listener)?
        };
        let (down, watch) = tokio::sync::watch::channel(false);
        runtime.spawn(relay(listener, hub.to_owned(), watch));
        Ok(Some(Self {
            windows,
            down,
            local,
        }))
    }

    /// Where the station's link connects instead of the hub.
    pub fn address(&self) -> std::net::SocketAddr {
        self.local
    }

    /// Session time is `t_ns`: the hub is down in a hub-down window, up otherwise (said in the
    /// log when it changes).
    pub fn at(&self, t_ns: u64) {
        let down = self
            .windows
            .iter()
            .any(|(start, end)| (*start..*end).contains(&t_ns));
        let changed = self
            .down
            .send_if_modified(|d| std::mem::replace(d, down) != down);
        if changed && down {
            tracing::warn!(
                t_s = t_ns as f64 * 1e-9,
                "the therapist's hub went away (injected fault): summaries wait in the queue"
            );
        } else if changed {
            tracing::info!(
                t_s = t_ns as f64 * 1e-9,
                "the therapist's hub is back (injected fault ended)"
            );
        }
    }
}

/// Accept the link's connections and relay each to `hub` while the hub is up.
async fn relay(
    listener: tokio::net::TcpListener,
    hub: String,
    down: tokio::sync::watch::Receiver<bool>,
) {
    loop {
        let Ok((station, _)) = listener.accept().await else {
            // Out of descriptors, say: try again shortly rather than spin.
            tokio::time::sleep(std::time::Duration::from_millis(10)).await;
            continue;
        };
        if *down.borrow() {
            // Refused: closed before a byte is read.
            drop(station);
            continue;
        }
        let hub = hub.clone();
        let mut down = down.clone();
        tokio::spawn(async move {
            let Ok(upstream) = tokio::net::TcpStream::connect(hub.as_str()).await else {
                return;
            };
            let (mut station, mut upstream) = (station, upstream);
            tokio::select! {
                _ = tokio::io::copy_bidirectional(&mut station, &mut upstream) => {}
                // Cut: both sockets close mid-stream, as a hub that went away does.
                _ = down.wait_for(|d| *d) => {}
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_hub_relay_cuts_and_refuses_while_down_and_relays_again_when_up() {
        use std::io::{Read, Write};
        // The "hub": echoes what it reads.
        let hub = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
        let hub_addr = hub.local_addr().unwrap().to_string();
        std::thread::spawn(move || {
            for conn in hub.incoming() {
                let Ok(mut c) = conn else { continue };
                std::thread::spawn(move || {
                    let mut buf = [0u8; 64];
                    while let Ok(n @ 1..) = c.read(&mut buf) {
                        let _ = c.write_all(&buf[..n]);
                    }
                });
            }
        });
        let runtime = tokio::runtime::Builder::new_multi_thread()
            .worker_threads(1)
            .enable_all()
            .build()
            .unwrap();
        let faults = [
            FaultSpec::parse("hub-down@1").unwrap(),
            FaultSpec::parse("hub-up@2").unwrap(),
        ];
        let switch = HubSwitch::start(runtime.handle(), &hub_addr, &faults)
            .unwrap()
            .expect("a relay for a hub-down");
        let connect = || {
            let c = std::net::TcpStream::connect(switch.address()).unwrap();
            c.set_read_timeout(Some(std::time::Duration::from_secs(10)))
                .unwrap();
            c
        };
        let echo = |c: &mut std::net::TcpStream| {
            c.write_all(b"seq 1").ok()?;
            let mut buf = [0u8; 5];
            c.read_exact(&mut buf).ok()?;
            Some(buf)
        };
        switch.at(500_000_000);
        let mut before = connect();
        assert_eq!(echo(&mut before), Some(*b"seq 1"), "up: relayed");
        // Down: the open connection is cut, a new one closed before it carries a byte.
        switch.at(1_000_000_000);
        let mut buf = [0u8; 1];
        assert!(matches!(before.read(&mut buf), Ok(0) | Err(_)), "cut");
        let mut refused = connect();
        assert_eq!(echo(&mut refused), None, "refused while down");
        // Up again: relayed.
        switch.at(2_000_000_000);
        let mut after = connect();
        assert_eq!(echo(&mut after), Some(*b"seq 1"), "up again");
        // Without a hub-down there is no relay.
        assert!(
            HubSwitch::start(runtime.handle(), &hub_addr, &[])
                .unwrap()
                .is_none()
        );
    }
}
