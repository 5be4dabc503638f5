//! A patient's rights over what the hub holds about them: [`export`] writes all of it into one
//! archive, [`erase`] removes it (recordings included), revoking their stations first and
//! leaving one audit entry of the erasure that holds no data.
//!
//! "All of it" is found from the schema, not a list kept by hand, so a table added later is
//! covered: every row of a table with a `patient_id` column of theirs, a `session_id` of one of
//! their sessions or a `station_id` of one of their stations; the patient's own row; the audit
//! entries whose target is one of those identifiers or whose actor is one of their stations;
//! and the recording files of their stations (`<station>/` in the recording store, local or S3,
//! and the station's partial uploads on this hub).
//!
//! The export (`.tar.zst`): `patient.json` (every such row, by table, each as an object of its
//! columns) and `recordings/<station>/<file>` byte for byte.

use std::collections::BTreeMap;
use std::future::Future;
use std::io::Write;
use std::path::Path;

use serde_json::{Map, Value};
use sqlx::{Column, Row};

use crate::clinic::Clinic;
use hub_care::recordings::{RecordingStore, StoredFile};
use hub_store::HubError;
use hub_store::db::{Backend, Db, Patient};

pub mod tombstones;

pub use tombstones::{Reapplied, Tombstone};

/// The export's format, in `patient.json`.
pub const EXPORT_FORMAT: u32 = 1;

/// The identifiers that find a patient's rows.
#[derive(Debug, Clone)]
struct Scope {
    patient: Patient,
    sessions: Vec<String>,
    stations: Vec<String>,
}

/// How a table's rows are found to be the patient's.
enum Link {
    /// The `patients` table: `id`.
    Own,
    /// A column holding one of the scope's identifiers.
    Column(&'static str),
    /// The audit log: by target or by a station actor.
    Audit,
}

/// What an export or erasure covered: rows by table, and recording files.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Covered {
    /// Rows by table (tables with none are left out).
    pub rows: BTreeMap<String, usize>,
    /// Recording files (finished and partial uploads).
    pub recording_files: usize,
    /// Their bytes.
    pub recording_bytes: u64,
}

impl Covered {
    /// The rows of `table`.
    pub fn rows_of(&self, table: &str) -> usize {
        self.rows.get(table).copied().unwrap_or(0)
    }
}

async fn find(db: &Db, pseudonym: &str) -> Result<Patient, HubError> {
    db.patient_by_pseudonym(pseudonym)
        .await?
        .ok_or_else(|| HubError::not_found("patient", pseudonym))
}

/// The patient's sessions and stations as `conn` sees them (inside the erasure's transaction,
/// once it holds the patient's rows).
async fn scope_in(conn: &mut sqlx::AnyConnection, patient: Patient) -> Result<Scope, HubError> {
    let mut ids = async |sql: &'static str| {
        let rows = sqlx::query(sql)
            .bind(&patient.id)
            .fetch_all(&mut *conn)
            .await
            .map_err(HubError::db("finding the patient's rows"))?;
        rows.iter()
            .map(|r| r.try_get::<String, _>(0))
            .collect::<Result<Vec<_>, _>>()
            .map_err(HubError::db("finding the patient's rows"))
    };
    let sessions =
        ids("SELECT session_id FROM sessions WHERE patient_id = $1 ORDER BY session_id").await?;
    let stations =
        ids("SELECT station_id FROM stations WHERE patient_id = $1 ORDER BY station_id").await?;
    Ok(Scope {
        patient,
        sessions,
        stations,
    })
}

async fn scope(db: &Db, pseudonym: &str) -> Result<Scope, HubError> {
    let patient = find(db, pseudonym).await?;
    let mut conn = db
        .pool()
        .acquire()
        .await
        .map_err(HubError::db("finding the patient's rows"))?;
    scope_in(&mut conn, patient).await
}

/// Every table with its columns, from the database's catalogue.
async fn tables(db: &Db) -> Result<Vec<(String, Vec<String>)>, HubError> {
    let names = hub_store::db::catalog::row_counts(db).await?;
    let mut out = Vec::new();
    for table in names.into_keys() {
        let sql = match db.backend() {
            Backend::Sqlite => "SELECT name FROM pragma_table_info($1) ORDER BY cid",
            Backend::Postgres => {
                "SELECT CAST(column_name AS TEXT) FROM information_schema.columns \
                 WHERE table_schema = 'public' AND table_name = $1 ORDER BY ordinal_position"
            }
        };
        let rows = sqlx::query(sql)
            .bind(&table)
            .fetch_all(db.pool())
            .await
            .map_err(HubError::db("listing a table's columns"))?;
        let cols = rows
            .iter()
            .map(|r| r.try_get::<String, _>(0))
            .collect::<Result<Vec<_>, _>>()
            .map_err(HubError::db("listing a table's columns"))?;
        out.push((table, cols));
    }
    Ok(out)
}

fn link_of(table: &str, cols: &[String]) -> Option<Link> {
    let has = |c: &str| cols.iter().any(|x| x == c);
    match table {
        "patients" => Some(Link::Own),
        "audit_log" => Some(Link::Audit),
        _ if has("patient_id") => Some(Link::Column("patient_id")),
        _ if has("session_id") => Some(Link::Column("session_id")),
        _ if has("station_id") => Some(Link::Column("station_id")),
        _ => None,
    }
}

/// `WHERE …` of the patient's rows of a table linked by `link`, with its values to bind.
fn selection(link: &Link, s: &Scope) -> (String, Vec<String>) {
    let list = |col: &str, values: &[String], from: usize| -> String {
        if values.is_empty() {
            return "1 = 0".into();
        }
        let marks: Vec<String> = (from..from + values.len())
            .map(|i| format!("${i}"))
            .collect();
        format!("{col} IN ({})", marks.join(", "))
    };
    match link {
        Link::Own => ("id = $1".into(), vec![s.patient.id.clone()]),
        Link::Column("patient_id") => ("patient_id = $1".into(), vec![s.patient.id.clone()]),
        Link::Column("session_id") => (list("session_id", &s.sessions, 1), s.sessions.clone()),
        Link::Column(col) => (list(col, &s.stations, 1), s.stations.clone()),
        Link::Audit => {
            let mut targets = vec![s.patient.id.clone()];
            targets.extend(s.sessions.iter().cloned());
            targets.extend(s.stations.iter().cloned());
            let actors: Vec<String> = s
                .stations
                .iter()
                .map(|id| format!("station:{id}"))
                .collect();
            let mut sql = list("target", &targets, 1);
            if !actors.is_empty() {
                sql = format!("{sql} OR {}", list("actor", &actors, targets.len() + 1));
            }
            targets.extend(actors);
            (sql, targets)
        }
    }
}

/// A row as a JSON object of its columns (integers, reals, text, or null).
fn row_json(row: &sqlx::any::AnyRow) -> Value {
    let mut obj = Map::new();
    for (i, col) in row.columns().iter().enumerate() {
        let v = if let Ok(v) = row.try_get::<Option<i64>, _>(i) {
            v.map_or(Value::Null, Value::from)
        } else if let Ok(v) = row.try_get::<Option<f64>, _>(i) {
            v.map_or(Value::Null, Value::from)
        } else if let Ok(v) = row.try_get::<Option<String>, _>(i) {
            v.map_or(Value::Null, Value::from)
        } else {
            Value::Null
        };
        obj.insert(col.name().to_owned(), v);
    }
    Value::Object(obj)
}

/// The tables that hold rows of a patient, each with how its rows are found.
async fn linked_tables(db: &Db) -> Result<Vec<(String, Link)>, HubError> {
    Ok(tables(db)
        .await?
        .into_iter()
        .filter_map(|(t, cols)| link_of(&t, &cols).map(|l| (t, l)))
        .collect())
}

/// `VERB … FROM "table" WHERE <the patient's rows>` with its values bound.
fn patient_query<'q>(
    verb: &str,
    table: &str,
    link: &Link,
    s: &Scope,
) -> sqlx::query::Query<'q, sqlx::Any, sqlx::any::AnyArguments> {
    let (filter, values) = selection(link, s);
    // Table and column names come from the database's catalogue; values are bound.
    let mut q = sqlx::query(sqlx::AssertSqlSafe(format!(
        "{verb} FROM \"{table}\" WHERE {filter}"
    )));
    for v in values {
        q = q.bind(v);
    }
    q
}

/// The patient's rows of each table, counted (nothing read into memory).
async fn row_counts(
    conn: &mut sqlx::AnyConnection,
    tables: &[(String, Link)],
    s: &Scope,
) -> Result<BTreeMap<String, usize>, HubError> {
    let mut out = BTreeMap::new();
    for (table, link) in tables {
        let n: i64 = patient_query("SELECT COUNT(*)", table, link, s)
            .fetch_one(&mut *conn)
            .await
            .and_then(|r| r.try_get(0))
            .map_err(HubError::db("counting the patient's rows"))?;
        if n > 0 {
            out.insert(table.clone(), usize::try_from(n).unwrap_or(0));
        }
    }
    Ok(out)
}

/// Write `"tables": {…}` — every linked table's rows of the patient, one row at a time as the
/// database streams them, so a year of summaries never sits in memory; the rows written, by
/// table (tables with none are written empty and not counted).
async fn write_rows(
    db: &Db,
    s: &Scope,
    w: &mut impl Write,
) -> Result<BTreeMap<String, usize>, std::io::Error> {
    use tokio_stream::StreamExt as _;
    let tables = linked_tables(db).await.map_err(std::io::Error::other)?;
    let mut counts = BTreeMap::new();
    w.write_all(b"\"tables\": {")?;
    for (i, (table, link)) in tables.iter().enumerate() {
        if i > 0 {
            w.write_all(b",")?;
        }
        write!(w, "\n  {}: [", Value::from(table.as_str()))?;
        let mut n = 0usize;
        let mut rows = patient_query("SELECT *", table, link, s).fetch(db.pool());
        while let Some(row) = rows.next().await {
            let row = row.map_err(std::io::Error::other)?;
            w.write_all(if n == 0 { b"\n    " } else { b",\n    " })?;
            serde_json::to_writer(&mut *w, &row_json(&row))?;
            n += 1;
        }
        w.write_all(b"]")?;
        if n > 0 {
            counts.insert(table.clone(), n);
        }
    }
    w.write_all(b"\n}")?;
    Ok(counts)
}

/// The recording files of the patient's stations (finished and partial), sorted: from the
/// recording store ([`hub_care::recordings`]) and the hub's partial uploads.
async fn recording_files(store: &RecordingStore, s: &Scope) -> Result<Vec<StoredFile>, HubError> {
    let mut files = Vec::new();
    for station in &s.stations {
        files.extend(store.station_files(station).await?);
    }
    files.sort_by(|a, b| a.name.cmp(&b.name));
    Ok(files)
}

fn covered(rows: BTreeMap<String, usize>, files: &[StoredFile]) -> Covered {
    Covered {
        rows,
        recording_files: files.len(),
        recording_bytes: files.iter().map(|f| f.size).sum(),
    }
}

/// Write everything the hub holds about the patient `pseudonym` into the new file `out`.
pub async fn export(
    clinic: &Clinic,
    db: &Db,
    pseudonym: &str,
    out: &Path,
    now_ms: i64,
) -> Result<Covered, HubError> {
    let s = scope(db, pseudonym).await?;
    let store = clinic.recordings()?;
    let files = recording_files(&store, &s).await?;
    let werr = |e| HubError::io(format!("writing {}", out.display()), e);
    let file = std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(out)
        .map_err(|e| HubError::io(format!("creating {}", out.display()), e))?;
    // patient.json goes to a file beside the archive first (tar states a size before the
    // bytes), written as the rows stream in.
    let parent = out
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let mut json = tempfile::NamedTempFile::new_in(parent).map_err(werr)?;
    let rows = {
        let mut w = std::io::BufWriter::new(json.as_file_mut());
        let head = serde_json::json!({
            "format": EXPORT_FORMAT,
            "pseudonym": s.patient.pseudonym,
            "patient_id": s.patient.id,
            "exported_at_ms": now_ms,
        });
        // The head's fields, then the tables, in one object.
        let head = serde_json::to_string(&head).map_err(|e| HubError::Corrupt(e.to_string()))?;
        w.write_all(head.trim_end_matches('}').as_bytes())
            .map_err(werr)?;
        w.write_all(b",\n").map_err(werr)?;
        let rows = write_rows(db, &s, &mut w).await.map_err(werr)?;
        w.write_all(b"}\n").map_err(werr)?;
        w.flush().map_err(werr)?;
        rows
    };
    let mut tar = tar::Builder::new(zstd::Encoder::new(file, 3).map_err(werr)?);
    tar.append_path_with_name(json.path(), "patient.json")
        .map_err(werr)?;
    for f in &files {
        // Streamed from the store (bounded memory whatever the recording's size).
        let mut header = tar::Header::new_gnu();
        header.set_size(f.size);
        header.set_mode(0o600);
        header.set_cksum();
        let reader = store.read(f)?;
        tar.append_data(&mut header, format!("recordings/{}", f.name), reader)
            .map_err(werr)?;
    }
    let mut done = tar.into_inner().map_err(werr)?.finish().map_err(werr)?;
    done.flush().map_err(werr)?;
    done.sync_all().map_err(werr)?;
    let what = covered(rows, &files);
    db.audit(
        "cli",
        "export_patient",
        &s.patient.id,
        &format!(
            "{} rows, {} recording files",
            what.rows.values().sum::<usize>(),
            what.recording_files
        ),
        now_ms,
    )
    .await?;
    Ok(what)
}

/// Remove everything the hub holds about the patient `pseudonym`: their stations are revoked
/// first (refused from their next frame on), a serving hub given two revocation polls to cut
/// their connections, then every row and recording file is removed in one transaction, and
/// one audit entry says how much was erased, holding none of it. The erasure's [`Tombstone`]
/// is written to the clinic's ledger before a row goes, and to the database with the rows, so
/// that no restore brings the patient back ([`tombstones`]).
pub async fn erase(
    clinic: &Clinic,
    db: &Db,
    pseudonym: &str,
    now_ms: i64,
) -> Result<Covered, HubError> {
    // A serving hub re-reads the revoked stations every `REVOCATION_POLL` and cuts their
    // connections: give it two before their rows go.
    let grace = tokio::time::sleep(2 * hub_care::ingest::REVOCATION_POLL);
    erase_after(clinic, db, pseudonym, now_ms, grace).await
}

/// [`erase`] with its revocation grace given: whatever arrives while `grace` runs — a session
/// of a station not cut yet, a newly paired station — is erased too, because the erasure's
/// transaction takes the patient's rows for itself before it looks for them.
pub async fn erase_after(
    clinic: &Clinic,
    db: &Db,
    pseudonym: &str,
    now_ms: i64,
    grace: impl Future<Output = ()>,
) -> Result<Covered, HubError> {
    let before = scope(db, pseudonym).await?;
    let patient = before.patient.clone();
    for station in &before.stations {
        db.revoke_station(station, now_ms).await?;
    }
    if !before.stations.is_empty() {
        grace.await;
    }
    let tombstone = Tombstone::of(clinic, &patient, "cli", now_ms)?;
    // In the ledger first: an erasure cut short is finished at the next start.
    tombstones::append_to_ledger(
        &tombstones::ledger_path(clinic),
        std::slice::from_ref(&tombstone),
    )?;
    let (s, what) = remove(clinic, db, patient, &tombstone, now_ms).await?;
    audit_erasure(db, "erase_patient", "erased on request", &s, &what, now_ms).await?;
    Ok(what)
}

/// Erases again a patient a tombstone names, who came back with an older backup (no grace:
/// no hub serves them while it runs).
async fn erase_again(
    clinic: &Clinic,
    db: &Db,
    patient: &Patient,
    tombstone: &Tombstone,
    now_ms: i64,
) -> Result<Covered, HubError> {
    let (s, what) = remove(clinic, db, patient.clone(), tombstone, now_ms).await?;
    let why = "erased again from its tombstone (restored from an older copy)";
    audit_erasure(db, "erase_patient_reapplied", why, &s, &what, now_ms).await?;
    Ok(what)
}

/// The erasure itself, in one transaction: it first takes the patient's rows for itself
/// (SQLite: a write, which holds the database's only write lock until the commit; PostgreSQL:
/// the patient's, their stations' and their sessions' rows locked `FOR UPDATE`, which a
/// session or summary being inserted for them waits on), and only then finds their sessions
/// and stations. A session stored before that is erased with the rest; one arriving after
/// waits, then finds its station gone and is refused. Nothing is half-erased: the rows, the
/// tombstone and the stations' revocation commit together, the recordings go after.
async fn remove(
    clinic: &Clinic,
    db: &Db,
    patient: Patient,
    tombstone: &Tombstone,
    now_ms: i64,
) -> Result<(Scope, Covered), HubError> {
    let mut tx = db
        .pool()
        .begin()
        .await
        .map_err(HubError::db("starting the erasure"))?;
    if db.backend() == Backend::Postgres {
        for sql in [
            "SELECT id FROM patients WHERE id = $1 FOR UPDATE",
            "SELECT station_id FROM stations WHERE patient_id = $1 FOR UPDATE",
            "SELECT session_id FROM sessions WHERE patient_id = $1 FOR UPDATE",
        ] {
            sqlx::query(sql)
                .bind(&patient.id)
                .fetch_all(&mut *tx)
                .await
                .map_err(HubError::db("holding the patient's rows"))?;
        }
    }
    // SQLite's write lock; and a station paired during the grace is revoked with the others.
    sqlx::query(
        "UPDATE stations SET revoked_at_ms = COALESCE(revoked_at_ms, $2) WHERE patient_id = $1",
    )
    .bind(&patient.id)
    .bind(now_ms)
    .execute(&mut *tx)
    .await
    .map_err(HubError::db("holding the patient's rows"))?;
    let s = scope_in(&mut tx, patient).await?;
    let plan = linked_tables(db).await?;
    let store = clinic.recordings()?;
    let files = recording_files(&store, &s).await?;
    let what = covered(row_counts(&mut tx, &plan, &s).await?, &files);
    tombstone.insert(&mut tx).await?;
    // Children before parents: rows keyed by session or station, then the other rows keyed
    // by patient (some also name a session), then the sessions, the stations and the patient.
    let order = |table: &str, link: &Link| match (table, link) {
        (_, Link::Audit) => 0,
        (_, Link::Column("session_id" | "station_id")) => 1,
        ("sessions", _) => 3,
        ("stations", _) => 4,
        (_, Link::Column(_)) => 2,
        (_, Link::Own) => 5,
    };
    let mut plan = plan;
    plan.sort_by_key(|(t, l)| (order(t, l), t.clone()));
    for (table, link) in &plan {
        patient_query("DELETE", table, link, &s)
            .execute(&mut *tx)
            .await
            .map_err(HubError::db("erasing the patient's rows"))?;
    }
    tx.commit()
        .await
        .map_err(HubError::db("committing the erasure"))?;
    for station in &s.stations {
        store.erase_station(station).await?;
    }
    db.scrub().await?;
    Ok((s, what))
}

/// The erasure's one audit entry: how much, none of it.
async fn audit_erasure(
    db: &Db,
    action: &str,
    why: &str,
    s: &Scope,
    what: &Covered,
    now_ms: i64,
) -> Result<(), HubError> {
    db.audit(
        "cli",
        action,
        &s.patient.id,
        &format!(
            "{why}: {} rows in {} tables, {} recording files ({} bytes); {} stations revoked",
            what.rows.values().sum::<usize>(),
            what.rows.len(),
            what.recording_files,
            what.recording_bytes,
            s.stations.len()
        ),
        now_ms,
    )
    .await
}
