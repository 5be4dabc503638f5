//! Recording uploads on loopback: whole, resumed from a partial copy, refused when the bytes do
//! not match the announced SHA-256 (then whole again), idempotent once stored, and held to the
//! hub's own limits (size per session, bytes per station per day, rate) whatever the station
//! does.

use std::path::Path;

use netlink::upload::{file_sha256, upload_recording};
use netlink::{Hello, PROTOCOL_VERSION, TherapistConfig, TherapistServer};

fn hello() -> Hello {
    hello_for("s-up")
}

fn hello_for(session_id: &str) -> Hello {
    Hello {
        protocol_version: PROTOCOL_VERSION,
        station_id: "st-up".into(),
        patient_id: "p-1".into(),
        session_id: session_id.into(),
        exercise: "sine-road".into(),
        started_unix_ms: 1_795_253_400_000,
        software_version: "telerehab-test".into(),
        min_protocol_version: None,
        wheel: None,
    }
}

/// 200 kB of deterministic bytes (a fixed LCG), standing in for an MCAP file.
fn recording(dir: &Path) -> std::path::PathBuf {
    recording_of(dir, "session.mcap", 200_000)
}

/// `len` deterministic bytes in `dir/name`.
fn recording_of(dir: &Path, name: &str, len: usize) -> std::path::PathBuf {
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

async fn hub(store: &Path) -> TherapistServer {
    hub_with(store, |_| {}).await
}

async fn hub_with(store: &Path, limits: impl FnOnce(&mut TherapistConfig)) -> TherapistServer {
    let mut config = TherapistConfig::new("127.0.0.1:0".parse().unwrap(), store, None);
    limits(&mut config);
    TherapistServer::bind(config).await.unwrap().0
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_recording_arrives_whole_resumes_from_a_partial_copy_and_is_verified() {
    let tmp = tempfile::tempdir().unwrap();
    let file = recording(tmp.path());
    let (size, sha) = file_sha256(&file).unwrap();
    let store = tmp.path().join("store");
    let server = hub(&store).await;
    let addr = server.local_addr().to_string();
    let stored = store.join("st-up/s-up.mcap");

    // A partial copy from an interrupted upload: only the rest is sent.
    std::fs::create_dir_all(store.join("st-up")).unwrap();
    let part = store.join(format!("st-up/s-up.{}.part", &sha[..16]));
    std::fs::write(&part, &std::fs::read(&file).unwrap()[..70_000]).unwrap();
    // A partial copy of another version of this recording is removed, not kept forever.
    let stale = store.join("st-up/s-up.0123456789abcdef.part");
    std::fs::write(&stale, [1u8; 1000]).unwrap();
    let done = upload_recording(&addr, None, hello(), &file, 50_000_000)
        .await
        .unwrap();
    assert_eq!((done.size_bytes, done.sent_bytes), (size, size - 70_000));
    assert_eq!(
        std::fs::read(&stored).unwrap(),
        std::fs::read(&file).unwrap()
    );
    assert!(!part.exists());
    assert!(!stale.exists(), "another version's partial copy is removed");

    // Again: the hub has it, nothing is sent.
    let again = upload_recording(&addr, None, hello(), &file, 50_000_000)
        .await
        .unwrap();
    assert_eq!(again.sent_bytes, 0);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_corrupt_partial_copy_is_discarded_and_the_next_upload_is_whole() {
    let tmp = tempfile::tempdir().unwrap();
    let file = recording(tmp.path());
    let (size, sha) = file_sha256(&file).unwrap();
    let store = tmp.path().join("store");
    let server = hub(&store).await;
    let addr = server.local_addr().to_string();
    std::fs::create_dir_all(store.join("st-up")).unwrap();
    let part = store.join(format!("st-up/s-up.{}.part", &sha[..16]));
    std::fs::write(&part, vec![0u8; 50_000]).unwrap();

    let err = upload_recording(&addr, None, hello(), &file, 50_000_000)
        .await
        .unwrap_err();
    assert!(
        matches!(&err, netlink::upload::UploadError::Refused(m) if m.contains("SHA-256")),
        "{err:?}"
    );
    assert!(!part.exists(), "the corrupt copy is discarded");
    let done = upload_recording(&addr, None, hello(), &file, 50_000_000)
        .await
        .unwrap();
    assert_eq!(done.sent_bytes, size);
    assert_eq!(
        std::fs::read(store.join("st-up/s-up.mcap")).unwrap(),
        std::fs::read(&file).unwrap()
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_recording_over_the_hubs_session_cap_is_refused_before_a_byte_is_stored() {
    let tmp = tempfile::tempdir().unwrap();
    let file = recording_of(tmp.path(), "big.mcap", (1 << 20) + 1);
    let store = tmp.path().join("store");
    let server = hub_with(&store, |c| c.max_upload_bytes_per_session = 1 << 20).await;
    let addr = server.local_addr().to_string();
    let err = upload_recording(&addr, None, hello(), &file, 50_000_000)
        .await
        .unwrap_err()
        .to_string();
    assert!(err.contains("max_upload_bytes_per_session"), "{err}");
    // The session's own files (hello, summaries) are there; no recording, not even a part.
    let recordings: Vec<_> = std::fs::read_dir(store.join("st-up"))
        .into_iter()
        .flatten()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "mcap" || e == "part"))
        .collect();
    assert!(recordings.is_empty(), "nothing kept: {recordings:?}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_station_past_its_daily_bytes_is_refused_until_tomorrow_and_others_are_not() {
    let tmp = tempfile::tempdir().unwrap();
    let store = tmp.path().join("store");
    let server = hub_with(&store, |c| c.max_upload_bytes_per_station_day = 1 << 20).await;
    let addr = server.local_addr().to_string();
    // Three sessions of 400 kB: the third passes the station's 1 MiB a day.
    for (i, session) in ["s-a", "s-b"].into_iter().enumerate() {
        let file = recording_of(tmp.path(), &format!("{i}.mcap"), 400_000);
        upload_recording(&addr, None, hello_for(session), &file, 50_000_000)
            .await
            .unwrap();
    }
    let file = recording_of(tmp.path(), "2.mcap", 400_000);
    let err = upload_recording(&addr, None, hello_for("s-c"), &file, 50_000_000)
        .await
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("today") && err.contains("max_upload_bytes_per_station_day"),
        "{err}"
    );
    // Another station's quota is its own.
    let mut other = hello_for("s-c");
    other.station_id = "st-other".into();
    upload_recording(&addr, None, other, &file, 50_000_000)
        .await
        .unwrap();
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_hub_paces_an_upload_to_its_own_rate_whatever_the_station_sends() {
    let tmp = tempfile::tempdir().unwrap();
    let file = recording(tmp.path());
    let store = tmp.path().join("store");
    // 64 KiB/s at the hub; the station would send at 50 MB/s.
    let server = hub_with(&store, |c| c.max_upload_bytes_per_s = 64 << 10).await;
    let addr = server.local_addr().to_string();
    let began = std::time::Instant::now();
    let done = upload_recording(&addr, None, hello(), &file, 50_000_000)
        .await
        .unwrap();
    let elapsed = began.elapsed().as_secs_f64();
    // 200 kB at 64 KiB/s: 3.05 s; the last chunk's wait ends the upload, so at least the
    // time for all but that chunk (a lower bound: a loaded machine is only slower).
    let floor_s = (done.size_bytes - 32 * 1024) as f64 / f64::from(64u32 << 10);
    assert!(elapsed >= floor_s, "{elapsed:.2} s < {floor_s:.2} s");
}

/// The directory store, whose recording record fails the first time: a hub that kept the
/// file but could not record it (a database down at that moment).
struct RecordFailsOnce {
    files: netlink::FileStore,
    failed: std::sync::atomic::AtomicBool,
    recorded: std::sync::Mutex<Vec<String>>,
}

impl netlink::HubStore for RecordFailsOnce {
    fn open_session<'a>(
        &'a self,
        hello: &'a Hello,
    ) -> netlink::BoxFuture<'a, Result<Box<dyn netlink::SessionStore>, netlink::Refusal>> {
        self.files.open_session(hello)
    }

    fn recording_path(&self, hello: &Hello) -> Option<std::path::PathBuf> {
        self.files.recording_path(hello)
    }

    fn recording_stored<'a>(
        &'a self,
        hello: &'a Hello,
        _sha256: &'a str,
        _size_bytes: u64,
        _path: &'a Path,
    ) -> netlink::BoxFuture<'a, Result<(), netlink::NetlinkError>> {
        Box::pin(async move {
            if !self.failed.swap(true, std::sync::atomic::Ordering::SeqCst) {
                return Err(netlink::NetlinkError::Store("the database is down".into()));
            }
            self.recorded.lock().unwrap().push(hello.session_id.clone());
            Ok(())
        })
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_recording_the_hub_could_not_record_is_not_complete_and_is_recorded_at_the_next_upload() {
    let tmp = tempfile::tempdir().unwrap();
    let file = recording(tmp.path());
    let store = tmp.path().join("store");
    let recorder = std::sync::Arc::new(RecordFailsOnce {
        files: netlink::FileStore::new(store.clone()),
        failed: std::sync::atomic::AtomicBool::new(false),
        recorded: std::sync::Mutex::default(),
    });
    let config = TherapistConfig::new("127.0.0.1:0".parse().unwrap(), &store, None);
    let server = TherapistServer::bind_with_store(config, recorder.clone())
        .await
        .unwrap()
        .0;
    let addr = server.local_addr().to_string();
    let err = upload_recording(&addr, None, hello(), &file, 50_000_000)
        .await
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("not recorded"),
        "the station is not told complete: {err}"
    );
    assert!(recorder.recorded.lock().unwrap().is_empty());
    // The file is kept; the next upload sends nothing and has it recorded.
    let again = upload_recording(&addr, None, hello(), &file, 50_000_000)
        .await
        .unwrap();
    assert_eq!(again.sent_bytes, 0);
    assert_eq!(*recorder.recorded.lock().unwrap(), vec!["s-up".to_owned()]);
}

/// Sets `path`'s modification time `age` ago.
fn age_file(path: &Path, age: std::time::Duration) {
    let f = std::fs::File::options().write(true).open(path).unwrap();
    f.set_modified(std::time::SystemTime::now() - age).unwrap();
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_stations_left_parts_are_bounded_to_one_sessions_recording_and_stale_ones_removed() {
    let tmp = tempfile::tempdir().unwrap();
    let file = recording(tmp.path());
    let store = tmp.path().join("store");
    let dir = store.join("st-up");
    std::fs::create_dir_all(&dir).unwrap();
    // Parts of other sessions' uploads a station (or a hostile one) began and left.
    let newer = dir.join("s-a.0123456789abcdef.part");
    let older = dir.join("s-b.0123456789abcdef.part");
    let stale = dir.join("s-c.0123456789abcdef.part");
    std::fs::write(&newer, vec![1u8; 600_000]).unwrap();
    std::fs::write(&older, vec![1u8; 600_000]).unwrap();
    std::fs::write(&stale, vec![1u8; 1_000]).unwrap();
    age_file(&older, std::time::Duration::from_secs(60));
    age_file(
        &stale,
        std::time::Duration::from_secs(netlink::therapist::station_limits::STALE_PART_S + 60),
    );
    // One session's recording is at most 1 MiB here: the parts of a station stay within it.
    let server = hub_with(&store, |c| c.max_upload_bytes_per_session = 1 << 20).await;
    let addr = server.local_addr().to_string();
    upload_recording(&addr, None, hello(), &file, 50_000_000)
        .await
        .unwrap();
    assert!(!stale.exists(), "a part not written for a week is removed");
    assert!(!older.exists(), "the oldest part makes room");
    assert!(
        newer.exists(),
        "parts within the bound are kept (their uploads resume)"
    );
    let parts: u64 = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(Result::ok)
        .filter(|e| e.path().extension().is_some_and(|x| x == "part"))
        .map(|e| e.metadata().unwrap().len())
        .sum();
    assert!(parts <= 1 << 20, "{parts} bytes of parts left");
}

/// The directory store with the day's upload counts kept in one place, as the hubs on one
/// database share them: each [`TherapistServer`] bound to it is another hub.
struct SharedDayCounts {
    files: netlink::FileStore,
    bytes: std::sync::Mutex<std::collections::HashMap<(String, u64), u64>>,
}

impl netlink::HubStore for SharedDayCounts {
    fn open_session<'a>(
        &'a self,
        hello: &'a Hello,
    ) -> netlink::BoxFuture<'a, Result<Box<dyn netlink::SessionStore>, netlink::Refusal>> {
        self.files.open_session(hello)
    }

    fn recording_path(&self, hello: &Hello) -> Option<std::path::PathBuf> {
        self.files.recording_path(hello)
    }

    fn upload_bytes_on<'a>(
        &'a self,
        station_id: &'a str,
        day: u64,
    ) -> netlink::BoxFuture<'a, Result<u64, netlink::NetlinkError>> {
        let key = (station_id.to_owned(), day);
        let n = self.bytes.lock().unwrap().get(&key).copied().unwrap_or(0);
        Box::pin(async move { Ok(n) })
    }

    fn add_upload_bytes<'a>(
        &'a self,
        station_id: &'a str,
        day: u64,
        bytes: u64,
    ) -> netlink::BoxFuture<'a, Result<Option<u64>, netlink::NetlinkError>> {
        let mut counts = self.bytes.lock().unwrap();
        let count = counts.entry((station_id.to_owned(), day)).or_default();
        *count += bytes;
        let total = *count;
        Box::pin(async move { Ok(Some(total)) })
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_station_alternating_between_two_hubs_is_held_to_one_days_bytes() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("store");
    let shared = std::sync::Arc::new(SharedDayCounts {
        files: netlink::FileStore::new(dir.clone()),
        bytes: std::sync::Mutex::default(),
    });
    // Two hubs on one store, each allowing 1 MiB a station a day.
    let mut hubs = Vec::new();
    for _ in 0..2 {
        let mut config = TherapistConfig::new("127.0.0.1:0".parse().unwrap(), &dir, None);
        config.max_upload_bytes_per_station_day = 1 << 20;
        let server = TherapistServer::bind_with_store(config, shared.clone())
            .await
            .unwrap()
            .0;
        hubs.push(server);
    }
    let (a, b) = (
        hubs[0].local_addr().to_string(),
        hubs[1].local_addr().to_string(),
    );
    // 400 kB to A, 400 kB to B: 800 kB of the day's 1 MiB.
    for (i, addr) in [&a, &b].into_iter().enumerate() {
        let file = recording_of(tmp.path(), &format!("{i}.mcap"), 400_000);
        upload_recording(addr, None, hello_for(&format!("s-{i}")), &file, 50_000_000)
            .await
            .unwrap();
    }
    // Back to A, which took only 400 kB itself: the day's count is the two hubs' together.
    let file = recording_of(tmp.path(), "2.mcap", 400_000);
    let err = upload_recording(&a, None, hello_for("s-2"), &file, 50_000_000)
        .await
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("today") && err.contains("max_upload_bytes_per_station_day"),
        "{err}"
    );
    let day = netlink::frame::unix_ms_now() / 86_400_000;
    let counted = shared.bytes.lock().unwrap()[&("st-up".to_owned(), day)];
    assert!(
        (800_000..=1 << 20).contains(&counted),
        "the shared count holds the cap: {counted}"
    );
}
