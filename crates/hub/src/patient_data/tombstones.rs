//! Erasure tombstones: an erased patient never comes back, whatever backup is restored.
//!
//! Every erasure is recorded as a [`Tombstone`] — the patient's internal id (random, `p-` + 16
//! hex digits), the keyed hash of their pseudonym, when and by whom; none of their data — in two
//! places:
//! - the ledger file `erasures.ndjson` of the data directory (one JSON object a line, appended
//!   and synced before a row is erased), which a restore does not overwrite (a restore makes a
//!   new data directory) and every later backup carries;
//! - the database's `erasure_tombstones` table (migration 0025), written in the erasure's own
//!   transaction, so every later backup's database holds them too, and every hub sharing a
//!   PostgreSQL database sees them.
//!
//! [`reapply`] merges the two (and any ledger an operator supplies to `hub restore
//! --erasures`), writes each tombstone missing from either, and erases again every patient a
//! tombstone names who is in the database: `hub restore` runs it after the backup's rows are
//! checked, and `hub serve` at start (idempotent: nothing to do when nobody came back).
//!
//! The pseudonym's hash is HMAC-SHA-256 keyed from the clinic's CA key (which every backup
//! carries and no restore changes): the ledger alone cannot be searched for a pseudonym, and a
//! tombstone is applied only to the patient whose pseudonym it was made from.

use std::collections::BTreeMap;
use std::io::{Read, Write};
use std::path::Path;

use hmac::{Hmac, Mac};
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
use sqlx::Row;

use crate::clinic::Clinic;
use hub_store::HubError;
use hub_store::db::{Db, Patient};

/// The ledger file, in the data directory (and in a backup).
pub const LEDGER_FILE: &str = "erasures.ndjson";

/// Largest ledger read, bytes (some 200 bytes an erasure).
pub const MAX_LEDGER_BYTES: u64 = 64 << 20;

/// One erasure, holding none of the patient's data.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Tombstone {
    /// The erased patient's internal id.
    pub erased_patient_id: String,
    /// HMAC-SHA-256 of their pseudonym, keyed from the clinic's CA key, lower-case hex.
    pub pseudonym_hmac: String,
    /// When, ms since the Unix epoch.
    pub erased_at_ms: i64,
    /// Who (`cli`, or the console login that asked).
    pub erased_by: String,
}

/// What [`reapply`] did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Reapplied {
    /// Tombstones known after the merge.
    pub tombstones: usize,
    /// Patients erased again (they were back, from an older backup).
    pub erased: usize,
}

/// The key of the pseudonyms' hashes: SHA-256 of a label and the clinic's CA key.
fn hmac_key(clinic: &Clinic) -> Result<[u8; 32], HubError> {
    let path = clinic.dir().join("tls").join("ca.key");
    let ca_key = std::fs::read(&path).map_err(HubError::io_at("reading", &path))?;
    let mut h = Sha256::new();
    h.update(b"telerehab erasure tombstone v1\0");
    h.update(&ca_key);
    Ok(h.finalize().into())
}

fn pseudonym_hmac(key: &[u8; 32], pseudonym: &str) -> String {
    let mut mac = Hmac::<Sha256>::new_from_slice(key).expect("HMAC takes a key of any length");
    mac.update(pseudonym.as_bytes());
    hub_store::db::hex(&mac.finalize().into_bytes())
}

impl Tombstone {
    /// The tombstone of erasing `patient` at `now_ms` by `by`.
    pub fn of(clinic: &Clinic, patient: &Patient, by: &str, now_ms: i64) -> Result<Self, HubError> {
        Ok(Self {
            erased_patient_id: patient.id.clone(),
            pseudonym_hmac: pseudonym_hmac(&hmac_key(clinic)?, &patient.pseudonym),
            erased_at_ms: now_ms,
            erased_by: by.to_owned(),
        })
    }

    /// Stores it in the database's table, in `conn`'s transaction (kept if already there).
    pub(super) async fn insert(&self, conn: &mut sqlx::AnyConnection) -> Result<(), HubError> {
        sqlx::query(
            "INSERT INTO erasure_tombstones \
             (erased_patient_id, pseudonym_hmac, erased_at_ms, erased_by) \
             VALUES ($1, $2, $3, $4) ON CONFLICT (erased_patient_id) DO NOTHING",
        )
        .bind(&self.erased_patient_id)
        .bind(&self.pseudonym_hmac)
        .bind(self.erased_at_ms)
        .bind(&self.erased_by)
        .execute(conn)
        .await
        .map_err(HubError::db("recording the erasure's tombstone"))?;
        Ok(())
    }
}

/// The tombstones of the ledger `path` (none when it does not exist); an error naming the
/// file and line that is not one.
pub fn read_ledger(path: &Path) -> Result<Vec<Tombstone>, HubError> {
    let bytes = match std::fs::metadata(path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(HubError::io_at("reading", path)(e)),
        Ok(m) if m.len() > MAX_LEDGER_BYTES => {
            return Err(HubError::Corrupt(format!(
                "{} is {} bytes, more than an erasure ledger's {MAX_LEDGER_BYTES}",
                path.display(),
                m.len()
            )));
        }
        Ok(_) => std::fs::read(path).map_err(HubError::io_at("reading", path))?,
    };
    // The one NDJSON reader (netlink::ndjson): a last line a crash cut short mid-append is left out (its
    // erasure had not begun: the line is synced before any row is deleted).
    netlink::ndjson::read_lines(&bytes[..])
        .map(|(n, line)| {
            netlink::ndjson::parse(&line).map_err(|e| {
                HubError::Corrupt(format!(
                    "{} line {n} is not an erasure tombstone: {e}",
                    path.display()
                ))
            })
        })
        .collect()
}

/// Appends `tombstones` to the ledger `path` (made 0600 if new) and syncs it.
pub fn append_to_ledger(path: &Path, tombstones: &[Tombstone]) -> Result<(), HubError> {
    if tombstones.is_empty() {
        return Ok(());
    }
    let mut options = std::fs::OpenOptions::new();
    options.create(true).read(true).append(true);
    #[cfg(unix)]
    std::os::unix::fs::OpenOptionsExt::mode(&mut options, 0o600);
    let mut file = options
        .open(path)
        .map_err(HubError::io_at("writing", path))?;
    // A last line a crash cut short mid-append is an erasure that never began: cut it off,
    // so the new tombstones start on a line of their own.
    let mut held = Vec::new();
    file.read_to_end(&mut held)
        .map_err(HubError::io_at("reading", path))?;
    let whole = netlink::ndjson::complete_len(&held);
    if whole < held.len() {
        file.set_len(whole as u64)
            .map_err(HubError::io_at("writing", path))?;
    }
    let mut text = String::new();
    for t in tombstones {
        text.push_str(&serde_json::to_string(t).map_err(|e| HubError::Corrupt(e.to_string()))?);
        text.push('\n');
    }
    file.write_all(text.as_bytes())
        .and_then(|()| file.sync_all())
        .map_err(HubError::io_at("writing", path))
}

/// The clinic's ledger file.
pub fn ledger_path(clinic: &Clinic) -> std::path::PathBuf {
    clinic.dir().join(LEDGER_FILE)
}

async fn table(db: &Db) -> Result<Vec<Tombstone>, HubError> {
    let rows = sqlx::query(
        "SELECT erased_patient_id, pseudonym_hmac, erased_at_ms, erased_by \
         FROM erasure_tombstones ORDER BY erased_at_ms, erased_patient_id",
    )
    .fetch_all(db.pool())
    .await
    .map_err(HubError::db("reading the erasure tombstones"))?;
    rows.iter()
        .map(|r| {
            Ok(Tombstone {
                erased_patient_id: r.try_get(0)?,
                pseudonym_hmac: r.try_get(1)?,
                erased_at_ms: r.try_get(2)?,
                erased_by: r.try_get(3)?,
            })
        })
        .collect::<Result<_, sqlx::Error>>()
        .map_err(HubError::db("reading the erasure tombstones"))
}

/// Merges the clinic's ledger, the database's tombstones and `supplied` (ledgers an operator
/// names), writes each one missing from the ledger or the table, and erases again every
/// patient a tombstone names who is in the database (their stations revoked, every row and
/// recording removed, one audit entry `erase_patient_reapplied`). A tombstone naming a patient
/// whose pseudonym it was not made from (another clinic's ledger) is refused before anything
/// is erased.
pub async fn reapply(
    clinic: &Clinic,
    db: &Db,
    supplied: &[Tombstone],
    now_ms: i64,
) -> Result<Reapplied, HubError> {
    let ledger_path = ledger_path(clinic);
    let in_ledger = read_ledger(&ledger_path)?;
    let in_table = table(db).await?;
    let mut all: BTreeMap<String, Tombstone> = BTreeMap::new();
    for t in in_ledger.iter().chain(&in_table).chain(supplied) {
        all.entry(t.erased_patient_id.clone())
            .or_insert_with(|| t.clone());
    }
    let missing_from_ledger: Vec<Tombstone> = all
        .values()
        .filter(|t| {
            !in_ledger
                .iter()
                .any(|l| l.erased_patient_id == t.erased_patient_id)
        })
        .cloned()
        .collect();
    append_to_ledger(&ledger_path, &missing_from_ledger)?;
    let key = hmac_key(clinic)?;
    let mut back = Vec::new();
    for t in all.values() {
        let Some(patient) = db.patient(&t.erased_patient_id).await? else {
            continue;
        };
        if pseudonym_hmac(&key, &patient.pseudonym) != t.pseudonym_hmac {
            return Err(HubError::Conflict(format!(
                "an erasure tombstone names patient {} but was not made from their pseudonym: \
                 the ledger is another clinic's (or was altered); nothing was erased",
                t.erased_patient_id
            )));
        }
        back.push((patient, t));
    }
    let mut conn = db
        .pool()
        .acquire()
        .await
        .map_err(HubError::db("recording the erasure tombstones"))?;
    for t in all.values() {
        t.insert(&mut conn).await?;
    }
    drop(conn);
    for (patient, tombstone) in &back {
        super::erase_again(clinic, db, patient, tombstone, now_ms).await?;
    }
    Ok(Reapplied {
        tombstones: all.len(),
        erased: back.len(),
    })
}
