//! The hub's system of record: one sqlx code path (the `Any` driver) for SQLite and
//! PostgreSQL.
//!
//! - [`Db::open`] takes `sqlite://PATH?mode=rwc` or `postgres://USER@HOST:PORT/DB` and applies
//!   the embedded migrations (`crates/hub-store/migrations/`, versioned; re-opening is a no-op).
//! - All SQL uses bound parameters written `$1`, `$2`, … (both backends accept them) and
//!   portable types: TEXT ids, BIGINT times in milliseconds since the Unix epoch, BIGINT
//!   0/1 flags, DOUBLE PRECISION floats. The `Any` driver decodes no NUMERIC: cast
//!   PostgreSQL's `SUM(bigint)` (NUMERIC) back with `CAST(SUM(x) AS BIGINT)`.
//! - Every method takes the current time as `now_ms` (milliseconds since the Unix epoch), so
//!   tests are deterministic; the caller owns the clock.
//!
//! ```no_run
//! # async fn demo() -> Result<(), hub_store::HubError> {
//! use hub_store::{Db, Role};
//! let db = Db::open_sqlite(std::path::Path::new("/var/lib/telerehab/hub.db")).await?;
//! let now_ms = 1_795_253_400_000;
//! let t = db.add_therapist("ada@clinic.example", "correct horse battery", Role::Therapist, now_ms).await?;
//! let p = db.add_patient("p-0042", Some(&t.id), now_ms).await?;
//! let code = db.create_pairing_code(&p.id, now_ms, 15 * 60 * 1000).await?; // e.g. "7K3M-Q9XD"
//! # Ok(())
//! # }
//! ```

mod alert_acks;
mod audit;
pub mod catalog;
mod checkins;
pub mod clinic_settings;
mod difficulty;
mod exercises;
mod logins;
mod measures;
pub use logins::address_key;
mod messages;
mod notes;
mod pain;
mod pairing;
mod pairing_windows;
mod patients;
mod regimens;
mod scales;
mod sessions;
mod station_limits;
mod stations;
mod summaries;
mod therapists;
mod wheels;
mod words;
pub use words::{RECORDING_STALLED_AFTER_MS, end_kind_of};

use std::path::{Path, PathBuf};

use sha2::{Digest, Sha256};
use sqlx::any::{AnyPoolOptions, AnyRow};
use sqlx::{AnyPool, Executor, Row};

use crate::error::HubError;

pub use pairing_windows::PairingEvent;

pub use alert_acks::{AlertAck, MAX_ALERT_KEY_CHARS, NewAck};
pub use audit::{
    AuditCursor, AuditEntry, AuditFilter, AuditPage, MAX_AUDIT_PAGE, MAX_DETAIL_CHARS,
};
pub use checkins::{PAIN_ALERT_AT, PAIN_RISE_ALERT, SessionCheckIn, pain_alert};
pub use difficulty::SessionDifficulty;
pub use exercises::{
    Assessment, AssessmentWithChanges, DEFAULT_ASSESSMENT_PAGE, MAX_ASSESSMENT_PAGE, MeasureChange,
    SessionExercise,
};
pub use logins::{
    ACCOUNT_FREE_FAILURES, ACCOUNT_MAX_DELAY_MS, ADDRESS_FREE_FAILURES, ADDRESS_MAX_DELAY_MS,
    BASE_DELAY_MS, DEVICE_TTL_MS, HASH_QUEUE, REFUSAL_AUDITS_PER_ACCOUNT_PER_MINUTE,
    REFUSAL_AUDITS_PER_MINUTE, REFUSAL_AUDITS_TOTAL_PER_MINUTE, THROTTLE_FORGET_MS,
};
pub use measures::MeasuresBySession;
pub use messages::{MAX_MESSAGES_LISTED, PatientMessage};
pub use notes::{MAX_NOTE_CHARS, MAX_NOTES_LISTED, SessionNote, check_note_text};
pub use pain::{MailRecipient, PAIN_MAIL_LOOKBACK_MS, PainMail, PainMailStatus};
pub use pairing::{
    ATTEMPTS_BEFORE_BACKOFF, MAX_ATTEMPT_WAIT_MS, MIN_ATTEMPT_WAIT_MS, PairingTicket,
    attempt_wait_ms,
};
pub use patients::{MAX_PSEUDONYM_LEN, Patient, PatientOverview, WEEK_MS, check_pseudonym};
pub use regimens::{MAX_REGIMEN_BYTES, RegimenVersion};
pub use scales::{
    DAY_MS, EARLIEST_ASSESSED_ON, MAX_SCALES_LISTED, NewScale, SCALES, ScaleDef, ScaleEntry,
    ScaleField, check_scale, day_of, iso_utc, scale_def,
};
pub use sessions::{Recording, SessionRow};
pub use station_limits::{MAX_SESSIONS_PER_STATION_DAY, TRAINING_SESSION_SQL};
pub use stations::Station;
pub use therapists::{
    COMMON_PASSWORDS, LOCKOUT_MS, LoginAttempt, LoginOk, MAX_FAILED_LOGINS, MAX_PASSWORD_BYTES,
    MIN_DISTINCT_CHARS, MIN_GUESSES_LOG10, MIN_PASSWORD_CHARS, Role, Therapist, check_new_password,
};
pub use wheels::PatientWheel;
pub use words::{
    COMPLETE, NamedSession, TREND_BASELINE_SESSIONS, exercise_kind, like_with_like, plain_name,
    trend,
};

/// The embedded, versioned migrations of `crates/hub-store/migrations/`.
static MIGRATOR: sqlx::migrate::Migrator = sqlx::migrate!("./migrations");

/// How long a connection waits for a locked SQLite database before failing, ms.
pub const SQLITE_BUSY_TIMEOUT_MS: u64 = 5_000;

/// WAL pages after which a committing SQLite connection checkpoints by itself (SQLite's
/// default is 1 000, about 4 MB: once a second at 1 000 stations, and the commit that does it
/// waits for the copy and its fsync, which was the ingest's latency tail). The hub checkpoints
/// from a task of its own instead ([`Db::checkpoint`]); this only bounds the WAL (≈ 400 MB) if
/// that task ever stops.
const SQLITE_WAL_AUTOCHECKPOINT_PAGES: u32 = 100_000;

/// Size of the SQLite write-ahead log past which [`Db::checkpoint`] copies it all back and
/// truncates it (`wal_checkpoint(TRUNCATE)`, which waits briefly for readers and the writer),
/// and to which SQLite itself cuts the file after a checkpoint (`journal_size_limit`), bytes.
/// Without it a WAL that a flood grew never shrinks.
pub const SQLITE_WAL_LIMIT_BYTES: u64 = 64 << 20;

/// Which database engine a [`Db`] talks to. Exhaustive: the crates above match on it where
/// the two differ, and a third engine must be handled in each of those places.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Backend {
    /// A SQLite file (WAL mode, foreign keys on).
    Sqlite,
    /// A PostgreSQL server.
    Postgres,
}

/// The hub's database: a connection pool, cheap to clone (clones share the pool).
#[derive(Debug, Clone)]
pub struct Db {
    pool: AnyPool,
    backend: Backend,
    /// The SQLite database's write-ahead log (`PATH-wal`), watched by [`Db::checkpoint`].
    wal_path: Option<PathBuf>,
    /// Login throttling's hashing pool and refusal limiter, shared by clones.
    guards: std::sync::Arc<logins::Guards>,
    /// The PostgreSQL server's URL (the hubs' shared channel listens on a connection of its
    /// own, `hub_care::fanout`); `None` on SQLite.
    postgres_url: Option<std::sync::Arc<str>>,
}

impl Db {
    /// Opens `url` — `sqlite://PATH?mode=rwc` (file created if missing) or
    /// `postgres://USER[:PASSWORD]@HOST[:PORT]/DATABASE` — and applies pending migrations.
    ///
    /// For SQLite, a missing parent directory is created with mode 0700 and a missing database
    /// file with mode 0600 before the driver opens it.
    pub async fn open(url: &str) -> Result<Self, HubError> {
        sqlx::any::install_default_drivers();
        let mut wal_path = None;
        let backend = if let Some(rest) = url.strip_prefix("sqlite:") {
            let path = rest.trim_start_matches("//");
            let path = path.split('?').next().unwrap_or_default();
            if path.is_empty() || path == ":memory:" {
                return Err(HubError::invalid(
                    "database url",
                    "a SQLite url must name a file: sqlite://PATH?mode=rwc",
                ));
            }
            prepare_sqlite_file(Path::new(path))?;
            wal_path = Some(PathBuf::from(format!("{path}-wal")));
            Backend::Sqlite
        } else if url.starts_with("postgres://") || url.starts_with("postgresql://") {
            Backend::Postgres
        } else {
            return Err(HubError::invalid(
                "database url",
                "must start with sqlite:// or postgres://",
            ));
        };
        let max_connections = match backend {
            Backend::Sqlite => 4,
            Backend::Postgres => 10,
        };
        let pool = AnyPoolOptions::new()
            .max_connections(max_connections)
            .after_connect(move |conn, _meta| {
                Box::pin(async move {
                    if backend == Backend::Sqlite {
                        // WAL: readers do not block the writer; busy_timeout: a writer waits for
                        // another instead of failing; foreign keys are off by default in SQLite;
                        // secure_delete: a deleted row's bytes are overwritten with zeros, not
                        // left in the page (or free page) until reused — an erased patient's
                        // data must not stay in the file ([`Db::scrub`] empties the WAL).
                        let pragmas = format!(
                            "PRAGMA journal_mode = WAL; PRAGMA busy_timeout = \
                             {SQLITE_BUSY_TIMEOUT_MS}; PRAGMA foreign_keys = ON; \
                             PRAGMA secure_delete = ON; \
                             PRAGMA synchronous = NORMAL; \
                             PRAGMA wal_autocheckpoint = {SQLITE_WAL_AUTOCHECKPOINT_PAGES}; \
                             PRAGMA journal_size_limit = {SQLITE_WAL_LIMIT_BYTES};"
                        );
                        conn.execute(sqlx::raw_sql(sqlx::AssertSqlSafe(pragmas)))
                            .await?;
                    }
                    Ok(())
                })
            })
            .connect(url)
            .await
            .map_err(|source| HubError::Database {
                context: format!("connecting to {}", redact_url(url)),
                source,
            })?;
        // Regimens stored before migration 4 have their sessions_per_week filled in once, when
        // it is applied, not scanned for at every open.
        let fill_sessions_per_week = !migration_applied(&pool, 4).await;
        // And their planned session length, once, when migration 10 is applied.
        let fill_planned_session_s = !migration_applied(&pool, 10).await;
        MIGRATOR.run(&pool).await.map_err(|e| HubError::Database {
            context: "applying migrations".to_owned(),
            source: e.into(),
        })?;
        let db = Self {
            pool,
            backend,
            wal_path,
            guards: std::sync::Arc::new(logins::Guards::new()),
            postgres_url: (backend == Backend::Postgres).then(|| url.into()),
        };
        if fill_sessions_per_week {
            db.fill_sessions_per_week().await?;
        }
        if fill_planned_session_s {
            db.fill_planned_session_s().await?;
        }
        Ok(db)
    }

    /// Opens (creating if needed) the SQLite database file at `path`; see [`Db::open`].
    pub async fn open_sqlite(path: &Path) -> Result<Self, HubError> {
        let text = path.to_str().ok_or_else(|| {
            HubError::invalid("database path", format!("{} is not UTF-8", path.display()))
        })?;
        if text.contains(['?', '#', '%']) {
            return Err(HubError::invalid(
                "database path",
                format!("{text:?} contains '?', '#' or '%', which a sqlite:// url cannot carry"),
            ));
        }
        Self::open(&format!("sqlite://{text}?mode=rwc")).await
    }

    /// The PostgreSQL server's URL; `None` on SQLite.
    pub fn postgres_url(&self) -> Option<&str> {
        self.postgres_url.as_deref()
    }

    /// The engine behind this database.
    pub fn backend(&self) -> Backend {
        self.backend
    }

    /// Copies what the SQLite write-ahead log holds into the database file without waiting
    /// for (or blocking) the writer or readers (`wal_checkpoint(PASSIVE)`); the hub runs it
    /// about once a second on a connection of its own. When the log has grown past
    /// [`SQLITE_WAL_LIMIT_BYTES`] it is copied back whole and truncated
    /// (`wal_checkpoint(TRUNCATE)`). Nothing to do on PostgreSQL.
    pub async fn checkpoint(&self) -> Result<(), HubError> {
        if self.backend == Backend::Sqlite {
            sqlx::raw_sql("PRAGMA wal_checkpoint(PASSIVE)")
                .execute(&self.pool)
                .await
                .map_err(HubError::db("checkpointing the write-ahead log"))?;
            if self.wal_bytes().is_some_and(|b| b > SQLITE_WAL_LIMIT_BYTES) {
                sqlx::raw_sql("PRAGMA wal_checkpoint(TRUNCATE)")
                    .execute(&self.pool)
                    .await
                    .map_err(HubError::db("truncating the write-ahead log"))?;
            }
        }
        Ok(())
    }

    /// After an erasure: SQLite copies the write-ahead log into the database file and truncates
    /// it (`wal_checkpoint(TRUNCATE)`, waiting up to the busy timeout for readers), so the
    /// erased rows' old pages, which the log still holds, are gone from it; with
    /// `secure_delete` the database file holds zeros where they were. Nothing to do on
    /// PostgreSQL (its own vacuum reclaims dead rows; see docs/BACKUP.md).
    pub async fn scrub(&self) -> Result<(), HubError> {
        if self.backend == Backend::Sqlite {
            let busy: i64 = sqlx::query_scalar("PRAGMA wal_checkpoint(TRUNCATE)")
                .fetch_one(&self.pool)
                .await
                .map_err(HubError::db(
                    "truncating the write-ahead log after an erasure",
                ))?;
            if busy != 0 {
                // The erasure itself is committed; only the log's old copy waits.
                tracing::warn!(
                    "a reader kept SQLite's write-ahead log from being emptied after an erasure: \
                     the erased rows' old pages stay in it until the next full checkpoint"
                );
            }
        }
        Ok(())
    }

    /// Size of the SQLite write-ahead log file, bytes; `None` on PostgreSQL or when it does
    /// not exist.
    pub fn wal_bytes(&self) -> Option<u64> {
        let path = self.wal_path.as_ref()?;
        std::fs::metadata(path).ok().map(|m| m.len())
    }

    /// The database's size on disk, bytes: PostgreSQL's `pg_database_size` (tables and
    /// indexes, not the write-ahead log), SQLite's pages (`page_count × page_size`, the
    /// write-ahead log not counted). What `hub bench` divides by the summaries it stored.
    pub async fn size_bytes(&self) -> Result<i64, HubError> {
        let sql = match self.backend {
            Backend::Postgres => "SELECT pg_database_size(current_database())",
            Backend::Sqlite => {
                "SELECT page_count * page_size FROM pragma_page_count(), pragma_page_size()"
            }
        };
        sqlx::query_scalar(sql)
            .fetch_one(&self.pool)
            .await
            .map_err(HubError::db("reading the database's size"))
    }

    /// The schema version applied (the highest migration number).
    pub async fn schema_version(&self) -> Result<i64, HubError> {
        sqlx::query_scalar("SELECT MAX(version) FROM _sqlx_migrations")
            .fetch_one(&self.pool)
            .await
            .map_err(HubError::db("reading the schema version"))
    }

    /// Closes every connection (waits for those in use to be returned).
    pub async fn close(&self) {
        self.pool.close().await;
    }

    /// The connection pool, for queries this type has no method for. Write placeholders as
    /// `$1`, `$2`, … and use only portable SQL (see the module documentation).
    pub fn pool(&self) -> &AnyPool {
        &self.pool
    }
}

/// `url` without its password, for messages.
fn redact_url(url: &str) -> String {
    match (url.find("://"), url.rfind('@')) {
        (Some(scheme), Some(at)) if at > scheme => {
            let userinfo = &url[scheme + 3..at];
            match userinfo.split_once(':') {
                Some((user, _)) => format!("{}{user}:***{}", &url[..scheme + 3], &url[at..]),
                None => url.to_owned(),
            }
        }
        _ => url.to_owned(),
    }
}

/// Creates the directory (0700) and the file (0600) of a SQLite database if missing, and
/// narrows an existing file to 0600.
fn prepare_sqlite_file(path: &Path) -> Result<(), HubError> {
    let dir: PathBuf = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_owned(),
        _ => PathBuf::from("."),
    };
    if !dir.exists() {
        std::fs::create_dir_all(&dir)
            .map_err(|e| HubError::io(format!("creating {}", dir.display()), e))?;
        set_mode(&dir, 0o700)?;
    }
    let mut options = std::fs::OpenOptions::new();
    options.create(true).append(true);
    #[cfg(unix)]
    std::os::unix::fs::OpenOptionsExt::mode(&mut options, 0o600);
    options
        .open(path)
        .map_err(|e| HubError::io(format!("creating {}", path.display()), e))?;
    set_mode(path, 0o600)
}

#[cfg(unix)]
fn set_mode(path: &Path, mode: u32) -> Result<(), HubError> {
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(path, std::fs::Permissions::from_mode(mode)).map_err(|e| {
        HubError::io(
            format!("setting permissions {mode:o} on {}", path.display()),
            e,
        )
    })
}

#[cfg(not(unix))]
fn set_mode(_path: &Path, _mode: u32) -> Result<(), HubError> {
    Ok(())
}

/// `n` bytes from the operating system's CSPRNG.
pub(crate) fn random_bytes<const N: usize>() -> Result<[u8; N], HubError> {
    let mut bytes = [0u8; N];
    getrandom::fill(&mut bytes).map_err(|e| {
        HubError::io(
            "reading the OS random generator",
            std::io::Error::other(e.to_string()),
        )
    })?;
    Ok(bytes)
}

/// 20 characters of Crockford base 32 (100 bits) from the OS CSPRNG.
pub fn one_time_password() -> Result<String, HubError> {
    let bytes = random_bytes::<20>()?;
    Ok(bytes
        .iter()
        .map(|b| netlink::pairing::CODE_ALPHABET[usize::from(b & 0x1f)] as char)
        .collect())
}

/// A new random identifier: `prefix` + 16 lowercase hex digits (64 bits).
pub fn new_id(prefix: &str) -> Result<String, HubError> {
    Ok(format!("{prefix}{}", hex(&random_bytes::<8>()?)))
}

/// Lowercase hex of `bytes`.
pub fn hex(bytes: &[u8]) -> String {
    use std::fmt::Write;
    bytes.iter().fold(String::new(), |mut s, b| {
        let _ = write!(s, "{b:02x}");
        s
    })
}

/// Lowercase hex SHA-256 of `data`.
pub fn sha256_hex(data: &[u8]) -> String {
    hex(&Sha256::digest(data))
}

/// Checks an identifier (patient, station, session id) with netlink's rule: 1 to 64 ASCII
/// letters, digits, `_`, `-`, `.`, not starting with `.`.
pub(crate) fn check_id(field: &'static str, value: &str) -> Result<(), HubError> {
    netlink::frame::check_id(field, value).map_err(|reason| HubError::invalid(field, reason))
}

/// A `u64` from the protocol as a BIGINT, refusing values above `i64::MAX`.
pub(crate) fn to_i64(field: &'static str, value: u64) -> Result<i64, HubError> {
    i64::try_from(value).map_err(|_| {
        HubError::invalid(
            field,
            format!("{value} is above the largest storable value {}", i64::MAX),
        )
    })
}

/// Column `col` of `row`, naming it on failure.
pub fn col<'r, T>(row: &'r AnyRow, col: &str) -> Result<T, HubError>
where
    T: sqlx::Decode<'r, sqlx::Any> + sqlx::Type<sqlx::Any>,
{
    row.try_get(col)
        .map_err(|e| HubError::Corrupt(format!("column {col}: {e}")))
}

/// Whether the database at `pool` has migration `version` applied (`false` for a new one,
/// which has no migrations table yet).
async fn migration_applied(pool: &AnyPool, version: i64) -> bool {
    sqlx::query("SELECT version FROM _sqlx_migrations WHERE version = $1")
        .bind(version)
        .fetch_optional(pool)
        .await
        .is_ok_and(|row| row.is_some())
}
