//! One station's connection to the hub, from accept to close: TLS handshake, `Hello` (and the
//! client certificate naming the station), registration for regimens, the frame loop, and
//! clean-up.

use std::net::SocketAddr;
use std::sync::Arc;
use std::sync::atomic::Ordering;
use std::time::Duration;

use rustls::pki_types::CertificateDer;
use tokio::net::{TcpListener, TcpStream};
use tokio::sync::{mpsc, watch};
use tokio::task::JoinHandle;

use crate::error::NetlinkError;
use crate::frame::{Ack, Bye, Frame, Hello};
use crate::proxy_protocol::ProxiedListener;
use crate::tls::certificate_names_station;
use crate::transport::{BoxStream, FrameReader, Outbox, spawn_outbox_writer};

use super::budget::{REFUSAL_LOG_INTERVAL, Ticket};
use super::outgoing::{coded_error_outgoing, error_outgoing, frame_outgoing, send};
use super::session::{Failure, Reply, handle_frame, last_seq, sync_file};
use super::{Hub, Peer, SessionSlot, StationRoute, TherapistEvent, lock};

/// The writer side of a connection: frames queued for the station (bounded) and its latest Ack.
type Out = Outbox;
/// The writer task; it ends with the first write error.
type Writer = JoinHandle<Result<(), NetlinkError>>;
/// A session's store, shared with the hub's session table.
type File = SessionSlot;

/// Accepts stations until `shutdown`, each served on its own task (which holds a clone of
/// `tasks` until it ends). A connection is counted by the hub's gate (per address and in all)
/// until the store admits its Hello, then against `max_connections`.
pub(super) async fn accept_loop(
    hub: Arc<Hub>,
    listener: TcpListener,
    mut shutdown: watch::Receiver<bool>,
    tasks: mpsc::Sender<()>,
) {
    let mut summary = tokio::time::interval(REFUSAL_LOG_INTERVAL);
    summary.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
    // Behind a balancer: each station's own address, from its PROXY header.
    let mut listener = ProxiedListener::new(
        listener,
        hub.config.proxy_protocol_from.clone(),
        Duration::from_millis(hub.config.hello_timeout_ms),
        "station port",
    );
    loop {
        tokio::select! {
            _ = shutdown.changed() => break,
            _ = summary.tick() => hub.summarise_refusals(false),
            accepted = listener.accept() => match accepted {
                Ok((tcp, peer)) => {
                    // Over a cap with nothing evictable: closed at once, counted.
                    let Some(ticket) = hub.gate.admit(peer.ip()) else {
                        continue;
                    };
                    let _ = tcp.set_nodelay(true);
                    let hub = hub.clone();
                    let shutdown = shutdown.clone();
                    let task = tasks.clone();
                    tokio::spawn(async move {
                        serve(hub, tcp, peer, ticket, shutdown).await;
                        drop(task);
                    });
                }
                Err(e) => {
                    // Typically EMFILE; back off briefly instead of spinning.
                    if hub.gate.refusals().detail("accept failed") {
                        tracing::warn!(error = %e, "therapist hub: accept failed");
                    }
                    tokio::time::sleep(Duration::from_millis(100)).await;
                }
            },
        }
    }
    hub.summarise_refusals(true);
}

/// Makes `ack` the next Ack for the station, replacing one not yet written.
fn send_ack(out: &Out, ack: Ack) {
    let seq = ack.seq;
    if let Some(o) = frame_outgoing(&Frame::Ack(ack)) {
        out.ack(seq, o.bytes);
    }
}

/// Tells the station about a protocol error and reports it; the reason the connection ends.
fn protocol_error(hub: &Hub, out: &Out, peer: SocketAddr, error: String) -> String {
    send(out, error_outgoing(&error));
    hub.emit(TherapistEvent::ProtocolError {
        peer,
        error: error.clone(),
    });
    format!("protocol error: {error}")
}

/// Serves one connection from TLS handshake to close. Never panics on peer input. It may
/// first wait in its address's line for a slot (`ticket`, within the Hello timeout); until its
/// first frame it may be evicted once it has stalled for a grace (the TLS handshake renews
/// the grace), or ended by shutdown; then it stays counted as unauthenticated until the store
/// admits it.
async fn serve(
    hub: Arc<Hub>,
    tcp: TcpStream,
    peer: SocketAddr,
    mut ticket: Ticket,
    mut shutdown: watch::Receiver<bool>,
) {
    let hello_timeout = Duration::from_millis(hub.config.hello_timeout_ms);
    let turn = tokio::select! {
        () = ticket.wait_turn() => true,
        () = tokio::time::sleep(hello_timeout) => false,
        _ = shutdown.changed() => return,
    };
    if !turn {
        hub.gate
            .refusals()
            .count("refused: no slot free within the Hello timeout");
        return;
    }
    let handshake = tokio::select! {
        h = handshake(&hub, tcp, peer) => h,
        () = ticket.evicted() => None,
        _ = shutdown.changed() => None,
    };
    let Some((stream, client_cert)) = handshake else {
        return;
    };
    // A step made: another grace to send the first frame.
    ticket.progress();
    let (rd, wr) = tokio::io::split(stream);
    let (out, mut writer) = spawn_outbox_writer(wr, hub.outbox_stats.clone());
    let mut reader = FrameReader::new(rd);

    let first = tokio::select! {
        f = first_frame(&hub, &mut reader) => Some(f),
        () = ticket.evicted() => None,
        _ = shutdown.changed() => None,
    };
    let Some(first) = first else {
        close(out, writer).await;
        return;
    };
    ticket.hold();
    let first = match first {
        Ok(Frame::PairStart(start)) => {
            let outcome = super::pairing::serve(&hub, start, &mut reader, &out, peer).await;
            hub.emit(TherapistEvent::Pairing { peer, outcome });
            close(out, writer).await;
            return;
        }
        other => other,
    };
    let peer_id = Peer {
        addr: peer,
        certificate: client_cert.as_ref(),
    };
    if let Ok(Frame::Hello(hello)) = &first
        && hello.exercise == crate::frame::CHECK_EXERCISE
    {
        // A station's check: answered as any Hello would be, nothing stored.
        answer_check(&hub, hello, peer_id, &out).await;
        close(out, writer).await;
        return;
    }
    let admitted = match hub.connections.clone().try_acquire_owned() {
        Ok(permit) => open_session(&hub, first, peer_id)
            .await
            .map(|(hello, file)| (hello, file, permit)),
        Err(_) => Err((
            format!(
                "the hub already serves {} stations (max_connections); try again later",
                hub.config.max_connections
            ),
            None,
        )),
    };
    let (hello, file, permit) = match admitted {
        Ok(v) => v,
        Err((error, code)) => {
            send(&out, coded_error_outgoing(&error, code));
            hub.refuse(peer, "not admitted", error);
            close(out, writer).await;
            return;
        }
    };
    // Admitted: no longer counted against the address or the unauthenticated cap.
    drop(ticket);
    let conn_id = register(&hub, peer, &hello, &file, &out).await;
    let reason = frame_loop(
        &hub,
        peer,
        &hello,
        &file,
        &out,
        &mut writer,
        &mut reader,
        shutdown,
    )
    .await;
    unregister(&hub, &hello, conn_id, file, reason).await;
    close(out, writer).await;
    drop(permit);
}

/// The TLS handshake (when the hub has TLS) within the Hello timeout: the stream and the
/// station's certificate, if it presented one. `None` (reported) if the handshake failed.
async fn handshake(
    hub: &Hub,
    tcp: TcpStream,
    peer: SocketAddr,
) -> Option<(BoxStream, Option<CertificateDer<'static>>)> {
    let hello_timeout = Duration::from_millis(hub.config.hello_timeout_ms);
    let Some(acceptor) = &hub.acceptor else {
        return Some((Box::new(tcp), None));
    };
    let error = match tokio::time::timeout(hello_timeout, acceptor.accept(tcp)).await {
        Ok(Ok(tls)) => {
            let cert = tls
                .get_ref()
                .1
                .peer_certificates()
                .and_then(|chain| chain.first())
                .map(|leaf| leaf.clone().into_owned());
            return Some((Box::new(tls), cert));
        }
        Ok(Err(e)) => format!("TLS handshake failed: {e}"),
        Err(_) => "TLS handshake timed out".into(),
    };
    hub.refuse(peer, "TLS handshake failed or timed out", error);
    None
}

/// The connection's first frame (`Hello`, or `PairStart` from a station being paired), within
/// the Hello timeout.
async fn first_frame(
    hub: &Hub,
    reader: &mut FrameReader,
) -> Result<Frame, (String, Option<&'static str>)> {
    let plain = |e: String| (e, None);
    let hello_timeout = Duration::from_millis(hub.config.hello_timeout_ms);
    match tokio::time::timeout(hello_timeout, reader.next_frame()).await {
        Ok(Ok(Some(frame @ (Frame::Hello(_) | Frame::PairStart(_))))) => Ok(frame),
        Ok(Ok(Some(other))) => Err(plain(format!("expected Hello first, got {}", other.kind()))),
        Ok(Ok(None)) => Err(plain("connection closed before Hello".into())),
        Ok(Err(e)) => Err(plain(e.to_string())),
        Err(_) => Err(plain(format!(
            "no Hello within {} ms",
            hello_timeout.as_millis()
        ))),
    }
}

/// Whether the hub serves the station of `hello`: a version both speak, and the client
/// certificate naming the station when the hub requires one.
fn admit(hub: &Hub, hello: &Hello, peer: Peer<'_>) -> Result<(), (String, Option<&'static str>)> {
    let plain = |e: String| (e, None);
    // No version both sides speak: not retriable, the station must stop and say so.
    hello
        .negotiate_with(hub.config.min_protocol_version)
        .map_err(|e| (e.to_string(), Some(crate::frame::UPDATE_REQUIRED)))?;
    let requires_identity = hub
        .config
        .tls
        .as_ref()
        .is_some_and(|t| t.client_ca_pem_path.is_some());
    if requires_identity {
        let cert = peer
            .certificate
            .ok_or_else(|| plain("no client certificate presented".into()))?;
        certificate_names_station(cert, &hello.station_id).map_err(|e| plain(e.to_string()))?;
    }
    Ok(())
}

/// Answers a station's check: at [`crate::frame::CHECK_NEWS_VERSION`] and above, once the store
/// admits the station as it would a session's, the patient's news ([`super::CheckNews`]), then
/// `Bye` with the hub's clock; below it the `Bye` alone, as older hubs did. A refusal is one
/// `Error` frame.
async fn answer_check(hub: &Hub, hello: &Hello, peer: Peer<'_>, out: &Out) {
    let refused = |error: String, code: Option<&str>| {
        send(out, coded_error_outgoing(&error, code));
        hub.refuse(peer.addr, "check refused", error);
    };
    if let Err((error, code)) = admit(hub, hello, peer) {
        return refused(error, code);
    }
    let version = hello
        .negotiate_with(hub.config.min_protocol_version)
        .unwrap_or(crate::frame::MIN_PROTOCOL_VERSION);
    if version >= crate::frame::CHECK_NEWS_VERSION {
        // The news is the patient's: only for a station the store lets speak for them.
        if let Err(r) = hub.store.admit(hello, peer).await {
            return refused(r.message, r.code);
        }
        let news = hub.store.station_check(hello).await;
        for frame in news.into_frames() {
            send(out, frame_outgoing(&frame));
        }
    }
    send(out, frame_outgoing(&Frame::Bye(check_answer(hello))));
}

/// The hub's answer to a station's check: `Bye` with its clock.
fn check_answer(hello: &Hello) -> Bye {
    Bye {
        session_id: hello.session_id.clone(),
        reason: "station check answered; nothing stored".into(),
        final_seq: None,
        measures: Default::default(),
        hub_unix_ms: Some(crate::frame::unix_ms_now()),
        checkin: None,
        difficulty: None,
        exercises: Vec::new(),
    }
}

/// Checks the station's `Hello` ([`admit`], then the store's admission) and opens its session.
async fn open_session(
    hub: &Hub,
    first: Result<Frame, (String, Option<&'static str>)>,
    peer: Peer<'_>,
) -> Result<(Hello, File), (String, Option<&'static str>)> {
    let plain = |e: String| (e, None);
    let Frame::Hello(hello) = first? else {
        return Err(plain("expected Hello first".into()));
    };
    admit(hub, &hello, peer)?;
    let file = hub
        .open_session(&hello, peer)
        .await
        .map_err(|r| (r.message, r.code))?;
    Ok((hello, file))
}

/// Routes regimens for the station to this connection, reports it connected and tells a
/// reconnecting station what is already stored, so it need not resend it. The connection id.
async fn register(hub: &Hub, peer: SocketAddr, hello: &Hello, file: &File, out: &Out) -> u64 {
    let conn_id = hub.next_conn_id.fetch_add(1, Ordering::Relaxed);
    lock(&hub.stations).insert(
        hello.station_id.clone(),
        StationRoute {
            conn_id,
            out: out.clone(),
            // Admitted, so a version was negotiated.
            version: hello
                .negotiate_with(hub.config.min_protocol_version)
                .unwrap_or(crate::frame::MIN_PROTOCOL_VERSION),
        },
    );
    hub.emit(TherapistEvent::Connected {
        peer,
        hello: hello.clone(),
    });
    let last_stored = last_seq(file).await;
    if let Some(seq) = last_stored {
        let ack = Ack {
            session_id: hello.session_id.clone(),
            seq,
        };
        send_ack(out, ack);
    }
    conn_id
}

/// Reads and answers frames until the session ends: hub shutdown, writer failure, idle
/// timeout, close, protocol error or `Bye`. The reason it ended.
#[allow(clippy::too_many_arguments)] // one connection's parts, borrowed from `serve`
async fn frame_loop(
    hub: &Hub,
    peer: SocketAddr,
    hello: &Hello,
    file: &File,
    out: &Out,
    writer: &mut Writer,
    reader: &mut FrameReader,
    mut shutdown: watch::Receiver<bool>,
) -> String {
    let idle = Duration::from_millis(hub.config.idle_timeout_ms);
    let mut upload = None;
    // An upload's connection is no route for the therapist's pushes.
    let mut uploading = false;
    loop {
        tokio::select! {
            _ = shutdown.changed() => {
                let bye = Frame::Bye(Bye {
                    session_id: hello.session_id.clone(),
                    reason: "therapist hub shutting down".into(),
                    final_seq: last_seq(file).await,
                    measures: Default::default(),
                    hub_unix_ms: Some(crate::frame::unix_ms_now()),
                    checkin: None,
                    difficulty: None,
                    exercises: Vec::new(),
                });
                send(out, frame_outgoing(&bye));
                return "therapist hub shut down".to_owned();
            }
            r = &mut *writer => {
                return match r {
                    Ok(Err(e)) => e.to_string(),
                    _ => "writer stopped".to_owned(),
                };
            }
            frame = tokio::time::timeout(idle, reader.next_frame()) => {
                let frame = match frame {
                    Err(_) => return format!("nothing received for {} ms", idle.as_millis()),
                    Ok(Ok(None)) => return "connection closed by station".to_owned(),
                    Ok(Ok(Some(frame))) => frame,
                    Ok(Err(e)) => return protocol_error(hub, out, peer, e.to_string()),
                };
                match handle_frame(hub, hello, file, &mut upload, frame).await {
                    Ok(Reply::Ack(ack)) => send_ack(out, ack),
                    Ok(Reply::Nothing) => {}
                    Ok(Reply::Frame(frame)) => {
                        if matches!(frame, Frame::UploadAt(_)) && !uploading {
                            uploading = true;
                            hub.stop_routing_to(&hello.station_id, out);
                        }
                        send(out, frame_outgoing(&frame));
                    }
                    Ok(Reply::Bye(bye, why)) => {
                        send(out, frame_outgoing(&bye));
                        return why;
                    }
                    Err(Failure::Protocol(error)) => return protocol_error(hub, out, peer, error),
                    Err(Failure::Refused(kind, why)) => {
                        hub.store.refused(hello, kind, &why).await;
                        return protocol_error(hub, out, peer, why);
                    }
                    Err(Failure::Closed(why)) => return why,
                    Err(Failure::Unavailable(why)) => {
                        send(out, error_outgoing(&why));
                        return why;
                    }
                }
            }
        }
    }
}

/// Stops routing regimens to this connection (unless a newer one took over), syncs and
/// releases the session file and reports the station disconnected.
async fn unregister(hub: &Hub, hello: &Hello, conn_id: u64, file: File, reason: String) {
    {
        let mut stations = lock(&hub.stations);
        if stations
            .get(&hello.station_id)
            .is_some_and(|r| r.conn_id == conn_id)
        {
            stations.remove(&hello.station_id);
        }
    }
    if let Err(e) = sync_file(&file, None).await {
        tracing::error!(error = %e, "therapist hub: fsync failed");
    }
    hub.release_session(hello, file);
    hub.emit(TherapistEvent::Disconnected {
        station_id: hello.station_id.clone(),
        session_id: hello.session_id.clone(),
        reason,
    });
}

/// Lets queued frames leave (bounded), then drops the connection.
async fn close(out: Out, mut writer: Writer) {
    drop(out);
    // A writer that has ended (the frame loop may have awaited it already) is not polled again.
    if !writer.is_finished()
        && tokio::time::timeout(Duration::from_secs(1), &mut writer)
            .await
            .is_err()
    {
        writer.abort();
    }
}
