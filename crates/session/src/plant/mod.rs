//! The plant the haptic loop drives: a wheel and whoever holds it (a simulated patient on a
//! simulated wheel, or a real patient on a real force-feedback wheel), the car on the road,
//! and between them the haptic chain and the assist controller — the same code for both.
//! One [`Plant::tick`] is one haptic-loop period; it allocates nothing. It reads as its
//! stages: sense → exercise → assist → haptic chain and actuation → body → record.

mod body;
mod exercise;
mod health;

pub use health::MAX_REFUSED_WRITES_NS;
mod raw;
#[cfg(test)]
mod tests;

pub use body::Body;
use measures::ExerciseScores;

use crate::config::StationConfig;
use crate::course::Segment;
use anyhow::Context;
use arm::trunk_cue::TrunkCue;
use arm::{SetupStep, WheelNow};
use assist::Measurement;
use body::BodyMotion;
use exercise::{AssistStep, Exercise, ExerciseStep};
use haptic_wheel::{
    CeilingReport, HapticChain, HapticChainConfig, TickInput, TickTelemetry, WatchdogState,
    WheelFault, WheelReading,
};
use health::WheelHealth;
use raw::RawInputs;
use record::raw::{ANGLE_QUANTUM_RAD, RawRead, on_grid};
use record::{TickRecord, WheelSample};

/// The wheel as the plant was built around it: what a replay of the raw inputs needs.
#[derive(Clone, Debug, PartialEq)]
pub struct WheelFacts {
    /// The wheel's profile as the plant read it.
    pub profile: haptic_wheel::DeviceProfile,
    /// The usable maximum torque the backend reported, N·m.
    pub max_torque_nm: f64,
    /// The encoder step the velocity estimator was tuned for, rad.
    pub encoder_step_rad: f64,
}

/// Wheel, body and course, stepped together through the haptic chain.
pub struct Plant {
    body: Body,
    chain: HapticChain,
    exercise: Exercise,
    health: WheelHealth,
    raw: RawInputs,
    clock: LoopClock,
    /// The chain's velocity estimate of the last tick, rad/s (what the assist measures).
    velocity_rad_s: f64,
    watchdog: WatchdogState,
    /// The wheel's motor and usable torque, for the ceiling stated in the log and report.
    ceiling: CeilingReport,
    /// The wheel the plant was built around.
    wheel_facts: WheelFacts,
    /// The most torque updates a second the wheel's rate policy sends to its motor, Hz
    /// (read at start-up: the backend's capabilities allocate its name).
    motor_update_policy_hz: f64,
    /// How long an asked-for rest and a pause may last.
    break_settings: crate::course::BreakSettings,
    /// The patient's pedals as last read off the haptic thread.
    live_pedals: exercises::Pedals,
    /// The patient's own torque on the wheel, estimated from the wheel's dynamics and the
    /// torque sent (it observes only: nothing it computes is commanded).
    effort: assist::HandTorqueObserver,
    /// The gentle cue to sit up (it writes the arm sample's cue fields, nothing else).
    trunk_cue: TrunkCue,
}

/// The loop's ticks.
struct LoopClock {
    dt_s: f64,
    tick: u64,
    /// Ticks the exercise ran (not paused): the exercise clock.
    active_ticks: u64,
}

/// When a tick runs.
#[derive(Clone, Copy)]
struct LoopTime {
    /// The tick's number.
    tick: u64,
    /// Loop time, ns.
    t_ns: u64,
    /// The exercise clock, which stops while paused, s.
    t_s: f64,
    /// The loop period, s.
    dt_s: f64,
}

impl LoopClock {
    fn now(&self) -> LoopTime {
        let period_ns = (self.dt_s * 1e9).round() as u64;
        LoopTime {
            tick: self.tick,
            t_ns: self.tick * period_ns,
            t_s: (self.active_ticks * period_ns) as f64 * 1e-9,
            dt_s: self.dt_s,
        }
    }

    fn advance(&mut self, paused: bool) {
        self.tick += 1;
        self.active_ticks += u64::from(!paused);
    }
}

/// The wheel as the sense stage found it.
struct Sensed {
    /// The reading the chain may use.
    reading: Option<WheelReading>,
    /// The angle the exercise runs on (the last good one without a reading), rad.
    angle_rad: f64,
    /// How the read came out and the reading, as `/raw/wheel` records them.
    raw: (RawRead, Option<WheelReading>),
}

/// What the stages of one tick produced, for its record.
struct Stages {
    now: LoopTime,
    paused: bool,
    sensed: Sensed,
    exercise: ExerciseStep,
    assist: AssistStep,
    tel: TickTelemetry,
    motion: BodyMotion,
    /// The patient's torque estimate, N·m (`assist::HAND_ESTIMATE_LAG_S` before the tick;
    /// `None` at the end stop).
    hand_est_nm: Option<f64>,
}

impl Plant {
    /// The fully simulated plant of a validated `cfg` on `course`, run as fast as possible;
    /// all noise is seeded from `cfg.session.seed`.
    pub fn simulated(cfg: &StationConfig, course: Vec<Segment>) -> anyhow::Result<Self> {
        Self::new(
            cfg,
            Body::simulated(cfg, false, clock::Clock::real())?,
            course,
        )
    }

    /// The plant of a validated `cfg` around `body`, running `course` (at least one exercise).
    pub fn new(cfg: &StationConfig, body: Body, course: Vec<Segment>) -> anyhow::Result<Self> {
        anyhow::ensure!(!course.is_empty(), "a session needs at least one exercise");
        let mut body = body;
        let h = &cfg.haptic;
        let chain_cfg = HapticChainConfig {
            safety: h.safety,
            model: course[0].haptic.model,
            passivity: h.passivity_enabled.then_some(h.passivity),
            ..HapticChainConfig::for_encoder_step(body.encoder_step_rad(cfg))
        };
        let device_max = body.wheel().max_torque_nm();
        let capabilities = body.wheel().capabilities();
        let half_range_rad = capabilities.half_range_rad;
        for (i, seg) in course.iter().enumerate() {
            seg.haptic.validate(device_max).with_context(|| {
                format!(
                    "haptic settings of exercise {} ({})",
                    i + 1,
                    seg.exercise.name
                )
            })?;
        }
        let wheel_facts = WheelFacts {
            profile: body.wheel().profile(),
            max_torque_nm: device_max,
            encoder_step_rad: body.encoder_step_rad(cfg),
        };
        let mut chain = HapticChain::new(chain_cfg, device_max).context("haptic chain")?;
        let dt_s = 1.0 / cfg.session.loop_rate_hz;
        let effort = assist::HandTorqueObserver::new(
            body.wheel_dynamics(cfg, dt_s, half_range_rad),
            assist::ObserverTuning::default(),
        );
        chain
            .apply_regimen(&course[0].haptic)
            .context("haptic settings of the first exercise")?;
        // The road-feel law never asks more than the chain's ceiling at the start.
        let ceiling_nm = chain.ceiling_nm();
        let profile = body.wheel().profile();
        // The wheel's usable maximum is what the backend reports (its gain included).
        let ceiling = CeilingReport {
            usable_max_nm: device_max,
            ..CeilingReport::new(&profile, 1.0, None)
        }
        .with_ceiling(ceiling_nm);
        // An unplugged wheel is waited for: the simulated one answers again, a real one is
        // re-opened by its identity (`EvdevWheel::reopen_with`; a backend without it stays
        // lost and the grace runs out). A replay waits as long as the recorded session did.
        let configured_grace_ns = (h.replug_grace_s * 1e9).round() as u64;
        let replug_grace_ns = match &body {
            Body::Recorded(r) => r.replug_grace_ns(configured_grace_ns),
            _ => configured_grace_ns,
        };
        let trunk_cue = TrunkCue::new(course[0].trunk_cue_deg);
        Ok(Self {
            body,
            chain,
            exercise: Exercise::new(cfg, course, ceiling_nm),
            health: WheelHealth::new(half_range_rad, replug_grace_ns),
            raw: RawInputs::new(),
            clock: LoopClock {
                dt_s,
                tick: 0,
                active_ticks: 0,
            },
            velocity_rad_s: 0.0,
            watchdog: WatchdogState::SoftStart,
            ceiling,
            wheel_facts,
            motor_update_policy_hz: capabilities.max_update_rate_hz,
            break_settings: crate::course::BreakSettings {
                asked_rest_s: cfg.session.asked_rest_s,
                pause_limit_s: cfg.session.pause_limit_s,
            },
            live_pedals: exercises::Pedals::default(),
            effort,
            trunk_cue,
        })
    }

    /// The loop period, s.
    pub fn dt_s(&self) -> f64 {
        self.clock.dt_s
    }

    /// Every exercise of the course is done.
    pub fn course_done(&self) -> bool {
        self.exercise.course_done
    }

    /// The session's time is up: the exercise in progress ends with it (a strength test's
    /// side in progress stops at its time limit with what it measured).
    pub fn time_up(&mut self) {
        self.exercise.time_up();
    }

    /// Ask the safety supervisor to fade the torque out; [`Plant::stopped`] turns true
    /// when it reached zero.
    pub fn request_stop(&mut self) {
        self.raw.stop_requested = true;
        self.exercise.stop();
        self.chain.request_stop();
    }

    /// The wheel the plant was built around (for the recording's metadata).
    pub fn wheel_facts(&self) -> &WheelFacts {
        &self.wheel_facts
    }

    /// Pause the exercise (its clock, the car and the scores freeze and the torque fades to
    /// zero; the loop and the recording go on) or resume it (the torque soft-starts).
    pub fn set_paused(&mut self, paused: bool) {
        self.raw.paused = paused;
    }

    /// How long an asked-for rest and a pause may last (`[session]`).
    pub fn break_settings(&self) -> crate::course::BreakSettings {
        self.break_settings
    }

    /// The break after exercise `segment` of the course (0-based), if any.
    pub fn break_after(&self, segment: usize) -> Option<crate::course::Break> {
        self.exercise.break_after(segment)
    }

    /// Ticks the exercise has run, pauses excluded.
    pub fn active_ticks(&self) -> u64 {
        self.clock.active_ticks
    }

    /// The first fault the wheel reported, if any (the haptic loop ends the session on it).
    pub fn wheel_fault(&self) -> Option<WheelFault> {
        self.health.fault
    }

    /// The wheel is away (unplugged, within the replug grace) or settling after it came back.
    pub fn wheel_away(&self) -> bool {
        self.health.away()
    }

    /// Times the wheel was unplugged and came back within the replug grace.
    pub fn wheel_replugs(&self) -> u32 {
        self.health.replugs
    }

    /// Force commands the wheel refused so far (while it answered reads).
    pub fn write_failures(&self) -> u64 {
        self.health.write_failures
    }

    /// An arm sensor (IMU) is away mid-session and the exercise waits for it: the arm sensing
    /// lost it after it was working. Never in a replay, which pauses where the recorded
    /// session did ([`Self::arm_sensor_lost`] still counts there, so the session ends where
    /// the recorded one did).
    pub fn arm_sensor_away(&self) -> bool {
        !matches!(self.body, Body::Recorded(_)) && self.arm_sensor_lost()
    }

    /// The arm sensing has lost a sensor after it was working, live or replayed.
    pub fn arm_sensor_lost(&self) -> bool {
        self.body.arm_setup() == Some(SetupStep::SensorLost)
    }

    /// How long an unplugged wheel (or arm sensor) is waited for, ns.
    pub fn replug_grace_ns(&self) -> u64 {
        self.health.replug_grace_ns
    }

    /// The torque ceiling in force on this wheel now (a regimen may have lowered it), N·m and
    /// as a share of its motor.
    pub fn ceiling(&self) -> CeilingReport {
        self.ceiling.with_ceiling(self.chain.ceiling_nm())
    }

    /// The most torque updates a second the wheel's rate policy sends to its motor, Hz.
    pub fn motor_update_policy_hz(&self) -> f64 {
        self.motor_update_policy_hz
    }

    /// The supervisor has faded the torque to zero for good.
    pub fn stopped(&self) -> bool {
        self.watchdog == WatchdogState::Stopped
    }

    /// Advance one loop period: sense → exercise → assist → haptic chain and actuation →
    /// body → record.
    ///
    /// The IMUs are read after the torque is sent: the wheel is read first (stage 1) and
    /// the torque computed from it goes out in stage 4, before anything else may delay it;
    /// the arm's IMUs are read in stage 5, with the body, so the arm sample of a tick is
    /// later than its wheel reading.
    pub fn tick(&mut self) -> TickRecord {
        let now = self.clock.now();
        self.follow_recorded_pause();
        // The exercise waits while the patient pauses it or the arm set-up asks them to do
        // something else; the torque fades out meanwhile, so the wheel turns freely…
        let setup = self.body.arm_setup().filter(|s| s.in_progress());
        // …and while the wheel is away or settling after it came back.
        let paused = self.raw.paused || setup.is_some() || self.health.away();
        self.chain.set_paused(paused);
        // 1. Read the wheel as the host sees it (quantised, delayed).
        let sensed = self.sense(now.t_ns);
        // 2. The exercise: drive the car with the wheel, or show the dial's desired angle.
        let pedals = self.pedals_now(now.dt_s);
        self.exercise.ceiling_nm = self.chain.ceiling_nm();
        let exercise = self.exercise.step(sensed.angle_rad, paused, now, pedals);
        // 3. The assist controller helps towards the exercise's target.
        let measured = Measurement {
            angle_rad: sensed.angle_rad,
            vel_rad_s: self.velocity_rad_s,
        };
        let ceiling_nm = self.chain.ceiling_nm();
        let assist = self
            .exercise
            .assist(&exercise, measured, ceiling_nm, paused, now.dt_s);
        if exercise.finished {
            self.next_segment(now.t_s + now.dt_s);
        }
        // 4. Haptic chain: model + road feel + assist → passivity → safety supervisor; the
        //    torque goes to the wheel.
        let tel = self.actuate(sensed.reading, exercise.road_feel_nm + assist.out.torque_nm);
        //    The patient's torque from the angle read and the torques sent (eq. E.2).
        let read_rad = sensed.reading.map_or(f64::NAN, |r| r.angle_rad);
        let hand_est_nm = self.effort.step(read_rad, now.dt_s);
        self.effort.commit(tel.torque_nm);
        // 5. Whoever holds the wheel moves it (following the arm set-up's prompts first); the
        //    arm's IMUs are read here.
        let aim_rad = aim_rad(setup, exercise.target_rad, now);
        let mut motion = self.body.move_to(
            aim_rad,
            WheelNow {
                t_ns: now.t_ns,
                angle_rad: sensed.angle_rad,
                rate_rad_s: tel.vel_rad_s,
                dt_s: now.dt_s,
            },
        );
        //    The trunk watched for the gentle cue to sit up, after the torque went out: it
        //    only writes the arm sample's cue fields.
        let running =
            !(paused || exercise.finished || self.exercise.course_done || self.raw.stop_requested);
        self.trunk_cue.step(motion.arm.as_mut(), running, now.dt_s);
        // 6. Record what every stage did, and the raw inputs.
        let rec = self.record(Stages {
            now,
            paused,
            sensed,
            exercise,
            assist,
            tel,
            motion,
            hand_est_nm,
        });
        self.clock.advance(paused);
        rec
    }

    /// Where the patient's pedals are now (read off the haptic thread, see
    /// [`crate::Controls::pedals`]); a simulated foot or a replay sets its own.
    pub fn set_pedals(&mut self, pedals: exercises::Pedals) {
        self.live_pedals = pedals.clamped();
    }

    /// The pedals this tick: the simulated foot's (aiming at the exercise's speed), the
    /// recording's, or the patient's as last read; released while the exercise in progress
    /// is not driven with the pedals, for a simulated foot.
    fn pedals_now(&mut self, dt_s: f64) -> exercises::Pedals {
        let speeds = self.exercise.pedal_speeds_m_s();
        let p = self.body.pedals(speeds, self.live_pedals, dt_s);
        // On the recording's grid: what a replay reads back is what drove the car.
        self.raw.pedals = exercises::Pedals {
            throttle: on_grid(p.throttle, record::raw::PEDAL_QUANTUM),
            brake: on_grid(p.brake, record::raw::PEDAL_QUANTUM),
        };
        self.raw.pedals
    }

    /// Each exercise's own scores so far, of the exercises started (in course order), handed
    /// over once, at the session's end (it allocates nothing).
    pub fn exercise_scores(&mut self) -> Vec<ExerciseScores> {
        self.exercise.exercise_scores()
    }

    /// A replay pauses where the patient did.
    fn follow_recorded_pause(&mut self) {
        if let Body::Recorded(r) = &self.body {
            self.raw.paused = r.paused();
        }
    }

    /// Stage 1: read the wheel at loop time `t_ns`, its angle on the recording's grid (the
    /// device edge) so that `/raw/wheel` holds exactly what the chain consumes.
    fn sense(&mut self, t_ns: u64) -> Sensed {
        let read = self.body.wheel().read().map(|r| WheelReading {
            angle_rad: on_grid(r.angle_rad, ANGLE_QUANTUM_RAD),
            ..r
        });
        let raw = (
            crate::recorded::raw_read(&read),
            read.as_ref().ok().copied(),
        );
        let reading = self.health.reading(read, t_ns);
        Sensed {
            reading,
            angle_rad: self.health.angle_rad(reading),
            raw,
        }
    }

    /// Move on to the next exercise at exercise time `t_s` (its haptic settings with it), or
    /// mark the course done after the last one.
    fn next_segment(&mut self, t_s: f64) {
        self.body.restart_trunk();
        if let Some(regimen) = self.exercise.next_segment(t_s) {
            // Validated when the session started; a refusal keeps the previous settings.
            let _ = self.chain.apply_regimen(regimen);
        }
        self.trunk_cue.next_exercise(self.exercise.trunk_cue_deg());
    }

    /// Gentle cues to sit up given so far.
    pub fn trunk_cues(&self) -> u64 {
        self.trunk_cue.cues()
    }

    /// Stage 4: the haptic chain turns `reading` and the `external_nm` torque (road feel and
    /// assist) into the torque the wheel is sent.
    fn actuate(&mut self, reading: Option<WheelReading>, external_nm: f64) -> TickTelemetry {
        let tel = self.chain.tick(TickInput {
            now_ns: self.body.now_ns(),
            reading,
            external_nm,
        });
        self.velocity_rad_s = tel.vel_rad_s;
        self.watchdog = tel.watchdog;
        self.health.supervisor_is(tel.watchdog);
        // Firmware effects play only while the supervisor runs at full scale. A refused
        // command is counted and recorded; a run of them is a fault (the wheel's health).
        let wheel = self.body.wheel();
        wheel.set_firmware_effects_active(tel.watchdog == WatchdogState::Running);
        let ceiling = wheel.set_torque_ceiling_nm(self.chain.ceiling_nm());
        let command = wheel.command_torque(tel.torque_nm);
        let taken = ceiling.is_ok() && command.is_ok();
        self.raw.write_failed = !taken;
        self.health.wrote(taken, tel.now_ns);
        tel
    }

    /// Stage 6: the tick's record.
    fn record(&mut self, stages: Stages) -> TickRecord {
        let Stages {
            now,
            paused,
            sensed,
            exercise,
            assist,
            tel,
            motion,
            hand_est_nm,
        } = stages;
        let updates = self.body.wheel().motor_updates();
        TickRecord {
            tick: now.tick,
            t_ns: now.t_ns,
            wheel: WheelSample {
                angle_rad: sensed.angle_rad,
                velocity_rad_s: tel.vel_rad_s,
                model_nm: tel.model_nm,
                road_feel_nm: exercise.road_feel_nm,
                requested_nm: tel.requested_nm,
                commanded_nm: tel.torque_nm,
                clipped: tel.clipped,
                safety_scale: tel.safety_scale,
                watchdog: tel.watchdog.into(),
                passivity_energy_j: tel.passivity_energy_j,
                passivity_damping_nm_s_per_rad: tel.passivity_damping_nm_s_per_rad,
                true_angle_rad: motion.true_angle_rad,
                hand_nm: motion.hand_nm,
                hand_est_nm,
                target_rad: exercise.target_rad,
                ceiling_nm: self.chain.ceiling_nm(),
                motor_rating_known: !self.ceiling.assumed,
                motor_updates: updates.map_or(0, |u| u.count),
                motor_update_worst_gap_ms: updates.map(|u| u.worst_gap_ms()),
                write_failures: self.health.write_failures,
            },
            vehicle: exercise.vehicle,
            score: self.exercise.score(exercise.segment_index, now.t_s, paused),
            assist: assist.sample(),
            arm: motion.arm,
            timing: Default::default(),
            raw: self.raw.tick(sensed.raw, tel.now_ns, motion.seam),
        }
    }

    /// Range of motion of each estimated joint angle so far, rad (order of
    /// `gyro_imu::arm::JointAngles::NAMES`); `None` without arm sensing.
    pub fn range_of_motion_rad(&self) -> Option<[f64; 5]> {
        self.body.range_of_motion_rad()
    }

    /// Why arm sensing stopped or never started, if it did.
    pub fn arm_failure(&self) -> Option<&arm::ArmFailure> {
        self.body.arm_failure()
    }

    /// Command zero torque directly and stop firmware effects (every exit path calls it;
    /// dropping the plant does too).
    pub fn zero_torque(&mut self) {
        self.body.wheel().set_firmware_effects_active(false);
        let _ = self.body.wheel().command_torque(0.0);
    }
}

/// Where whoever holds the wheel aims it, rad: the exercise's `target_rad`, or what the arm
/// set-up's `setup` step asks for.
fn aim_rad(setup: Option<SetupStep>, target_rad: f64, now: LoopTime) -> f64 {
    match setup {
        Some(SetupStep::TurnWheel { .. }) => {
            // Slowly left and right, about ±60°.
            let t = now.tick as f64 * now.dt_s;
            1.05 * (std::f64::consts::TAU * 0.2 * t).sin()
        }
        Some(_) => 0.0,
        None => target_rad,
    }
}
