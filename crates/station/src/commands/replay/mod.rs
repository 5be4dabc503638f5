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

use crate::config::StationConfig;
use crate::session::haptic::Pacing;
use crate::session::{self, BodyKind, Controls, SessionOptions};
use anyhow::{Context, bail};
use clock::Clock;
use record::{Channel, RecordedRows, Row, SessionMetadata, recorded_rows};
use regimen::Regimen;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

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
/// raw inputs when it was a real-device session or `from_raw`, else from its seed.
pub fn replay_with(path: &Path, from_raw: bool) -> anyhow::Result<ReplayOutcome> {
    let bytes = std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))?;
    let (meta, recorded) = recorded_rows(&bytes)
        .with_context(|| format!("{} is not a readable recording", path.display()))?;
    let real = meta
        .body
        .as_ref()
        .is_some_and(|b| b.kind == record::raw::BodyKindName::Real);
    if from_raw || real {
        return raw::replay_from_raw(&bytes, &meta, &recorded)
            .with_context(|| format!("replaying {} from its raw inputs", path.display()));
    }
    let wheel = recorded.get(&Channel::Wheel).map_or(&[][..], Vec::as_slice);
    let first = match wheel.first() {
        Some(m) => m,
        None => bail!(
            "{} has no /wheel messages: nothing to replay",
            path.display()
        ),
    };
    if first.get("true_angle_rad").is_none() {
        bail!(
            "{} is a session on a real wheel recorded before the raw inputs were: its patient's \
             hands cannot be re-run, nor its device readings replayed",
            path.display()
        );
    }
    let (opts, caveats) = options(&meta, wheel.len(), &recorded)?;
    let dir = tempfile::tempdir().context("cannot make a temporary directory")?;
    let again_path = dir.path().join("replay.mcap");
    let opts = SessionOptions {
        record: Some(again_path.clone()),
        ..opts
    };
    let report = session::run(&opts, &Controls::default(), &mut ())?;
    compare(&report, &again_path, &recorded, caveats, false)
}

/// The replay's outcome: what the re-run (`report`, recorded to `again_path`) reproduced of
/// `recorded`, the raw channels compared too when `from_raw`.
fn compare(
    report: &session::SessionReport,
    again_path: &Path,
    recorded: &RecordedRows,
    caveats: Vec<String>,
    from_raw: bool,
) -> anyhow::Result<ReplayOutcome> {
    if let Some(e) = &report.recorder.error {
        bail!("the replay's own recording failed: {e}");
    }
    let again_bytes = std::fs::read(again_path).context("cannot read the replay's recording")?;
    let (_, again) = recorded_rows(&again_bytes).context("the replay's recording")?;
    Ok(ReplayOutcome {
        compared: compared(from_raw)
            .map(|c| (c.topic(), recorded.get(&c).map_or(0, Vec::len)))
            .collect(),
        first_difference: first_difference_on(recorded, &again, from_raw),
        caveats,
        from_raw,
    })
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

/// The session options that re-run the recorded session, and what may keep it from being
/// reproduced.
fn options(
    meta: &SessionMetadata,
    recorded_ticks: usize,
    recorded: &RecordedRows,
) -> anyhow::Result<(SessionOptions, Vec<String>)> {
    let (config, regimen) = recorded_plan(meta)?;
    let mut caveats = Vec::new();
    let expected = (config.session.duration_s * config.session.loop_rate_hz).round() as usize;
    if recorded_ticks < expected {
        caveats.push(format!(
            "the session was stopped after {recorded_ticks} of {expected} ticks; the replay runs \
             them all, so it differs from the stop on"
        ));
    }
    if patient_paused(recorded) {
        caveats.push(
            "the patient paused this session; pauses are not replayed, so it differs from the \
             first pause on"
                .into(),
        );
    }
    Ok((
        SessionOptions {
            config,
            pacing: Pacing::Max,
            record: None,
            body: BodyKind::Simulated,
            regimen,
            isolate_core: false,
            clock: Clock::mock().0,
        },
        caveats,
    ))
}

/// Whether the patient paused the exercise: a recorded pause after the arm procedure (which
/// holds the exercise paused itself, and is replayed).
fn patient_paused(recorded: &RecordedRows) -> bool {
    let in_procedure = |v: &&Row| {
        matches!(
            v["setup"].as_str(),
            Some("hold-still" | "turn-wheel" | "solving")
        )
    };
    let procedure_end = recorded.get(&Channel::Arm).map_or(0, |arm| {
        arm.iter()
            .filter(in_procedure)
            .filter_map(|v| v["tick"].as_u64())
            .max()
            .map_or(0, |t| t + 1)
    });
    recorded.get(&Channel::Score).is_some_and(|scores| {
        scores
            .iter()
            .any(|v| v["paused"] == true && v["tick"].as_u64().is_some_and(|t| t > procedure_end))
    })
}

/// The channels a replay compares: every one but `/timing` (wall-clock); from the seed, not
/// the raw inputs either (`/raw/wheel`, `/raw/imu`), which the seed does not fix: in real time
/// the arm solver's answer comes from its thread when it does.
fn compared(from_raw: bool) -> impl Iterator<Item = Channel> {
    Channel::ALL.into_iter().filter(move |c| {
        *c != Channel::Timing && (from_raw || !matches!(c, Channel::RawWheel | Channel::RawImu))
    })
}

/// The first sample (channel order, then index) that differs, named down to the field, on
/// the channels a replay compares (`from_raw`: a replay from the raw inputs, which compares
/// them too).
fn first_difference_on(
    recorded: &RecordedRows,
    again: &RecordedRows,
    from_raw: bool,
) -> Option<Difference> {
    let none = Vec::new();
    compared(from_raw).find_map(|channel| {
        let (a, b) = (
            recorded.get(&channel).unwrap_or(&none),
            again.get(&channel).unwrap_or(&none),
        );
        let topic = channel.topic();
        if let Some(index) = a.iter().zip(b).position(|(x, y)| x != y) {
            return Some(Difference {
                topic,
                index,
                what: field_difference(&a[index], &b[index]),
            });
        }
        (a.len() != b.len()).then(|| Difference {
            topic,
            index: a.len().min(b.len()),
            what: format!("{} samples recorded, {} replayed", a.len(), b.len()),
        })
    })
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
        let recorded = BTreeMap::from([(Channel::Wheel, vec![message(0, 0.5), message(1, 0.25)])]);
        let mut again = recorded.clone();
        assert_eq!(first_difference_on(&recorded, &again, false), None);
        again.get_mut(&Channel::Wheel).unwrap()[1] = message(1, 0.250_000_000_000_000_06);
        let d = first_difference_on(&recorded, &again, false).unwrap();
        assert_eq!((d.topic, d.index), ("/wheel", 1));
        assert_eq!(
            d.what,
            "tick 1, t = 0.001 s: angle_rad recorded 0.25, replayed 0.25000000000000006"
        );
        again.get_mut(&Channel::Wheel).unwrap().truncate(1);
        let d = first_difference_on(&recorded, &again, false).unwrap();
        assert_eq!(d.what, "2 samples recorded, 1 replayed");
    }

    #[test]
    fn the_arm_procedures_pause_is_not_the_patients() {
        let score =
            |tick: u64, paused: bool| row(serde_json::json!({"tick": tick, "paused": paused}));
        let arm = |tick: u64, setup: &str| row(serde_json::json!({"tick": tick, "setup": setup}));
        let mut recorded = BTreeMap::from([
            (
                Channel::Arm,
                vec![
                    arm(0, "hold-still"),
                    arm(100, "solving"),
                    arm(200, "tracking"),
                ],
            ),
            (Channel::Score, vec![score(100, true), score(200, false)]),
        ]);
        assert!(!patient_paused(&recorded));
        recorded
            .get_mut(&Channel::Score)
            .unwrap()
            .push(score(300, true));
        assert!(patient_paused(&recorded));
    }

    #[test]
    fn timing_is_not_compared() {
        let recorded = BTreeMap::from([(Channel::Timing, vec![message(0, 1.0)])]);
        let again = BTreeMap::from([(Channel::Timing, vec![message(0, 2.0)])]);
        assert_eq!(first_difference_on(&recorded, &again, false), None);
    }
}
