//! The PROXY protocol (HAProxy's, versions 1 and 2) on the hub's ports: behind a load balancer
//! that passes TCP through (`mode tcp`, so mutual TLS stays end to end), every connection comes
//! from the balancer; with `send-proxy-v2` the balancer first sends a header naming the client,
//! and the hub's per-address guards and audit lines use that address.
//!
//! - [`trust`]: [`TrustedProxies`], the peers a header is read from (`proxy_protocol_from`).
//! - [`header`]: reading and parsing one header, bounded, no byte past its end.
//! - [`ProxiedListener`]: a TCP listener whose `accept` gives each connection's client address.
//!
//! A connection from a trusted peer must start with a valid header within the handshake
//! timeout, or it is closed with a log line naming the peer; `LOCAL` (a health check) keeps the
//! balancer's address. From any other peer nothing is read: the address is the peer's own, and
//! a header it sends is just bytes that fail the TLS handshake.

pub mod header;
pub mod trust;

use std::io;
use std::net::SocketAddr;
use std::time::Duration;

use tokio::net::{TcpListener, TcpStream};
use tokio::task::JoinSet;

pub use header::{ProxyHeader, ProxyHeaderError, read_header};
pub use trust::{Cidr, TrustedProxies};

/// Most connections from trusted peers whose headers are being read at once; past it, new
/// connections wait in the listen backlog.
pub const MAX_PENDING_HEADERS: usize = 1_024;

/// A connection from a trusted peer whose header is being read: the peer, and the stream with
/// its client's address once read.
type Pending = (
    SocketAddr,
    Result<(TcpStream, SocketAddr), ProxyHeaderError>,
);

/// A TCP listener that reads the PROXY protocol header of connections from [`TrustedProxies`]
/// (each on its own task, within `timeout`) and gives every connection with the address it is
/// taken to come from. With nobody trusted it is the bare listener.
#[derive(Debug)]
pub struct ProxiedListener {
    listener: TcpListener,
    trusted: TrustedProxies,
    timeout: Duration,
    /// The port's name in log lines (`station port`, `console port`).
    port: &'static str,
    pending: JoinSet<Pending>,
}

impl From<TcpListener> for ProxiedListener {
    /// Trusts nobody: every connection's address is its peer's.
    fn from(listener: TcpListener) -> Self {
        Self::new(listener, TrustedProxies::default(), Duration::ZERO, "port")
    }
}

impl ProxiedListener {
    /// Accepts on `listener`, reading a header from connections of `trusted` peers within
    /// `timeout` (the port's handshake timeout); `port` names it in log lines.
    pub fn new(
        listener: TcpListener,
        trusted: TrustedProxies,
        timeout: Duration,
        port: &'static str,
    ) -> Self {
        if !trusted.is_empty() {
            tracing::info!(%port, %trusted, "PROXY protocol headers read from these peers only");
        }
        Self {
            listener,
            trusted,
            timeout,
            port,
            pending: JoinSet::new(),
        }
    }

    /// The address it listens on.
    pub fn local_addr(&self) -> io::Result<SocketAddr> {
        self.listener.local_addr()
    }

    /// The next connection and its client's address: the peer's own, or from a trusted peer
    /// the one its header names. A trusted peer's connection without a valid header is closed
    /// and logged, never given. Cancel-safe (headers in progress stay with the listener).
    pub async fn accept(&mut self) -> io::Result<(TcpStream, SocketAddr)> {
        loop {
            let room = self.pending.len() < MAX_PENDING_HEADERS;
            tokio::select! {
                accepted = self.listener.accept(), if room => {
                    let (tcp, peer) = accepted?;
                    if !self.trusted.trusts(peer.ip()) {
                        return Ok((tcp, peer));
                    }
                    let timeout = self.timeout;
                    self.pending.spawn(async move { (peer, read_client(tcp, peer, timeout).await) });
                }
                Some(done) = self.pending.join_next(), if !self.pending.is_empty() => {
                    let Ok((peer, read)) = done else {
                        continue; // a header task that panicked or was aborted: its connection is gone
                    };
                    match read {
                        Ok(accepted) => return Ok(accepted),
                        Err(e @ ProxyHeaderError::Closed { read: 0 }) => {
                            // A bare TCP check of the balancer's: not worth a warning.
                            tracing::debug!(%peer, port = self.port, "connection from a trusted balancer {e}; closed");
                        }
                        Err(e) => {
                            tracing::warn!(%peer, port = self.port, "connection from a trusted balancer {e}; closed");
                        }
                    }
                }
            }
        }
    }
}

/// Reads the header of `tcp` from the trusted `peer` within `timeout`: the stream and the
/// address its client is taken to have.
async fn read_client(
    mut tcp: TcpStream,
    peer: SocketAddr,
    timeout: Duration,
) -> Result<(TcpStream, SocketAddr), ProxyHeaderError> {
    let header = tokio::time::timeout(timeout, read_header(&mut tcp))
        .await
        .map_err(|_| ProxyHeaderError::TimedOut)??;
    Ok((tcp, header.client_address(peer)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use tokio::io::{AsyncReadExt, AsyncWriteExt};

    async fn listener(trusted: &[&str]) -> ProxiedListener {
        let l = TcpListener::bind("127.0.0.1:0").await.unwrap();
        ProxiedListener::new(
            l,
            TrustedProxies::parse(trusted).unwrap(),
            Duration::from_millis(500),
            "test port",
        )
    }

    /// Connects from `from` (a loopback address) to `to`, sends `bytes`.
    async fn connect_from(from: &str, to: SocketAddr, bytes: &[u8]) -> TcpStream {
        let socket = tokio::net::TcpSocket::new_v4().unwrap();
        socket.bind(format!("{from}:0").parse().unwrap()).unwrap();
        let mut tcp = socket.connect(to).await.unwrap();
        tcp.write_all(bytes).await.unwrap();
        tcp
    }

    #[tokio::test]
    async fn a_trusted_peers_header_names_the_client_and_an_untrusted_peers_is_not_read() {
        let mut l = listener(&["127.0.0.1/32"]).await;
        let to = l.local_addr().unwrap();
        // From the balancer (127.0.0.1): the client its header names.
        let _c = connect_from(
            "127.0.0.1",
            to,
            b"PROXY TCP4 192.0.2.44 127.0.0.1 4000 443\r\nhello",
        )
        .await;
        let (mut tcp, addr) = l.accept().await.unwrap();
        assert_eq!(addr, "192.0.2.44:4000".parse::<SocketAddr>().unwrap());
        let mut rest = [0u8; 5];
        tcp.read_exact(&mut rest).await.unwrap();
        assert_eq!(&rest, b"hello");
        // From anyone else: its own address, the forged header left as bytes for TLS to refuse.
        let _c = connect_from(
            "127.0.0.2",
            to,
            b"PROXY TCP4 192.0.2.45 127.0.0.1 4000 443\r\n",
        )
        .await;
        let (mut tcp, addr) = l.accept().await.unwrap();
        assert_eq!(addr.ip(), "127.0.0.2".parse::<std::net::IpAddr>().unwrap());
        let mut rest = [0u8; 6];
        tcp.read_exact(&mut rest).await.unwrap();
        assert_eq!(&rest, b"PROXY ");
    }

    #[tokio::test]
    async fn a_trusted_peer_without_a_valid_header_is_closed_and_the_next_one_served() {
        let mut l = listener(&["127.0.0.0/8"]).await;
        let to = l.local_addr().unwrap();
        // No header (a TLS hello), a silent one (times out), then a good one.
        let mut bad = connect_from("127.0.0.5", to, &[0x16, 3, 1, 0, 200, 1, 0, 0, 196]).await;
        let _silent = connect_from("127.0.0.6", to, b"").await;
        let _good = connect_from(
            "127.0.0.7",
            to,
            b"PROXY TCP4 192.0.2.46 127.0.0.1 4001 443\r\n",
        )
        .await;
        let (_, addr) = l.accept().await.unwrap();
        assert_eq!(addr, "192.0.2.46:4001".parse::<SocketAddr>().unwrap());
        // The header-less one is closed by the hub.
        let mut buf = [0u8; 1];
        let n = tokio::time::timeout(Duration::from_secs(5), bad.read(&mut buf))
            .await
            .unwrap()
            .unwrap_or(0);
        assert_eq!(n, 0);
        // The silent one never comes out: the next accept has only the timeout to wait for.
        let next = tokio::time::timeout(Duration::from_millis(1_500), l.accept()).await;
        assert!(next.is_err(), "a connection without a header was given");
    }
}
