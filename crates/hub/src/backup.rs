//! `hub backup` and `hub restore`: one file that holds everything a clinic would need to start
//! again on a new machine, taken while the hub serves.
//!
//! The archive is a tar stream compressed with zstd (`.tar.zst`):
//!
//! ```text
//! MANIFEST.json        format, time, backend, every table's row count, every recording's
//!                      size and SHA-256 (the restore checks all of them)
//! hub.toml             the clinic's configuration
//! tls/…                the clinic's CA and the hub's certificate (keys included: guard the file)
//! database/hub.db      SQLite: an online copy (`VACUUM INTO`, one consistent snapshot)
//! database/hub.pgdump  PostgreSQL: `pg_dump --format=custom` of an exported snapshot
//! recordings/…         every finished upload (`*.part` files are unfinished and left out)
//! ```
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
use crate::db::{Backend, Db};
use crate::error::HubError;

/// The archive's format, in its manifest.
pub const BACKUP_FORMAT: u32 = 1;

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
/// file `out`, while the hub may be serving. Refuses to overwrite `out`.
pub async fn backup(
    clinic: &Clinic,
    db_url: Option<&str>,
    out: &Path,
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
    let result = snapshot_and_write(clinic, &db, &url, scratch.path(), out).await;
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
    scratch: &Path,
    out: &Path,
) -> Result<Manifest, HubError> {
    let taken_at_ms = clock::Clock::real().unix_ns() as i64 / 1_000_000;
    let (database_file, name, rows) = match db.backend() {
        Backend::Sqlite => {
            let copy = scratch.join("hub.db");
            sqlite_copy(db, &copy).await?;
            let snapshot = Db::open_sqlite(&copy).await?;
            let rows = row_counts(&snapshot).await;
            snapshot.close().await;
            (copy, SQLITE_COPY, rows?)
        }
        Backend::Postgres => {
            let dump = scratch.join("hub.pgdump");
            let rows = postgres_dump(db, url, &dump).await?;
            (dump, PG_DUMP, rows)
        }
    };
    let recordings_dir = clinic.dir().join("recordings");
    let recordings = list_recordings(&recordings_dir)?;
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
    let encoder = zstd::Encoder::new(file, ZSTD_LEVEL).map_err(io("compressing", out))?;
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
    append_file(&mut tar, name, &database_file, out)?;
    for (rel, _, path) in &recordings {
        append_file(&mut tar, &format!("recordings/{rel}"), path, out)?;
    }
    let encoder = tar.into_inner().map_err(io("writing", out))?;
    let file = encoder.finish().map_err(io("writing", out))?;
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
    for table in table_names(&mut *tx, Backend::Postgres).await? {
        rows.insert(table.clone(), count_rows(&mut *tx, &table).await?);
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

/// The database's own tables (not the migration bookkeeping, which the schema version states).
async fn table_names<'c, E>(conn: E, backend: Backend) -> Result<Vec<String>, HubError>
where
    E: sqlx::Executor<'c, Database = sqlx::Any>,
{
    let sql = match backend {
        Backend::Sqlite => {
            "SELECT name FROM sqlite_master WHERE type = 'table' \
             AND name NOT LIKE 'sqlite_%' AND name NOT LIKE '_sqlx%' ORDER BY name"
        }
        Backend::Postgres => {
            "SELECT CAST(table_name AS TEXT) FROM information_schema.tables \
             WHERE table_schema = 'public' AND table_type = 'BASE TABLE' \
             AND table_name NOT LIKE '_sqlx%' ORDER BY table_name"
        }
    };
    let rows = sqlx::query(sql)
        .fetch_all(conn)
        .await
        .map_err(HubError::db("listing the tables"))?;
    rows.iter()
        .map(|r| r.try_get::<String, _>(0))
        .collect::<Result<_, _>>()
        .map_err(HubError::db("listing the tables"))
}

async fn count_rows<'c, E>(conn: E, table: &str) -> Result<i64, HubError>
where
    E: sqlx::Executor<'c, Database = sqlx::Any>,
{
    // The name comes from the database's own catalogue, quoted as an identifier.
    let sql = format!("SELECT COUNT(*) FROM \"{}\"", table.replace('"', "\"\""));
    sqlx::query(sqlx::AssertSqlSafe(sql))
        .fetch_one(conn)
        .await
        .and_then(|r| r.try_get::<i64, _>(0))
        .map_err(HubError::db("counting rows"))
}

/// Every table's rows in `db`.
pub async fn row_counts(db: &Db) -> Result<BTreeMap<String, i64>, HubError> {
    let mut rows = BTreeMap::new();
    for table in table_names(db.pool(), db.backend()).await? {
        let n = count_rows(db.pool(), &table).await?;
        rows.insert(table, n);
    }
    Ok(rows)
}

/// The finished recordings under `dir` (`<station>/<file>`, no `*.part`), each with its
/// digest and path, sorted.
fn list_recordings(dir: &Path) -> Result<Vec<(String, FileDigest, PathBuf)>, HubError> {
    let mut found = Vec::new();
    let stations = match std::fs::read_dir(dir) {
        Ok(s) => s,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(found),
        Err(e) => return Err(io("listing", dir)(e)),
    };
    for station in stations {
        let station = station.map_err(io("listing", dir))?.path();
        if !station.is_dir() {
            continue;
        }
        for file in std::fs::read_dir(&station).map_err(io("listing", &station))? {
            let path = file.map_err(io("listing", &station))?.path();
            if !path.is_file() || path.extension().is_some_and(|e| e == "part") {
                continue;
            }
            let rel = path
                .strip_prefix(dir)
                .ok()
                .and_then(Path::to_str)
                .map(|s| s.replace('\\', "/"))
                .ok_or_else(|| HubError::Corrupt(format!("{} is not UTF-8", path.display())))?;
            let digest = digest_of(&path)?;
            found.push((rel, digest, path));
        }
    }
    found.sort_by(|a, b| a.0.cmp(&b.0));
    Ok(found)
}

fn digest_of(path: &Path) -> Result<FileDigest, HubError> {
    let mut file = std::fs::File::open(path).map_err(io("reading", path))?;
    let mut hasher = Sha256::new();
    let mut buf = vec![0u8; 1 << 16];
    let mut bytes = 0u64;
    loop {
        let n = file.read(&mut buf).map_err(io("reading", path))?;
        if n == 0 {
            break;
        }
        hasher.update(&buf[..n]);
        bytes += n as u64;
    }
    Ok(FileDigest {
        bytes,
        sha256: crate::db::hex(&hasher.finalize()),
    })
}

/// Restore the backup `archive` into the new data directory `data` (absent or empty); a
/// PostgreSQL backup goes into the empty database at `db_url`, which `hub.toml` then names.
/// Every table's rows and every recording's SHA-256 are checked against the manifest.
pub async fn restore(
    archive: &Path,
    data: &Path,
    db_url: Option<&str>,
) -> Result<Manifest, HubError> {
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
    create_private_dirs(data)?;
    let manifest = unpack(archive, data)?;
    let clinic = Clinic::at(data);
    let url = match (manifest.backend.as_str(), db_url) {
        ("sqlite", None) => {
            std::fs::rename(data.join(SQLITE_COPY), data.join("hub.db"))
                .map_err(io("placing the database in", data))?;
            set_private(&data.join("hub.db"))?;
            rewrite_database(&clinic, "")?;
            clinic.database_url(None)?
        }
        ("sqlite", Some(_)) => {
            return Err(HubError::invalid(
                "--db",
                "this backup is of a SQLite database; restore it without --db",
            ));
        }
        ("postgres", Some(url)) => {
            pg_restore(&data.join(PG_DUMP), url)?;
            rewrite_database(&clinic, url)?;
            url.to_owned()
        }
        ("postgres", None) => {
            return Err(HubError::invalid(
                "--db",
                "this backup is of a PostgreSQL database; name an empty database to restore it into",
            ));
        }
        (other, _) => {
            return Err(HubError::Corrupt(format!(
                "the backup names an unknown database kind {other:?}"
            )));
        }
    };
    let _ = std::fs::remove_dir_all(data.join("database"));
    let db = Db::open(&url).await?;
    let rows = row_counts(&db).await;
    db.close().await;
    let rows = rows?;
    if rows != manifest.rows {
        return Err(HubError::Corrupt(format!(
            "the restored database's rows differ from the backup's: {rows:?} restored, {:?} in the backup",
            manifest.rows
        )));
    }
    for (rel, expected) in &manifest.recordings {
        let got = digest_of(&data.join("recordings").join(rel))?;
        if &got != expected {
            return Err(HubError::Corrupt(format!(
                "recording {rel} differs from the backup's ({} bytes, sha256 {}; expected {} bytes, {})",
                got.bytes, got.sha256, expected.bytes, expected.sha256
            )));
        }
    }
    Ok(manifest)
}

/// Unpack `archive` into `data`; its manifest. Entries must be plain files at relative paths
/// without `..`.
fn unpack(archive: &Path, data: &Path) -> Result<Manifest, HubError> {
    let file = std::fs::File::open(archive).map_err(io("reading", archive))?;
    let decoder = zstd::Decoder::new(file).map_err(io("reading", archive))?;
    let mut tar = tar::Archive::new(decoder);
    let mut manifest = None;
    let not_a_backup = |why: String| {
        HubError::Corrupt(format!(
            "{} is not a telerehab backup: {why}",
            archive.display()
        ))
    };
    for entry in tar.entries().map_err(io("reading", archive))? {
        let mut entry = entry.map_err(io("reading", archive))?;
        let path = entry.path().map_err(io("reading", archive))?.into_owned();
        let safe = path.components().all(|c| matches!(c, Component::Normal(_)));
        if !safe || entry.header().entry_type() != tar::EntryType::Regular {
            return Err(not_a_backup(format!("unexpected entry {}", path.display())));
        }
        if path == Path::new(MANIFEST) {
            let mut text = String::new();
            entry
                .read_to_string(&mut text)
                .map_err(io("reading", archive))?;
            let m: Manifest = serde_json::from_str(&text)
                .map_err(|e| not_a_backup(format!("its manifest: {e}")))?;
            if m.format != BACKUP_FORMAT {
                return Err(not_a_backup(format!(
                    "format {} (this build reads {BACKUP_FORMAT})",
                    m.format
                )));
            }
            manifest = Some(m);
            continue;
        }
        if manifest.is_none() {
            return Err(not_a_backup("no manifest first".into()));
        }
        let dest = data.join(&path);
        if let Some(parent) = dest.parent() {
            create_private_dirs(parent)?;
        }
        entry.unpack(&dest).map_err(io("writing", &dest))?;
        set_private(&dest)?;
    }
    manifest.ok_or_else(|| not_a_backup("no manifest".into()))
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
    let mut config = clinic.config()?;
    config.database = url.to_owned();
    let text = toml::to_string(&config).map_err(|e| HubError::Config(format!("hub.toml: {e}")))?;
    let path = clinic.dir().join("hub.toml");
    std::fs::write(&path, text).map_err(io("writing", &path))
}
