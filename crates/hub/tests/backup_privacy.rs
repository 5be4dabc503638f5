//! Backups and erasure a data-protection officer signs (issue 45): a backup is encrypted to
//! the clinic's key (age) and restores only with it — a wrong key, a truncated and an altered
//! file are refused by name and nothing is restored; Debian's `age` decrypts it; an erased
//! patient never comes back from an older backup (tombstones re-applied by the restore and at
//! start); SQLite keeps no byte of an erased pseudonym in its file or WAL; and a session or
//! station arriving during an erasure's revocation grace is erased with the rest.

mod common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use hub::backup::{RestoreFrom, Restored, Sealing};
use hub::clinic::Clinic;
use hub::db::Db;
use hub::patient_data::tombstones;
use netlink::Summary;
use sqlx::Row;

const FP1: &str = "1111111111111111111111111111111111111111111111111111111111111111";
const FP2: &str = "2222222222222222222222222222222222222222222222222222222222222222";
const FP3: &str = "3333333333333333333333333333333333333333333333333333333333333333";

/// The pseudonym erased: long and unusual, so that its bytes are found only where it is.
const ERASED: &str = "P-ZQXJ-ERASED-7731";
const KEPT: &str = "P-KEPT-0042";

/// Every file under `dir` (relative path → size), to see that a refusal changed nothing.
fn listing(dir: &Path) -> BTreeMap<String, u64> {
    let mut out = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p.clone());
            }
            let rel = p.strip_prefix(dir).unwrap().display().to_string();
            out.insert(rel, p.metadata().unwrap().len());
        }
    }
    out
}

/// A new clinic at `tmp/clinic` with patients [`ERASED`] (station st-1, session s-1 of three
/// summaries, a recording) and [`KEPT`] (station st-2, session s-2, a recording).
async fn clinic(tmp: &Path) -> (Clinic, Db) {
    let clinic = Clinic::at(tmp.join("clinic"));
    clinic
        .init(
            "dpo@clinic.example",
            &["localhost".into()],
            None,
            common::T0,
        )
        .await
        .unwrap();
    let db = clinic.open_db(None).await.unwrap();
    for (pseudonym, station, session, fp) in
        [(ERASED, "st-1", "s-1", FP1), (KEPT, "st-2", "s-2", FP2)]
    {
        let p = db.add_patient(pseudonym, None, common::T0).await.unwrap();
        db.audit("cli", "add_patient", &p.id, pseudonym, common::T0)
            .await
            .unwrap();
        db.add_station(station, &p.id, fp, common::T0)
            .await
            .unwrap();
        db.open_session(&common::hello(station, &p.id, session), common::T0)
            .await
            .unwrap();
        let summaries: Vec<Summary> = (1..=3).map(|seq| Summary::example(session, seq)).collect();
        db.store_summaries(&summaries, common::T0).await.unwrap();
        let dir = clinic.dir().join("recordings").join(station);
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(
            dir.join(format!("{session}.mcap")),
            format!("{pseudonym}'s recording"),
        )
        .unwrap();
    }
    (clinic, db)
}

/// A new key pair: the identity file written under `tmp`, and the sealing to its recipient.
fn key_pair(tmp: &Path, name: &str) -> (PathBuf, Sealing) {
    let (identity, recipient) = hub::backup::new_key_pair();
    let path = tmp.join(name);
    std::fs::write(&path, identity).unwrap();
    let sealing = Sealing::to_recipients(&[recipient], tmp).unwrap();
    (path, sealing)
}

async fn restore(archive: &Path, data: &Path, from: RestoreFrom<'_>) -> Result<Restored, String> {
    hub::backup::restore(archive, data, from, common::T0 + 1)
        .await
        .map_err(|e| e.to_string())
}

/// The count `sql` answers, `$1` bound to `id` when it has one.
async fn rows(db: &Db, sql: &'static str, id: &str) -> i64 {
    let mut q = sqlx::query(sql);
    if sql.contains("$1") {
        q = q.bind(id.to_owned());
    }
    q.fetch_one(db.pool()).await.unwrap().get::<i64, _>(0)
}

/// Occurrences of `needle` in `haystack`.
fn count(haystack: &[u8], needle: &[u8]) -> usize {
    haystack
        .windows(needle.len())
        .filter(|w| *w == needle)
        .count()
}

#[tokio::test]
async fn a_backup_without_a_clinic_key_is_refused_saying_how_to_make_one() {
    let tmp = tempfile::tempdir().unwrap();
    let e = Sealing::to_recipients(&[], tmp.path())
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("telerehab hub backup-key"), "{e}");
    assert!(e.contains("--unencrypted"), "{e}");
    let e = Sealing::to_recipients(&["age1notakey".into()], tmp.path())
        .err()
        .unwrap()
        .to_string();
    assert!(
        e.contains("backup_recipients") && e.contains("\"age1notakey\""),
        "{e}"
    );
}

#[tokio::test]
async fn an_encrypted_backup_holds_nothing_in_clear_and_restores_only_with_its_identity() {
    let tmp = tempfile::tempdir().unwrap();
    let (clinic, db) = clinic(tmp.path()).await;
    db.close().await;
    // A recording zstd cannot shrink (a fixed-seed xorshift), so the file spans several of
    // age's 64 KiB chunks.
    let mut x = 0x9E37_79B9_7F4A_7C15_u64;
    let noise: Vec<u8> = (0..200_000)
        .map(|_| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 24) as u8
        })
        .collect();
    std::fs::write(clinic.dir().join("recordings/st-1/s-0.mcap"), noise).unwrap();
    let (identity, sealing) = key_pair(tmp.path(), "clinic-backup.key");
    let (other, _) = key_pair(tmp.path(), "another-clinic.key");
    let archive = tmp.path().join("clinic.tar.zst.age");
    hub::backup::backup(&clinic, None, &archive, &sealing)
        .await
        .unwrap();
    let bytes = std::fs::read(&archive).unwrap();
    assert!(bytes.starts_with(b"age-encryption.org/v1\n"));
    for secret in [&b"PRIVATE KEY"[..], ERASED.as_bytes(), b"'s recording"] {
        assert_eq!(
            count(&bytes, secret),
            0,
            "{:?} in clear",
            String::from_utf8_lossy(secret)
        );
    }
    let parent = tmp.path().join("restores");
    std::fs::create_dir(&parent).unwrap();
    let before = listing(&parent);
    let target = parent.join("clinic");
    let damaged = |name: &str, f: &dyn Fn(&mut Vec<u8>)| {
        let mut b = bytes.clone();
        f(&mut b);
        let path = tmp.path().join(format!("{name}.tar.zst.age"));
        std::fs::write(&path, b).unwrap();
        path
    };
    let len = bytes.len();
    let cases: Vec<(&str, PathBuf, Option<&Path>, &str)> = vec![
        (
            "no identity",
            archive.clone(),
            None,
            "is encrypted: name the clinic's backup identity file",
        ),
        (
            "another clinic's key",
            archive.clone(),
            Some(&other),
            "does not hold the key",
        ),
        (
            "a file cut in half",
            damaged("half", &|b| b.truncate(len / 2)),
            Some(&identity),
            "cut short or altered",
        ),
        (
            "a file cut at a chunk's end",
            // The header (up to its MAC line), the 16-byte nonce and one whole 64 KiB chunk.
            damaged("one-chunk", &|b| {
                let header = b.windows(4).position(|w| w == b"--- ").unwrap();
                let header_end = header + b[header..].iter().position(|c| *c == b'\n').unwrap() + 1;
                b.truncate(header_end + 16 + 65_536 + 16);
            }),
            Some(&identity),
            "truncated",
        ),
        (
            "a byte changed in the last chunk",
            damaged("last-chunk-changed", &|b| b[len - 40] ^= 1),
            Some(&identity),
            "altered",
        ),
        (
            "a byte changed in the header's MAC",
            damaged("mac-changed", &|b| {
                let mac = b.windows(4).position(|w| w == b"--- ").unwrap() + 6;
                b[mac] = if b[mac] == b'A' { b'B' } else { b'A' };
            }),
            Some(&identity),
            "header",
        ),
    ];
    assert!(
        len > 2 * 65_536,
        "the backup spans several chunks ({len} bytes)"
    );
    for (what, file, identity, says) in cases {
        let from = RestoreFrom {
            identity,
            ..Default::default()
        };
        let e = restore(&file, &target, from)
            .await
            .err()
            .unwrap_or_else(|| panic!("{what} restored"));
        eprintln!("{what}: {e}");
        assert!(e.contains(says), "{what}: {e}");
        assert_eq!(listing(&parent), before, "{what}: something was restored");
    }
    let from = RestoreFrom {
        identity: Some(&identity),
        ..Default::default()
    };
    let r = restore(&archive, &target, from).await.unwrap();
    assert!(r.encrypted);
    assert_eq!(r.manifest.format, hub::backup::BACKUP_FORMAT);
    assert_eq!(
        std::fs::read(target.join("recordings/st-1/s-1.mcap")).unwrap(),
        format!("{ERASED}'s recording").as_bytes()
    );
}

#[tokio::test]
async fn debians_age_tool_decrypts_a_backup_with_the_identity_file() {
    let tmp = tempfile::tempdir().unwrap();
    let (clinic, db) = clinic(tmp.path()).await;
    db.close().await;
    let (identity, sealing) = key_pair(tmp.path(), "clinic-backup.key");
    let archive = tmp.path().join("clinic.tar.zst.age");
    hub::backup::backup(&clinic, None, &archive, &sealing)
        .await
        .unwrap();
    let out = std::process::Command::new("age")
        .arg("-d")
        .arg("-i")
        .arg(&identity)
        .arg(&archive)
        .output()
        .expect("Debian's age (apt install age; scripts/setup.sh installs it)");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut tar = tar::Archive::new(zstd::Decoder::new(out.stdout.as_slice()).unwrap());
    let names: Vec<String> = tar
        .entries()
        .unwrap()
        .map(|e| e.unwrap().path().unwrap().display().to_string())
        .collect();
    for name in [
        "MANIFEST.json",
        "tls/ca.key",
        "erasures.ndjson",
        "database/hub.db",
    ] {
        assert!(names.iter().any(|n| n == name), "{name} not in {names:?}");
    }
    assert!(
        names.iter().any(|n| n == "recordings/st-1/s-1.mcap"),
        "{names:?}"
    );
}

/// What the restored clinic at `data` still holds of the patient `id`: their rows (patient,
/// sessions, summaries, stations, audit entries other than the erasure's own), and whether
/// their recordings' directory exists.
async fn remains(data: &Path, id: &str) -> (i64, i64, i64, i64, i64, bool) {
    let db = Clinic::at(data).open_db(None).await.unwrap();
    let found = (
        rows(&db, "SELECT COUNT(*) FROM patients WHERE id = $1", id).await,
        rows(
            &db,
            "SELECT COUNT(*) FROM sessions WHERE patient_id = $1",
            id,
        )
        .await,
        rows(
            &db,
            "SELECT COUNT(*) FROM summaries WHERE session_id = 's-1'",
            id,
        )
        .await,
        rows(
            &db,
            "SELECT COUNT(*) FROM stations WHERE patient_id = $1",
            id,
        )
        .await,
        rows(
            &db,
            "SELECT COUNT(*) FROM audit_log WHERE target = $1 AND action NOT LIKE 'erase_patient%'",
            id,
        )
        .await,
        data.join("recordings/st-1").exists(),
    );
    db.close().await;
    found
}

/// A clinic backed up (clear, `older.tar.zst` in `tmp`) and then [`ERASED`] erased; its
/// erased patient's internal id.
async fn backed_up_then_erased(tmp: &Path) -> (Clinic, String, PathBuf) {
    let (clinic, db) = clinic(tmp).await;
    let erased_id = db.patient_by_pseudonym(ERASED).await.unwrap().unwrap().id;
    let older = tmp.join("older.tar.zst");
    hub::backup::backup(&clinic, None, &older, &Sealing::Clear)
        .await
        .unwrap();
    hub::patient_data::erase_after(&clinic, &db, ERASED, common::T0 + 5, async {})
        .await
        .unwrap();
    db.close().await;
    (clinic, erased_id, older)
}

#[tokio::test]
async fn an_erased_patient_does_not_come_back_when_an_older_backup_is_restored() {
    let tmp = tempfile::tempdir().unwrap();
    let (clinic, erased_id, older) = backed_up_then_erased(tmp.path()).await;
    let ledger = tombstones::ledger_path(&clinic);
    let written = std::fs::read(&ledger).unwrap();
    assert_eq!(
        count(&written, ERASED.as_bytes()),
        0,
        "the ledger holds the pseudonym"
    );
    assert_eq!(count(&written, erased_id.as_bytes()), 1);

    // On this machine (the clinic's ledger supplied): the patient is erased again.
    let restored = tmp.path().join("restored");
    let from = RestoreFrom {
        erasures: std::slice::from_ref(&ledger),
        ..Default::default()
    };
    let r = restore(&older, &restored, from).await.unwrap();
    assert_eq!((r.erasures.erased, r.erasures.tombstones), (1, 1));
    assert_eq!(
        r.manifest.rows_of("patients"),
        2,
        "the backup itself held them"
    );
    assert_eq!(remains(&restored, &erased_id).await, (0, 0, 0, 0, 0, false));
    let kept = Clinic::at(&restored).open_db(None).await.unwrap();
    let kept_patient = kept.patient_by_pseudonym(KEPT).await.unwrap().unwrap();
    assert_eq!(
        remains(&restored, &kept_patient.id).await.1,
        1,
        "others intact"
    );
    assert!(restored.join("recordings/st-2/s-2.mcap").is_file());
    kept.close().await;

    // A later backup carries the tombstone in its ledger and its database.
    let later = tmp.path().join("later.tar.zst");
    hub::backup::backup(&Clinic::at(&restored), None, &later, &Sealing::Clear)
        .await
        .unwrap();
    let again = tmp.path().join("again");
    let r = restore(&later, &again, RestoreFrom::default())
        .await
        .unwrap();
    assert_eq!((r.erasures.erased, r.erasures.tombstones), (0, 1));
    assert_eq!(
        std::fs::read(again.join("erasures.ndjson")).unwrap(),
        written,
        "the ledger came along"
    );
}

#[tokio::test]
async fn on_a_new_machine_the_supplied_ledger_is_reapplied_once_at_the_next_start() {
    let tmp = tempfile::tempdir().unwrap();
    let (clinic, erased_id, older) = backed_up_then_erased(tmp.path()).await;
    // Restored without the ledger: the backup predates the erasure and knows nothing of it.
    let restored = tmp.path().join("restored");
    let r = restore(&older, &restored, RestoreFrom::default())
        .await
        .unwrap();
    assert_eq!((r.erasures.erased, r.erasures.tombstones), (0, 0));
    assert_eq!(remains(&restored, &erased_id).await.0, 1);
    // The operator then puts the ledger kept off the machine in place; the hub's start
    // re-applies it, once.
    std::fs::copy(
        tombstones::ledger_path(&clinic),
        restored.join("erasures.ndjson"),
    )
    .unwrap();
    let restored_clinic = Clinic::at(&restored);
    let db = restored_clinic.open_db(None).await.unwrap();
    let first = tombstones::reapply(&restored_clinic, &db, &[], common::T0 + 9)
        .await
        .unwrap();
    let second = tombstones::reapply(&restored_clinic, &db, &[], common::T0 + 10)
        .await
        .unwrap();
    db.close().await;
    assert_eq!((first.erased, second.erased, second.tombstones), (1, 0, 1));
    assert_eq!(remains(&restored, &erased_id).await, (0, 0, 0, 0, 0, false));
}

#[tokio::test]
async fn another_clinics_ledger_is_refused_and_nothing_is_erased() {
    let tmp = tempfile::tempdir().unwrap();
    let (clinic, db) = clinic(tmp.path()).await;
    let kept = db.patient_by_pseudonym(KEPT).await.unwrap().unwrap();
    let forged = tombstones::Tombstone {
        erased_patient_id: kept.id.clone(),
        pseudonym_hmac: "00".repeat(32),
        erased_at_ms: common::T0,
        erased_by: "cli".into(),
    };
    let e = tombstones::reapply(&clinic, &db, &[forged], common::T0)
        .await
        .unwrap_err()
        .to_string();
    assert!(e.contains("another clinic's"), "{e}");
    assert!(db.patient_by_pseudonym(KEPT).await.unwrap().is_some());
    db.close().await;
}

#[tokio::test]
async fn a_sqlite_erasure_leaves_no_byte_of_the_pseudonym_in_the_file_or_its_wal() {
    let tmp = tempfile::tempdir().unwrap();
    let (clinic, db) = clinic(tmp.path()).await;
    let file = clinic.dir().join("hub.db");
    let wal = clinic.dir().join("hub.db-wal");
    let found = || {
        let read = |p: &Path| std::fs::read(p).unwrap_or_default();
        count(&read(&file), ERASED.as_bytes()) + count(&read(&wal), ERASED.as_bytes())
    };
    assert!(found() > 0, "the pseudonym is stored before the erasure");
    hub::patient_data::erase_after(&clinic, &db, ERASED, common::T0 + 5, async {})
        .await
        .unwrap();
    // The hub still holds the database open (its connections, its WAL) while this is read.
    assert_eq!(
        found(),
        0,
        "the erased pseudonym's bytes remain in hub.db or hub.db-wal"
    );
    assert!(db.patient_by_pseudonym(KEPT).await.unwrap().is_some());
    db.close().await;
}

#[tokio::test]
async fn a_session_and_a_station_arriving_during_the_erasures_grace_are_erased_with_the_rest() {
    let tmp = tempfile::tempdir().unwrap();
    let (clinic, db) = clinic(tmp.path()).await;
    let patient = db.patient_by_pseudonym(ERASED).await.unwrap().unwrap();
    // During the grace (the station revoked, its connection not cut yet): a session whose
    // Hello was checked before the revocation is stored, with summaries, and a station
    // paired a moment before gets its row, with a session of its own.
    let late = async {
        let id = patient.id.as_str();
        sqlx::query(
            "INSERT INTO sessions (session_id, station_id, patient_id, exercise, \
             started_unix_ms, software_version, opened_at_ms) \
             VALUES ('s-late', 'st-1', $1, 'sine-road', $2, 'telerehab 0.1.0', $2)",
        )
        .bind(id)
        .bind(common::T0)
        .execute(db.pool())
        .await
        .unwrap();
        let summaries: Vec<Summary> = (1..=2).map(|seq| Summary::example("s-late", seq)).collect();
        db.store_summaries(&summaries, common::T0).await.unwrap();
        db.add_station("st-new", id, FP3, common::T0).await.unwrap();
        db.open_session(&common::hello("st-new", id, "s-new"), common::T0)
            .await
            .unwrap();
    };
    let covered = hub::patient_data::erase_after(&clinic, &db, ERASED, common::T0 + 5, late)
        .await
        .unwrap();
    assert_eq!(
        covered.rows_of("sessions"),
        3,
        "s-1, s-late and s-new: {covered:?}"
    );
    assert_eq!(covered.rows_of("stations"), 2);
    let id = patient.id.as_str();
    let sessions = "SELECT COUNT(*) FROM sessions WHERE patient_id = $1 \
                    OR session_id IN ('s-1', 's-late', 's-new')";
    assert_eq!(rows(&db, sessions, id).await, 0);
    let summaries = "SELECT COUNT(*) FROM summaries WHERE session_id IN ('s-1', 's-late')";
    assert_eq!(rows(&db, summaries, "").await, 0);
    let stations = "SELECT COUNT(*) FROM stations WHERE patient_id = $1";
    assert_eq!(rows(&db, stations, id).await, 0);
    // And a session arriving after the erasure is refused (its station is gone).
    let e = db
        .open_session(
            &common::hello("st-new", &patient.id, "s-after"),
            common::T0 + 6,
        )
        .await
        .unwrap_err();
    assert!(e.to_string().contains("st-new"), "{e}");
    db.close().await;
}

#[tokio::test]
async fn a_ledger_line_a_crash_cut_short_is_left_out_and_a_damaged_whole_line_is_named() {
    let tmp = tempfile::tempdir().unwrap();
    let (clinic, _, _) = backed_up_then_erased(tmp.path()).await;
    let ledger = tombstones::ledger_path(&clinic);
    let whole = tombstones::read_ledger(&ledger).unwrap();
    assert_eq!(whole.len(), 1);
    // A crash mid-append: the erasure it began had deleted nothing yet.
    let mut cut = std::fs::read(&ledger).unwrap();
    cut.extend_from_slice(br#"{"erased_patient_id":"p-"#);
    std::fs::write(&ledger, &cut).unwrap();
    assert_eq!(tombstones::read_ledger(&ledger).unwrap().len(), 1);
    // The next erasure's tombstone replaces the cut line rather than joining it.
    tombstones::append_to_ledger(&ledger, &whole).unwrap();
    assert_eq!(
        tombstones::read_ledger(&ledger).unwrap(),
        [whole.clone(), whole].concat()
    );
    // A whole line that is not a tombstone is refused by its number.
    cut.extend_from_slice(b"\n");
    std::fs::write(&ledger, &cut).unwrap();
    let e = tombstones::read_ledger(&ledger).unwrap_err().to_string();
    assert!(e.contains("line 2 is not an erasure tombstone"), "{e}");
}
