//! `telerehab replay` from the raw inputs: the recorded session's pure part (vehicle, haptic
//! model and effects, assist, safety chain, arm fusion and pose, scores) re-run around a body
//! made of its `/raw/wheel` and `/raw/imu` (`session::recorded`), through the session's own
//! loop and recorder, and every recorded output compared bit for bit. The way to replay a
//! real-device session (no wheel or patient to re-run); `--from-raw` forces it on a simulated
//! one, which proves the raw inputs enough.

use super::{ReplayOutcome, compare, recorded_plan};
use crate::session::haptic::Pacing;
use crate::session::plant::Body;
use crate::session::recorded::{RecordedBody, RecordedInputs};
use crate::session::{self, BodyKind, Controls, SessionOptions};
use anyhow::{Context, bail};
use clock::Clock;
use record::{BodyFacts, RecordedRows, Recording, SessionMetadata};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// Re-run the session recorded in `bytes` (its metadata `meta`, its samples `recorded`) from
/// its raw inputs and compare every channel but `/timing`.
pub(super) fn replay_from_raw(
    bytes: &[u8],
    meta: &SessionMetadata,
    recorded: &RecordedRows,
) -> anyhow::Result<ReplayOutcome> {
    let Some(facts) = meta.body.clone() else {
        bail!(
            "the recording does not say who held the wheel (no `body` metadata): it was made \
             before the raw inputs were recorded, so it cannot be re-run from them"
        );
    };
    let recording = Recording::from_bytes(bytes).context("the recording")?;
    let inputs = RecordedInputs::from_recording(&recording)?;
    rerun(meta, recorded, facts, inputs)
}

/// Re-run the session of `meta` around `inputs` (a body of `facts`) and compare its outputs
/// with `recorded`.
fn rerun(
    meta: &SessionMetadata,
    recorded: &RecordedRows,
    facts: BodyFacts,
    inputs: RecordedInputs,
) -> anyhow::Result<ReplayOutcome> {
    let (config, regimen) = recorded_plan(meta)?;
    let stop = Arc::new(AtomicBool::new(false));
    let recorded_ticks = inputs.ticks();
    let body = RecordedBody::new(&facts, inputs, stop.clone())?;
    let ran_out = body.ran_out();
    let dir = tempfile::tempdir().context("cannot make a temporary directory")?;
    let again_path = dir.path().join("replay.mcap");
    let opts = SessionOptions {
        config,
        pacing: Pacing::Max,
        record: Some(again_path.clone()),
        // Not used: the body is the recording's.
        body: BodyKind::Simulated,
        regimen,
        isolate_core: false,
        clock: Clock::mock().0,
    };
    let report = session::run_with_body(
        &opts,
        &Controls::with_stop(stop),
        &mut (),
        Body::Recorded(Box::new(body)),
        Some(facts),
    )?;
    let caveats = if ran_out.load(Ordering::Relaxed) {
        vec![format!(
            "the recording ends after {recorded_ticks} ticks without its session's end (a \
             killed session, recovered, or a file cut short): the replay stops where its \
             inputs end, so it differs from there on"
        )]
    } else {
        Vec::new()
    };
    compare(&report, &again_path, recorded, caveats, true)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::MountingMode;

    /// A simulated session of `seconds` with the guided arm procedure, recorded in memory.
    fn recorded_session(seconds: f64) -> Vec<u8> {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("s.mcap");
        let mut config = crate::config::StationConfig::default();
        config.session.duration_s = seconds;
        config.session.seed = 5;
        config.arm.sim_mounting = MountingMode::Guided;
        let opts = SessionOptions {
            config,
            pacing: Pacing::Max,
            record: Some(path.clone()),
            body: BodyKind::Simulated,
            regimen: None,
            isolate_core: false,
            clock: Clock::mock().0,
        };
        session::run(&opts, &Controls::default(), &mut ()).unwrap();
        std::fs::read(path).unwrap()
    }

    /// A recorded session read back with what re-running it takes.
    struct Rerunnable {
        meta: SessionMetadata,
        recorded: RecordedRows,
        facts: BodyFacts,
        recording: Recording,
        inputs: RecordedInputs,
    }

    /// [`recorded_session`] of `seconds`, read back.
    fn rerunnable(seconds: f64) -> Rerunnable {
        let bytes = recorded_session(seconds);
        let (meta, recorded) = record::recorded_rows(&bytes).unwrap();
        let recording = Recording::from_bytes(&bytes).unwrap();
        Rerunnable {
            facts: meta.body.clone().unwrap(),
            inputs: RecordedInputs::from_recording(&recording).unwrap(),
            meta,
            recorded,
            recording,
        }
    }

    #[test]
    fn the_raw_inputs_reproduce_a_session_and_a_changed_input_is_found_where_it_acts() {
        let Rerunnable {
            meta,
            recorded,
            facts,
            recording,
            inputs,
        } = rerunnable(14.0);
        assert_eq!(facts.kind, record::raw::BodyKindName::Simulated);
        let answered = recording
            .raw_wheel
            .iter()
            .position(|w| w.data.solver_answered)
            .expect("the mounting was solved within the session");
        let tracking = recording
            .arm
            .iter()
            .position(|a| a.tick > answered as u64 && a.data.setup.as_str() == "tracking")
            .expect("tracking began within the session");

        let same = rerun(&meta, &recorded, facts.clone(), inputs.clone()).unwrap();
        assert_eq!(same.first_difference, None);
        assert!(same.caveats.is_empty(), "{:?}", same.caveats);

        // One wheel reading a micro-radian off: /wheel differs from that tick on.
        let mut nudged = inputs.clone();
        nudged.nudge_angle(500, 1e-6);
        let d = rerun(&meta, &recorded, facts.clone(), nudged)
            .unwrap()
            .first_difference
            .expect("a difference");
        assert_eq!((d.topic, d.index), ("/wheel", 500), "{}", d.what);
        assert!(d.what.contains("angle_rad"), "{}", d.what);

        // The solver's answer recorded 2 s later: tracking, and the exercise the set-up held
        // paused, begin later; nothing differs before the answer.
        let mut late = inputs;
        late.delay_solver_answer(answered, 2000);
        let d = rerun(&meta, &recorded, facts, late)
            .unwrap()
            .first_difference
            .expect("a difference");
        assert_eq!(d.topic, "/wheel", "{}", d.what);
        assert!(
            (answered..=recording.arm[tracking].tick as usize + 2000).contains(&d.index),
            "{answered} {}: {}",
            d.index,
            d.what
        );
    }

    #[test]
    fn a_recording_cut_short_replays_up_to_its_end_stops_there_and_says_why() {
        let Rerunnable {
            meta,
            recorded,
            facts,
            mut inputs,
            ..
        } = rerunnable(6.0);
        // A session killed at 3 s: its inputs end there, its outputs (here) go on.
        inputs.cut_after(3000);
        let outcome = rerun(&meta, &recorded, facts, inputs).unwrap();
        assert!(
            outcome.caveats.len() == 1 && outcome.caveats[0].contains("ends after 3000 ticks"),
            "{:?}",
            outcome.caveats
        );
        // Identical up to where the inputs end; no replug grace waited out past it.
        let d = outcome
            .first_difference
            .expect("a difference from the cut on");
        assert!(d.index >= 3000, "{} {}: {}", d.topic, d.index, d.what);
    }
}
