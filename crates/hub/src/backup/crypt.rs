//! The backup's encryption: the standard age format (`age-encryption.org/v1`, rage's library)
//! to the clinic's X25519 recipients (`age1…`, hub.toml's `backup_recipients`). Any `age` or
//! `rage` command decrypts a backup with the identity file: `age -d -i clinic-backup.key
//! clinic.tar.zst.age | zstd -d | tar -tf -`.
//!
//! age authenticates the whole file (a keyed header MAC, then every 64 KiB chunk sealed with
//! ChaCha20-Poly1305, the last one marked), so a wrong key, a truncated file and a changed
//! byte are each refused, the key told apart from damage: [`Opened`] records why decryption
//! stopped, and the restore says it.
//!
//! X25519, not age 0.13's post-quantum hybrid (`age1pq…`): the clinic's backups must open with
//! the `age` its operators have (Debian 12 ships age 1.1, which reads X25519 only). age marks
//! X25519 deprecated for new keys for that reason; the warning is allowed here, in the one
//! module that names it.
#![allow(deprecated)]

use std::cell::Cell;
use std::io::{BufRead, BufReader, Read, Write};
use std::path::Path;
use std::rc::Rc;

use age::secrecy::ExposeSecret;

use hub_store::HubError;

/// How an age file starts.
const AGE_MAGIC: &[u8] = b"age-encryption.org/v1\n";

/// How a zstd frame starts: a clear backup (format 1, or one written with `--unencrypted`).
const ZSTD_MAGIC: [u8; 4] = [0x28, 0xB5, 0x2F, 0xFD];

/// The config key naming the recipients, as its messages say it.
const RECIPIENTS_KEY: &str = "hub.toml's backup_recipients";

/// How a backup is written.
pub enum Sealing {
    /// Encrypted to these recipients (any one of their identities decrypts it).
    To(Vec<age::x25519::Recipient>),
    /// In clear, asked for explicitly (`hub backup --unencrypted`).
    Clear,
}

impl Sealing {
    /// The clinic's recipients (`age1…` strings from hub.toml), each checked; a clear refusal
    /// naming the entry that is not one, or saying what to do when there are none.
    pub fn to_recipients(recipients: &[String], data: &Path) -> Result<Self, HubError> {
        if recipients.is_empty() {
            return Err(HubError::Config(format!(
                "no backup key: a backup holds the clinic's CA key and every patient's data, so \
                 it is written encrypted. Make the clinic's key pair once with `telerehab hub \
                 backup-key --data {} --identity-out FILE` (keep FILE offline, away from this \
                 machine: it is what restores), or write a clear backup with --unencrypted",
                data.display()
            )));
        }
        recipients
            .iter()
            .map(|r| {
                parse_recipient(r)
                    .map_err(|why| HubError::Config(format!("{RECIPIENTS_KEY} {why}")))
            })
            .collect::<Result<Vec<_>, _>>()
            .map(Self::To)
    }
}

/// `text` as an age X25519 recipient; why not otherwise.
pub fn parse_recipient(text: &str) -> Result<age::x25519::Recipient, String> {
    text.parse::<age::x25519::Recipient>()
        .map_err(|e| format!("{text:?} is not an age X25519 recipient (age1…): {e}"))
}

/// A new key pair: the identity file's text (`AGE-SECRET-KEY-1…`, as `age-keygen` writes it)
/// and its recipient (`age1…`).
pub fn new_key_pair() -> (String, String) {
    let created = jiff::Timestamp::now();
    let identity = age::x25519::Identity::generate();
    let recipient = identity.to_public().to_string();
    let text = format!(
        "# telerehab clinic backup key, created: {created}\n# public key: {recipient}\n{}\n",
        identity.to_string().expose_secret()
    );
    (text, recipient)
}

/// The identities in the file `path` (`age-keygen`'s format: `#` comments, blank lines and
/// `AGE-SECRET-KEY-1…` lines); an error naming the file and the line that is not one.
pub fn read_identities(path: &Path) -> Result<Vec<age::x25519::Identity>, HubError> {
    let text = std::fs::read_to_string(path).map_err(HubError::io_at("reading", path))?;
    let mut found = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let identity = line.parse::<age::x25519::Identity>().map_err(|_| {
            HubError::invalid(
                "--identity",
                format!(
                    "{} line {} is not an age identity (AGE-SECRET-KEY-1…); name the identity \
                     file `hub backup-key` or `age-keygen` made",
                    path.display(),
                    n + 1
                ),
            )
        })?;
        found.push(identity);
    }
    if found.is_empty() {
        return Err(HubError::invalid(
            "--identity",
            format!("{} holds no age identity", path.display()),
        ));
    }
    Ok(found)
}

/// Where a backup's bytes go: the file itself, or age's encryption of it.
pub enum Sink {
    /// A clear backup.
    Clear(std::fs::File),
    /// An encrypted one.
    Sealed(age::stream::StreamWriter<std::fs::File>),
}

impl Sink {
    /// Starts writing `file` as `sealing` says (an encrypted file starts with age's header).
    pub fn new(file: std::fs::File, sealing: &Sealing) -> std::io::Result<Self> {
        match sealing {
            Sealing::Clear => Ok(Self::Clear(file)),
            Sealing::To(recipients) => {
                let encryptor = age::Encryptor::with_recipients(
                    recipients.iter().map(|r| r as &dyn age::Recipient),
                )
                .map_err(std::io::Error::other)?;
                encryptor.wrap_output(file).map(Self::Sealed)
            }
        }
    }

    /// Ends the file (age's last chunk) and hands it back.
    pub fn finish(self) -> std::io::Result<std::fs::File> {
        match self {
            Self::Clear(f) => Ok(f),
            Self::Sealed(w) => w.finish(),
        }
    }
}

impl Write for Sink {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        match self {
            Self::Clear(f) => f.write(buf),
            Self::Sealed(w) => w.write(buf),
        }
    }

    fn flush(&mut self) -> std::io::Result<()> {
        match self {
            Self::Clear(f) => f.flush(),
            Self::Sealed(w) => w.flush(),
        }
    }
}

/// A backup file opened for reading: its clear bytes (the zstd stream), decrypted when it is
/// encrypted.
pub struct Opened {
    source: Source,
    /// Why decryption stopped, once it has (a truncated or altered file), for the restore's
    /// error.
    failure: Rc<Cell<Option<&'static str>>>,
}

enum Source {
    Clear(BufReader<std::fs::File>),
    Sealed(age::stream::StreamReader<BufReader<std::fs::File>>),
}

impl Opened {
    /// Opens `archive`: an encrypted backup is decrypted with the identities of the file
    /// `identity`, a clear one read as it is. Refused, saying why: an encrypted backup
    /// without an identity, an identity that is not the backup's key, a damaged header, or a
    /// file that is neither.
    pub fn open(archive: &Path, identity: Option<&Path>) -> Result<Self, HubError> {
        let file = std::fs::File::open(archive).map_err(HubError::io_at("reading", archive))?;
        let mut reader = BufReader::new(file);
        let head = reader
            .fill_buf()
            .map_err(HubError::io_at("reading", archive))?;
        let failure = Rc::new(Cell::new(None));
        if head.starts_with(&ZSTD_MAGIC) {
            return Ok(Self {
                source: Source::Clear(reader),
                failure,
            });
        }
        if !head.starts_with(AGE_MAGIC) {
            return Err(HubError::Corrupt(format!(
                "{} is not a telerehab backup: it is neither encrypted (age) nor a clear \
                 (.tar.zst) backup",
                archive.display()
            )));
        }
        let Some(identity) = identity else {
            return Err(HubError::invalid(
                "--identity",
                format!(
                    "{} is encrypted: name the clinic's backup identity file (made by `hub \
                     backup-key`) with --identity FILE",
                    archive.display()
                ),
            ));
        };
        let identities = read_identities(identity)?;
        let refused = |why: String| HubError::Corrupt(format!("{}: {why}", archive.display()));
        let decryptor = age::Decryptor::new_buffered(reader).map_err(|e| match e {
            age::DecryptError::Io(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => {
                refused("the file is truncated (it ends inside its encryption header)".into())
            }
            other => refused(format!(
                "its encryption header is damaged or was altered ({other})"
            )),
        })?;
        let stream = decryptor
            .decrypt(identities.iter().map(|i| i as &dyn age::Identity))
            .map_err(|e| match e {
                age::DecryptError::NoMatchingKeys => HubError::invalid(
                    "--identity",
                    format!(
                        "{} does not hold the key {} was encrypted to: name this clinic's \
                         backup identity file",
                        identity.display(),
                        archive.display()
                    ),
                ),
                other => refused(format!(
                    "its encryption header is damaged or was altered ({other})"
                )),
            })?;
        Ok(Self {
            source: Source::Sealed(stream),
            failure,
        })
    }

    /// Whether the backup is encrypted.
    pub fn encrypted(&self) -> bool {
        matches!(self.source, Source::Sealed(_))
    }

    /// Why decryption stopped, shared with the reader (read it after a failed unpack).
    pub fn failure(&self) -> Rc<Cell<Option<&'static str>>> {
        Rc::clone(&self.failure)
    }
}

impl Read for Opened {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        match &mut self.source {
            Source::Clear(r) => r.read(buf),
            Source::Sealed(r) => r.read(buf).inspect_err(|e| {
                self.failure.set(Some(match e.kind() {
                    std::io::ErrorKind::UnexpectedEof => {
                        "the file is truncated (its encrypted stream ends before its last chunk)"
                    }
                    // A file cut inside a chunk fails that chunk's authentication too.
                    _ => {
                        "the file was cut short or altered after it was written (an encrypted \
                         chunk fails its authentication)"
                    }
                }));
            }),
        }
    }
}
