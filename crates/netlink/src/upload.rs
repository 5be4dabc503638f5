//! The station's side of a recording upload: [`upload_recording`] sends a session's MCAP file
//! to the hub over a connection of that session (mutual TLS for a paired station), resuming
//! where the hub's copy ends, at most `bytes_per_s`, and returns once the hub has verified it.
//!
//! The hub may send on any connection after the `Hello`, whatever the connection is for, what
//! it pushes to a station: the therapist's [`Message`]s, the patient's [`Regimen`] and `Ack`s.
//! An upload takes them at every step and keeps the messages and the newest regimen
//! ([`Pushed`]) for the station to keep as its live link does; an `Error` stays a refusal and
//! a `Bye` ends the attempt (it resumes on the next).
//!
//! Chunks are sent ahead of the hub's answers, up to [`UPLOAD_WINDOW_CHUNKS`] at a time, so a
//! home link's round trip does not bound the upload (one chunk a round trip would be 320 kB/s
//! at 100 ms). The hub writes a chunk only at the offset it holds and answers every chunk with
//! that offset; when an answer is not the one expected (the hub resynchronises), the chunks
//! still in flight are let through unanswered by new ones and the upload goes on from where the
//! hub's last answer says.

use std::io::Read;
use std::path::Path;
use std::time::{Duration, Instant};

use base64::Engine;
use tokio::io::AsyncWriteExt;

use crate::codec::encode_to_vec;
use crate::frame::{
    Frame, Hello, MAX_CHUNK_BYTES, Message, Regimen, UploadAt, UploadChunk, UploadStart,
};
use crate::station::HubAddress;
use crate::tls::ClientTls;
use crate::transport::{BoxStream, FrameReader};

/// Chunks sent ahead of the hub's answers (× [`MAX_CHUNK_BYTES`] = 256 KiB in flight: 2.6 MB/s
/// over a 100 ms round trip, more than the upload's pace).
pub const UPLOAD_WINDOW_CHUNKS: usize = 8;

/// Size and lowercase hex SHA-256 of a file, read in a stream.
pub fn file_sha256(path: &Path) -> std::io::Result<(u64, String)> {
    let mut file = std::fs::File::open(path)?;
    let mut ctx = ring::digest::Context::new(&ring::digest::SHA256);
    let mut buf = vec![0u8; 1 << 16];
    let mut size = 0u64;
    loop {
        let n = file.read(&mut buf)?;
        if n == 0 {
            break;
        }
        size += n as u64;
        ctx.update(&buf[..n]);
    }
    Ok((size, crate::pairing::to_hex(ctx.finish().as_ref())))
}

/// What an upload did.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Uploaded {
    /// The file's size, bytes.
    pub size_bytes: u64,
    /// Bytes sent on this connection (less than the size when resumed).
    pub sent_bytes: u64,
}

/// Most of the therapist's messages one upload keeps: as many as the live link buffers. The
/// hub sends each unseen message again on the next connection, so one left out is not lost.
pub const MAX_PUSHED_MESSAGES: usize = crate::station::MESSAGE_CAPACITY;

/// What the hub pushed on an upload's connection that the station keeps as its live link
/// does: the therapist's messages (each once, by id, oldest first, at most
/// [`MAX_PUSHED_MESSAGES`]) and the newest regimen. Filled in as the frames arrive, so what
/// came before a failure is kept too.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Pushed {
    /// The therapist's messages, for the station's message store.
    pub messages: Vec<Message>,
    /// The newest regimen, to be validated and kept as a prescription pushed on the live link.
    pub regimen: Option<Regimen>,
    /// The clinic's newest pain settings.
    pub care: Option<crate::frame::Care>,
}

impl Pushed {
    /// Keeps `message` unless one with its id is kept or [`MAX_PUSHED_MESSAGES`] are; true if
    /// it was kept.
    pub fn keep_message(&mut self, message: Message) -> bool {
        if self.messages.len() >= MAX_PUSHED_MESSAGES
            || self.messages.iter().any(|m| m.id == message.id)
        {
            return false;
        }
        self.messages.push(message);
        true
    }

    /// Moves what `other` holds into this (its regimen is the newer).
    pub fn append(&mut self, other: Pushed) {
        for m in other.messages {
            self.keep_message(m);
        }
        if other.regimen.is_some() {
            self.regimen = other.regimen;
        }
        if other.care.is_some() {
            self.care = other.care;
        }
    }

    /// Nothing was pushed.
    pub fn is_empty(&self) -> bool {
        self.messages.is_empty() && self.regimen.is_none() && self.care.is_none()
    }
}

/// Why an upload stopped (it resumes where it stopped on the next attempt).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum UploadError {
    /// A plaintext upload to an address other than loopback.
    #[error("plaintext upload to {addr} refused: only loopback")]
    Plaintext {
        /// The hub's address.
        addr: String,
    },
    /// Reading the file, connecting, the TLS handshake or sending failed.
    #[error("{step}: {source}")]
    Io {
        /// What was being done, e.g. `connecting to 127.0.0.1:7000` or `seeking`.
        step: String,
        /// The reason.
        source: std::io::Error,
    },
    /// The file could not be hashed (its task ended without an answer).
    #[error("hashing task: {0}")]
    Hashing(tokio::task::JoinError),
    /// The link's TLS settings, the frame codec or the connection failed.
    #[error(transparent)]
    Link(#[from] crate::NetlinkError),
    /// A frame could not be encoded.
    #[error(transparent)]
    Codec(#[from] crate::CodecError),
    /// The hub answered with an error (e.g. a SHA-256 mismatch or a quota).
    #[error("the hub refused: {0}")]
    Refused(String),
    /// The hub ended the connection with a `Bye` (it is shutting down) before the upload was
    /// complete.
    #[error("the hub ended the connection: {0}")]
    Ended(String),
    /// The hub sent a frame that has no place on a station's connection (one a station sends,
    /// or a pairing frame).
    #[error("unexpected {0} during upload")]
    Unexpected(crate::frame::FrameKind),
    /// The hub closed the connection before the upload was complete.
    #[error("the hub closed the connection")]
    Closed,
    /// The file is shorter than where the hub asked to resume.
    #[error("the file ended at {offset} of {size} bytes")]
    FileEnded {
        /// The offset the hub asked for.
        offset: u64,
        /// The file's size when the upload began.
        size: u64,
    },
}

fn io(step: impl Into<String>) -> impl FnOnce(std::io::Error) -> UploadError {
    let step = step.into();
    move |source| UploadError::Io { step, source }
}

async fn connect(addr: &str, tls: Option<&ClientTls>) -> Result<BoxStream, UploadError> {
    let plaintext = tls.is_none();
    let address = HubAddress::from(addr);
    if plaintext && !address.is_loopback() {
        return Err(UploadError::Plaintext {
            addr: addr.to_owned(),
        });
    }
    let tcp = tokio::net::TcpStream::connect(addr)
        .await
        .map_err(io(format!("connecting to {addr}")))?;
    let _ = tcp.set_nodelay(true);
    Ok(match tls {
        None => Box::new(tcp),
        Some(tls) => {
            let (connector, name) = tls.connector()?;
            Box::new(
                connector
                    .connect(name, tcp)
                    .await
                    .map_err(io("TLS handshake"))?,
            )
        }
    })
}

/// Uploads `path`, the recording of the session `hello` opened, to the hub at `addr`. What the
/// hub pushes meanwhile is not kept ([`upload_recording_keeping`] keeps it).
pub async fn upload_recording(
    addr: &str,
    tls: Option<&ClientTls>,
    hello: Hello,
    path: &Path,
    bytes_per_s: u64,
) -> Result<Uploaded, UploadError> {
    let mut pushed = Pushed::default();
    upload_recording_keeping(addr, tls, hello, path, bytes_per_s, &mut pushed).await
}

/// The hub's next answer to the upload: its [`UploadAt`], taking on the way what it pushes at
/// any time (into `pushed`; an `Ack` needs nothing). An `Error` is a refusal, a `Bye` ends it.
async fn next_upload_at(
    reader: &mut FrameReader,
    pushed: &mut Pushed,
) -> Result<UploadAt, UploadError> {
    loop {
        match reader.next_frame().await? {
            Some(Frame::UploadAt(at)) => return Ok(at),
            Some(Frame::Ack(_)) => {}
            Some(Frame::Message(m)) => {
                let id = m.id.clone();
                if pushed.keep_message(m) {
                    tracing::info!(%id, "message received from therapist during an upload");
                } else {
                    tracing::debug!(%id, "message not kept: kept already, or too many");
                }
            }
            Some(Frame::Regimen(r)) => {
                tracing::info!(id = %r.id, "regimen received from therapist during an upload");
                pushed.regimen = Some(r);
            }
            Some(Frame::Care(c)) => pushed.care = Some(c),
            Some(Frame::Error(e)) => return Err(UploadError::Refused(e.message)),
            Some(Frame::Bye(b)) => return Err(UploadError::Ended(b.reason)),
            Some(other) => return Err(UploadError::Unexpected(other.kind())),
            None => return Err(UploadError::Closed),
        }
    }
}

/// [`upload_recording`], keeping in `pushed` the therapist's messages and the newest regimen
/// the hub sends on the connection (also when the upload then fails).
pub async fn upload_recording_keeping(
    addr: &str,
    tls: Option<&ClientTls>,
    hello: Hello,
    path: &Path,
    bytes_per_s: u64,
    pushed: &mut Pushed,
) -> Result<Uploaded, UploadError> {
    let owned = path.to_owned();
    let (size, sha256) = tokio::task::spawn_blocking(move || file_sha256(&owned))
        .await
        .map_err(UploadError::Hashing)?
        .map_err(io(format!("reading {}", path.display())))?;
    let stream = connect(addr, tls).await?;
    let (rd, mut wr) = tokio::io::split(stream);
    let mut reader = FrameReader::new(rd);
    let session_id = hello.session_id.clone();
    let mut send = async |frame: Frame| -> Result<(), UploadError> {
        let bytes = encode_to_vec(&frame)?;
        wr.write_all(&bytes).await.map_err(io("sending"))
    };
    send(Frame::Hello(hello)).await?;
    send(Frame::UploadStart(UploadStart {
        session_id: session_id.clone(),
        size_bytes: size,
        sha256,
    }))
    .await?;
    let mut file = std::fs::File::open(path).map_err(io("opening"))?;
    let mut buf = vec![0u8; MAX_CHUNK_BYTES];
    let started = Instant::now();
    let mut sent = 0u64;
    // The end offset of each chunk sent and not answered yet, oldest first.
    let mut in_flight = std::collections::VecDeque::with_capacity(UPLOAD_WINDOW_CHUNKS);
    let mut next = 0u64;
    let mut resync = false;
    loop {
        let at = next_upload_at(&mut reader, pushed).await?;
        if at.complete {
            return Ok(Uploaded {
                size_bytes: size,
                sent_bytes: sent,
            });
        }
        match in_flight.pop_front() {
            // The answer to UploadStart: where the hub's copy ends.
            None => next = at.offset,
            Some(end) if !resync && end == at.offset => {}
            // Not where this chunk ends: the hub holds `at.offset`; the chunks sent after it
            // are answered (not written) before anything new is sent.
            Some(_) => {
                resync = !in_flight.is_empty();
                if !resync {
                    next = at.offset;
                }
            }
        }
        if resync {
            continue;
        }
        while in_flight.len() < UPLOAD_WINDOW_CHUNKS && next < size {
            use std::io::Seek;
            file.seek(std::io::SeekFrom::Start(next))
                .map_err(io("seeking"))?;
            let n = file.read(&mut buf).map_err(io("reading"))?;
            if n == 0 {
                return Err(UploadError::FileEnded { offset: next, size });
            }
            // Bandwidth cap: never ahead of `bytes_per_s` since the start.
            let due = Duration::from_secs_f64(sent as f64 / bytes_per_s.max(1) as f64);
            if let Some(wait) = due.checked_sub(started.elapsed()) {
                tokio::time::sleep(wait).await;
            }
            send(Frame::UploadChunk(UploadChunk {
                session_id: session_id.clone(),
                offset: next,
                data: base64::engine::general_purpose::STANDARD.encode(&buf[..n]),
            }))
            .await?;
            sent += n as u64;
            next += n as u64;
            in_flight.push_back(next);
        }
        if in_flight.is_empty() {
            // The hub asks for bytes past the file's end and did not say it is complete.
            return Err(UploadError::FileEnded {
                offset: at.offset,
                size,
            });
        }
    }
}
