//! Recordings in a real S3 store (SeaweedFS, started by each test: `common::s3`): a station's
//! upload over the link lands as one object whose SHA-256 is the file's, the console replays it
//! from there, a patient's export, erasure and the backup reach it, and a store that is gone
//! when an upload completes refuses the station, which completes the upload at its next
//! attempt without sending it again — nothing half-written listed in between; the hub's
//! readiness names a store that does not answer.

mod common;

use std::io::Read;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use axum::body::Body;
use axum::http::{Request, StatusCode, header};
use http_body_util::BodyExt;
use hub::clinic::Clinic;
use hub::recordings::RecordingStore;
use netlink::upload::{UploadError, file_sha256, upload_recording};
use netlink::{Hello, HubStore, TherapistConfig, TherapistServer};
use tower::ServiceExt;

use common::s3::SeaweedS3;
use common::{T0, honest_recording};

/// `len` deterministic bytes (a fixed LCG) in `dir/name`, standing in for a recording.
fn recording_of(dir: &Path, name: &str, len: usize) -> PathBuf {
    let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
    let bytes: Vec<u8> = (0..len)
        .map(|_| {
            x = x.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            (x >> 56) as u8
        })
        .collect();
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

/// The station link's store as `hub serve` has it for recordings (`DbStore` asks the same
/// [`RecordingStore`] calls), sessions kept in files: the link's tests run without TLS, which
/// `DbStore`'s admission requires.
struct S3Hub {
    files: netlink::FileStore,
    recordings: RecordingStore,
}

impl HubStore for S3Hub {
    fn open_session<'a>(
        &'a self,
        hello: &'a Hello,
    ) -> netlink::BoxFuture<'a, Result<Box<dyn netlink::SessionStore>, netlink::Refusal>> {
        self.files.open_session(hello)
    }

    fn recording_path(&self, hello: &Hello) -> Option<PathBuf> {
        Some(
            self.recordings
                .staging_path(&hello.station_id, &hello.session_id),
        )
    }

    fn recording_held<'a>(
        &'a self,
        hello: &'a Hello,
        _path: &'a Path,
    ) -> netlink::BoxFuture<'a, Result<Option<(u64, String)>, netlink::NetlinkError>> {
        Box::pin(async move {
            self.recordings
                .held(&hello.station_id, &hello.session_id)
                .await
                .map_err(|e| netlink::NetlinkError::Store(e.to_string()))
        })
    }

    fn keep_recording<'a>(
        &'a self,
        hello: &'a Hello,
        part: &'a Path,
        _path: &'a Path,
    ) -> netlink::BoxFuture<'a, Result<(), netlink::NetlinkError>> {
        Box::pin(async move {
            self.recordings
                .keep(&hello.station_id, &hello.session_id, part)
                .await
                .map_err(|e| netlink::NetlinkError::Store(e.to_string()))
        })
    }
}

async fn link_to(s3: &SeaweedS3, data: &Path) -> (TherapistServer, RecordingStore) {
    let recordings = s3.store(data);
    let store = Arc::new(S3Hub {
        files: netlink::FileStore::new(data.join("sessions")),
        recordings: recordings.clone(),
    });
    let config = TherapistConfig::new("127.0.0.1:0".parse().unwrap(), data.join("sessions"), None);
    let server = TherapistServer::bind_with_store(config, store)
        .await
        .unwrap()
        .0;
    (server, recordings)
}

/// Every file under `dir`, relative.
fn files_under(dir: &Path) -> Vec<String> {
    let mut out = Vec::new();
    let mut dirs = vec![dir.to_path_buf()];
    while let Some(d) = dirs.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in entries {
            let p = e.unwrap().path();
            if p.is_dir() {
                dirs.push(p);
            } else {
                out.push(p.strip_prefix(dir).unwrap().display().to_string());
            }
        }
    }
    out.sort();
    out
}

const MB: u64 = 1 << 20;

/// Bytes of the `.part` files in `dir`.
fn part_bytes(dir: &Path) -> u64 {
    std::fs::read_dir(dir)
        .map(|entries| {
            entries
                .filter_map(Result::ok)
                .filter(|e| e.path().extension().is_some_and(|x| x == "part"))
                .filter_map(|e| e.metadata().ok())
                .map(|m| m.len())
                .sum()
        })
        .unwrap_or(0)
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_upload_lands_in_s3_as_one_object_whose_sha256_matches_and_leaves_no_part_behind() {
    let s3 = SeaweedS3::start().await;
    let tmp = tempfile::tempdir().unwrap();
    let data = tmp.path().join("hub");
    let (server, store) = link_to(&s3, &data).await;
    // 20 MB: three parts of the multipart upload.
    let file = recording_of(tmp.path(), "session.mcap", 20 * MB as usize);
    let (size, sha) = file_sha256(&file).unwrap();
    let hello = common::hello("st-s3", "p-1", "s-s3");
    let addr = server.local_addr().to_string();
    let up = upload_recording(&addr, None, hello.clone(), &file, u64::MAX)
        .await
        .unwrap();
    assert_eq!(up.sent_bytes, size);
    assert_eq!(
        store.held("st-s3", "s-s3").await.unwrap(),
        Some((size, sha))
    );
    let listed = store.finished().await.unwrap();
    assert_eq!(listed.len(), 1, "{listed:?}");
    assert_eq!(listed[0].name, "st-s3/s-s3.mcap");
    assert_eq!(listed[0].size, size);
    // Nothing of it on the hub's disk: the part went to the store and was removed.
    assert_eq!(files_under(&data.join("recordings")), Vec::<String>::new());
    // Stored once: a second upload is answered complete at once.
    let again = upload_recording(&addr, None, hello, &file, u64::MAX)
        .await
        .unwrap();
    assert_eq!(again.sent_bytes, 0);
    assert_eq!(store.finished().await.unwrap().len(), 1);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_store_gone_when_an_upload_completes_refuses_it_and_the_next_attempt_completes_it() {
    let mut s3 = SeaweedS3::start().await;
    let tmp = tempfile::tempdir().unwrap();
    let data = tmp.path().join("hub");
    let (server, store) = link_to(&s3, &data).await;
    let file = recording_of(tmp.path(), "session.mcap", 12 * MB as usize);
    let (size, sha) = file_sha256(&file).unwrap();
    let hello = common::hello("st-gone", "p-1", "s-gone");
    let addr = server.local_addr().to_string();
    // 12 MB at 4 MB/s: the store is killed once the hub has taken the first MB (past the
    // upload's start, which asks the store whether it holds the recording).
    let upload = {
        let (addr, hello, file) = (addr.clone(), hello.clone(), file.clone());
        tokio::spawn(async move { upload_recording(&addr, None, hello, &file, 4 * MB).await })
    };
    let staging = data.join("recordings").join("st-gone");
    while part_bytes(&staging) < MB {
        assert!(
            !upload.is_finished(),
            "the upload ended before the store was stopped"
        );
        tokio::time::sleep(std::time::Duration::from_millis(20)).await;
    }
    s3.stop();
    let refused = upload.await.unwrap().unwrap_err();
    let UploadError::Refused(why) = &refused else {
        panic!("not a refusal: {refused}");
    };
    assert!(why.contains("received whole but not stored"), "{why}");
    // The hub keeps the whole verified part for the next attempt.
    let parts = files_under(&data.join("recordings"));
    assert_eq!(parts.len(), 1, "{parts:?}");
    assert!(parts[0].ends_with(".part"), "{parts:?}");
    assert_eq!(part_bytes(&staging), size);
    // While the store stays away, an attempt is refused at its start, the part kept.
    let refused = upload_recording(&addr, None, hello.clone(), &file, u64::MAX)
        .await
        .unwrap_err();
    assert!(
        matches!(&refused, UploadError::Refused(why) if why.contains("cannot tell whether")),
        "{refused}"
    );
    assert_eq!(part_bytes(&staging), size);
    s3.restart().await;
    // Nothing half-written is listed as stored.
    assert_eq!(store.finished().await.unwrap(), Vec::new());
    assert_eq!(store.held("st-gone", "s-gone").await.unwrap(), None);
    let done = upload_recording(&addr, None, hello, &file, u64::MAX)
        .await
        .unwrap();
    assert_eq!(done.sent_bytes, 0, "the part on the hub's disk was kept");
    assert_eq!(
        store.held("st-gone", "s-gone").await.unwrap(),
        Some((size, sha))
    );
    assert_eq!(files_under(&data.join("recordings")), Vec::<String>::new());
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_recording_in_s3_replays_on_the_console_to_its_end() {
    let s3 = SeaweedS3::start().await;
    let tmp = tempfile::tempdir().unwrap();
    let store = s3.store(&tmp.path().join("hub"));
    let in_state = store.clone();
    let f = common::fixture::Fixture::new(move |s| s.with_recordings(in_state)).await;
    let station = "st-replay";
    let fp = format!("{:0>64}", "ab");
    f.db.add_station(station, &f.p_ada.id, &fp, T0)
        .await
        .unwrap();
    f.db.open_session(&common::hello(station, &f.p_ada.id, "s-replay"), T0)
        .await
        .unwrap();
    let bytes = honest_recording(3);
    let part = tmp.path().join("s-replay.part");
    std::fs::write(&part, &bytes).unwrap();
    store.keep(station, "s-replay", &part).await.unwrap();
    f.db.put_recording(&hub::db::Recording {
        session_id: "s-replay".into(),
        sha256: "0".repeat(64),
        size_bytes: bytes.len() as i64,
        received_bytes: bytes.len() as i64,
        path: store.location(station, "s-replay"),
        complete: true,
        last_part_ms: None,
    })
    .await
    .unwrap();
    let cookie = common::api::login(&f.app, "ada@clinic.example").await;
    let request = Request::builder()
        .uri("/api/sessions/s-replay/replay")
        .header(header::COOKIE, cookie)
        .body(Body::empty())
        .unwrap();
    let response = f.app.clone().oneshot(request).await.unwrap();
    assert_eq!(response.status(), StatusCode::OK);
    let text = String::from_utf8(
        response
            .into_body()
            .collect()
            .await
            .unwrap()
            .to_bytes()
            .to_vec(),
    )
    .unwrap();
    let lines: Vec<serde_json::Value> = text
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines[0]["exercise"], "sine-road");
    let end = lines.last().unwrap();
    assert_eq!(end["end"], true, "{end}");
    assert_eq!(end["total_frames"], 60);
}

/// The entries of a `.tar.zst` archive: name → bytes.
fn archive_entries(path: &Path) -> std::collections::BTreeMap<String, Vec<u8>> {
    let decoder = zstd::Decoder::new(std::fs::File::open(path).unwrap()).unwrap();
    let mut archive = tar::Archive::new(decoder);
    archive
        .entries()
        .unwrap()
        .map(|e| {
            let mut e = e.unwrap();
            let name = e.path().unwrap().display().to_string();
            let mut bytes = Vec::new();
            e.read_to_end(&mut bytes).unwrap();
            (name, bytes)
        })
        .collect()
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_backup_export_erasure_and_restore_reach_the_recordings_in_s3_and_an_erased_one_stays_erased()
 {
    let s3 = SeaweedS3::start().await;
    let tmp = tempfile::tempdir().unwrap();
    let clinic = Clinic::at(tmp.path().join("clinic"));
    clinic
        .init("ana@clinic.example", &["localhost".into()], None, T0)
        .await
        .unwrap();
    let mut config = clinic.config().unwrap();
    config.recordings = Some(s3.config());
    std::fs::write(
        clinic.dir().join("hub.toml"),
        toml::to_string(&config).unwrap(),
    )
    .unwrap();
    let store = clinic.recordings().unwrap();
    assert!(store.is_s3());
    let db = hub::Db::open_sqlite(&clinic.dir().join("hub.db"))
        .await
        .unwrap();
    let patient = db.add_patient("p-erase", None, T0).await.unwrap();
    db.add_station("st-erase", &patient.id, &format!("{:0>64}", "cd"), T0)
        .await
        .unwrap();
    let part = tmp.path().join("one.part");
    let bytes = honest_recording(1);
    std::fs::write(&part, &bytes).unwrap();
    store.keep("st-erase", "s-erase", &part).await.unwrap();

    let backup = tmp.path().join("backup.tar.zst");
    let manifest = hub::backup::backup(&clinic, None, &backup, &hub::backup::Sealing::Clear)
        .await
        .unwrap();
    assert_eq!(
        manifest.recordings.keys().collect::<Vec<_>>(),
        ["st-erase/s-erase.mcap"]
    );
    let entries = archive_entries(&backup);
    assert_eq!(entries["recordings/st-erase/s-erase.mcap"], bytes);

    let export = tmp.path().join("export.tar.zst");
    let what = hub::patient_data::export(&clinic, &db, "p-erase", &export, T0)
        .await
        .unwrap();
    assert_eq!(what.recording_files, 1);
    assert_eq!(what.recording_bytes, bytes.len() as u64);
    assert_eq!(
        archive_entries(&export)["recordings/st-erase/s-erase.mcap"],
        bytes
    );

    let erased = hub::patient_data::erase(&clinic, &db, "p-erase", T0)
        .await
        .unwrap();
    assert_eq!(erased.recording_files, 1);
    assert_eq!(store.finished().await.unwrap(), Vec::new());
    assert_eq!(store.held("st-erase", "s-erase").await.unwrap(), None);

    // A restore of the backup made before the erasure, on a machine whose `hub.toml` (the
    // backup's) names the store: the recording goes back into S3, not into the data directory…
    let sha = hub_store::db::hex(&<sha2::Sha256 as sha2::Digest>::digest(&bytes));
    let restore = |data: PathBuf, erasures: Vec<PathBuf>| {
        let backup = backup.clone();
        async move {
            let from = hub::backup::RestoreFrom {
                erasures: &erasures,
                ..Default::default()
            };
            hub::backup::restore(&backup, &data, from, T0)
                .await
                .unwrap();
            data
        }
    };
    let restored = restore(tmp.path().join("restored"), Vec::new()).await;
    assert_eq!(
        store.held("st-erase", "s-erase").await.unwrap(),
        Some((bytes.len() as u64, sha))
    );
    assert!(
        !files_under(&restored.join("recordings"))
            .iter()
            .any(|f| f.ends_with(".mcap")),
        "{:?}",
        files_under(&restored)
    );
    // …and with the clinic's erasure ledger the erased patient's recording does not come back.
    let ledger = clinic
        .dir()
        .join(hub::patient_data::tombstones::LEDGER_FILE);
    restore(tmp.path().join("restored-with-ledger"), vec![ledger]).await;
    assert_eq!(store.held("st-erase", "s-erase").await.unwrap(), None);
}

/// The hub's readiness asks the S3 store too: ready while SeaweedFS answers, 503-worthy
/// ("recording store: …") once it is gone — within the check's own deadline, not the store
/// client's 5 s of retries — and ready again when it is back.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn readiness_names_an_s3_store_that_does_not_answer_and_is_ready_again_when_it_does() {
    let mut s3 = SeaweedS3::start().await;
    let tmp = tempfile::tempdir().unwrap();
    let store = s3.store(&tmp.path().join("hub"));
    let (db, _db_dir) = common::sqlite_db().await;
    let readiness =
        |store: &RecordingStore| hub::web::Readiness::new(db.clone(), None, Some(store.clone()));
    assert_eq!(readiness(&store).not_ready().await, Vec::<String>::new());

    s3.stop();
    let asked = std::time::Instant::now();
    let problems = readiness(&store).not_ready().await;
    let took = asked.elapsed();
    assert_eq!(problems.len(), 1, "{problems:?}");
    assert!(problems[0].starts_with("recording store: "), "{problems:?}");
    // Answered before the store client's own retries would have given up: the limit a
    // balancer's probe must beat.
    let retries_give_up = std::time::Duration::from_secs(s3.config().requests.retry_timeout_s);
    assert!(hub::web::READY_STORE_TIMEOUT < retries_give_up);
    assert!(took < retries_give_up, "{took:?}");

    s3.restart().await;
    assert_eq!(readiness(&store).not_ready().await, Vec::<String>::new());
}
