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
                half.write_all(&out.bytes).await.map_err(write_err)?;
                if let Some(hook) = out.on_written {
                    hook();
                }
                next = rx.try_recv().ok();
            }
            half.flush().await.map_err(write_err)?;
        }
        half.shutdown().await.map_err(write_err)?;
        Ok(())
    })
}
