//! `hub backup` while the hub serves a station streaming a session (refused until the clinic
//! has a backup key, then encrypted to it), and `hub restore --identity` into a new data
//! directory: every summary, regimen and recording stored before the backup is found again,
//! and the restored clinic serves. On SQLite and on PostgreSQL.

use std::path::Path;

use telerehab_tests::clinic::{
    Hub, clinic_on, fresh_postgres_database, ok, pair, prescribe, run_session, show_json, telerehab,
};
use telerehab_tests::spawn_real_time_session;

/// The finished recordings under a clinic's `recordings/`, by path below it, with their bytes.
fn recordings(data: &Path) -> Vec<(String, Vec<u8>)> {
    let mut found = Vec::new();
    let root = data.join("recordings");
    for station in std::fs::read_dir(&root).into_iter().flatten().flatten() {
        for file in std::fs::read_dir(station.path()).unwrap().flatten() {
            let p = file.path();
            if p.extension().is_some_and(|e| e == "mcap") {
                let rel = p.strip_prefix(&root).unwrap().display().to_string();
                found.push((rel, std::fs::read(&p).unwrap()));
            }
        }
    }
    found.sort();
    found
}

/// Each session's id and the summaries stored for it.
fn sessions(shown: &serde_json::Value) -> Vec<(String, u64)> {
    let mut s: Vec<_> = shown["sessions"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| {
            (
                s["session"]["session_id"].as_str().unwrap().to_owned(),
                s["summaries_stored"].as_u64().unwrap(),
            )
        })
        .collect();
    s.sort();
    s
}

/// Waits (30 s at most) until `done` holds, asking every 100 ms; fails naming `what`.
fn until(what: &str, done: impl Fn() -> bool) {
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(30);
    while !done() {
        assert!(
            std::time::Instant::now() < deadline,
            "waited 30 s for {what}"
        );
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
}

/// A clinic (on `db`, or SQLite) with a regimen and two finished sessions, backed up while a
/// third streams; restored into a new directory (and `restore_db`), which must hold all of it.
fn backup_under_load_restores_everything(db: Option<&str>, restore_db: Option<&str>) {
    let tmp = tempfile::tempdir().unwrap();
    let (data, code) = clinic_on(tmp.path(), db);
    let d = data.to_str().unwrap();
    prescribe(&data, "easy");
    let hub = Hub::serve(&data, "127.0.0.1:0");
    let home = tmp.path().join("station");
    pair(&hub, &code, &home);
    run_session(&home, "2");
    run_session(&home, "2");
    // The recordings reach the hub after their sessions: wait for both.
    until("both recordings uploaded", || recordings(&data).len() >= 2);
    let before = show_json(&data);
    let stored_before = recordings(&data);
    // Under load: a session streaming its summaries while the backup is taken, from when the
    // hub holds it.
    let mut streaming = spawn_real_time_session("4", |c| c.env("TELEREHAB_HOME", &home));
    let was = sessions(&before).len();
    until("the streaming session on the hub", || {
        sessions(&show_json(&data)).len() > was
    });
    let backup = tmp.path().join("clinic.tar.zst.age");
    let backup_args = [
        "hub",
        "backup",
        "--data",
        d,
        "--out",
        backup.to_str().unwrap(),
    ];
    // No clinic key yet: refused, saying how to make one.
    let refused = telerehab(&backup_args, None);
    assert!(!refused.status.success());
    let why = String::from_utf8_lossy(&refused.stderr);
    assert!(why.contains("hub backup-key"), "{why}");
    assert!(!backup.exists());
    let key = tmp.path().join("offline/clinic-backup.key");
    std::fs::create_dir_all(key.parent().unwrap()).unwrap();
    let k = key.to_str().unwrap();
    let said = ok(
        &["hub", "backup-key", "--data", d, "--identity-out", k],
        None,
    );
    assert!(said.contains("backups are now encrypted to age1"), "{said}");
    let said = ok(&backup_args, None);
    assert!(said.contains("recording files 2 "), "{said}");
    assert!(said.contains("encrypted to 1 recipients"), "{said}");
    assert!(streaming.wait().unwrap().success());
    hub.stop();

    let restored = tmp.path().join("restored");
    let r = restored.to_str().unwrap();
    let mut args = vec![
        "hub",
        "restore",
        "--from",
        backup.to_str().unwrap(),
        "--data",
        r,
        "--identity",
        k,
    ];
    if let Some(url) = restore_db {
        args.extend(["--db", url]);
    }
    let said = ok(&args, None);
    assert!(said.contains("checksum match the backup"), "{said}");
    assert!(said.contains("erasures re-applied: 0"), "{said}");
    let after = show_json(&restored);
    // Every session finished before the backup, with every summary; the one streaming is
    // there with what had arrived when the snapshot was taken.
    let (was, now) = (sessions(&before), sessions(&after));
    for s in &was {
        assert!(now.contains(s), "{s:?} missing from {now:?}");
    }
    assert_eq!(
        now.len(),
        was.len() + 1,
        "the streaming session too: {now:?}"
    );
    assert!(said.contains("regimen versions 1,"), "{said}");
    assert_eq!(
        recordings(&restored),
        stored_before,
        "every recording, byte for byte"
    );
    // The restored clinic serves: its CA and certificate came along.
    let again = Hub::serve(&restored, "127.0.0.1:0");
    again.stop();
    // A restore never mixes two clinics.
    let out = telerehab(&args, None);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("is not empty"));
}

#[test]
fn a_sqlite_clinic_backed_up_under_load_restores_every_summary_regimen_and_recording() {
    backup_under_load_restores_everything(None, None);
}

#[test]
fn a_postgresql_clinic_backed_up_under_load_restores_every_summary_regimen_and_recording() {
    let (Some(db), Some(empty)) = (fresh_postgres_database(), fresh_postgres_database()) else {
        return;
    };
    backup_under_load_restores_everything(Some(&db), Some(&empty));
}

#[test]
fn a_damaged_backup_is_refused_naming_the_file() {
    let tmp = tempfile::tempdir().unwrap();
    let (data, _) = clinic_on(tmp.path(), None);
    let backup = tmp.path().join("b.tar.zst");
    ok(
        &[
            "hub",
            "backup",
            "--data",
            data.to_str().unwrap(),
            "--out",
            backup.to_str().unwrap(),
            "--unencrypted",
        ],
        None,
    );
    let mut bytes = std::fs::read(&backup).unwrap();
    bytes.truncate(bytes.len() / 2);
    std::fs::write(&backup, &bytes).unwrap();
    let out = telerehab(
        &[
            "hub",
            "restore",
            "--from",
            backup.to_str().unwrap(),
            "--data",
            tmp.path().join("r").to_str().unwrap(),
        ],
        None,
    );
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("b.tar.zst"), "{err}");
}
