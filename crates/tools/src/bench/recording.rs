//! `telerehab bench recording`: bytes per hour and the recorder's encoding time, the compact
//! encoding (`record::blocks`: protobuf blocks of delta-coded quantised columns) against the
//! all-JSON encoding it replaced (one JSON message per channel per tick), on the same ticks.
//!
//! The ticks come from one simulated session at `--speed max`, kept in memory; each encoding
//! then writes them all to memory `--repeats` times, alternating, and the median time counts.
//! Both write zstd-compressed MCAP chunks of the same size: only the message encoding differs.
//!
//! Then the session's own recorder (`session::recorder::McapRecorder`) writes the compact
//! encoding to a file in `--dir`, alternately without syncing and syncing (`fsync`) after every
//! chunk: the difference per chunk is what a sync costs the recorder thread, which syncs at
//! most once a second of wall time.

use clock::Clock;
use mcap::records::MessageHeader;
use record::channels::{MESSAGE_ENCODING, SCHEMA_ENCODING};
use record::writer::mcap_options;
use record::{CHANNELS, Channel, RecordWriter, SessionMetadata, Stamped, TickRecord};
use serde::Serialize;
use session::recorder::McapRecorder;
use session::{self, BodyKind, SessionObserver, SessionOptions, haptic::Pacing};
use station::commands::run::{self, RunArgs};
use std::collections::BTreeMap;
use std::io::Cursor;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// `telerehab bench recording`.
#[derive(Debug, clap::Args)]
pub struct BenchRecordingArgs {
    /// Session length, s.
    #[arg(long, default_value_t = 60.0)]
    pub duration: f64,
    /// Exercise to run.
    #[arg(long, default_value = "sine-road")]
    pub exercise: String,
    /// Seed of the simulation.
    #[arg(long, default_value_t = 7)]
    pub seed: u64,
    /// Times each encoding writes the session (the median counts).
    #[arg(long, default_value_t = 5)]
    pub repeats: usize,
    /// Directory the recorder's file is written to (the sync measurement; default: the
    /// system's temporary directory).
    #[arg(long)]
    pub dir: Option<PathBuf>,
}

/// Every tick of a session, as the recorder thread saw them.
#[derive(Default)]
struct Keep(Vec<TickRecord>);

impl SessionObserver for Keep {
    fn on_tick(&mut self, record: &TickRecord) {
        self.0.push(*record);
    }
}

/// The score is recorded every 100 ms of session time.
fn with_score(rec: &TickRecord) -> bool {
    rec.t_ns.is_multiple_of(100_000_000)
}

/// The compact recording of `ticks`, bytes.
fn compact(ticks: &[TickRecord], meta: &SessionMetadata) -> anyhow::Result<usize> {
    let mut w = RecordWriter::new(Cursor::new(Vec::new()), 0, meta)?;
    for (i, t) in ticks.iter().enumerate() {
        w.write_tick(t, with_score(t))?;
        if i % 1000 == 999 {
            w.flush()?;
        }
    }
    Ok(w.finish()?.into_inner().len())
}

/// The all-JSON recording of `ticks` (the encoding before compact blocks), bytes.
fn all_json(ticks: &[TickRecord], meta: &SessionMetadata) -> anyhow::Result<usize> {
    let mut w =
        mcap_options("telerehab bench (all-JSON reference)").create(Cursor::new(Vec::new()))?;
    let mut ids = BTreeMap::new();
    for spec in &CHANNELS {
        let schema = spec.schema().to_string();
        let schema_id = w.add_schema(spec.schema_name, SCHEMA_ENCODING, schema.as_bytes())?;
        let id = w.add_channel(schema_id, spec.topic, MESSAGE_ENCODING, &BTreeMap::new())?;
        ids.insert(spec.channel, id);
    }
    w.write_metadata(&mcap::records::Metadata {
        name: SessionMetadata::NAME.into(),
        metadata: meta.to_map(),
    })?;
    let mut buf = Vec::with_capacity(1024);
    let mut sequence = 0u32;
    let mut write =
        |w: &mut mcap::Writer<_>, channel, rec: &TickRecord, data: &dyn erased::Json| {
            buf.clear();
            data.write_stamped(rec, &mut buf);
            sequence += 1;
            let header = MessageHeader {
                channel_id: ids[&channel],
                sequence,
                log_time: rec.t_ns,
                publish_time: rec.t_ns,
            };
            w.write_to_known_channel(&header, &buf)
        };
    for (i, t) in ticks.iter().enumerate() {
        write(&mut w, Channel::Wheel, t, &t.wheel)?;
        if let Some(v) = &t.vehicle {
            write(&mut w, Channel::Vehicle, t, v)?;
        }
        if with_score(t) {
            write(&mut w, Channel::Score, t, &t.score)?;
        }
        write(&mut w, Channel::Assist, t, &t.assist)?;
        write(&mut w, Channel::Timing, t, &t.timing)?;
        if let Some(a) = &t.arm {
            write(&mut w, Channel::Arm, t, a)?;
        }
        // The raw inputs too, so that both files hold the same content.
        write(&mut w, Channel::RawWheel, t, &t.raw.wheel)?;
        for sample in t.raw.imu.iter().flatten() {
            write(&mut w, Channel::RawImu, t, sample)?;
        }
        if i % 1000 == 999 {
            w.flush()?;
        }
    }
    w.finish()?;
    Ok(w.into_inner().into_inner().len())
}

/// The session's recorder writing `ticks` to a new file in `dir`, a chunk closed every 1000
/// ticks, synced after every chunk when `sync` (else never); the time it took, and the
/// longest chunk close (flush, and sync).
fn to_file(
    ticks: &[TickRecord],
    meta: &SessionMetadata,
    dir: &Path,
    sync: bool,
) -> anyhow::Result<(Duration, Duration)> {
    let tmp = tempfile::tempdir_in(dir)?;
    let every = if sync { Duration::ZERO } else { Duration::MAX };
    let mut rec = McapRecorder::create(&tmp.path().join("bench.mcap"), 0, meta)?
        .sync_every(every)
        .keep_free(0);
    let mut longest = Duration::ZERO;
    let t0 = Instant::now();
    for (i, t) in ticks.iter().enumerate() {
        rec.record(t, with_score(t))?;
        if i % 1000 == 999 {
            let f0 = Instant::now();
            rec.flush()?;
            longest = longest.max(f0.elapsed());
        }
    }
    rec.finish()?;
    Ok((t0.elapsed(), longest))
}

/// A sample written as the JSON message of its channel, whatever its type.
mod erased {
    use super::{Serialize, Stamped, TickRecord};

    pub trait Json {
        fn write_stamped(&self, rec: &TickRecord, out: &mut Vec<u8>);
    }

    impl<T: Serialize + Copy> Json for T {
        fn write_stamped(&self, rec: &TickRecord, out: &mut Vec<u8>) {
            serde_json::to_writer(out, &Stamped::at(rec, *self)).expect("plain data serialises");
        }
    }
}

/// The median of `times`.
fn median(mut times: Vec<Duration>) -> Duration {
    times.sort();
    times[times.len() / 2]
}

/// `telerehab bench recording`.
pub(super) fn recording(args: BenchRecordingArgs) -> anyhow::Result<()> {
    anyhow::ensure!(
        args.duration.is_finite() && (1.0..=3600.0).contains(&args.duration),
        "--duration must be 1 to 3600 s"
    );
    anyhow::ensure!(
        (1..=50).contains(&args.repeats),
        "--repeats must be 1 to 50"
    );
    let run_args = RunArgs {
        exercise: Some(args.exercise.clone()),
        ..RunArgs::simulated(args.duration, args.seed)
    };
    let (cfg, regimen) = run::plan(&run_args)?;
    let opts = SessionOptions {
        config: cfg.clone(),
        pacing: Pacing::Max,
        record: None,
        body: BodyKind::Simulated,
        regimen,
        isolate_core: false,
        difficulty: None,
        clock: Clock::real(),
    };
    let mut keep = Keep::default();
    session::run(&opts, &session::Controls::default(), &mut keep)?;
    let ticks = keep.0;
    let meta = SessionMetadata {
        exercise: args.exercise.clone(),
        seed: args.seed,
        loop_rate_hz: cfg.session.loop_rate_hz,
        ..Default::default()
    };
    let (mut t_compact, mut t_json) = (Vec::new(), Vec::new());
    let (mut b_compact, mut b_json) = (0, 0);
    for _ in 0..args.repeats {
        let t0 = Instant::now();
        b_json = all_json(&ticks, &meta)?;
        t_json.push(t0.elapsed());
        let t0 = Instant::now();
        b_compact = compact(&ticks, &meta)?;
        t_compact.push(t0.elapsed());
    }
    let (t_compact, t_json) = (median(t_compact), median(t_json));
    let dir = args.dir.clone().unwrap_or_else(std::env::temp_dir);
    let (mut t_nosync, mut t_sync, mut longest) = (Vec::new(), Vec::new(), Duration::ZERO);
    for _ in 0..args.repeats {
        t_nosync.push(to_file(&ticks, &meta, &dir, false)?.0);
        let (t, l) = to_file(&ticks, &meta, &dir, true)?;
        t_sync.push(t);
        longest = longest.max(l);
    }
    let (t_nosync, t_sync) = (median(t_nosync), median(t_sync));
    let chunks = (ticks.len() / 1000).max(1) as f64;
    let hours = args.duration / 3600.0;
    let per_tick_us = |t: Duration| t.as_secs_f64() * 1e6 / ticks.len() as f64;
    println!(
        "── recording, {} ticks of {} ({} s), median of {} ──",
        ticks.len(),
        args.exercise,
        args.duration,
        args.repeats
    );
    for (name, bytes, t) in [
        ("all-JSON (before)", b_json, t_json),
        ("compact blocks", b_compact, t_compact),
    ] {
        println!(
            "{name:<18} {:>9.1} MB/h  {:>6.2} µs/tick to encode and compress",
            bytes as f64 / hours / 1e6,
            per_tick_us(t)
        );
    }
    println!(
        "compact / all-JSON: bytes {:.3} (1/{:.1}), encoding time {:.2}",
        b_compact as f64 / b_json as f64,
        b_json as f64 / b_compact as f64,
        t_compact.as_secs_f64() / t_json.as_secs_f64()
    );
    let per_sync_ms = (t_sync.as_secs_f64() - t_nosync.as_secs_f64()) * 1e3 / chunks;
    println!(
        "recorder to a file in {}: {:.2} µs/tick unsynced, {:.2} µs/tick synced after every \
         chunk; a sync costs {per_sync_ms:.2} ms ({:.2} % of each second at one a second), \
         longest chunk close with its sync {:.1} ms",
        dir.display(),
        per_tick_us(t_nosync),
        per_tick_us(t_sync),
        per_sync_ms / 10.0,
        longest.as_secs_f64() * 1e3
    );
    Ok(())
}
