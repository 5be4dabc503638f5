//! `telerehab replay` from the raw inputs: the recorded session's pure part (vehicle, haptic
//! model and effects, assist, safety chain, arm fusion and pose, scores) re-run around a body
//! made of its `/raw/wheel` and `/raw/imu` (`session::recorded`), through the session's own
//! loop and recorder, and every recorded output compared bit for bit. The way to replay a
//! real-device session (no wheel or patient to re-run); `--from-raw` forces it on a simulated
//! one, which proves the raw inputs enough.

use super::{ReplayOutcome, own_recording, recorded_plan, rerun_and_compare};
use anyhow::{Context, bail};
use clock::Clock;
use record::{BodyFacts, SessionMetadata};
use session::haptic::Pacing;
use session::plant::Body;
use session::recorded::{RecordedBody, RecordedInputs};
use session::{self, BodyKind, Controls, SessionOptions};
use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// Re-run the session recorded at `path` (its metadata `meta`) from its raw inputs, read as
/// they are played, and compare every channel but `/timing`.
pub(super) fn replay_from_raw(
    path: &Path,
    meta: &SessionMetadata,
) -> anyhow::Result<ReplayOutcome> {
    let Some(facts) = meta.body.clone() else {
        bail!(
            "the recording does not say who held the wheel (no `body` metadata): it was made \
             before the raw inputs were recorded, so it cannot be re-run from them"
        );
    };
    let inputs = RecordedInputs::stream_from(path)?;
    rerun(path, meta, facts, inputs)
}

/// Re-run the session of `meta` around `inputs` (a body of `facts`) and compare its outputs
/// with the recording at `recorded`.
fn rerun(
    recorded: &Path,
    meta: &SessionMetadata,
    facts: BodyFacts,
    inputs: RecordedInputs,
) -> anyhow::Result<ReplayOutcome> {
    let (config, regimen) = recorded_plan(meta)?;
    let stop = Arc::new(AtomicBool::new(false));
    let (failure, played) = (inputs.failure(), inputs.played());
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
        difficulty: None,
        clock: Clock::mock().0,
    };
    let (report, compared) = rerun_and_compare(recorded, &again_path, true, || {
        session::run_with_body(
            &opts,
            &Controls::with_stop(stop),
            &mut (),
            Body::Recorded(Box::new(body)),
            Some(facts),
        )
    });
    let report = report?;
    if let Some(why) = failure.lock().unwrap_or_else(|e| e.into_inner()).take() {
        bail!(why);
    }
    own_recording(&report)?;
    let (mut outcome, _) = compared?;
    let count = |topic: &str| outcome.compared.get(topic).copied().unwrap_or(0);
    let (ticks, with_raw) = (count("/wheel"), count("/raw/wheel"));
    if with_raw != ticks {
        bail!("the recording holds {ticks} ticks on /wheel but {with_raw} on /raw/wheel");
    }
    if ran_out.load(Ordering::Relaxed) {
        let recorded_ticks = played.load(Ordering::Relaxed);
        outcome.caveats.push(format!(
            "the recording ends after {recorded_ticks} ticks without its session's end (a \
             killed session, recovered, or a file cut short): the replay stops where its \
             inputs end, so it differs from there on"
        ));
    }
    Ok(outcome)
}

#[cfg(test)]
mod tests {
    use super::*;
    use arm::MountingMode;
    use record::Recording;

    /// A simulated session of `seconds` with the guided arm procedure, recorded in `dir`.
    fn recorded_session(dir: &Path, seconds: f64) -> std::path::PathBuf {
        let path = dir.join("s.mcap");
        let mut config = session::config::StationConfig::default();
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
            difficulty: None,
            clock: Clock::mock().0,
        };
        session::run(&opts, &Controls::default(), &mut ()).unwrap();
        path
    }

    /// A recorded session read back with what re-running it takes.
    struct Rerunnable {
        _dir: tempfile::TempDir,
        path: std::path::PathBuf,
        meta: SessionMetadata,
        facts: BodyFacts,
        recording: Recording,
    }

    impl Rerunnable {
        /// Its inputs, held.
        fn inputs(&self) -> RecordedInputs {
            RecordedInputs::from_recording(&self.recording).unwrap()
        }

        /// Re-run around `inputs`.
        fn rerun(&self, inputs: RecordedInputs) -> ReplayOutcome {
            rerun(&self.path, &self.meta, self.facts.clone(), inputs).unwrap()
        }
    }

    /// [`recorded_session`] of `seconds`, read back.
    fn rerunnable(seconds: f64) -> Rerunnable {
        let dir = tempfile::tempdir().unwrap();
        let path = recorded_session(dir.path(), seconds);
        let recording = Recording::open(&path).unwrap();
        Rerunnable {
            facts: recording.metadata.body.clone().unwrap(),
            meta: recording.metadata.clone(),
            recording,
            path,
            _dir: dir,
        }
    }

    #[test]
    fn the_raw_inputs_reproduce_a_session_and_a_changed_input_is_found_where_it_acts() {
        let r = rerunnable(14.0);
        let recording = &r.recording;
        assert_eq!(r.facts.kind, record::raw::BodyKindName::Simulated);
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

        let same = r.rerun(r.inputs());
        assert_eq!(same.first_difference, None);
        assert!(same.caveats.is_empty(), "{:?}", same.caveats);
        // Read from the file as they are played, the inputs reproduce it too.
        let streamed = r.rerun(RecordedInputs::stream_from(&r.path).unwrap());
        assert_eq!(streamed, same);

        // One wheel reading a micro-radian off: /wheel differs from that tick on.
        let mut nudged = r.inputs();
        nudged.nudge_angle(500, 1e-6);
        let d = r.rerun(nudged).first_difference.expect("a difference");
        assert_eq!((d.topic, d.index), ("/wheel", 500), "{}", d.what);
        assert!(d.what.contains("angle_rad"), "{}", d.what);

        // The solver's answer recorded 2 s later: tracking, and the exercise the set-up held
        // paused, begin later; nothing differs before the answer.
        let mut late = r.inputs();
        late.delay_solver_answer(answered, 2000);
        let d = r.rerun(late).first_difference.expect("a difference");
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
        let r = rerunnable(6.0);
        // A session killed at 3 s: its inputs end there, its outputs (here) go on.
        let mut inputs = r.inputs();
        inputs.cut_after(3000);
        let outcome = r.rerun(inputs);
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
