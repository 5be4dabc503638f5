//! `hub backup` and `hub restore`: one file that holds everything a clinic would need to start
//! again on a new machine, taken while the hub serves.
//!
//! The archive is a tar stream compressed with zstd, encrypted with age to the clinic's
//! recipients (`.tar.zst.age`; `backup/crypt.rs`: any `age -d -i KEY` decrypts it):
//!
//! ```text
//! MANIFEST.json        format, time, backend, every table's row count, every recording's
//!                      size and SHA-256 (the restore checks all of them)
//! hub.toml             the clinic's configuration
//! tls/…                the clinic's CA and the hub's certificate (keys included)
//! erasures.ndjson      the erasure ledger (format 2 on; `patient_data::tombstones`)
//! database/hub.db      SQLite: an online copy (`VACUUM INTO`, one consistent snapshot)
//! database/hub.pgdump  PostgreSQL: `pg_dump --format=custom` of an exported snapshot
//! recordings/…         every finished upload (`*.part` files are unfinished and left out)
//! ```
//!
//! A backup is written encrypted unless the operator asks for a clear one (`--unencrypted`);
//! a clear backup, and one of format 1 (always clear), still restores, with a warning. A
//! restore re-applies every erasure the backup's ledger, the restored database and the
//! ledgers the operator supplies record: a patient erased after the backup was taken does not
//! come back. The recordings go back where the restored `hub.toml` keeps them: the S3 store it
//! names, or the data directory.
//!
//! The row counts are taken inside the snapshot the database copy is made from (SQLite: the
//! copy itself; PostgreSQL: a repeatable-read transaction whose snapshot `pg_dump` is given),
//! so they are exactly what the copy holds, however busy the hub is. The recordings are listed
//! after the snapshot: every recording the copy knows of is complete on disk by then (a file
//! is renamed into place before its row is written), and a later one is carried along too.

use std::collections::BTreeMap;
use std::io::{Read, Write};
use std::path::{Component, Path, PathBuf};
use std::process::Command;

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
use sqlx::Row;

use crate::clinic::Clinic;
use crate::patient_data::tombstones;
use hub_store::HubError;
use hub_store::db::{Backend, Db, catalog};

mod crypt;

pub use crypt::{Sealing, new_key_pair, read_identities};

/// The archive's format, in its manifest: 2 carries the erasure ledger and is written
/// encrypted by default.
pub const BACKUP_FORMAT: u32 = 2;

/// The first format: no erasure ledger, never encrypted; still restored.
const FORMAT_CLEAR_ONLY: u32 = 1;

/// zstd level of the archive: recordings are already compressed, the dump compresses well.
const ZSTD_LEVEL: i32 = 3;

const MANIFEST: &str = "MANIFEST.json";
const SQLITE_COPY: &str = "database/hub.db";
const PG_DUMP: &str = "database/hub.pgdump";

/// What a backup holds, written first in the archive and checked by the restore.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Manifest {
    /// [`BACKUP_FORMAT`].
    pub format: u32,
    /// When the snapshot was taken, ms since the Unix epoch.
    pub taken_at_ms: i64,
    /// `sqlite` or `postgres`.
    pub backend: String,
    /// The database's schema version (the last migration applied).
    pub schema_version: i64,
    /// Rows of every table in the snapshot, by table name.
    pub rows: BTreeMap<String, i64>,
    /// Every recording carried, by its path under `recordings/`.
    pub recordings: BTreeMap<String, FileDigest>,
}

/// A file's size and SHA-256.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct FileDigest {
    /// Bytes.
    pub bytes: u64,
    /// SHA-256, lower-case hex.
    pub sha256: String,
}

impl Manifest {
    /// The rows of `table` in the snapshot (0 for a table it does not have).
    pub fn rows_of(&self, table: &str) -> i64 {
        self.rows.get(table).copied().unwrap_or(0)
    }

    /// The recordings' total size, bytes.
    pub fn recording_bytes(&self) -> u64 {
        self.recordings.values().map(|d| d.bytes).sum()
    }
}

fn io(what: &str, path: &Path) -> impl Fn(std::io::Error) -> HubError + use<> {
    HubError::io_at(what, path)
}

fn backend_name(backend: Backend) -> &'static str {
    match backend {
        Backend::Sqlite => "sqlite",
        Backend::Postgres => "postgres",
    }
}

/// Back up the clinic at `clinic` (its database at `db_url`, or the configured one) into a new
/// file `out`, while the hub may be serving, encrypted or not as `sealing` says. Refuses to
/// overwrite `out`.
pub async fn backup(
    clinic: &Clinic,
    db_url: Option<&str>,
    out: &Path,
    sealing: &Sealing,
) -> Result<Manifest, HubError> {
    if out.exists() {
        return Err(HubError::invalid(
            "--out",
            format!("{} exists; a backup never overwrites a file", out.display()),
        ));
    }
    let url = clinic.database_url(db_url)?;
    let db = Db::open(&url).await?;
    let scratch = scratch_dir(out)?;
    let result = snapshot_and_write(clinic, &db, &url, (scratch.path(), out), sealing).await;
    db.close().await;
    if result.is_err() {
        let _ = std::fs::remove_file(out);
    }
    result
}

/// A temporary directory beside `out` (on its disk: the database copy can be large).
fn scratch_dir(out: &Path) -> Result<tempfile::TempDir, HubError> {
    let parent = match out.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    tempfile::Builder::new()
        .prefix(".telerehab-backup-")
        .tempdir_in(&parent)
        .map_err(io("making a scratch directory in", &parent))
}

async fn snapshot_and_write(
    clinic: &Clinic,
    db: &Db,
    url: &str,
    (scratch, out): (&Path, &Path),
    sealing: &Sealing,
) -> Result<Manifest, HubError> {
    let taken_at_ms = clock::Clock::real().unix_ns() as i64 / 1_000_000;
    let (database_file, name, rows) = match db.backend() {
        Backend::Sqlite => {
            let copy = scratch.join("hub.db");
            sqlite_copy(db, &copy).await?;
            let snapshot = Db::open_sqlite(&copy).await?;
            let rows = catalog::row_counts(&snapshot).await;
            snapshot.close().await;
            (copy, SQLITE_COPY, rows?)
        }
        Backend::Postgres => {
            let dump = scratch.join("hub.pgdump");
            let rows = postgres_dump(db, url, &dump).await?;
            (dump, PG_DUMP, rows)
        }
    };
    let store = clinic.recordings()?;
    let recordings = list_recordings(&store).await?;
    let manifest = Manifest {
        format: BACKUP_FORMAT,
        taken_at_ms,
        backend: backend_name(db.backend()).to_owned(),
        schema_version: db.schema_version().await?,
        rows,
        recordings: recordings
            .iter()
            .map(|(rel, digest, _)| (rel.clone(), digest.clone()))
            .collect(),
    };
    let file = std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(out)
        .map_err(io("creating", out))?;
    set_private(out)?;
    let sink = crypt::Sink::new(file, sealing).map_err(io("encrypting", out))?;
    let encoder = zstd::Encoder::new(sink, ZSTD_LEVEL).map_err(io("compressing", out))?;
    let mut tar = tar::Builder::new(encoder);
    let json = serde_json::to_vec_pretty(&manifest)
        .map_err(|e| HubError::Corrupt(format!("manifest: {e}")))?;
    append_bytes(&mut tar, MANIFEST, &json, out)?;
    append_file(&mut tar, "hub.toml", &clinic.dir().join("hub.toml"), out)?;
    for name in ["ca.crt", "ca.key", "hub.crt", "hub.key"] {
        append_file(
            &mut tar,
            &format!("tls/{name}"),
            &clinic.dir().join("tls").join(name),
            out,
        )?;
    }
    // The ledger as it is now: every erasure up to this backup, and any later one the hub's
    // ledger holds when this backup is restored.
    let ledger = std::fs::read(tombstones::ledger_path(clinic)).or_else(|e| match e.kind() {
        std::io::ErrorKind::NotFound => Ok(Vec::new()),
        _ => Err(io("reading", &tombstones::ledger_path(clinic))(e)),
    })?;
    append_bytes(&mut tar, tombstones::LEDGER_FILE, &ledger, out)?;
    append_file(&mut tar, name, &database_file, out)?;
    for (rel, digest, file) in &recordings {
        let mut header = tar::Header::new_gnu();
        header.set_size(digest.bytes);
        header.set_mode(0o600);
        header.set_cksum();
        let reader = store.read(file)?.take(digest.bytes);
        tar.append_data(&mut header, format!("recordings/{rel}"), reader)
            .map_err(io("writing", out))?;
    }
    let encoder = tar.into_inner().map_err(io("writing", out))?;
    let sink = encoder.finish().map_err(io("writing", out))?;
    let file = sink.finish().map_err(io("encrypting", out))?;
    file.sync_all().map_err(io("syncing", out))?;
    Ok(manifest)
}

#[cfg(unix)]
fn set_private(path: &Path) -> Result<(), HubError> {
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(path, std::fs::Permissions::from_mode(0o600))
        .map_err(io("restricting", path))
}

#[cfg(not(unix))]
fn set_private(_path: &Path) -> Result<(), HubError> {
    Ok(())
}

/// `dir` and its missing parents, each new one readable by the clinic's user only (0700), as
/// `hub init` makes them.
fn create_private_dirs(dir: &Path) -> Result<(), HubError> {
    let mut builder = std::fs::DirBuilder::new();
    builder.recursive(true);
    #[cfg(unix)]
    std::os::unix::fs::DirBuilderExt::mode(&mut builder, 0o700);
    builder.create(dir).map_err(io("creating", dir))
}

fn append_bytes<W: Write>(
    tar: &mut tar::Builder<W>,
    name: &str,
    data: &[u8],
    out: &Path,
) -> Result<(), HubError> {
    let mut header = tar::Header::new_gnu();
    header.set_size(data.len() as u64);
    header.set_mode(0o600);
    header.set_cksum();
    tar.append_data(&mut header, name, data)
        .map_err(io("writing", out))
}

fn append_file<W: Write>(
    tar: &mut tar::Builder<W>,
    name: &str,
    path: &Path,
    out: &Path,
) -> Result<(), HubError> {
    let mut file = std::fs::File::open(path).map_err(io("reading", path))?;
    let meta = file.metadata().map_err(io("reading", path))?;
    let len = meta.len();
    let mut header = tar::Header::new_gnu();
    header.set_size(len);
    header.set_mode(0o600);
    if let Ok(t) = meta.modified()
        && let Ok(since) = t.duration_since(std::time::UNIX_EPOCH)
    {
        header.set_mtime(since.as_secs());
    }
    header.set_cksum();
    // Exactly the length stated: a file still growing is cut where it was measured.
    tar.append_data(&mut header, name, (&mut file).take(len))
        .map_err(io("writing", out))
}

/// SQLite's online copy of the whole database into `copy`: one consistent snapshot, taken
/// while other connections write.
async fn sqlite_copy(db: &Db, copy: &Path) -> Result<(), HubError> {
    let text = copy.to_str().ok_or_else(|| {
        HubError::invalid(
            "--out",
            "the scratch path is not UTF-8; choose another directory",
        )
    })?;
    sqlx::query("VACUUM INTO $1")
        .bind(text)
        .execute(db.pool())
        .await
        .map_err(HubError::db("copying the SQLite database"))?;
    Ok(())
}

/// `pg_dump` of a snapshot exported from a repeatable-read transaction, whose row counts are
/// read in the same snapshot.
async fn postgres_dump(db: &Db, url: &str, dump: &Path) -> Result<BTreeMap<String, i64>, HubError> {
    let mut tx = db
        .pool()
        .begin()
        .await
        .map_err(HubError::db("starting the backup's transaction"))?;
    sqlx::query("SET TRANSACTION ISOLATION LEVEL REPEATABLE READ, READ ONLY")
        .execute(&mut *tx)
        .await
        .map_err(HubError::db("starting the backup's snapshot"))?;
    let snapshot: String = sqlx::query("SELECT pg_export_snapshot()")
        .fetch_one(&mut *tx)
        .await
        .and_then(|r| r.try_get(0))
        .map_err(HubError::db("exporting the backup's snapshot"))?;
    let mut rows = BTreeMap::new();
    for table in catalog::table_names(&mut *tx, Backend::Postgres).await? {
        rows.insert(table.clone(), catalog::count_rows(&mut *tx, &table).await?);
    }
    let out = Command::new("pg_dump")
        .args(["--format=custom", "--no-owner", "--no-privileges"])
        .arg(format!("--snapshot={snapshot}"))
        .arg(format!("--file={}", dump.display()))
        .arg(format!("--dbname={url}"))
        .output()
        .map_err(|e| {
            HubError::io(
                "running pg_dump (install PostgreSQL's client tools: apt install postgresql-client)",
                e,
            )
        })?;
    // The snapshot must stay open until pg_dump has taken it; closed either way.
    let _ = tx.rollback().await;
    if !out.status.success() {
        return Err(HubError::Config(format!(
            "pg_dump failed: {}",
            String::from_utf8_lossy(&out.stderr).trim()
        )));
    }
    Ok(rows)
}

/// The finished recordings in the clinic's recording store (`<station>/<file>`, no `*.part`;
/// the local directory or S3, [`hub_care::recordings`]), each with its digest (read as a stream),
/// sorted.
async fn list_recordings(
    store: &hub_care::recordings::RecordingStore,
) -> Result<Vec<(String, FileDigest, hub_care::recordings::StoredFile)>, HubError> {
    let mut found = Vec::new();
    for file in store.finished().await? {
        let digest = digest_of(store.read(&file)?, &file.name)?;
        found.push((file.name.clone(), digest, file));
    }
    Ok(found)
}

fn digest_of(mut reader: impl Read, name: &str) -> Result<FileDigest, HubError> {
    let read = |e| HubError::io(format!("reading the recording {name}"), e);
    let mut hasher = Sha256::new();
    let mut buf = vec![0u8; 1 << 16];
    let mut bytes = 0u64;
    loop {
        let n = reader.read(&mut buf).map_err(read)?;
        if n == 0 {
            break;
        }
        hasher.update(&buf[..n]);
        bytes += n as u64;
    }
    Ok(FileDigest {
        bytes,
        sha256: hub_store::db::hex(&hasher.finalize()),
    })
}

/// Where a restore's keys, database and erasure ledgers come from.
#[derive(Debug, Clone, Copy, Default)]
pub struct RestoreFrom<'a> {
    /// The identity file of an encrypted backup (`hub backup-key`'s, or `age-keygen`'s).
    pub identity: Option<&'a Path>,
    /// An empty PostgreSQL database for a PostgreSQL backup (`postgres://…`).
    pub db_url: Option<&'a str>,
    /// Erasure ledgers the operator supplies (the clinic's current `erasures.ndjson`, or the
    /// copy kept off the machine), re-applied with the backup's own.
    pub erasures: &'a [PathBuf],
}

/// What a restore did.
#[derive(Debug, Clone)]
pub struct Restored {
    /// The backup's manifest (its rows, checked, are before the erasures were re-applied).
    pub manifest: Manifest,
    /// Whether the backup was encrypted (a clear one is restored with a warning).
    pub encrypted: bool,
    /// The erasures known and re-applied.
    pub erasures: tombstones::Reapplied,
}

/// Restore the backup `archive` into the new data directory `data` (absent or empty); a
/// PostgreSQL backup goes into the empty database `from.db_url` names, which `hub.toml` then
/// names. An encrypted backup is decrypted with `from.identity`; a wrong key, a truncated or
/// an altered file is refused, saying which, and nothing is restored. Every erasure recorded
/// in the backup's ledger, its database or `from.erasures` is then applied again
/// ([`tombstones::reapply`]), so that no erased patient comes back.
///
/// Nothing in the archive is trusted: it is unpacked into a new staging directory beside
/// `data` — only the files its manifest implies, each recording at a relative path of plain
/// names, of the manifest's size and SHA-256 (checked as it is written), every size checked
/// from its tar header before a byte is written, nothing read from outside the archive — the
/// database restored and every table's rows checked against the manifest there, and the
/// staging directory is renamed to `data` only then. On any failure `data` is left as it was and the staging directory is removed (a
/// PostgreSQL database already filled by `pg_restore` stays filled: drop it before trying
/// again).
pub async fn restore(
    archive: &Path,
    data: &Path,
    from: RestoreFrom<'_>,
    now_ms: i64,
) -> Result<Restored, HubError> {
    let mut supplied = Vec::new();
    for ledger in from.erasures {
        if !ledger.is_file() {
            return Err(HubError::invalid(
                "--erasures",
                format!("{} is not an erasure ledger file", ledger.display()),
            ));
        }
        supplied.extend(tombstones::read_ledger(ledger)?);
    }
    let empty = match std::fs::read_dir(data) {
        Ok(mut entries) => entries.next().is_none(),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => true,
        Err(e) => return Err(io("reading", data)(e)),
    };
    if !empty {
        return Err(HubError::invalid(
            "--data",
            format!(
                "{} is not empty; restore into a new directory (a restore never mixes two clinics)",
                data.display()
            ),
        ));
    }
    let parent = match data.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    create_private_dirs(&parent)?;
    // Beside the target, on its disk: moved into place by one rename. Dropped (removed) on
    // any failure.
    let staging = tempfile::Builder::new()
        .prefix(".telerehab-restore-")
        .tempdir_in(&parent)
        .map_err(io("making a staging directory in", &parent))?;
    let restored = restore_staged(archive, staging.path(), from, &supplied, now_ms).await?;
    std::fs::rename(staging.path(), data).map_err(io("moving the restored clinic to", data))?;
    let _ = staging.keep();
    Ok(restored)
}

/// The whole restore into the new directory `staged`.
async fn restore_staged(
    archive: &Path,
    staged: &Path,
    from: RestoreFrom<'_>,
    supplied: &[tombstones::Tombstone],
    now_ms: i64,
) -> Result<Restored, HubError> {
    let db_url = from.db_url;
    let opened = crypt::Opened::open(archive, from.identity)?;
    let encrypted = opened.encrypted();
    let failure = opened.failure();
    // The database kind is known from the manifest, the first entry; check the command line
    // against it before anything large is written.
    let unpacked = unpack(opened, archive, staged, |m| {
        match (m.backend.as_str(), db_url) {
            ("sqlite", None) | ("postgres", Some(_)) => Ok(()),
            ("sqlite", Some(_)) => Err(HubError::invalid(
                "--db",
                "this backup is of a SQLite database; restore it without --db",
            )),
            ("postgres", None) => Err(HubError::invalid(
                "--db",
                "this backup is of a PostgreSQL database; name an empty database to restore it into",
            )),
            (other, _) => Err(HubError::Corrupt(format!(
                "the backup names an unknown database kind {other:?}"
            ))),
        }
    });
    // A decryption that stopped says why (the tar and zstd errors it causes say less).
    let manifest = match (unpacked, failure.get()) {
        (Err(_), Some(why)) => {
            return Err(HubError::Corrupt(format!(
                "{}: {why}; nothing was restored",
                archive.display()
            )));
        }
        (result, _) => result?,
    };
    let clinic = Clinic::at(staged);
    let url = match db_url {
        None => {
            std::fs::rename(staged.join(SQLITE_COPY), staged.join("hub.db"))
                .map_err(io("placing the database in", staged))?;
            set_private(&staged.join("hub.db"))?;
            rewrite_database(&clinic, "")?;
            clinic.database_url(None)?
        }
        Some(url) => {
            pg_restore(&staged.join(PG_DUMP), url)?;
            rewrite_database(&clinic, url)?;
            url.to_owned()
        }
    };
    std::fs::remove_dir_all(staged.join("database"))
        .map_err(io("tidying", &staged.join("database")))?;
    let db = Db::open(&url).await?;
    let rows = catalog::row_counts(&db).await;
    db.close().await;
    let rows = rows?;
    if rows != manifest.rows {
        return Err(HubError::Corrupt(format!(
            "the restored database's rows differ from the backup's: {rows:?} restored, {:?} in the backup",
            manifest.rows
        )));
    }
    // Before the erasures: those reach the store the restored clinic names.
    into_configured_store(&clinic, &manifest).await?;
    let db = Db::open(&url).await?;
    let erasures = tombstones::reapply(&clinic, &db, supplied, now_ms).await;
    db.close().await;
    Ok(Restored {
        manifest,
        encrypted,
        erasures: erasures?,
    })
}

/// When the restored `hub.toml` keeps recordings in an S3-compatible store (`[recordings]`),
/// the recordings just unpacked (each checked against the manifest's SHA-256) go into it,
/// each as the hub keeps an upload (one multipart upload, completed or aborted), and leave
/// the data directory; on the local default they stay where they were unpacked. A store that
/// does not answer fails the restore, naming the recording (nothing is moved into place).
async fn into_configured_store(clinic: &Clinic, manifest: &Manifest) -> Result<(), HubError> {
    let store = clinic.recordings()?;
    if !store.is_s3() {
        return Ok(());
    }
    for rel in manifest.recordings.keys() {
        let (station, session) = rel
            .split_once('/')
            .and_then(|(st, file)| Some((st, file.strip_suffix(".mcap")?)))
            .ok_or_else(|| {
                HubError::Corrupt(format!(
                    "the backup lists {rel}, which is not <station>/<session>.mcap"
                ))
            })?;
        let unpacked = store.staging_path(station, session);
        store.keep(station, session, &unpacked).await?;
    }
    if !manifest.recordings.is_empty() {
        tracing::info!(
            recordings = manifest.recordings.len(),
            "restored recordings put into the clinic's S3 recording store"
        );
    }
    Ok(())
}

/// Largest manifest read, bytes (some 150 bytes a recording: a clinic's years of sessions).
const MAX_MANIFEST_BYTES: u64 = 64 << 20;

/// Largest `hub.toml` or TLS file read, bytes (they are a few KB).
const MAX_SMALL_FILE_BYTES: u64 = 1 << 20;

/// Bytes kept free on the staging disk beyond what the archive's files declare.
const FREE_SPACE_RESERVE_BYTES: u64 = 64 << 20;

/// A recording's path under `recordings/` as a manifest names it, if it is one `hub backup`
/// writes: relative, plain names only (no `..`, no root, no empty or `.` part), UTF-8
/// without backslashes or NULs.
fn is_recording_path(rel: &str) -> bool {
    !rel.is_empty()
        && !rel.contains(['\\', '\0'])
        && rel
            .split('/')
            .all(|part| !part.is_empty() && part != "." && part != "..")
        && Path::new(rel)
            .components()
            .all(|c| matches!(c, Component::Normal(_)))
}

/// The bytes free for the clinic on the disk holding `dir` (`u64::MAX` where unknown).
fn free_bytes(dir: &Path) -> u64 {
    #[cfg(unix)]
    {
        rustix::fs::statvfs(dir)
            .map(|s| s.f_bavail.saturating_mul(s.f_frsize))
            .unwrap_or(u64::MAX)
    }
    #[cfg(not(unix))]
    {
        let _ = dir;
        u64::MAX
    }
}

/// A writer computing the SHA-256 of what passes through it.
struct Hashing<W> {
    inner: W,
    hasher: Sha256,
}

impl<W: Write> Write for Hashing<W> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let n = self.inner.write(buf)?;
        self.hasher.update(&buf[..n]);
        Ok(n)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.inner.flush()
    }
}

/// Unpack `archive` into the new, empty directory `data`; its manifest, once `accept` has
/// taken it. The archive must be exactly what `hub backup` writes, and is refused, naming the
/// entry, otherwise:
/// - the manifest first, at most [`MAX_MANIFEST_BYTES`], every recording it lists at a
///   relative path of plain names ([`is_recording_path`]);
/// - then only the files the manifest implies: `hub.toml`, the four TLS files, the database
///   of its kind, and `recordings/<path>` for each recording listed — an unlisted entry, a
///   second copy of one, a link, a directory or a path outside is refused before a byte of
///   it is written;
/// - each entry's size from its tar header checked before it is written: a recording's
///   against the manifest, `hub.toml` and the TLS files against [`MAX_SMALL_FILE_BYTES`], all
///   of them against the space free on the disk; each written to a new file of exactly that
///   many bytes (a stream that ends sooner is refused), a recording's SHA-256 computed as it
///   is written and checked against the manifest;
/// - every file the manifest implies must be there.
///
/// Nothing is read from outside the archive, and nothing written outside `data`.
fn unpack(
    source: crypt::Opened,
    archive: &Path,
    data: &Path,
    accept: impl FnOnce(&Manifest) -> Result<(), HubError>,
) -> Result<Manifest, HubError> {
    let decoder = zstd::Decoder::new(source).map_err(io("reading", archive))?;
    let mut tar = tar::Archive::new(decoder);
    let not_a_backup = |why: String| {
        HubError::Corrupt(format!(
            "{} is not a telerehab backup: {why}",
            archive.display()
        ))
    };
    let mut accept = Some(accept);
    let mut manifest: Option<Manifest> = None;
    let mut expected = BTreeMap::new();
    let mut free = free_bytes(data).saturating_sub(FREE_SPACE_RESERVE_BYTES);
    for entry in tar.entries().map_err(io("reading", archive))? {
        let mut entry = entry.map_err(io("reading", archive))?;
        let path = entry.path().map_err(io("reading", archive))?.into_owned();
        let name = path.to_str().map(str::to_owned).unwrap_or_default();
        let safe = path.components().all(|c| matches!(c, Component::Normal(_)));
        if !safe || name.is_empty() || entry.header().entry_type() != tar::EntryType::Regular {
            return Err(not_a_backup(format!("unexpected entry {}", path.display())));
        }
        let declared = entry.header().size().map_err(io("reading", archive))?;
        if manifest.is_none() {
            if name != MANIFEST {
                return Err(not_a_backup("no manifest first".into()));
            }
            let m = read_manifest(&mut entry, declared, archive).map_err(not_a_backup)?;
            if let Some(accept) = accept.take() {
                accept(&m)?;
            }
            let listed = m.recording_bytes();
            if listed > free {
                return Err(HubError::Conflict(format!(
                    "the backup's recordings need {:.1} MB and the disk it is restored to has \
                     {:.1} MB free; nothing was restored",
                    listed as f64 / 1e6,
                    free as f64 / 1e6
                )));
            }
            expected = expected_files(&m);
            manifest = Some(m);
            continue;
        }
        let Some(want) = expected.remove(&name) else {
            return Err(not_a_backup(format!(
                "it holds {name}, which its manifest does not list (or holds it twice)"
            )));
        };
        want.check_size(&name, declared).map_err(not_a_backup)?;
        if declared > free {
            return Err(HubError::Conflict(format!(
                "{name} in the backup declares {:.1} MB and the disk it is restored to has \
                 {:.1} MB free; nothing was restored",
                declared as f64 / 1e6,
                free as f64 / 1e6
            )));
        }
        free -= declared;
        let sha256 =
            write_new(&mut entry, declared, &data.join(&path), archive)?.map_err(|copied| {
                not_a_backup(format!(
                    "it ends in the middle of {name} ({copied} of {declared} bytes)"
                ))
            })?;
        if let Expected::Recording { sha256: want, .. } = want
            && sha256 != want
        {
            return Err(not_a_backup(format!(
                "{name} does not match its manifest's SHA-256 (sha256 {sha256}; the manifest \
                 says {want})"
            )));
        }
    }
    let manifest = manifest.ok_or_else(|| not_a_backup("no manifest".into()))?;
    if let Some(missing) = expected.keys().next() {
        return Err(not_a_backup(format!(
            "its manifest lists {missing}, which the archive does not hold"
        )));
    }
    Ok(manifest)
}

/// The manifest, `entry` of `declared` bytes; why it is refused otherwise.
fn read_manifest(entry: &mut impl Read, declared: u64, archive: &Path) -> Result<Manifest, String> {
    if declared > MAX_MANIFEST_BYTES {
        return Err(format!(
            "its manifest declares {declared} bytes, more than the {MAX_MANIFEST_BYTES} a \
             manifest may have"
        ));
    }
    let mut text = String::new();
    entry
        .take(declared)
        .read_to_string(&mut text)
        .map_err(|e| {
            format!(
                "its manifest cannot be read from {}: {e}",
                archive.display()
            )
        })?;
    let m: Manifest = serde_json::from_str(&text).map_err(|e| format!("its manifest: {e}"))?;
    if m.format != BACKUP_FORMAT && m.format != FORMAT_CLEAR_ONLY {
        return Err(format!(
            "format {} (this build reads {FORMAT_CLEAR_ONLY} and {BACKUP_FORMAT})",
            m.format
        ));
    }
    if let Some(bad) = m.recordings.keys().find(|rel| !is_recording_path(rel)) {
        return Err(format!(
            "its manifest names a recording at {bad:?}, outside the clinic's recordings (a \
             recording's path is relative, of plain names)"
        ));
    }
    Ok(m)
}

/// A file the archive must hold, by what its size may be.
enum Expected {
    /// `hub.toml` or a TLS file: at most [`MAX_SMALL_FILE_BYTES`].
    Small,
    /// The erasure ledger: at most [`tombstones::MAX_LEDGER_BYTES`].
    Ledger,
    /// The database: any size the disk has room for.
    Database,
    /// A recording: exactly the manifest's size and SHA-256.
    Recording { bytes: u64, sha256: String },
}

impl Expected {
    /// Why an entry `name` of `declared` bytes is refused, if it is.
    fn check_size(&self, name: &str, declared: u64) -> Result<(), String> {
        match self {
            Self::Small if declared > MAX_SMALL_FILE_BYTES => Err(format!(
                "{name} declares {declared} bytes, more than the {MAX_SMALL_FILE_BYTES} such a \
                 file has"
            )),
            Self::Ledger if declared > tombstones::MAX_LEDGER_BYTES => Err(format!(
                "{name} declares {declared} bytes, more than the {} an erasure ledger may have",
                tombstones::MAX_LEDGER_BYTES
            )),
            Self::Recording { bytes, .. } if declared != *bytes => Err(format!(
                "{name} is {declared} bytes in the archive and {bytes} in its manifest"
            )),
            _ => Ok(()),
        }
    }
}

/// Every file a backup with manifest `m` holds besides the manifest, by archive path.
fn expected_files(m: &Manifest) -> BTreeMap<String, Expected> {
    let mut expected = BTreeMap::new();
    expected.insert("hub.toml".to_owned(), Expected::Small);
    for tls in ["ca.crt", "ca.key", "hub.crt", "hub.key"] {
        expected.insert(format!("tls/{tls}"), Expected::Small);
    }
    if m.format >= BACKUP_FORMAT {
        expected.insert(tombstones::LEDGER_FILE.to_owned(), Expected::Ledger);
    }
    let database = if m.backend == "postgres" {
        PG_DUMP
    } else {
        SQLITE_COPY
    };
    expected.insert(database.to_owned(), Expected::Database);
    for (rel, digest) in &m.recordings {
        expected.insert(
            format!("recordings/{rel}"),
            Expected::Recording {
                bytes: digest.bytes,
                sha256: digest.sha256.clone(),
            },
        );
    }
    expected
}

/// Writes `bytes` bytes of `entry` to the new file `dest` (0600, its directories 0700); the
/// SHA-256 of what was written, or `Err(bytes written)` when the entry ends sooner.
fn write_new(
    entry: &mut impl Read,
    bytes: u64,
    dest: &Path,
    archive: &Path,
) -> Result<Result<String, u64>, HubError> {
    if let Some(parent) = dest.parent() {
        create_private_dirs(parent)?;
    }
    let mut options = std::fs::OpenOptions::new();
    options.write(true).create_new(true);
    #[cfg(unix)]
    std::os::unix::fs::OpenOptionsExt::mode(&mut options, 0o600);
    let file = options.open(dest).map_err(io("writing", dest))?;
    let mut out = Hashing {
        inner: std::io::BufWriter::new(file),
        hasher: Sha256::new(),
    };
    let copied = std::io::copy(&mut entry.take(bytes), &mut out).map_err(io("reading", archive))?;
    out.flush().map_err(io("writing", dest))?;
    Ok(if copied < bytes {
        Err(copied)
    } else {
        Ok(hub_store::db::hex(&out.hasher.finalize()))
    })
}

fn pg_restore(dump: &Path, url: &str) -> Result<(), HubError> {
    let out = Command::new("pg_restore")
        .args(["--no-owner", "--no-privileges", "--exit-on-error"])
        .arg(format!("--dbname={url}"))
        .arg(dump)
        .output()
        .map_err(|e| {
            HubError::io(
                "running pg_restore (install PostgreSQL's client tools: apt install postgresql-client)",
                e,
            )
        })?;
    if !out.status.success() {
        return Err(HubError::Config(format!(
            "pg_restore failed (the database must be empty): {}",
            String::from_utf8_lossy(&out.stderr).trim()
        )));
    }
    Ok(())
}

/// Point the restored `hub.toml` at the database it now uses (`""`: `hub.db` in the directory).
fn rewrite_database(clinic: &Clinic, url: &str) -> Result<(), HubError> {
    rewrite_config(clinic, |c| c.database = url.to_owned())
}

/// `hub.toml` changed by `change`.
fn rewrite_config(
    clinic: &Clinic,
    change: impl FnOnce(&mut crate::clinic::ClinicConfig),
) -> Result<(), HubError> {
    let mut config = clinic.config()?;
    change(&mut config);
    let text = toml::to_string(&config).map_err(|e| HubError::Config(format!("hub.toml: {e}")))?;
    let path = clinic.dir().join("hub.toml");
    std::fs::write(&path, text).map_err(io("writing", &path))
}

/// Adds `recipient` (`age1…`) to the clinic's backup recipients in `hub.toml` (kept once);
/// refused, naming it, when it is not an age X25519 recipient.
pub fn add_recipient(clinic: &Clinic, recipient: &str) -> Result<(), HubError> {
    let recipient = recipient.trim();
    crypt::parse_recipient(recipient).map_err(|why| HubError::invalid("--recipient", why))?;
    rewrite_config(clinic, |c| {
        if !c.backup_recipients.iter().any(|r| r == recipient) {
            c.backup_recipients.push(recipient.to_owned());
        }
    })
}
