//! One connection of the link task: connect (TCP, then TLS), say `Hello`, send what is
//! unacknowledged, read `Ack`s and regimens, and say `Bye` at the end.

use std::net::SocketAddr;
use std::sync::atomic::Ordering;
use std::time::Duration;

use tokio::net::TcpStream;
use tokio::sync::mpsc;
use tokio::time::Instant;

use crate::codec::encode_to_vec;
use crate::error::NetlinkError;
use crate::frame::{Bye, ErrorFrame, Frame};
use crate::transport::{BoxStream, FrameReader, Outgoing, spawn_writer};

use super::task::{ConnEnd, LinkTask, Pending};
use super::*;

impl LinkTask {
    /// Connects (TCP, then TLS if configured) within the connect timeout and the finish
    /// deadline. `None` if the link should stop.
    pub(super) async fn connect(&mut self) -> Option<Result<BoxStream, NetlinkError>> {
        let addr = self.config.addr.clone();
        let limit = Duration::from_millis(self.config.connect_timeout_ms);
        let tls = self.tls.clone();
        let plaintext = tls.is_none();
        let attempt = tokio::time::timeout(limit, async move {
            // Resolved on every attempt: a name that does not resolve now may later.
            let mut candidates: Vec<SocketAddr> = match &addr {
                HubAddress::Socket(a) => vec![*a],
                HubAddress::Name(name) => tokio::net::lookup_host(name.as_str())
                    .await
                    .map_err(|e| NetlinkError::io(format!("resolving {name}"), e))?
                    .collect(),
            };
            if plaintext {
                // Without TLS only loopback may be reached, whatever a name resolves to.
                candidates.retain(|a| a.ip().is_loopback());
            }
            let mut last_error = NetlinkError::io(
                format!("resolving {addr}"),
                std::io::Error::new(
                    std::io::ErrorKind::NotFound,
                    "no usable address (plaintext allows only loopback)",
                ),
            );
            let mut connected = None;
            for candidate in candidates {
                match TcpStream::connect(candidate).await {
                    Ok(tcp) => {
                        connected = Some(tcp);
                        break;
                    }
                    Err(e) => {
                        last_error =
                            NetlinkError::io(format!("connecting to {addr} ({candidate})"), e);
                    }
                }
            }
            let tcp = connected.ok_or(last_error)?;
            let _ = tcp.set_nodelay(true);
            let stream: BoxStream = match tls {
                None => Box::new(tcp),
                Some((connector, name)) => Box::new(
                    connector
                        .connect(name, tcp)
                        .await
                        .map_err(|e| NetlinkError::io(format!("TLS handshake with {addr}"), e))?,
                ),
            };
            Ok(stream)
        });
        tokio::pin!(attempt);
        loop {
            let deadline = self.deadline();
            tokio::select! {
                r = &mut attempt => {
                    return Some(r.unwrap_or_else(|_| Err(NetlinkError::io(
                        format!("connecting to {}", self.config.addr),
                        std::io::Error::new(std::io::ErrorKind::TimedOut, format!("no connection within {} ms", limit.as_millis())),
                    ))));
                }
                q = self.rx.recv(), if self.rx_open => { self.on_queued(q); }
                f = &mut self.finish_rx, if self.finish_rx_open => self.on_finish(f),
                () = tokio::time::sleep_until(deadline) => return None,
            }
            if self.should_stop() {
                return None;
            }
        }
    }

    pub(super) fn outgoing(&self, p: &Pending) -> Outgoing {
        let shared = self.shared.clone();
        let written = p.written.clone();
        Outgoing {
            bytes: p.bytes.clone(),
            on_written: Some(Box::new(move || {
                if written.swap(true, Ordering::Relaxed) {
                    Shared::bump(&shared.resent);
                } else {
                    Shared::bump(&shared.sent);
                }
            })),
        }
    }

    /// Apply an Ack from the therapist: drop what it acknowledges; true when that was
    /// progress. An Ack for another session or above what this station can produce (the
    /// summaries handed over, or a resent session's known last `seq`,
    /// [`StationLinkConfig::replay_last_seq`]) is a protocol error (told to the hub in an
    /// Error frame when it is impossible).
    fn on_ack(
        &mut self,
        ack: &crate::frame::Ack,
        session_id: &str,
        out_tx: &mpsc::UnboundedSender<Outgoing>,
    ) -> Result<bool, NetlinkError> {
        if ack.session_id != session_id {
            return Err(NetlinkError::Protocol(format!(
                "Ack for session {:?}, expected {session_id:?}",
                ack.session_id
            )));
        }
        // Everything handed to the link counts as produced, even if it is still in the
        // channel.
        self.drain_channel();
        // A resent session's summaries exist before they are handed over: the hub may
        // acknowledge up to their last seq while the replay is behind.
        let possible = self.last_produced_seq.max(self.config.replay_last_seq);
        if possible.is_none_or(|p| ack.seq > p) {
            let error = NetlinkError::Protocol(format!(
                "impossible Ack: the therapist acknowledged seq {} but this station has {}; \
                 reconnecting to resend what is unacknowledged",
                ack.seq,
                possible.map_or_else(
                    || "produced no summary".to_owned(),
                    |p| format!("summaries only up to seq {p}")
                )
            ));
            send_error_frame(out_tx, &error);
            return Err(error);
        }
        self.acked_upto = self.acked_upto.max(Some(ack.seq));
        let mut n = 0;
        while self.pending.front().is_some_and(|p| p.seq <= ack.seq) {
            self.pending.pop_front();
            n += 1;
        }
        if n > 0 {
            self.shared.acked.fetch_add(n, Ordering::Relaxed);
            self.update_pending();
        }
        Ok(n > 0)
    }

    pub(super) async fn run_connection(&mut self, stream: BoxStream) -> ConnEnd {
        let (rd, wr) = tokio::io::split(stream);
        let (out_tx, out_rx) = mpsc::unbounded_channel();
        let mut writer = spawn_writer(wr, out_rx);
        let mut reader = FrameReader::new(rd);
        let _ = out_tx.send(Outgoing::new(self.hello_bytes.clone()));
        while let Ok(seen) = self.seen_rx.try_recv() {
            self.seen.push(seen);
        }
        for seen in &self.seen {
            let _ = out_tx.send(Outgoing::new(seen.clone()));
        }
        self.shared.connected.store(true, Ordering::Relaxed);
        let ack_timeout = Duration::from_millis(self.config.ack_timeout_ms);
        let mut liveness = tokio::time::interval(Duration::from_millis(500));
        let mut enqueued_upto: Option<u64> = None;
        let mut bye_sent = false;
        let mut last_heard = Instant::now();
        let mut progress = false;
        let mut writer_done = false;
        let session_id = self.config.hello.session_id.clone();
        let lost = |error, progress| ConnEnd::Lost { error, progress };
        let end = loop {
            let start = self
                .pending
                .partition_point(|p| enqueued_upto.is_some_and(|u| p.seq <= u));
            for p in self.pending.range(start..) {
                let _ = out_tx.send(self.outgoing(p));
                enqueued_upto = Some(p.seq);
            }
            if self.finishing.is_some() && !bye_sent {
                self.say_bye(&session_id, &out_tx);
                bye_sent = true;
            }
            let deadline = self.deadline();
            tokio::select! {
                r = &mut writer => {
                    writer_done = true;
                    let error = match r {
                        Ok(Ok(())) => NetlinkError::Closed,
                        Ok(Err(e)) => e,
                        Err(e) => NetlinkError::Protocol(format!("writer task failed: {e}")),
                    };
                    break lost(error, progress);
                }
                frame = reader.next_frame() => {
                    last_heard = Instant::now();
                    let seen = (bye_sent, session_id.as_str(), &out_tx);
                    if let Some(end) = self.on_frame(frame, seen, &mut progress) {
                        break end;
                    }
                }
                q = self.rx.recv(), if self.rx_open => {
                    if self.on_queued(q) {
                        last_heard = Instant::now();
                    }
                }
                Some(seen) = self.seen_rx.recv() => {
                    let _ = out_tx.send(Outgoing::new(seen.clone()));
                    self.seen.push(seen);
                }
                f = &mut self.finish_rx, if self.finish_rx_open => {
                    self.on_finish(f);
                    if self.finishing.is_none() {
                        break ConnEnd::Done;
                    }
                }
                () = tokio::time::sleep_until(deadline) => break ConnEnd::Done,
                _ = liveness.tick() => {
                    if !self.pending.is_empty() && last_heard.elapsed() > ack_timeout {
                        break lost(NetlinkError::Protocol(format!(
                            "no acknowledgement from the therapist for {} ms; reconnecting",
                            ack_timeout.as_millis()
                        )), progress);
                    }
                }
            }
        };
        // Let the writer send what is queued (a Bye or an Error frame) and close the stream,
        // but not past the deadline, and only briefly for a broken connection.
        drop(out_tx);
        if !writer_done {
            let limit = match end {
                ConnEnd::Done | ConnEnd::UpdateRequired(_) => self.deadline(),
                ConnEnd::Lost { .. } => {
                    (Instant::now() + Duration::from_millis(100)).min(self.deadline())
                }
            };
            if tokio::time::timeout_at(limit, &mut writer).await.is_err() {
                writer.abort();
            }
        }
        end
    }

    /// Queue the `Bye` of a finishing session on `out_tx`.
    fn say_bye(&self, session_id: &str, out_tx: &mpsc::UnboundedSender<Outgoing>) {
        let Some(f) = self.finishing.as_ref() else {
            return;
        };
        let bye = Frame::Bye(Bye {
            session_id: session_id.to_owned(),
            reason: f.reason.clone(),
            final_seq: self.last_produced_seq,
            measures: f.measures.clone(),
            hub_unix_ms: None,
            checkin: f.checkin.clone(),
            difficulty: f.difficulty.clone(),
            exercises: f.exercises.clone(),
        });
        match encode_to_vec(&bye) {
            Ok(bytes) => {
                let _ = out_tx.send(Outgoing::new(bytes.into()));
            }
            Err(e) => self.shared.set_error(format!("cannot encode Bye: {e}")),
        }
    }

    /// What the hub sent (`frame`) on a connection that has sent its `Bye` or not, for
    /// session `session_id`, answering on `out_tx`: how the connection ends, or `None` if it
    /// goes on. `progress` turns true when an Ack acknowledged something.
    fn on_frame(
        &mut self,
        frame: Result<Option<Frame>, NetlinkError>,
        (bye_sent, session_id, out_tx): (bool, &str, &mpsc::UnboundedSender<Outgoing>),
        progress: &mut bool,
    ) -> Option<ConnEnd> {
        let lost = |error, progress| Some(ConnEnd::Lost { error, progress });
        match frame {
            Ok(Some(Frame::Ack(ack))) => match self.on_ack(&ack, session_id, out_tx) {
                Ok(acked) => {
                    *progress |= acked;
                    None
                }
                Err(error) => lost(error, *progress),
            },
            Ok(Some(Frame::Regimen(r))) => {
                Shared::bump(&self.shared.regimens_received);
                tracing::info!(id = %r.id, "regimen received from therapist");
                if self.regimen_tx.try_send(r).is_err() {
                    self.shared.set_error(format!(
                        "regimen dropped: {REGIMEN_CAPACITY} unread regimens waiting"
                    ));
                }
                None
            }
            Ok(Some(Frame::Message(m))) => {
                tracing::info!(id = %m.id, "message received from therapist");
                if self.message_tx.try_send(m).is_err() {
                    self.shared.set_error(format!(
                        "message dropped: {} unread messages waiting",
                        MESSAGE_CAPACITY
                    ));
                }
                None
            }
            Ok(Some(Frame::Care(c))) => {
                tracing::info!(
                    threshold = c.pain_threshold_0_10,
                    "the clinic's pain settings received"
                );
                if let Ok(mut slot) = self.shared.care.lock() {
                    *slot = Some(c);
                }
                None
            }
            Ok(Some(Frame::Bye(b))) if bye_sent && self.pending.is_empty() => {
                tracing::info!(final_seq = ?b.final_seq, "therapist confirmed end of session");
                self.shared.bye_acknowledged.store(true, Ordering::Relaxed);
                Some(ConnEnd::Done)
            }
            Ok(Some(Frame::Bye(b))) => {
                let error = NetlinkError::Protocol(format!(
                    "therapist ended the connection: {} ({} summaries unacknowledged)",
                    b.reason,
                    self.pending.len()
                ));
                lost(error, *progress)
            }
            Ok(Some(Frame::Error(e)))
                if e.code.as_deref() == Some(crate::frame::UPDATE_REQUIRED) =>
            {
                Some(ConnEnd::UpdateRequired(e.message))
            }
            Ok(Some(Frame::Error(e))) => {
                let error =
                    NetlinkError::Protocol(format!("therapist reported an error: {}", e.message));
                lost(error, *progress)
            }
            Ok(Some(other)) => {
                let error = NetlinkError::Protocol(format!(
                    "unexpected {} frame from the therapist",
                    other.kind()
                ));
                send_error_frame(out_tx, &error);
                lost(error, *progress)
            }
            Ok(None) => {
                let error = NetlinkError::Protocol("therapist closed the connection".into());
                lost(error, *progress)
            }
            Err(error) => {
                send_error_frame(out_tx, &error);
                lost(error, *progress)
            }
        }
    }
}

fn send_error_frame(out_tx: &mpsc::UnboundedSender<Outgoing>, error: &NetlinkError) {
    let message = crate::frame::printable(&error.to_string(), crate::frame::MAX_MESSAGE_LEN);
    if let Ok(bytes) = encode_to_vec(&Frame::Error(ErrorFrame {
        message,
        code: None,
    })) {
        let _ = out_tx.send(Outgoing::new(bytes.into()));
    }
}
