//! Recording uploads on loopback: whole, resumed from a partial copy, refused when the bytes do
//! not match the announced SHA-256 (then whole again), and idempotent once stored.

use std::path::Path;

use netlink::upload::{file_sha256, upload_recording};
use netlink::{Hello, PROTOCOL_VERSION, TherapistConfig, TherapistServer};

fn hello() -> Hello {
    Hello {
        protocol_version: PROTOCOL_VERSION,
        station_id: "st-up".into(),
        patient_id: "p-1".into(),
        session_id: "s-up".into(),
        exercise: "sine-road".into(),
        started_unix_ms: 1_795_253_400_000,
        software_version: "telerehab-test".into(),
        min_protocol_version: None,
    }
}

/// 200 kB of deterministic bytes (a fixed LCG), standing in for an MCAP file.
fn recording(dir: &Path) -> std::path::PathBuf {
    let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
    let bytes: Vec<u8> = (0..200_000)
        .map(|_| {
            x = x.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            (x >> 56) as u8
        })
        .collect();
    let path = dir.join("session.mcap");
    std::fs::write(&path, bytes).unwrap();
    path
}

async fn hub(store: &Path) -> TherapistServer {
    let config = TherapistConfig::new("127.0.0.1:0".parse().unwrap(), store, None);
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
    assert!(err.contains("SHA-256"), "{err}");
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
