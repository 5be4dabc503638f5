//! `hub restore` trusts nothing in the archive: crafted backups — a manifest naming
//! `/etc/hostname`, `/dev/zero`, `../x` or a recording the archive does not hold, an unlisted
//! entry declaring 1 GiB, a recording whose size or content is not the manifest's, a
//! database declaring more than the disk holds — are each refused by name, and the target
//! directory is left exactly as it was (absent, or empty) with no staging directory beside
//! it. A good backup still restores.

mod common;

use std::collections::BTreeMap;
use std::io::{Read, Write};

use std::path::{Path, PathBuf};

use hub::clinic::Clinic;
use sha2::{Digest, Sha256};

/// Every file and directory under `dir` (relative paths), each file with its SHA-256.
fn listing(dir: &Path) -> BTreeMap<String, String> {
    let mut out = BTreeMap::new();
    let mut dirs = vec![dir.to_path_buf()];
    while let Some(d) = dirs.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in entries {
            let p = e.unwrap().path();
            let rel = p.strip_prefix(dir).unwrap().display().to_string();
            if p.is_dir() {
                out.insert(format!("{rel}/"), String::new());
                dirs.push(p);
            } else {
                let sha = Sha256::digest(std::fs::read(&p).unwrap());
                out.insert(rel, format!("{sha:x}"));
            }
        }
    }
    out
}

/// A clinic with one recording, backed up: the archive's entries, in order.
async fn good_backup(tmp: &Path) -> (PathBuf, Vec<(String, Vec<u8>)>) {
    let clinic = Clinic::at(tmp.join("clinic"));
    clinic
        .init(
            "ana@clinic.example",
            &["localhost".into()],
            None,
            common::T0,
        )
        .await
        .unwrap();
    let station = tmp.join("clinic/recordings/st-1");
    std::fs::create_dir_all(&station).unwrap();
    std::fs::write(station.join("s1.mcap"), b"a recording's bytes").unwrap();
    let out = tmp.join("good.tar.zst");
    hub::backup::backup(&clinic, None, &out, &hub::backup::Sealing::Clear)
        .await
        .unwrap();
    let decoder = zstd::Decoder::new(std::fs::File::open(&out).unwrap()).unwrap();
    let mut archive = tar::Archive::new(decoder);
    let entries = archive
        .entries()
        .unwrap()
        .map(|e| {
            let mut e = e.unwrap();
            let name = e.path().unwrap().display().to_string();
            let mut bytes = Vec::new();
            e.read_to_end(&mut bytes).unwrap();
            (name, bytes)
        })
        .collect();
    (out, entries)
}

/// Restores `archive` (clear, SQLite) into `data`.
async fn restore(archive: &Path, data: &Path) -> Result<hub::backup::Restored, hub::HubError> {
    hub::backup::restore(archive, data, Default::default(), common::T0).await
}

/// A tar header for `name` declaring `size` bytes.
fn header(name: &str, size: u64) -> tar::Header {
    let mut h = tar::Header::new_gnu();
    h.set_path(name).unwrap();
    h.set_size(size);
    h.set_mode(0o600);
    h.set_cksum();
    h
}

/// A `.tar.zst` of `entries`, then (when given) a header declaring `declared` bytes for
/// `name` followed by one block of data and the end of the stream: a truncated entry whose
/// size is only declared (nothing near 1 GiB is written to make it).
fn craft(entries: &[(String, Vec<u8>)], truncated: Option<(&str, u64)>) -> Vec<u8> {
    let encoder = zstd::Encoder::new(Vec::new(), 1).unwrap();
    let mut tar = tar::Builder::new(encoder);
    for (name, bytes) in entries {
        tar.append_data(
            &mut header(name, bytes.len() as u64),
            name,
            bytes.as_slice(),
        )
        .unwrap();
    }
    if let Some((name, declared)) = truncated {
        // The header says `declared`; one block follows (then the archive's end blocks,
        // read as the entry's data, and the stream ends).
        tar.append(&header(name, declared), &[7u8; 512][..])
            .unwrap();
    }
    let mut encoder = tar.into_inner().unwrap();
    encoder.flush().unwrap();
    encoder.finish().unwrap()
}

/// `entries` with the manifest changed by `change`.
fn with_manifest(
    entries: &[(String, Vec<u8>)],
    change: impl FnOnce(&mut serde_json::Value),
) -> Vec<(String, Vec<u8>)> {
    let mut out = entries.to_vec();
    let mut m: serde_json::Value = serde_json::from_slice(&out[0].1).unwrap();
    change(&mut m);
    out[0].1 = serde_json::to_vec(&m).unwrap();
    out
}

/// The crafted archives made from the entries of a good backup: what each is, its bytes,
/// and what its refusal must say.
fn crafted(good: &[(String, Vec<u8>)]) -> Vec<(&'static str, Vec<u8>, String)> {
    assert_eq!(good[0].0, "MANIFEST.json");
    let recording = "recordings/st-1/s1.mcap";
    let index = good.iter().position(|(n, _)| n == recording).unwrap();
    let sha_of = |b: &[u8]| format!("{:x}", Sha256::digest(b));
    let listed = |rel: &str, bytes: u64, sha: String| {
        let rel = rel.to_owned();
        move |m: &mut serde_json::Value| {
            m["recordings"][rel] = serde_json::json!({"bytes": bytes, "sha256": sha});
        }
    };
    let hostname_sha = sha_of(b"");
    let mut cases: Vec<(&str, Vec<u8>, String)> = vec![
        (
            "a manifest naming /etc/hostname",
            craft(
                &with_manifest(good, listed("/etc/hostname", 9, hostname_sha.clone())),
                None,
            ),
            "names a recording at \"/etc/hostname\"".into(),
        ),
        (
            "a manifest naming /dev/zero by ../",
            craft(
                &with_manifest(
                    good,
                    listed("../../../../../../dev/zero", 1 << 40, hostname_sha.clone()),
                ),
                None,
            ),
            "names a recording at \"../../../../../../dev/zero\"".into(),
        ),
        (
            "a manifest naming ../x",
            craft(
                &with_manifest(good, listed("../x", 1, hostname_sha.clone())),
                None,
            ),
            "names a recording at \"../x\"".into(),
        ),
        (
            "a manifest naming a recording the archive does not hold",
            craft(
                &with_manifest(good, listed("st-1/missing.mcap", 3, hostname_sha.clone())),
                None,
            ),
            "lists recordings/st-1/missing.mcap, which the archive does not hold".into(),
        ),
        (
            "a manifest listing a recording of 1 PiB",
            craft(
                &with_manifest(
                    good,
                    listed("st-1/huge.mcap", 1 << 50, hostname_sha.clone()),
                ),
                None,
            ),
            "the backup's recordings need 1125899906.8 MB".into(),
        ),
        (
            "an unlisted entry declaring 1 GiB",
            craft(good, Some(("recordings/st-1/big.mcap", 1 << 30))),
            "holds recordings/st-1/big.mcap, which its manifest does not list".into(),
        ),
        (
            "an unlisted file at the top",
            craft(
                &[good.to_vec(), vec![("hub.db".into(), b"x".to_vec())]].concat(),
                None,
            ),
            "holds hub.db, which its manifest does not list".into(),
        ),
        (
            "a recording declaring more than its manifest",
            craft(&good[..index], Some((recording, 1 << 30))),
            format!("{recording} is 1073741824 bytes in the archive and 19 in its manifest"),
        ),
        (
            "a database declaring 1 PiB",
            craft(
                &good
                    .iter()
                    .filter(|(n, _)| n == "MANIFEST.json")
                    .cloned()
                    .collect::<Vec<_>>(),
                Some(("database/hub.db", 1 << 50)),
            ),
            "database/hub.db in the backup declares 1125899906.8 MB".into(),
        ),
    ];
    let mut other = good.to_vec();
    other[index].1 = b"another recording!!".to_vec();
    cases.push((
        "a recording whose content is not the manifest's",
        craft(&other, None),
        format!("{recording} does not match its manifest's SHA-256"),
    ));
    let mut twice = good.to_vec();
    twice.push(good[index].clone());
    cases.push((
        "a recording held twice",
        craft(&twice, None),
        format!("holds {recording}, which its manifest does not list (or holds it twice)"),
    ));
    cases
}

#[tokio::test]
async fn crafted_backups_are_refused_by_name_and_leave_the_target_as_it_was() {
    let tmp = tempfile::tempdir().unwrap();
    let (_, good) = good_backup(tmp.path()).await;
    let cases = crafted(&good);
    let parent = tmp.path().join("restores");
    std::fs::create_dir(&parent).unwrap();
    std::fs::create_dir(parent.join("empty")).unwrap();
    let before = listing(&parent);
    let started = std::time::Instant::now();
    for (what, bytes, expected) in &cases {
        let archive = tmp.path().join("crafted.tar.zst");
        std::fs::write(&archive, bytes).unwrap();
        for target in ["absent", "empty"] {
            let case_started = std::time::Instant::now();
            let e = restore(&archive, &parent.join(target))
                .await
                .expect_err(what)
                .to_string();
            eprintln!(
                "{what} into an {target} directory: refused in {:.3} s: {e}",
                case_started.elapsed().as_secs_f64()
            );
            assert!(e.contains(expected.as_str()), "{what}: {e}");
            assert_eq!(
                listing(&parent),
                before,
                "{what}: the target and its parent changed"
            );
        }
    }
    eprintln!(
        "{} crafted archives, each into an absent and an empty target: {:.2} s",
        cases.len(),
        started.elapsed().as_secs_f64()
    );
}

#[tokio::test]
async fn a_good_backup_restores_into_an_absent_or_an_empty_directory_with_nothing_left_beside() {
    let tmp = tempfile::tempdir().unwrap();
    let (archive, _) = good_backup(tmp.path()).await;
    let recording = "recordings/st-1/s1.mcap";
    let parent = tmp.path().join("restores");
    std::fs::create_dir(&parent).unwrap();
    std::fs::create_dir(parent.join("empty")).unwrap();
    for target in ["absent", "empty"] {
        let r = restore(&archive, &parent.join(target)).await.unwrap();
        assert_eq!(r.manifest.recordings.len(), 1);
        assert!(!r.encrypted);
        let restored = parent.join(target);
        assert_eq!(
            std::fs::read(restored.join(recording)).unwrap(),
            b"a recording's bytes"
        );
        for file in ["hub.db", "hub.toml", "tls/ca.key", "tls/hub.crt"] {
            assert!(restored.join(file).is_file(), "{file}");
        }
        assert!(!restored.join("database").exists());
    }
    let names: Vec<String> = std::fs::read_dir(&parent)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names.len(), 2, "no staging directory left: {names:?}");
}

#[tokio::test]
async fn a_format_1_backup_from_before_encryption_still_restores() {
    let tmp = tempfile::tempdir().unwrap();
    let (_, good) = good_backup(tmp.path()).await;
    // Format 1: the same entries without the erasure ledger, never encrypted.
    let old: Vec<(String, Vec<u8>)> = with_manifest(&good, |m| m["format"] = 1.into())
        .into_iter()
        .filter(|(name, _)| name != "erasures.ndjson")
        .collect();
    assert_eq!(old.len() + 1, good.len(), "the good backup holds a ledger");
    let archive = tmp.path().join("format1.tar.zst");
    std::fs::write(&archive, craft(&old, None)).unwrap();
    let r = restore(&archive, &tmp.path().join("restored"))
        .await
        .unwrap();
    assert_eq!((r.manifest.format, r.encrypted), (1, false));
    assert_eq!(
        std::fs::read(tmp.path().join("restored/recordings/st-1/s1.mcap")).unwrap(),
        b"a recording's bytes"
    );
}
