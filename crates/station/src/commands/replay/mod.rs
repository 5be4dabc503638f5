//! `telerehab replay`: re-run a recorded simulated session from its seed, configuration and
//! regimen (all in the recording's `session` metadata) as fast as possible, and say whether
//! every recorded output is reproduced bit for bit — the first difference named if not. A
//! real-device session (its metadata's `body` says so), or any session with `--from-raw`, is
//! re-run from its recorded raw inputs instead (`raw.rs`).
//!
//! Bit for bit means the same recorded value of every field of every sample on every channel
//! but `/timing` (wall-clock loop timing, which no two runs share): the high-rate channels
//! record whole numbers of each field's quantum (`record::blocks`), the low-rate ones the
//! shortest JSON text that reads back to the same `f64`; both are compared exactly.

use anyhow::{Context, bail};
use clock::Clock;
use record::compare::{ChannelComparison, MAX_PENDING_SAMPLES, Sample, SampleDifference};
use record::{Channel, Row, SessionMetadata, StreamLimits, TickStream};
use regimen::Regimen;
use session::config::StationConfig;
use session::haptic::Pacing;
use session::{self, BodyKind, Controls, SessionOptions};
use std::collections::BTreeMap;
use std::io::{BufReader, Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

mod raw;
mod window;

pub use window::Playback;

/// `telerehab replay`.
#[derive(Debug, clap::Args)]
pub struct ReplayArgs {
    /// The session's recording (MCAP), as `telerehab run --record` wrote it.
    pub recording: PathBuf,
    /// Play the recording in the patient's window instead of re-running it: Space plays and
    /// pauses, ←/→ seek 5 s, ↑/↓ double or halve the speed, Home restarts, Esc closes.
    #[arg(long)]
    pub window: bool,
    /// With `--window`: the playback speed to start at (1 = real time).
    #[arg(long, default_value_t = 1.0, requires = "window")]
    pub play_speed: f64,
    /// With `--window`: close the window when the playback reaches the end (otherwise it
    /// stays open on the last frame).
    #[arg(long, requires = "window")]
    pub close_at_end: bool,
    /// Re-run a simulated session from its recorded raw inputs (`/raw/wheel`, `/raw/imu`)
    /// instead of its seed: the simulated body replaced by what it delivered, as a real
    /// session is always replayed.
    #[arg(long, conflicts_with = "window")]
    pub from_raw: bool,
}

/// Where a replay first left the recording.
#[derive(Debug, Clone, PartialEq)]
pub struct Difference {
    /// The channel's topic.
    pub topic: &'static str,
    /// The sample's index on its channel.
    pub index: usize,
    /// What differs, for a person.
    pub what: String,
}

/// What a replay found.
#[derive(Debug, Clone, PartialEq)]
pub struct ReplayOutcome {
    /// Samples compared on each channel (recorded count).
    pub compared: BTreeMap<&'static str, usize>,
    /// The first difference, if any.
    pub first_difference: Option<Difference>,
    /// Why the recording cannot be reproduced exactly, if something says so in advance
    /// (patient pauses, an early stop).
    pub caveats: Vec<String>,
    /// Re-run from the recorded raw inputs (a real-device session, or `--from-raw`) rather
    /// than from the seed.
    pub from_raw: bool,
}

/// Replay `args.recording` and print what was reproduced; fails on a difference.
pub fn run(args: &ReplayArgs) -> anyhow::Result<()> {
    if args.window {
        return window::play(args);
    }
    let outcome = replay_with(&args.recording, args.from_raw)?;
    let total: usize = outcome.compared.values().sum();
    for c in &outcome.caveats {
        println!("replay: note: {c}");
    }
    match &outcome.first_difference {
        None => {
            let how = if outcome.from_raw {
                " from the recorded raw inputs"
            } else {
                ""
            };
            let not_compared = if outcome.from_raw {
                "/timing is wall-clock and not compared"
            } else {
                "/timing is wall-clock and the raw inputs /raw/* are not compared"
            };
            println!(
                "replay: identical — every recorded output reproduced bit for bit{how} ({total} samples on {} channels; {not_compared})",
                outcome.compared.len()
            );
            if outcome.from_raw {
                println!(
                    "replay: a simulated body's own observations (true wheel and joint angles, hand torque) are inputs here, taken from the recording"
                );
            }
            Ok(())
        }
        Some(d) => bail!(
            "replay differs: first at {} sample {}: {}",
            d.topic,
            d.index,
            d.what
        ),
    }
}

/// Re-run the simulated session recorded at `path` and compare every channel but `/timing`.
pub fn replay(path: &Path) -> anyhow::Result<ReplayOutcome> {
    replay_with(path, false)
}

/// Re-run the session recorded at `path` and compare every channel but `/timing`: from its
/// raw inputs when it was a real-device session or `from_raw`, else from its seed. Neither
/// run is held: the re-run is recorded to a temporary file, which is read as it is written,
/// side by side with the recording, and compared as it is read (`record::compare`), so memory
/// does not grow with the session's length.
pub fn replay_with(path: &Path, from_raw: bool) -> anyhow::Result<ReplayOutcome> {
    let unreadable = || format!("{} is not a readable recording", path.display());
    let mut stream =
        TickStream::open_path(path, StreamLimits::default(), &[]).with_context(unreadable)?;
    let meta = stream.metadata().clone();
    let real = meta
        .body
        .as_ref()
        .is_some_and(|b| b.kind == record::raw::BodyKindName::Real);
    if from_raw || real {
        return raw::replay_from_raw(path, &meta)
            .with_context(|| format!("replaying {} from its raw inputs", path.display()));
    }
    let first = match stream.next() {
        Some(tick) => tick.with_context(unreadable)?,
        None => bail!(
            "{} has no /wheel messages: nothing to replay",
            path.display()
        ),
    };
    drop(stream);
    if first.wheel.true_angle_rad.is_none() {
        bail!(
            "{} is a session on a real wheel recorded before the raw inputs were: its patient's \
             hands cannot be re-run, nor its device readings replayed",
            path.display()
        );
    }
    let (opts, expected_ticks) = options(&meta)?;
    let dir = tempfile::tempdir().context("cannot make a temporary directory")?;
    let again_path = dir.path().join("replay.mcap");
    let opts = SessionOptions {
        record: Some(again_path.clone()),
        ..opts
    };
    let (report, compared) = rerun_and_compare(path, &again_path, false, || {
        session::run(&opts, &Controls::default(), &mut ())
    });
    own_recording(&report?)?;
    let (mut outcome, pauses) = compared?;
    let recorded_ticks = outcome.compared.get(Channel::Wheel.topic()).copied();
    let recorded_ticks = recorded_ticks.unwrap_or(0);
    if recorded_ticks < expected_ticks {
        outcome.caveats.push(format!(
            "the session was stopped after {recorded_ticks} of {expected_ticks} ticks; the \
             replay runs them all, so it differs from the stop on"
        ));
    }
    if pauses.patient_paused() {
        outcome.caveats.push(
            "the patient paused this session; pauses are not replayed, so it differs from the \
             first pause on"
                .into(),
        );
    }
    Ok(outcome)
}

/// Runs the re-run (`run`, which records to `again_path`) on a thread of its own while this
/// one reads its recording as it is written and compares it with the recording at
/// `recorded` (`compare`): the two take the time of the longer, not of both. Gives the
/// re-run's report and the comparison.
fn rerun_and_compare(
    recorded: &Path,
    again_path: &Path,
    from_raw: bool,
    run: impl FnOnce() -> anyhow::Result<session::SessionReport> + Send,
) -> (
    anyhow::Result<session::SessionReport>,
    anyhow::Result<(ReplayOutcome, Pauses)>,
) {
    let done = AtomicBool::new(false);
    std::thread::scope(|s| {
        let rerun = std::thread::Builder::new()
            .name("replay-rerun".into())
            .spawn_scoped(s, || {
                let _done = SetOnDrop(&done);
                run()
            });
        let rerun = match rerun {
            Ok(handle) => handle,
            Err(e) => {
                let e = anyhow::Error::new(e).context("cannot start the re-run's thread");
                return (Err(e), Err(anyhow::anyhow!("the session was not re-run")));
            }
        };
        let compared = Following::open(again_path, &done)
            .map_err(|source| record::compare::CompareError {
                second: true,
                source: record::ReadError::Io {
                    path: format!(" {}", again_path.display()),
                    source,
                },
            })
            .and_then(|again| compare(recorded, again, from_raw))
            .map_err(|e| {
                let which = if e.second {
                    "the replay's recording".to_owned()
                } else {
                    format!("{} is not a readable recording", recorded.display())
                };
                anyhow::Error::new(e.source).context(which)
            });
        let report = rerun
            .join()
            .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
        (report, compared)
    })
}

/// Fails if the re-run's own recording failed (its comparison then means nothing).
fn own_recording(report: &session::SessionReport) -> anyhow::Result<()> {
    match &report.recorder.error {
        Some(e) => bail!("the replay's own recording failed: {e}"),
        None => Ok(()),
    }
}

/// Sets its flag when dropped: the re-run has ended, however it ended.
struct SetOnDrop<'a>(&'a AtomicBool);

impl Drop for SetOnDrop<'_> {
    fn drop(&mut self) {
        self.0.store(true, Ordering::Release);
    }
}

/// A recording read as it is written: at the end of what is written it waits for more until
/// the writer has ended (`done`), and only then ends. Only whole records are given while the
/// writer runs: the MCAP writer starts a chunk with a placeholder header (its length all ones)
/// and writes the real one over it when the chunk closes, so a chunk is given once its header
/// is the real one and its bytes are all there.
struct Following<'a> {
    file: std::fs::File,
    done: &'a AtomicBool,
    /// Bytes given so far.
    at: u64,
    /// Bytes known final: the magic and every whole record up to here.
    stable: u64,
}

impl<'a> Following<'a> {
    /// How long a reader at the end of what is written waits before it looks again.
    const POLL: Duration = Duration::from_millis(1);

    /// Opens `path` once the writer has created it, buffered.
    fn open(path: &Path, done: &'a AtomicBool) -> std::io::Result<BufReader<Self>> {
        loop {
            let ended = done.load(Ordering::Acquire);
            match std::fs::File::open(path) {
                Ok(file) => {
                    let following = Self {
                        file,
                        done,
                        at: 0,
                        stable: 0,
                    };
                    return Ok(BufReader::with_capacity(256 << 10, following));
                }
                Err(e) if e.kind() == std::io::ErrorKind::NotFound && !ended => {
                    std::thread::sleep(Self::POLL);
                }
                Err(e) => return Err(e),
            }
        }
    }

    /// Reads `buf.len()` bytes at `offset`, if the file holds them.
    fn bytes_at(&mut self, offset: u64, buf: &mut [u8]) -> std::io::Result<bool> {
        self.file.seek(SeekFrom::Start(offset))?;
        match self.file.read_exact(buf) {
            Ok(()) => Ok(true),
            Err(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => Ok(false),
            Err(e) => Err(e),
        }
    }

    /// Moves `stable` past every record now whole and final.
    fn advance(&mut self) -> std::io::Result<()> {
        const CHUNK: u8 = 0x06;
        const PLACEHOLDER: u64 = !0;
        let len = self.file.metadata()?.len();
        if self.stable == 0 {
            if len < 8 {
                return Ok(());
            }
            self.stable = 8;
        }
        loop {
            let mut head = [0u8; 9 + 24];
            if !self.bytes_at(self.stable, &mut head[..9])? {
                return Ok(());
            }
            let body = u64::from_le_bytes(head[1..9].try_into().expect("8 bytes"));
            if head[0] == CHUNK {
                // opcode, length, start and end times, uncompressed size, its CRC, the
                // compression's name (length first), compressed size.
                if body == PLACEHOLDER || !self.bytes_at(self.stable, &mut head)? {
                    return Ok(());
                }
                let uncompressed = u64::from_le_bytes(head[25..33].try_into().expect("8 bytes"));
                let mut name = [0u8; 4];
                if uncompressed == PLACEHOLDER || !self.bytes_at(self.stable + 37, &mut name)? {
                    return Ok(());
                }
                let name = u64::from(u32::from_le_bytes(name));
                let mut compressed = [0u8; 8];
                if !self.bytes_at(self.stable + 41 + name, &mut compressed)?
                    || u64::from_le_bytes(compressed) == PLACEHOLDER
                {
                    return Ok(());
                }
            }
            let end = self.stable.saturating_add(9).saturating_add(body);
            if end > len {
                return Ok(());
            }
            self.stable = end;
        }
    }
}

impl Read for Following<'_> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        loop {
            // Look at the flag first: once the writer has ended, every byte is final.
            let ended = self.done.load(Ordering::Acquire);
            if ended {
                self.stable = self.file.metadata()?.len();
            } else {
                self.advance()?;
            }
            if self.at < self.stable || ended || buf.is_empty() {
                let want = usize::try_from(self.stable.saturating_sub(self.at))
                    .unwrap_or(usize::MAX)
                    .min(buf.len());
                self.file.seek(SeekFrom::Start(self.at))?;
                let n = self.file.read(&mut buf[..want])?;
                self.at += n as u64;
                return Ok(n);
            }
            std::thread::sleep(Self::POLL);
        }
    }
}

/// The replay's outcome (no caveats yet): what the re-run, read from `again` as it is
/// written, reproduced of the recording at `recorded`, the raw channels compared too when
/// `from_raw`; and the recording's pauses.
fn compare(
    recorded: &Path,
    again: impl Read,
    from_raw: bool,
) -> Result<(ReplayOutcome, Pauses), record::compare::CompareError> {
    let channels: Vec<Channel> = compared(from_raw).collect();
    let mut pauses = Pauses::default();
    let observed = [Channel::Arm, Channel::Score];
    let comparison =
        record::compare::compare_with(recorded, again, &channels, &observed, |c, s| {
            pauses.observe(c, s);
        })?;
    Ok((
        ReplayOutcome {
            compared: comparison
                .iter()
                .map(|(c, cmp)| (c.topic(), cmp.samples[0]))
                .collect(),
            first_difference: channels
                .iter()
                .find_map(|c| comparison.get(c).and_then(|cmp| difference_on(*c, cmp))),
            caveats: Vec::new(),
            from_raw,
        },
        pauses,
    ))
}

/// The configuration and regimen a recorded session ran with (from its metadata), read
/// leniently so that a recording of any version replays; what had to be dropped or defaulted,
/// and a format newer than this build's, are said as notes.
pub(crate) fn recorded_plan(
    meta: &SessionMetadata,
) -> anyhow::Result<(StationConfig, Option<Regimen>)> {
    let (config, mut notes) =
        StationConfig::from_recorded(&meta.config_toml, "the recording's configuration")?;
    let regimen = match meta.regimen_toml.as_deref() {
        Some(text) => {
            let (regimen, more) = Regimen::from_recorded(text, "the recording's regimen")?;
            notes.extend(more);
            Some(regimen)
        }
        None => None,
    };
    for note in meta.format_note().into_iter().chain(notes) {
        println!("replay: note: {note}");
    }
    Ok((config, regimen))
}

/// The session options that re-run the recorded session, and the ticks it was to run.
fn options(meta: &SessionMetadata) -> anyhow::Result<(SessionOptions, usize)> {
    let (config, regimen) = recorded_plan(meta)?;
    let expected = (config.session.duration_s * config.session.loop_rate_hz).round() as usize;
    Ok((
        SessionOptions {
            config,
            pacing: Pacing::Max,
            record: None,
            body: BodyKind::Simulated,
            regimen,
            isolate_core: false,
            difficulty: None,
            clock: Clock::mock().0,
        },
        expected,
    ))
}

/// What a recording says of its pauses, gathered as it is read.
#[derive(Debug, Default)]
struct Pauses {
    /// One past the last tick of the arm procedure (which holds the exercise paused itself,
    /// and is replayed); 0 without one.
    procedure_end: u64,
    /// The tick of the last score recorded paused.
    last_paused: Option<u64>,
}

impl Pauses {
    /// Takes one recorded sample.
    fn observe(&mut self, channel: Channel, sample: &Sample) {
        match channel {
            Channel::Arm => {
                let setup = sample.field("setup");
                if matches!(
                    setup.as_ref().and_then(serde_json::Value::as_str),
                    Some("hold-still" | "turn-wheel" | "solving")
                ) && let Some(t) = sample.tick()
                {
                    self.procedure_end = self.procedure_end.max(t + 1);
                }
            }
            Channel::Score if sample.field("paused") == Some(serde_json::Value::Bool(true)) => {
                if let Some(t) = sample.tick() {
                    self.last_paused = Some(self.last_paused.map_or(t, |l| l.max(t)));
                }
            }
            _ => {}
        }
    }

    /// Whether the patient paused the exercise: a recorded pause after the arm procedure.
    fn patient_paused(&self) -> bool {
        self.last_paused.is_some_and(|t| t > self.procedure_end)
    }
}

/// The channels a replay compares: every one but `/timing` (wall-clock); from the seed, not
/// the raw inputs either (`/raw/wheel`, `/raw/imu`), which the seed does not fix: in real time
/// the arm solver's answer comes from its thread when it does.
fn compared(from_raw: bool) -> impl Iterator<Item = Channel> {
    Channel::ALL.into_iter().filter(move |c| {
        *c != Channel::Timing && (from_raw || !matches!(c, Channel::RawWheel | Channel::RawImu))
    })
}

/// The first difference on `channel` ([`ChannelComparison`]), named down to the field.
fn difference_on(channel: Channel, c: &ChannelComparison) -> Option<Difference> {
    let topic = channel.topic();
    let [recorded, replayed] = c.samples;
    match &c.difference {
        Some(SampleDifference::Values {
            index,
            first,
            second,
        }) => Some(Difference {
            topic,
            index: *index,
            what: field_difference(first, second),
        }),
        Some(SampleDifference::Lag { index }) => Some(Difference {
            topic,
            index: *index,
            what: format!(
                "one run's samples lag the other's by more than {MAX_PENDING_SAMPLES}: not \
                 compared from here"
            ),
        }),
        // A calibration recorded by a version without physiological bounds that this one
        // rejects (`arm::calibration::UPPER_ARM_M`): no result is the right answer now.
        None if channel == Channel::ArmCalibration && recorded == 1 && replayed == 0 => None,
        None => (recorded != replayed).then(|| Difference {
            topic,
            index: recorded.min(replayed),
            what: format!("{recorded} samples recorded, {replayed} replayed"),
        }),
    }
}

/// The first field whose value differs between two samples of one channel.
fn field_difference(a: &Row, b: &Row) -> String {
    let at = format!("tick {}, t = {} s", a["tick"], a["t_s"]);
    a.iter()
        .find(|(k, v)| b.get(*k) != Some(v))
        .map(|(k, v)| {
            let replayed = b.get(k).map_or("absent".to_owned(), ToString::to_string);
            format!("{at}: {k} recorded {v}, replayed {replayed}")
        })
        .or_else(|| {
            b.keys()
                .find(|k| !a.contains_key(*k))
                .map(|k| format!("{at}: {k} absent from the recording, replayed {}", b[k]))
        })
        .unwrap_or_else(|| format!("{at}: the same values written differently"))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(v: serde_json::Value) -> Row {
        v.as_object().unwrap().clone()
    }

    fn message(tick: u64, angle: f64) -> Row {
        row(serde_json::json!({"tick": tick, "t_s": tick as f64 / 1000.0, "angle_rad": angle}))
    }

    #[test]
    fn the_first_difference_is_named_by_channel_tick_and_field() {
        let same = ChannelComparison {
            samples: [2, 2],
            difference: None,
        };
        assert_eq!(difference_on(Channel::Wheel, &same), None);
        let values = ChannelComparison {
            samples: [2, 2],
            difference: Some(SampleDifference::Values {
                index: 1,
                first: message(1, 0.25),
                second: message(1, 0.250_000_000_000_000_06),
            }),
        };
        let d = difference_on(Channel::Wheel, &values).unwrap();
        assert_eq!((d.topic, d.index), ("/wheel", 1));
        assert_eq!(
            d.what,
            "tick 1, t = 0.001 s: angle_rad recorded 0.25, replayed 0.25000000000000006"
        );
        let shorter = ChannelComparison {
            samples: [2, 1],
            difference: None,
        };
        let d = difference_on(Channel::Wheel, &shorter).unwrap();
        assert_eq!(
            (d.index, d.what.as_str()),
            (1, "2 samples recorded, 1 replayed")
        );
    }

    #[test]
    fn the_arm_procedures_pause_is_not_the_patients() {
        let score = |tick: u64, paused: bool| {
            Sample::Row(row(serde_json::json!({"tick": tick, "paused": paused})))
        };
        let arm = |tick: u64, setup: &str| {
            Sample::Row(row(serde_json::json!({"tick": tick, "setup": setup})))
        };
        let mut pauses = Pauses::default();
        for (c, s) in [
            (Channel::Arm, arm(0, "hold-still")),
            (Channel::Score, score(100, true)),
            (Channel::Arm, arm(100, "solving")),
            (Channel::Score, score(200, false)),
            (Channel::Arm, arm(200, "tracking")),
        ] {
            pauses.observe(c, &s);
        }
        assert!(!pauses.patient_paused());
        pauses.observe(Channel::Score, &score(300, true));
        assert!(pauses.patient_paused());
    }

    #[test]
    fn timing_is_not_compared_nor_the_raw_inputs_from_the_seed() {
        assert!(!compared(true).any(|c| c == Channel::Timing));
        assert!(compared(true).any(|c| c == Channel::RawImu));
        assert!(!compared(false).any(|c| matches!(c, Channel::RawWheel | Channel::RawImu)));
        assert_eq!(compared(false).count(), Channel::ALL.len() - 3);
    }
}
