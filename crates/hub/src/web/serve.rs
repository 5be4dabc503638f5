//! Serving the API over HTTPS (rustls with `ring`, HTTP/1.1) with graceful shutdown.

use std::future::Future;
use std::path::Path;
use std::time::Duration;

use axum::Router;
use hyper_util::rt::TokioIo;
use hyper_util::server::graceful::GracefulShutdown;
use hyper_util::service::TowerToHyperService;
use tokio::io::{AsyncRead, AsyncWrite};
use tokio::net::TcpListener;
use tokio_rustls::TlsAcceptor;

use super::{AppState, router};
use crate::error::HubError;

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

/// Serves [`router`]`(state)` on `listener` until `shutdown` completes; see [`serve_router`].
pub async fn serve(
    listener: TcpListener,
    tls: Option<TlsAcceptor>,
    state: AppState,
    shutdown: impl Future<Output = ()> + Send,
) -> Result<(), HubError> {
    serve_router(listener, tls, router(state), shutdown).await
}

/// Serves `app` on `listener` over TLS until `shutdown` completes, then stops accepting and
/// waits up to [`SHUTDOWN_GRACE_S`] for open requests. `tls: None` serves plain HTTP and is
/// refused unless the listener is bound to a loopback address.
pub async fn serve_router(
    listener: TcpListener,
    tls: Option<TlsAcceptor>,
    app: Router,
    shutdown: impl Future<Output = ()> + Send,
) -> Result<(), HubError> {
    let local = listener
        .local_addr()
        .map_err(|e| HubError::io("reading the listening address", e))?;
    if tls.is_none() && !local.ip().is_loopback() {
        return Err(HubError::Config(format!(
            "plain HTTP is allowed only on a loopback address, not {local}; give a TLS \
             certificate and key"
        )));
    }
    tracing::info!(address = %local, tls = tls.is_some(), "therapist console API listening");
    let graceful = GracefulShutdown::new();
    let mut shutdown = std::pin::pin!(shutdown);
    loop {
        let (stream, peer) = tokio::select! {
            accepted = listener.accept() => match accepted {
                Ok(pair) => pair,
                Err(e) => {
                    // Out of file descriptors and the like: wait instead of spinning.
                    tracing::warn!(error = %e, "accept failed");
                    tokio::time::sleep(Duration::from_millis(100)).await;
                    continue;
                }
            },
            () = &mut shutdown => break,
        };
        let app = app.clone();
        let tls = tls.clone();
        let watcher = graceful.watcher();
        tokio::spawn(async move {
            match tls {
                None => serve_connection(stream, app, watcher).await,
                Some(acceptor) => {
                    let handshake = tokio::time::timeout(
                        Duration::from_secs(TLS_HANDSHAKE_TIMEOUT_S),
                        acceptor.accept(stream),
                    )
                    .await;
                    match handshake {
                        Ok(Ok(tls_stream)) => serve_connection(tls_stream, app, watcher).await,
                        Ok(Err(e)) => tracing::debug!(%peer, error = %e, "TLS handshake failed"),
                        Err(_) => tracing::debug!(%peer, "TLS handshake timed out"),
                    }
                }
            }
        });
    }
    drop(listener);
    tokio::select! {
        () = graceful.shutdown() => {}
        () = tokio::time::sleep(Duration::from_secs(SHUTDOWN_GRACE_S)) => {
            tracing::warn!("open requests did not finish within the grace period");
        }
    }
    Ok(())
}

async fn serve_connection<S>(stream: S, app: Router, watcher: hyper_util::server::graceful::Watcher)
where
    S: AsyncRead + AsyncWrite + Unpin + Send + 'static,
{
    let connection = hyper::server::conn::http1::Builder::new()
        .timer(hyper_util::rt::TokioTimer::new())
        .header_read_timeout(Duration::from_secs(30))
        .serve_connection(TokioIo::new(stream), TowerToHyperService::new(app));
    if let Err(e) = watcher.watch(connection).await {
        tracing::debug!(error = %e, "connection ended with an error");
    }
}
