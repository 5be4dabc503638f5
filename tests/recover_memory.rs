//! `telerehab recover` streams its input: recovering a large killed recording grows the
//! process's peak memory by a bounded amount, not by the file's size.
//!
//! One test in its own binary, so no other test's allocations land in the measured peak.
//! The peak is the kernel's `VmHWM` (peak resident set), reset just before the recovery by
//! writing 5 to `/proc/self/clear_refs`.

use std::collections::BTreeMap;
use std::io::BufWriter;

/// Size of the synthetic recording: 4096 messages of 64 KiB, MiB.
const FILE_MIB: u64 = 256;
/// The most the recovery may add to the peak resident set, MiB (a quarter of the file).
const BOUND_MIB: u64 = 64;

/// A `FILE_MIB` recording written in uncompressed 1 MiB chunks (so the file is as large as its
/// contents), then cut inside its last chunks as a SIGKILL leaves a file.
fn big_killed_recording(path: &std::path::Path) -> u64 {
    let file = BufWriter::new(std::fs::File::create(path).unwrap());
    let mut w = mcap::WriteOptions::new()
        .compression(None)
        .chunk_size(Some(1 << 20))
        .create(file)
        .unwrap();
    let channel = w
        .add_channel(0, "/big", "application/octet-stream", &BTreeMap::new())
        .unwrap();
    let messages = FILE_MIB * 16;
    let mut payload = vec![0u8; 64 * 1024];
    for i in 0..messages {
        payload[..8].copy_from_slice(&i.to_le_bytes());
        let header = mcap::records::MessageHeader {
            channel_id: channel,
            sequence: i as u32,
            log_time: i * 1_000_000,
            publish_time: i * 1_000_000,
        };
        w.write_to_known_channel(&header, &payload).unwrap();
    }
    w.finish().unwrap();
    drop(w);
    let len = std::fs::metadata(path).unwrap().len();
    let cut = len - 2_500_000;
    std::fs::OpenOptions::new()
        .write(true)
        .open(path)
        .unwrap()
        .set_len(cut)
        .unwrap();
    messages
}

#[test]
fn recovering_a_256_mib_killed_recording_grows_peak_memory_by_less_than_64_mib() {
    if session::resident::status_kib("VmHWM").is_none() {
        println!("SKIPPED: no VmHWM in /proc/self/status (not Linux?)");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("big.mcap");
    let written = big_killed_recording(&input);
    let size = std::fs::metadata(&input).unwrap().len();
    assert!(size > (FILE_MIB - 4) << 20, "{size} bytes");
    // Writing the file was streamed too; start the peak from here all the same.
    let reset = std::fs::write("/proc/self/clear_refs", "5").is_ok();
    let before_kb = session::resident::status_kib("VmHWM").unwrap();
    let out = dir.path().join("fixed.mcap");
    let copied = station::commands::recover::recover(&input, &out).unwrap();
    let growth_mib = (session::resident::status_kib("VmHWM").unwrap() - before_kb) / 1024;
    println!(
        "recovered {} of {written} messages from {:.0} MiB: peak RSS +{growth_mib} MiB \
         (peak reset: {reset})",
        copied.messages,
        size as f64 / (1 << 20) as f64
    );
    assert!(
        growth_mib < BOUND_MIB,
        "recovering a {} MiB file grew the peak RSS by {growth_mib} MiB",
        size >> 20
    );
    // Everything up to the cut is kept: at most the last ~2.5 MB (40 messages) are lost.
    assert!(copied.stopped_at.is_some());
    assert!(
        copied.messages + 40 >= written && copied.messages < written,
        "{} of {written}",
        copied.messages
    );
    let bytes = std::fs::read(&out).unwrap();
    assert!(mcap::Summary::read(&bytes).unwrap().is_some());
}
