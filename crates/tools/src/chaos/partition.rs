//! Network partitions of the chaos day (`--kinds partition`): one hub cut off from the
//! database and the recording store while its stations still reach it.
//!
//! Each hub reaches the database and the store through relays of its own (one TCP relay per
//! upstream, in this process, on tokio), and a partition of that hub makes its relays go
//! silent: bytes stop flowing in both directions on every open connection, WITHOUT closing
//! any socket (a real partition is silence, not a reset: no FIN, no RST reaches either side),
//! and a new connection is accepted and then held silent (the hub's connect succeeds at the
//! TCP level, as to a half-reachable address, and nothing answers). When the partition ends,
//! forwarding resumes where it stopped — bytes read just before the cut are delivered then, as
//! TCP's retransmissions would after a real partition heals — and held connections are joined
//! to their upstream. What brings the hub back is its own deadlines (database pool and query
//! timeouts, the store's request timeouts), never a socket error the relay makes up.
//!
//! Honestly: this partitions at the TCP level on loopback, not with network namespaces or
//! packet filters; the kernel still acknowledges the hub's segments (its send buffers do not
//! fill the way they would on a dead route) and a connection attempt completes its handshake.

use std::net::SocketAddr;
use std::sync::Arc;

use anyhow::Context;
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::{TcpListener, TcpStream};
use tokio::sync::watch;

/// Bytes one relay direction moves at a time.
const CHUNK_BYTES: usize = 16 * 1024;

/// One hub's link to everything it shares (database, store): open or cut.
#[derive(Debug, Clone)]
pub struct Link {
    cut: Arc<watch::Sender<bool>>,
}

impl Default for Link {
    fn default() -> Self {
        Self::new()
    }
}

impl Link {
    /// An open link.
    pub fn new() -> Self {
        Self {
            cut: Arc::new(watch::Sender::new(false)),
        }
    }

    /// Cuts (true) or heals (false) the link.
    pub fn set_cut(&self, cut: bool) {
        self.cut.send_replace(cut);
    }

    /// Starts a relay on a free loopback port that forwards to `upstream` through this link;
    /// its address. It runs until the process ends (the chaos day's relays live as long as it).
    pub async fn relay(&self, upstream: SocketAddr) -> anyhow::Result<SocketAddr> {
        let listener = TcpListener::bind("127.0.0.1:0")
            .await
            .context("cannot bind a relay")?;
        let addr = listener.local_addr()?;
        let link = self.clone();
        tokio::spawn(async move {
            while let Ok((client, _)) = listener.accept().await {
                tokio::spawn(link.clone().join(client, upstream));
            }
        });
        Ok(addr)
    }

    /// Waits until the link is open.
    async fn open(&self) {
        let mut rx = self.cut.subscribe();
        let _ = rx.wait_for(|cut| !cut).await;
    }

    /// One relayed connection: held silent while the link is cut, then joined to `upstream`.
    async fn join(self, client: TcpStream, upstream: SocketAddr) {
        self.open().await;
        let Ok(server) = TcpStream::connect(upstream).await else {
            // The upstream is down (a killed server): the client sees it refused, as it would
            // without the relay.
            return;
        };
        let _ = client.set_nodelay(true);
        let _ = server.set_nodelay(true);
        let (cr, cw) = client.into_split();
        let (sr, sw) = server.into_split();
        tokio::join!(self.pump(cr, sw), self.pump(sr, cw));
    }

    /// One direction: reads only while the link is open, writes only while it is open; the
    /// end of one side's stream is passed on as the end of the other's.
    async fn pump(
        &self,
        mut from: tokio::net::tcp::OwnedReadHalf,
        mut to: tokio::net::tcp::OwnedWriteHalf,
    ) {
        let mut buf = vec![0u8; CHUNK_BYTES];
        loop {
            self.open().await;
            let n = match from.read(&mut buf).await {
                Ok(0) | Err(_) => break,
                Ok(n) => n,
            };
            self.open().await;
            if to.write_all(&buf[..n]).await.is_err() {
                break;
            }
        }
        let _ = to.shutdown().await;
    }
}

/// `url` with its `host:port` (after `//` and any `user@`) replaced by `addr`: the database URL
/// or store endpoint through a relay.
pub fn through(url: &str, addr: SocketAddr) -> anyhow::Result<String> {
    let (scheme, rest) = url.split_once("//").context("a URL without //")?;
    let (auth, tail) = match rest.find('/') {
        Some(k) => rest.split_at(k),
        None => (rest, ""),
    };
    let user = auth.rsplit_once('@').map_or("", |(u, _)| u);
    let at = if user.is_empty() { "" } else { "@" };
    Ok(format!("{scheme}//{user}{at}{addr}{tail}"))
}

/// The `host:port` a URL names.
pub fn upstream_of(url: &str) -> anyhow::Result<SocketAddr> {
    let (_, rest) = url.split_once("//").context("a URL without //")?;
    let auth = rest.split('/').next().unwrap_or(rest);
    let host = auth.rsplit_once('@').map_or(auth, |(_, h)| h);
    host.parse()
        .with_context(|| format!("{host:?} is not an address and port"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    #[test]
    fn urls_go_through_the_relay_with_user_and_path_kept() {
        let relay: SocketAddr = "127.0.0.1:9999".parse().unwrap();
        let db = "postgres://postgres:pw@127.0.0.1:5432/postgres";
        assert_eq!(
            through(db, relay).unwrap(),
            "postgres://postgres:pw@127.0.0.1:9999/postgres"
        );
        assert_eq!(
            upstream_of(db).unwrap(),
            "127.0.0.1:5432".parse::<SocketAddr>().unwrap()
        );
        assert_eq!(
            through("http://127.0.0.1:8333", relay).unwrap(),
            "http://127.0.0.1:9999"
        );
    }

    /// An echo server; its address.
    async fn echo() -> SocketAddr {
        let l = TcpListener::bind("127.0.0.1:0").await.unwrap();
        let addr = l.local_addr().unwrap();
        tokio::spawn(async move {
            while let Ok((mut s, _)) = l.accept().await {
                tokio::spawn(async move {
                    let (mut r, mut w) = s.split();
                    let _ = tokio::io::copy(&mut r, &mut w).await;
                });
            }
        });
        addr
    }

    async fn round_trip(s: &mut TcpStream, within: Duration) -> Option<u8> {
        s.write_all(b"x").await.unwrap();
        let mut b = [0u8; 1];
        match tokio::time::timeout(within, s.read(&mut b)).await {
            Ok(Ok(1)) => Some(b[0]),
            Ok(Ok(_) | Err(_)) => panic!("the relay closed or broke the connection"),
            Err(_) => None,
        }
    }

    #[tokio::test]
    async fn a_cut_is_silence_not_a_reset_and_healing_resumes_every_connection() {
        let link = Link::new();
        let relay = link.relay(echo().await).await.unwrap();
        let mut open = TcpStream::connect(relay).await.unwrap();
        assert_eq!(
            round_trip(&mut open, Duration::from_secs(5)).await,
            Some(b'x')
        );
        link.set_cut(true);
        // Silence on the open connection (no answer, no end, no error) …
        assert_eq!(
            round_trip(&mut open, Duration::from_millis(300)).await,
            None
        );
        // … and a new connection is taken and held silent.
        let mut held = TcpStream::connect(relay).await.unwrap();
        assert_eq!(
            round_trip(&mut held, Duration::from_millis(300)).await,
            None
        );
        link.set_cut(false);
        // The bytes sent during the cut arrive after it, on both.
        let mut b = [0u8; 1];
        for s in [&mut open, &mut held] {
            tokio::time::timeout(Duration::from_secs(5), s.read_exact(&mut b))
                .await
                .expect("forwarding resumed")
                .unwrap();
            assert_eq!(b[0], b'x');
            assert_eq!(round_trip(s, Duration::from_secs(5)).await, Some(b'x'));
        }
    }
}
