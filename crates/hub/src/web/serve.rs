//! Serving the API over HTTPS (rustls with `ring`, HTTP/1.1) with graceful shutdown.

use std::future::Future;
use std::net::SocketAddr;
use std::path::Path;
use std::pin::Pin;
use std::sync::{Arc, Mutex, PoisonError};
use std::task::{Context, Poll};
use std::time::Duration;

use axum::body::{Body, Bytes};
use axum::http::Request;
use axum::{BoxError, Router};
use hyper::body::{Body as _, Incoming};
use hyper_util::rt::TokioIo;
use hyper_util::server::graceful::{GracefulShutdown, Watcher};
use netlink::proxy_protocol::ProxiedListener;
use netlink::therapist::budget::{
    ConnectionGate, EVICTION_GRACE, Eviction, GateLimits, REFUSAL_LOG_INTERVAL, Ticket,
};
use tokio::io::{AsyncRead, AsyncWrite};
use tokio::net::TcpStream;
use tokio::sync::Semaphore;
use tokio_rustls::TlsAcceptor;
use tower::ServiceExt as _;

use super::{AppState, router};
use hub_store::HubError;

/// Longest a client may take to complete the TLS handshake, s.
pub const TLS_HANDSHAKE_TIMEOUT_S: u64 = 10;

/// Longest shutdown waits for open requests (e.g. live streams) to finish, s.
pub const SHUTDOWN_GRACE_S: u64 = 5;

/// A TLS acceptor from the hub's certificate chain and private key (PEM files).
pub fn acceptor_from_pem(cert_pem: &Path, key_pem: &Path) -> Result<TlsAcceptor, HubError> {
    netlink::ServerTls {
        cert_pem_path: cert_pem.to_owned(),
        key_pem_path: key_pem.to_owned(),
        client_ca_pem_path: None,
    }
    .acceptor()
    .map_err(|e| HubError::Config(e.to_string()))
}

/// Deadlines and connection caps of the console's port.
///
/// A connection is *unanswered* until one of its requests has been answered: its TLS
/// handshake, request head and body are still on their way. Unanswered connections are capped
/// per address and in all (`netlink::therapist::budget`): a newcomer over the per-address cap
/// waits in that address's line and takes the slot of the oldest unanswered connection that
/// has stalled — made no progress (TLS handshake, request head) for
/// [`EVICTION_GRACE`](netlink::therapist::budget::EVICTION_GRACE) — so a client holding
/// half-sent requests cannot lock anyone out, and one reconnecting fast from the same address
/// (a shared NAT) cannot push out a slow handshake. All connections together are capped by
/// `max_connections`; answered ones idle longer than `header_read_timeout_ms` are closed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct WebLimits {
    /// Longest a client may take to complete the TLS handshake, ms.
    pub tls_handshake_timeout_ms: u64,
    /// Longest a request head may take to arrive, ms, counted from when the connection is
    /// ready for it: also how long an idle keep-alive connection stays open.
    pub header_read_timeout_ms: u64,
    /// Longest a request body may take to arrive, ms, counted from the end of its head; a
    /// body not complete by then is refused (400) and the connection closed.
    pub body_timeout_ms: u64,
    /// Most simultaneous connections.
    pub max_connections: usize,
    /// Most simultaneous unanswered connections.
    pub max_unanswered: usize,
    /// Most simultaneous unanswered connections from one address.
    pub max_unanswered_per_address: usize,
}

impl Default for WebLimits {
    fn default() -> Self {
        Self {
            tls_handshake_timeout_ms: TLS_HANDSHAKE_TIMEOUT_S * 1000,
            header_read_timeout_ms: 10_000,
            body_timeout_ms: 10_000,
            max_connections: 1_024,
            max_unanswered: 512,
            max_unanswered_per_address: 16,
        }
    }
}

/// Serves [`router`]`(state)` on `listener` until `shutdown` completes; see [`serve_router`].
pub async fn serve(
    listener: impl Into<ProxiedListener>,
    tls: Option<TlsAcceptor>,
    state: AppState,
    shutdown: impl Future<Output = ()> + Send,
) -> Result<(), HubError> {
    serve_router(listener, tls, router(state), shutdown).await
}

/// [`serve`] within `limits`.
pub async fn serve_with_limits(
    listener: impl Into<ProxiedListener>,
    tls: Option<TlsAcceptor>,
    state: AppState,
    limits: WebLimits,
    shutdown: impl Future<Output = ()> + Send,
) -> Result<(), HubError> {
    serve_router_with_limits(listener, tls, router(state), limits, shutdown).await
}

/// Serves `app` on `listener` over TLS until `shutdown` completes, then stops accepting and
/// waits up to [`SHUTDOWN_GRACE_S`] for open requests. `tls: None` serves plain HTTP and is
/// refused unless the listener is bound to a loopback address. Default [`WebLimits`].
pub async fn serve_router(
    listener: impl Into<ProxiedListener>,
    tls: Option<TlsAcceptor>,
    app: Router,
    shutdown: impl Future<Output = ()> + Send,
) -> Result<(), HubError> {
    serve_router_with_limits(listener, tls, app, WebLimits::default(), shutdown).await
}

/// [`serve_router`] within `limits`.
pub async fn serve_router_with_limits(
    listener: impl Into<ProxiedListener>,
    tls: Option<TlsAcceptor>,
    app: Router,
    limits: WebLimits,
    shutdown: impl Future<Output = ()> + Send,
) -> Result<(), HubError> {
    // A bare listener, or one reading trusted balancers' PROXY headers (clients' addresses).
    let mut listener = listener.into();
    let local = listener
        .local_addr()
        .map_err(|e| HubError::io("reading the listening address", e))?;
    if tls.is_none() && !local.ip().is_loopback() {
        return Err(HubError::Config(format!(
            "plain HTTP is allowed only on a loopback address, not {local}; give a TLS \
             certificate and key"
        )));
    }
    tracing::info!(address = %local, tls = tls.is_some(), ?limits, "therapist console API listening");
    let gate = ConnectionGate::new(
        GateLimits {
            max_total: limits.max_unanswered.max(1),
            max_per_address: limits.max_unanswered_per_address.max(1),
            grace: EVICTION_GRACE,
        },
        "console port",
    );
    let connections = Arc::new(Semaphore::new(limits.max_connections.max(1)));
    let graceful = GracefulShutdown::new();
    let mut summary = tokio::time::interval(REFUSAL_LOG_INTERVAL);
    summary.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
    let mut shutdown = std::pin::pin!(shutdown);
    loop {
        let (stream, peer) = tokio::select! {
            accepted = listener.accept() => match accepted {
                Ok(pair) => pair,
                Err(e) => {
                    // Out of file descriptors and the like: wait instead of spinning.
                    if gate.refusals().detail("accept failed") {
                        tracing::warn!(error = %e, "accept failed");
                    }
                    tokio::time::sleep(Duration::from_millis(100)).await;
                    continue;
                }
            },
            _ = summary.tick() => {
                if let Some(s) = gate.refusals().take_summary() {
                    tracing::warn!("console API: {s}");
                }
                continue;
            }
            () = &mut shutdown => break,
        };
        let Ok(permit) = connections.clone().try_acquire_owned() else {
            gate.refusals().count("refused: max_connections");
            continue;
        };
        // Over a cap with nothing evictable: closed at once, counted.
        let Some(ticket) = gate.admit(peer.ip()) else {
            continue;
        };
        let conn = Conn {
            app: app.clone(),
            limits,
            watcher: graceful.watcher(),
            refusals: gate.clone(),
        };
        let tls = tls.clone();
        tokio::spawn(async move {
            conn.run(stream, peer, tls, ticket).await;
            drop(permit);
        });
    }
    drop(listener);
    if let Some(s) = gate.refusals().take_summary_now() {
        tracing::warn!("console API: {s}");
    }
    tokio::select! {
        () = graceful.shutdown() => {}
        () = tokio::time::sleep(Duration::from_secs(SHUTDOWN_GRACE_S)) => {
            tracing::warn!("open requests did not finish within the grace period");
        }
    }
    Ok(())
}

/// A connection's ticket at the gate, shared with its requests: taken (uncounted) once a
/// request is answered, held (no longer evictable) once a request has arrived whole.
type SharedTicket = Arc<Mutex<Option<Ticket>>>;

fn hold(ticket: &SharedTicket) {
    if let Some(t) = ticket
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
        .as_mut()
    {
        t.hold();
    }
}

/// A step made (a request head arrived): another grace before it may be evicted.
fn progress(ticket: &SharedTicket) {
    if let Some(t) = ticket
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
        .as_mut()
    {
        t.progress();
    }
}

/// What one connection's task needs.
struct Conn {
    app: Router,
    limits: WebLimits,
    watcher: Watcher,
    refusals: Arc<ConnectionGate>,
}

impl Conn {
    async fn run(
        self,
        stream: TcpStream,
        peer: SocketAddr,
        tls: Option<TlsAcceptor>,
        mut ticket: Ticket,
    ) {
        let handshake_timeout = Duration::from_millis(self.limits.tls_handshake_timeout_ms);
        let refusals = self.refusals.refusals();
        // Nothing is read before the connection has a slot; it waits in its address's line
        // at most as long as a handshake may take.
        if tokio::time::timeout(handshake_timeout, ticket.wait_turn())
            .await
            .is_err()
        {
            refusals.count("refused: no slot free within the TLS handshake timeout");
            return;
        }
        let mut eviction = ticket.eviction();
        let ticket: SharedTicket = Arc::new(Mutex::new(Some(ticket)));
        let Some(acceptor) = tls else {
            self.serve_connection(stream, peer, ticket, eviction).await;
            return;
        };
        let handshake = tokio::select! {
            h = tokio::time::timeout(handshake_timeout, acceptor.accept(stream)) => h,
            () = eviction.wait() => return,
        };
        match handshake {
            Ok(Ok(tls_stream)) => {
                progress(&ticket);
                self.serve_connection(tls_stream, peer, ticket, eviction)
                    .await;
            }
            Ok(Err(e)) => {
                if refusals.detail("TLS handshake failed") {
                    tracing::debug!(%peer, error = %e, "TLS handshake failed");
                }
            }
            Err(_) => {
                if refusals.detail("TLS handshake timed out") {
                    tracing::debug!(%peer, "TLS handshake timed out");
                }
            }
        }
    }

    /// Serves HTTP/1.1 on `stream` from `peer`; each request carries the client's address
    /// (`ConnectInfo`), which the login throttle keys on.
    async fn serve_connection<S>(
        self,
        stream: S,
        peer: SocketAddr,
        ticket: SharedTicket,
        mut eviction: Eviction,
    ) where
        S: AsyncRead + AsyncWrite + Unpin + Send + 'static,
    {
        let Self {
            app,
            limits,
            watcher,
            ..
        } = self;
        let body_timeout = Duration::from_millis(limits.body_timeout_ms);
        let service = hyper::service::service_fn(move |request: Request<Incoming>| {
            let app = app.clone();
            let ticket = ticket.clone();
            async move {
                if request.body().is_end_stream() {
                    hold(&ticket);
                } else {
                    progress(&ticket);
                }
                let mut request = request;
                request
                    .extensions_mut()
                    .insert(axum::extract::ConnectInfo(peer));
                let request = request.map(|inner| {
                    Body::new(DeadlineBody {
                        inner,
                        deadline: Box::pin(tokio::time::sleep(body_timeout)),
                        timeout: body_timeout,
                        ticket: ticket.clone(),
                    })
                });
                let response = app.oneshot(request).await;
                // Answered: no longer counted as unanswered.
                drop(ticket.lock().unwrap_or_else(PoisonError::into_inner).take());
                response
            }
        });
        let connection = hyper::server::conn::http1::Builder::new()
            .timer(hyper_util::rt::TokioTimer::new())
            .header_read_timeout(Duration::from_millis(limits.header_read_timeout_ms))
            .serve_connection(TokioIo::new(stream), service);
        tokio::select! {
            r = watcher.watch(connection) => {
                if let Err(e) = r {
                    tracing::debug!(error = %e, "connection ended with an error");
                }
            }
            // Dropping the connection closes it.
            () = eviction.wait() => {}
        }
    }
}

/// A request body that must arrive whole within a deadline (from the end of the request's
/// head); past it, reading it fails, the handler answers 400 and hyper closes the connection.
struct DeadlineBody {
    inner: Incoming,
    deadline: Pin<Box<tokio::time::Sleep>>,
    timeout: Duration,
    ticket: SharedTicket,
}

impl hyper::body::Body for DeadlineBody {
    type Data = Bytes;
    type Error = BoxError;

    fn poll_frame(
        mut self: Pin<&mut Self>,
        cx: &mut Context<'_>,
    ) -> Poll<Option<Result<hyper::body::Frame<Bytes>, BoxError>>> {
        let this = &mut *self;
        match Pin::new(&mut this.inner).poll_frame(cx) {
            Poll::Ready(frame) => {
                if frame.is_none() || this.inner.is_end_stream() {
                    hold(&this.ticket);
                }
                Poll::Ready(frame.map(|f| f.map_err(BoxError::from)))
            }
            Poll::Pending => match this.deadline.as_mut().poll(cx) {
                Poll::Ready(()) => Poll::Ready(Some(Err(format!(
                    "the request body did not arrive within {} ms",
                    this.timeout.as_millis()
                )
                .into()))),
                Poll::Pending => Poll::Pending,
            },
        }
    }

    fn is_end_stream(&self) -> bool {
        self.inner.is_end_stream()
    }

    fn size_hint(&self) -> hyper::body::SizeHint {
        self.inner.size_hint()
    }
}
