//! Upload and replay-read throughput of one recording through the hub's recording store, and
//! the memory a replay's reader holds: the local directory against an S3 store.
//!
//! ```sh
//! cargo run --release -p hub --example recording_store_bench -- --mb 100 --data /tmp/rsb
//! cargo run --release -p hub --example recording_store_bench -- --mb 100 --data /tmp/rsb \
//!     --s3 http://127.0.0.1:8333 --bucket recordings --credentials /tmp/creds.toml
//! ```
//!
//! The file is deterministic bytes (a fixed LCG): the store's cost does not depend on them,
//! and decoding a recording costs the same wherever it is read from (BENCHMARKS.md, "Console
//! replay of uploaded recordings"). Upload = `RecordingStore::keep` of a verified part (a
//! rename locally, one multipart upload on S3); replay read = a sequential read of the whole
//! recording through `RecordingStore::open_reader`, the reader the console's replay decodes
//! from, while a thread samples the process's resident memory.

use std::io::{Read, Write};
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

use hub::recordings::{RecordingStore, RecordingsConfig};

struct Args {
    mb: u64,
    data: PathBuf,
    s3: Option<String>,
    bucket: String,
    credentials: Option<PathBuf>,
}

fn args() -> Args {
    let mut a = Args {
        mb: 100,
        data: PathBuf::from("/tmp/recording-store-bench"),
        s3: None,
        bucket: "recordings".into(),
        credentials: None,
    };
    let mut it = std::env::args().skip(1);
    while let Some(flag) = it.next() {
        let mut value = || it.next().unwrap_or_else(|| panic!("{flag} needs a value"));
        match flag.as_str() {
            "--mb" => a.mb = value().parse().expect("--mb: a number of MiB"),
            "--data" => a.data = value().into(),
            "--s3" => a.s3 = Some(value()),
            "--bucket" => a.bucket = value(),
            "--credentials" => a.credentials = Some(value().into()),
            other => panic!("unknown flag {other}"),
        }
    }
    a
}

/// The process's resident memory, bytes.
fn rss_bytes() -> u64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmRSS:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<u64>().ok())
        .map_or(0, |kb| kb * 1024)
}

fn write_part(path: &std::path::Path, mb: u64) {
    let mut out = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
    let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut block = vec![0u8; 1 << 20];
    for _ in 0..mb {
        for b in &mut block {
            x = x.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            *b = (x >> 56) as u8;
        }
        out.write_all(&block).unwrap();
    }
    out.into_inner().unwrap().sync_all().unwrap();
}

#[tokio::main(flavor = "multi_thread", worker_threads = 2)]
async fn main() {
    let a = args();
    std::fs::create_dir_all(&a.data).unwrap();
    let store = match &a.s3 {
        None => RecordingStore::local(a.data.join("recordings")).unwrap(),
        Some(endpoint) => {
            let mut c = RecordingsConfig::s3(&a.bucket, endpoint);
            c.credentials_file = a.credentials.clone();
            RecordingStore::open(&a.data, Some(&c)).unwrap()
        }
    };
    let (station, session) = ("st-bench", format!("s-{}", std::process::id()));
    let part = store
        .staging_path(station, &session)
        .with_extension("0123456789abcdef.part");
    std::fs::create_dir_all(part.parent().unwrap()).unwrap();
    write_part(&part, a.mb);
    let bytes = a.mb << 20;

    let started = Instant::now();
    store.keep(station, &session, &part).await.unwrap();
    let upload_s = started.elapsed().as_secs_f64();

    let baseline = rss_bytes();
    let peak = Arc::new(AtomicU64::new(baseline));
    let done = Arc::new(AtomicBool::new(false));
    let sampler = {
        let (peak, done) = (Arc::clone(&peak), Arc::clone(&done));
        std::thread::spawn(move || {
            while !done.load(Ordering::SeqCst) {
                peak.fetch_max(rss_bytes(), Ordering::SeqCst);
                std::thread::sleep(Duration::from_millis(5));
            }
        })
    };
    let reader_store = store.clone();
    let session_r = session.clone();
    let (read, replay_s) = tokio::task::spawn_blocking(move || {
        let started = Instant::now();
        let reader = reader_store.open_reader(station, &session_r).unwrap();
        // The replay's own buffering: a 64 KiB BufReader over the store's reader.
        let mut input = std::io::BufReader::with_capacity(64 << 10, reader);
        let mut buf = vec![0u8; 64 << 10];
        let mut n = 0u64;
        loop {
            let got = input.read(&mut buf).unwrap();
            if got == 0 {
                break;
            }
            n += got as u64;
        }
        (n, started.elapsed().as_secs_f64())
    })
    .await
    .unwrap();
    done.store(true, Ordering::SeqCst);
    sampler.join().unwrap();
    assert_eq!(read, bytes, "the whole recording read back");
    store.erase_station(station).await.unwrap();

    let mb = bytes as f64 / f64::from(1 << 20);
    println!(
        "store {}: {mb:.0} MiB; upload {upload_s:.2} s ({:.0} MiB/s); replay read {replay_s:.2} s \
         ({:.0} MiB/s); resident memory during the replay read +{:.1} MiB over {:.1} MiB",
        if store.is_s3() { "s3" } else { "local" },
        mb / upload_s,
        mb / replay_s,
        peak.load(Ordering::SeqCst).saturating_sub(baseline) as f64 / f64::from(1 << 20),
        baseline as f64 / f64::from(1 << 20),
    );
}
