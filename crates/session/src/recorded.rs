//! A body made of a recording's raw inputs (`/raw/wheel`, `/raw/imu`): the wheel reads what
//! the device gave, the body clock says what it said, the patient pauses and stops when they
//! did, and the arm tracker is handed the IMU samples and solver events it was handed. The
//! plant around it — haptic chain, vehicle, assist, arm fusion and pose, scores — is the
//! session's own code, so re-running it reproduces a session bit for bit (`telerehab replay`),
//! whether a real patient or the simulated one held the wheel.
//!
//! A simulated session's body also recorded what it alone observes (the true wheel angle,
//! the hand's torque, the true joint angles): they are taken from `/wheel` and `/arm` as they
//! were recorded, as inputs, not re-run.

use anyhow::{Context, bail};
use arm::{ArmSeam, ArmTracker, RecordedSolver, SetupStep, WheelNow};
use gyro_imu::ImuError;
use gyro_imu::device::ImuSample;
use gyro_imu::pose::Mounting;
use haptic_wheel::{DeviceProfile, MotorUpdates, Wheel, WheelError, WheelFault, WheelReading};
use nalgebra::UnitQuaternion;
use record::raw::{ArmFacts, BodyFacts, RawRead, RawTick};
use record::{ArmSample, Recording};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// One tick of the recording as the body plays it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct InputTick {
    raw: RawTick,
    /// The simulated wheel's true angle, rad (simulation only).
    true_angle_rad: Option<f64>,
    /// The simulated hand's torque, N·m (simulation only).
    hand_nm: Option<f64>,
    /// The simulated arm's true shoulder elevation and elbow flexion, rad, on `/arm`.
    true_arm_rad: Option<(f64, f64)>,
    /// The torque updates the recorded wheel's backend had written, on `/wheel` (a device's
    /// observation, like the true angle: played as recorded).
    motor: Option<MotorUpdates>,
}

/// A recording's ticks read as a stream.
type Ticks = record::TickStream<std::io::BufReader<std::fs::File>>;

/// The raw inputs of a recorded session, tick by tick: held whole (tests), or read from the
/// recording's file as the replay plays them, in bounded memory whatever its length.
#[derive(Default)]
pub struct RecordedInputs {
    /// The ticks held, from the next one to play on (reversed: the next is the last).
    held: Vec<InputTick>,
    /// The recording read as the ticks are played.
    stream: Option<Box<Ticks>>,
    /// Ticks given to the body so far.
    given: usize,
    /// The same, shared with the replay.
    played: Arc<std::sync::atomic::AtomicUsize>,
    /// Why the inputs ended before the recording did, if they did (shared with the replay).
    failure: Arc<std::sync::Mutex<Option<String>>>,
}

/// Why the raw inputs of tick `k` cannot be played (the next recorded being `next`).
fn dropped_tick(k: usize, next: u64) -> String {
    format!(
        "the recording lacks the raw inputs of tick {k} (the next recorded is {next}): its \
         recorder dropped ticks, so the session cannot be re-run from them"
    )
}

/// The inputs of one recorded tick.
fn input_tick(rec: &record::TickRecord) -> InputTick {
    InputTick {
        raw: rec.raw,
        true_angle_rad: rec.wheel.true_angle_rad,
        hand_nm: rec.wheel.hand_nm,
        true_arm_rad: rec
            .arm
            .map(|a| (a.true_shoulder_elevation_rad, a.true_elbow_flexion_rad)),
        motor: rec
            .wheel
            .motor_update_worst_gap_ms
            .map(|gap_ms| MotorUpdates {
                count: rec.wheel.motor_updates,
                worst_gap_ns: (gap_ms * 1e6).round() as u64,
                last_ns: None,
            }),
    }
}

impl RecordedInputs {
    /// The inputs of `recording`, which must hold `/raw/wheel` on every tick from 0 (a
    /// real-time session whose recorder dropped ticks cannot be re-run: the inputs are gone).
    pub fn from_recording(recording: &Recording) -> anyhow::Result<Self> {
        if recording.raw_wheel.is_empty() {
            bail!(
                "the recording has no raw inputs (/raw/wheel): it was made before they were \
                 recorded"
            );
        }
        let mut ticks = Vec::with_capacity(recording.raw_wheel.len());
        for (k, rec) in recording.ticks().enumerate() {
            if rec.tick != k as u64 {
                bail!(dropped_tick(k, rec.tick));
            }
            ticks.push(input_tick(&rec));
        }
        let with_raw = recording.raw_wheel.len();
        if with_raw != ticks.len() {
            bail!(
                "the recording holds {} ticks on /wheel but {with_raw} on /raw/wheel",
                ticks.len()
            );
        }
        ticks.reverse();
        Ok(Self {
            held: ticks,
            ..Self::default()
        })
    }

    /// The inputs of the recording at `path`, read tick by tick as they are played. A tick
    /// missing (a recorder that dropped ticks) or a damaged file ends them there, and
    /// [`Self::failure`] says why; a file without `/raw/wheel` is refused here.
    pub fn stream_from(path: &std::path::Path) -> anyhow::Result<Self> {
        let channels = [
            record::Channel::Arm,
            record::Channel::RawWheel,
            record::Channel::RawImu,
        ];
        let mut stream =
            record::TickStream::open_path(path, record::StreamLimits::default(), &channels)
                .with_context(|| format!("{} is not a readable recording", path.display()))?;
        // The first tick read, to know whether the file records raw inputs at all.
        let first = stream.next().transpose().context("the recording")?;
        if first.is_none() || !stream.has_channel(record::Channel::RawWheel) {
            bail!(
                "the recording has no raw inputs (/raw/wheel): it was made before they were \
                 recorded"
            );
        }
        let mut inputs = Self {
            stream: Some(Box::new(stream)),
            ..Self::default()
        };
        if let Some(rec) = first {
            if rec.tick != 0 {
                bail!(dropped_tick(0, rec.tick));
            }
            inputs.held.push(input_tick(&rec));
        }
        Ok(inputs)
    }

    /// Why the inputs ended before the recording did (a dropped tick, a damaged file), once
    /// they have.
    pub fn failure(&self) -> Arc<std::sync::Mutex<Option<String>>> {
        Arc::clone(&self.failure)
    }

    /// How many ticks have been played (shared: read it once the replay has run).
    pub fn played(&self) -> Arc<std::sync::atomic::AtomicUsize> {
        Arc::clone(&self.played)
    }

    /// The next tick's inputs; `None` past the last.
    fn next(&mut self) -> Option<InputTick> {
        let tick = match self.held.pop() {
            Some(t) => Some(t),
            None => self.next_streamed(),
        };
        if tick.is_some() {
            self.given += 1;
            self.played.store(self.given, Ordering::Relaxed);
        }
        tick
    }

    /// The next tick read from the file, if it is the tick due.
    fn next_streamed(&mut self) -> Option<InputTick> {
        let stream = self.stream.as_mut()?;
        let why = match stream.next()? {
            Ok(rec) if rec.tick == self.given as u64 => return Some(input_tick(&rec)),
            Ok(rec) => dropped_tick(self.given, rec.tick),
            Err(e) => format!("the recording cannot be read past tick {}: {e}", self.given),
        };
        self.stream = None;
        *self.failure.lock().unwrap_or_else(|e| e.into_inner()) = Some(why);
        None
    }

    /// Change the wheel angle read on `tick` by `by_rad` (tests: a replay must notice).
    #[cfg(feature = "test-hooks")]
    pub fn nudge_angle(&mut self, tick: usize, by_rad: f64) {
        let n = self.held.len();
        self.held[n - 1 - tick].raw.wheel.angle_rad += by_rad;
    }

    /// Keep the first `ticks` ticks only, as a killed session's file holds (tests).
    #[cfg(feature = "test-hooks")]
    pub fn cut_after(&mut self, ticks: usize) {
        let n = self.held.len();
        self.held.drain(..n - ticks);
    }

    /// Hold back the solver's answer, first in hand on tick `from`, by `ticks` (tests).
    #[cfg(feature = "test-hooks")]
    pub fn delay_solver_answer(&mut self, from: usize, ticks: usize) {
        let n = self.held.len();
        for t in &mut self.held[n - from - ticks..n - from] {
            t.raw.wheel.solver_answered = false;
        }
    }
}

/// The arm tracker fed from the recording, as the session's sensing fed it.
struct RecordedArm {
    tracker: ArmTracker,
    /// The latest sample of sensor 0 and 1 (held between a device's reports).
    latest: [Option<ImuSample>; 2],
    last: ArmSample,
}

/// What the recorded body did in one tick.
pub struct RecordedMotion {
    /// The simulated hand's torque, N·m, as recorded.
    pub hand_nm: Option<f64>,
    /// The simulated wheel's true angle, rad, as recorded.
    pub true_angle_rad: Option<f64>,
    /// The arm's pose, without arm sensing `None`.
    pub arm: Option<ArmSample>,
    /// The tracker's raw inputs this tick (recorded again by the replay).
    pub seam: Option<ArmSeam>,
}

/// The body of a recorded session (see the module docs).
pub struct RecordedBody {
    inputs: RecordedInputs,
    /// The tick being played (`None` past the recording's last).
    now: Option<InputTick>,
    /// The last tick the recording holds, once played.
    last: Option<InputTick>,
    profile: DeviceProfile,
    max_torque_nm: f64,
    encoder_step_rad: f64,
    arm: Option<RecordedArm>,
    /// The session's stop flag, raised when the recording says a stop was asked for.
    stop: Arc<AtomicBool>,
    /// A real wheel held by a real patient was recorded.
    real: bool,
    /// The replug grace the recorded session gave an unplugged wheel, ns, if recorded.
    replug_grace_ns: Option<u64>,
    /// The replay asked for a tick past the recording's last (a killed or cut-short session).
    ran_out: Arc<AtomicBool>,
    /// The torque updates recorded at the tick played last.
    motor: Option<MotorUpdates>,
}

impl RecordedBody {
    /// The body of `inputs` with the device facts of `facts`; `stop` is the session's stop
    /// flag (the haptic loop's `Controls::stop`).
    pub fn new(
        facts: &BodyFacts,
        inputs: RecordedInputs,
        stop: Arc<AtomicBool>,
    ) -> anyhow::Result<Self> {
        let arm = facts
            .arm
            .map(|a| -> anyhow::Result<RecordedArm> {
                let mut tracker = tracker(&a).context("the recorded arm tracker")?;
                tracker.replay_solver(RecordedSolver::default());
                Ok(RecordedArm {
                    tracker,
                    latest: [None; 2],
                    last: ArmSample::default(),
                })
            })
            .transpose()?;
        let mut inputs = inputs;
        let now = inputs.next();
        let body = Self {
            inputs,
            now,
            last: now,
            profile: facts.wheel_profile.clone(),
            max_torque_nm: facts.wheel_max_torque_nm,
            encoder_step_rad: facts.encoder_step_rad,
            arm,
            stop,
            real: facts.kind == record::raw::BodyKindName::Real,
            replug_grace_ns: facts.replug_grace_ns,
            ran_out: Arc::default(),
            motor: None,
        };
        body.raise_stop();
        Ok(body)
    }

    fn now(&self) -> Option<&InputTick> {
        self.now.as_ref()
    }

    /// Raise the stop flag before the tick that recorded a stop asked for.
    fn raise_stop(&self) {
        if self.now().is_some_and(|t| t.raw.wheel.stop) {
            self.stop.store(true, Ordering::Relaxed);
        }
    }

    /// The recorded session ran on a real wheel (not the simulated one).
    pub fn real(&self) -> bool {
        self.real
    }

    /// Raised when the replay asks for a tick past the recording's last: the recorded session
    /// went on (it was killed, or its file cut short), its inputs did not.
    pub fn ran_out(&self) -> Arc<AtomicBool> {
        self.ran_out.clone()
    }

    /// How long the recorded session waited for an unplugged wheel to come back, ns: as
    /// recorded, else (a recording made before it was) none for a real wheel, which an unplug
    /// then ended at once, and `configured_ns` for a simulated one. A replay must wait as long
    /// as the session did, or it ends elsewhere.
    pub fn replug_grace_ns(&self, configured_ns: u64) -> u64 {
        match self.replug_grace_ns {
            Some(ns) => ns,
            None if self.real => 0,
            None => configured_ns,
        }
    }

    /// The patient had the exercise paused this tick.
    pub fn paused(&self) -> bool {
        self.now().is_some_and(|t| t.raw.wheel.paused)
    }

    /// The pedals as recorded (released past the end).
    pub fn pedals(&self) -> exercises::Pedals {
        self.now()
            .map_or_else(exercises::Pedals::default, |t| exercises::Pedals {
                throttle: t.raw.wheel.throttle,
                brake: t.raw.wheel.brake,
            })
    }

    /// Now on the body clock, ns, as recorded (the last recorded past the end).
    pub fn now_ns(&self) -> u64 {
        self.now()
            .or(self.last.as_ref())
            .map_or(0, |t| t.raw.wheel.now_ns)
    }

    /// The encoder step the velocity estimator was tuned for, rad.
    pub fn encoder_step_rad(&self) -> f64 {
        self.encoder_step_rad
    }

    /// Where the arm sensing is; `None` without it.
    pub fn arm_setup(&self) -> Option<SetupStep> {
        self.arm.as_ref().map(|a| a.tracker.step_now())
    }

    /// The body's part of the tick with the wheel as read (`read`); the next tick follows.
    pub fn step(&mut self, read: WheelNow) -> RecordedMotion {
        let tick = self.now().copied().unwrap_or_default();
        self.motor = tick.motor;
        let arm = self.arm.as_mut().map(|arm| {
            for sample in tick.raw.imu.iter().flatten() {
                if let Some(slot) = arm.latest.get_mut(sample.sensor as usize) {
                    *slot = Some(sample.sample());
                }
            }
            let w = &tick.raw.wheel;
            arm.tracker.replay_solver(RecordedSolver {
                answered: w.solver_answered,
                timed_out: w.solver_timed_out,
            });
            if w.arm_lost {
                arm.tracker
                    .lose_sensor(ImuError::Gone("an IMU stopped answering (recorded)"));
            }
            if w.arm_regained {
                arm.tracker.regain_sensor();
            }
            if let (true, [Some(a), Some(b)]) = (w.arm_stepped, arm.latest) {
                let mut sample = arm.tracker.update(read, &a, &b);
                if let Some((shoulder, elbow)) = tick.true_arm_rad {
                    sample.true_shoulder_elevation_rad = shoulder;
                    sample.true_elbow_flexion_rad = elbow;
                }
                arm.last = sample;
            }
            (arm.last, arm.tracker.take_seam())
        });
        self.now = self.inputs.next();
        if self.now.is_some() {
            self.last = self.now;
        }
        self.raise_stop();
        RecordedMotion {
            hand_nm: tick.hand_nm,
            true_angle_rad: tick.true_angle_rad,
            arm: arm.map(|(sample, _)| sample),
            seam: arm.map(|(_, seam)| seam),
        }
    }

    /// Range of motion of each estimated joint angle, rad; `None` without arm sensing.
    pub fn range_of_motion_rad(&self) -> Option<[f64; 5]> {
        self.arm.as_ref().map(|a| a.tracker.range_of_motion_rad())
    }

    /// Why arm sensing stopped or never started, if it did.
    pub fn arm_failure(&self) -> Option<&arm::ArmFailure> {
        self.arm.as_ref().and_then(|a| a.tracker.failure())
    }
}

/// The tracker the session built.
fn tracker(a: &ArmFacts) -> Result<ArmTracker, ImuError> {
    if a.guided {
        // In line: the solver's answer is used from the recorded tick on.
        ArmTracker::guided(a.geometry, a.swivel_rad, false, clock::Clock::real())
    } else {
        let square = Mounting {
            upper: UnitQuaternion::identity(),
            fore: UnitQuaternion::identity(),
        };
        ArmTracker::known(a.geometry, square, a.swivel_rad)
    }
}

impl Wheel for RecordedBody {
    fn read(&mut self) -> Result<WheelReading, WheelError> {
        let Some(t) = self.now() else {
            // Stop where the inputs end, rather than wait out the replug grace for a wheel
            // that can never answer.
            self.ran_out.store(true, Ordering::Relaxed);
            self.stop.store(true, Ordering::Relaxed);
            return Err(WheelError::Disconnected("the recording ends here".into()));
        };
        let w = t.raw.wheel;
        match w.read {
            RawRead::Ok => Ok(WheelReading {
                angle_rad: w.angle_rad,
                t_ns: w.reading_t_ns,
            }),
            RawRead::Unplugged => Err(WheelError::Fault(WheelFault::Unplugged)),
            RawRead::Silent => Err(WheelError::Fault(WheelFault::Silent)),
            RawRead::OutOfRange => Err(WheelError::Fault(WheelFault::OutOfRange)),
            RawRead::Error => Err(WheelError::Unsupported {
                device: "the recording".into(),
                reason: "a read failed without a fault".into(),
            }),
        }
    }

    /// Refused as the recorded wheel refused it (so a replay counts the same refusals and
    /// stops where the session did), else taken.
    fn command_torque(&mut self, _torque_nm: f64) -> Result<(), WheelError> {
        match self.now() {
            Some(t) if t.raw.wheel.write_failed => Err(WheelError::write_refused()),
            _ => Ok(()),
        }
    }

    fn max_torque_nm(&self) -> f64 {
        self.max_torque_nm
    }

    fn profile(&self) -> DeviceProfile {
        self.profile.clone()
    }

    fn motor_updates(&self) -> Option<MotorUpdates> {
        self.motor
    }
}

/// How the wheel's read came out, as recorded.
pub fn raw_read(read: &Result<WheelReading, WheelError>) -> RawRead {
    match read {
        Ok(_) => RawRead::Ok,
        Err(e) => match e.fault() {
            Some(WheelFault::Unplugged) => RawRead::Unplugged,
            Some(WheelFault::Silent) => RawRead::Silent,
            Some(WheelFault::OutOfRange) => RawRead::OutOfRange,
            _ => RawRead::Error,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use record::raw::BodyKindName;

    fn body(kind: BodyKindName, replug_grace_ns: Option<u64>) -> RecordedBody {
        let facts = BodyFacts {
            kind,
            wheel_profile: DeviceProfile::thesis_sidewinder(),
            wheel_max_torque_nm: 1.87,
            encoder_step_rad: 0.002_253,
            arm: None,
            replug_grace_ns,
        };
        RecordedBody::new(&facts, RecordedInputs::default(), Arc::default()).unwrap()
    }

    #[test]
    fn a_replay_waits_for_an_unplugged_wheel_as_long_as_the_recorded_session_did() {
        let configured = 30_000_000_000;
        // Recorded: whatever the configuration says now.
        for kind in [BodyKindName::Real, BodyKindName::Simulated] {
            assert_eq!(body(kind, Some(7)).replug_grace_ns(configured), 7);
        }
        // Recorded before the grace was: a real wheel was not waited for, a simulated one
        // was, for the configured grace.
        assert_eq!(
            body(BodyKindName::Real, None).replug_grace_ns(configured),
            0
        );
        assert_eq!(
            body(BodyKindName::Simulated, None).replug_grace_ns(configured),
            configured
        );
    }
}
