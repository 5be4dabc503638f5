//! Byte-stream plumbing shared by both sides: a boxed (TLS or plain) stream, a cancel-safe
//! frame reader and a writer task fed by a channel, so a blocked peer never blocks the caller.

use tokio::io::{AsyncRead, AsyncReadExt, AsyncWrite, AsyncWriteExt, ReadHalf, WriteHalf};
use tokio::sync::mpsc;
use tokio::task::JoinHandle;

use crate::codec::FrameDecoder;
use crate::error::NetlinkError;
use crate::frame::Frame;

/// A bidirectional byte stream: plain TCP or TLS over TCP.
pub(crate) trait Stream: AsyncRead + AsyncWrite + Unpin + Send {}
impl<T: AsyncRead + AsyncWrite + Unpin + Send> Stream for T {}

/// A boxed [`Stream`].
pub(crate) type BoxStream = Box<dyn Stream>;

/// Reads frames from the read half of a stream.
pub(crate) struct FrameReader {
    half: ReadHalf<BoxStream>,
    decoder: FrameDecoder,
    chunk: Vec<u8>,
}

impl FrameReader {
    pub(crate) fn new(half: ReadHalf<BoxStream>) -> Self {
        Self {
            half,
            decoder: FrameDecoder::new(),
            chunk: vec![0; 16 * 1024],
        }
    }

    /// The next frame; `Ok(None)` on a clean end of stream between frames.
    ///
    /// Cancel-safe: bytes read before a cancellation stay in the decoder.
    pub(crate) async fn next_frame(&mut self) -> Result<Option<Frame>, NetlinkError> {
        loop {
            if let Some(frame) = self.decoder.next_frame()? {
                return Ok(Some(frame));
            }
            let n = self
                .half
                .read(&mut self.chunk)
                .await
                .map_err(|e| NetlinkError::io("reading from peer", e))?;
            if n == 0 {
                if self.decoder.buffered_len() > 0 {
                    return Err(NetlinkError::Protocol(format!(
                        "connection closed in the middle of a frame ({} bytes pending)",
                        self.decoder.buffered_len()
                    )));
                }
                return Ok(None);
            }
            self.decoder.extend(&self.chunk[..n]);
        }
    }
}

/// One encoded frame queued for the writer task, with a hook run once it is written.
pub(crate) struct Outgoing {
    pub(crate) bytes: std::sync::Arc<[u8]>,
    pub(crate) on_written: Option<Box<dyn FnOnce() + Send>>,
}

impl Outgoing {
    pub(crate) fn new(bytes: std::sync::Arc<[u8]>) -> Self {
        Self {
            bytes,
            on_written: None,
        }
    }
}

/// Write one queued frame and run its "written" hook.
async fn write_outgoing(
    half: &mut WriteHalf<BoxStream>,
    out: Outgoing,
) -> Result<(), NetlinkError> {
    half.write_all(&out.bytes)
        .await
        .map_err(|e| NetlinkError::io("writing to peer", e))?;
    if let Some(hook) = out.on_written {
        hook();
    }
    Ok(())
}

/// Spawns a task that writes queued frames in order and flushes after each burst.
///
/// The task ends when the channel closes (after writing and shutting down the stream) or on
/// the first write error, which it returns.
pub(crate) fn spawn_writer(
    mut half: WriteHalf<BoxStream>,
    mut rx: mpsc::UnboundedReceiver<Outgoing>,
) -> JoinHandle<Result<(), NetlinkError>> {
    tokio::spawn(async move {
        let write_err = |e| NetlinkError::io("writing to peer", e);
        while let Some(first) = rx.recv().await {
            let mut next = Some(first);
            while let Some(out) = next {
                write_outgoing(&mut half, out).await?;
                next = rx.try_recv().ok();
            }
            half.flush().await.map_err(write_err)?;
        }
        half.shutdown().await.map_err(write_err)?;
        Ok(())
    })
}

/// Frames a hub may queue for one connection besides the latest Ack (Regimen, Bye, Error).
/// A station that does not read makes further frames fail to queue instead of growing the
/// hub's memory.
pub(crate) const OUTBOX_CAPACITY: usize = 64;

/// The latest Ack waiting to be written: each new one replaces the previous (Acks are
/// cumulative, only the latest matters).
#[derive(Default)]
struct AckSlot {
    latest: std::sync::Mutex<Option<(u64, std::sync::Arc<[u8]>)>>,
    notify: tokio::sync::Notify,
}

impl AckSlot {
    fn take(&self) -> Option<(u64, std::sync::Arc<[u8]>)> {
        self.latest
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .take()
    }
}

/// Counters shared by every [`Outbox`] of a hub.
#[derive(Debug, Default)]
pub(crate) struct OutboxStats {
    /// Most frames ever waiting for one connection (queued frames plus a waiting Ack).
    pub(crate) high_water: std::sync::atomic::AtomicUsize,
    /// Acks replaced by a newer one before they were written.
    pub(crate) acks_coalesced: std::sync::atomic::AtomicU64,
    /// Frames not queued because a connection's outbox was full.
    pub(crate) refused: std::sync::atomic::AtomicU64,
}

/// The hub's sending side of one connection: a bounded queue of frames and a slot holding the
/// latest Ack. Cheap to clone. The writer writes a waiting Ack before each queued frame, so an
/// Ack set before a frame is queued reaches the peer before that frame.
#[derive(Clone)]
pub(crate) struct Outbox {
    tx: mpsc::Sender<Outgoing>,
    ack: std::sync::Arc<AckSlot>,
    stats: std::sync::Arc<OutboxStats>,
}

impl Outbox {
    /// Queues `frame` unless the outbox is full or closed. False if it was not queued.
    pub(crate) fn send(&self, frame: Outgoing) -> bool {
        let queued = self.tx.try_send(frame).is_ok();
        if queued {
            self.note_depth();
        } else {
            self.stats
                .refused
                .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        }
        queued
    }

    /// Whether `other` is a clone of this outbox (the same connection).
    pub(crate) fn same_connection(&self, other: &Outbox) -> bool {
        std::sync::Arc::ptr_eq(&self.ack, &other.ack)
    }

    /// Makes `bytes` (an encoded Ack for `seq`) the Ack to write next, replacing any waiting one.
    pub(crate) fn ack(&self, seq: u64, bytes: std::sync::Arc<[u8]>) {
        let replaced = self
            .ack
            .latest
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .replace((seq, bytes))
            .is_some();
        if replaced {
            self.stats
                .acks_coalesced
                .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        }
        self.ack.notify.notify_one();
        self.note_depth();
    }

    fn note_depth(&self) {
        let ack_waiting = self
            .ack
            .latest
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .is_some();
        let depth = OUTBOX_CAPACITY - self.tx.capacity() + usize::from(ack_waiting);
        self.stats
            .high_water
            .fetch_max(depth, std::sync::atomic::Ordering::Relaxed);
    }
}

/// Spawns a hub connection's writer and returns its [`Outbox`]. The writer writes the latest
/// Ack (skipping one not above the last Ack written) before each queued frame, flushes after
/// each burst, and ends when every `Outbox` clone is dropped (after writing what is waiting
/// and shutting the stream down) or on the first write error, which it returns.
pub(crate) fn spawn_outbox_writer(
    mut half: WriteHalf<BoxStream>,
    stats: std::sync::Arc<OutboxStats>,
) -> (Outbox, JoinHandle<Result<(), NetlinkError>>) {
    let (tx, mut rx) = mpsc::channel::<Outgoing>(OUTBOX_CAPACITY);
    let ack = std::sync::Arc::new(AckSlot::default());
    let outbox = Outbox {
        tx,
        ack: ack.clone(),
        stats,
    };
    let task = tokio::spawn(async move {
        let write_err = |e| NetlinkError::io("writing to peer", e);
        let mut last_ack: Option<u64> = None;
        let mut open = true;
        while open {
            let mut next = tokio::select! {
                biased;
                () = ack.notify.notified() => None,
                o = rx.recv() => {
                    open = o.is_some();
                    o
                }
            };
            loop {
                if let Some((seq, bytes)) = ack.take()
                    && last_ack.is_none_or(|l| seq > l)
                {
                    half.write_all(&bytes).await.map_err(write_err)?;
                    last_ack = Some(seq);
                }
                let Some(out) = next else { break };
                write_outgoing(&mut half, out).await?;
                next = rx.try_recv().ok();
            }
            half.flush().await.map_err(write_err)?;
        }
        half.shutdown().await.map_err(write_err)?;
        Ok(())
    });
    (outbox, task)
}
