//! The plant the haptic loop drives: a wheel and whoever holds it (a simulated patient on a
//! simulated wheel, or a real patient on a real force-feedback wheel), the car on the road,
//! and between them the haptic chain and the assist controller — the same code for both.
//! One [`Plant::tick`] is one haptic-loop period; it allocates nothing.

use crate::config::StationConfig;
use crate::session::arm::sim::SimArmSensing;
use crate::session::arm::{ArmSeam, SetupStep, WheelNow};
use crate::session::course::Segment;
use crate::session::faults::FaultyWheel;
use anyhow::Context;
use assist::{HumanArm, Limits, Measurement};
use haptic_wheel::{
    CeilingReport, HapticChain, HapticChainConfig, SimWheel, TickInput, WatchdogState, Wheel,
    WheelFault, WheelReading, ZeroTorqueOnDrop,
};
use record::raw::{
    ANGLE_QUANTUM_RAD, RawImuSample, RawRead, RawTick, RawWheelSample, TORQUE_QUANTUM_NM, on_grid,
    same_sample,
};
use record::{ArmSample, AssistSample, ScoreSample, TickRecord, VehicleSample, WheelSample};
use vehicle::{
    AligningTorque, DialScore, DrivingScore, PreviewDriver, Projection, SpeedController,
};

/// Who holds the wheel.
// One body per session, built once and never moved on the hot path: its size does not matter.
#[allow(clippy::large_enum_variant)]
pub enum Body {
    /// A simulated wheel held by a simulated patient who wears simulated IMUs.
    Sim {
        /// The simulated wheel (zero torque when dropped), failing as the session's injected
        /// faults say.
        wheel: ZeroTorqueOnDrop<FaultyWheel<SimWheel>>,
        /// The simulated patient's arm control.
        arm: HumanArm,
        /// The simulated arm kinematics, IMUs and pose estimator.
        sensing: Box<SimArmSensing>,
    },
    /// A real force-feedback wheel (Linux kernel FF API) held by the patient, who may wear
    /// two controller IMUs.
    #[cfg(target_os = "linux")]
    Evdev {
        /// The device (zero torque, effects erased and gain restored when dropped). Boxed so
        /// that the kernel backend can run over any device seam (tests use an in-memory one).
        wheel: ZeroTorqueOnDrop<Box<dyn Wheel + Send>>,
        /// The arm's IMUs, when two are present.
        arm: Option<Box<crate::session::arm::hid::HidArmSensing>>,
        /// The clock of the wheel's readings.
        clock: clock::Clock,
    },
    /// A recording's raw inputs played back (`telerehab replay`).
    Recorded(Box<crate::session::recorded::RecordedBody>),
}

impl Body {
    /// The simulated body of `cfg`, seeded from `cfg.session.seed`; `real_time` when the
    /// session runs on the wall clock; `clock` is the session's.
    pub fn simulated(
        cfg: &StationConfig,
        real_time: bool,
        clock: clock::Clock,
    ) -> anyhow::Result<Self> {
        let dt_s = 1.0 / cfg.session.loop_rate_hz;
        let mut wheel_params = cfg.sim_wheel.clone();
        wheel_params.seed = cfg.session.seed;
        Ok(Body::Sim {
            wheel: ZeroTorqueOnDrop::new(FaultyWheel::new(
                SimWheel::new(wheel_params),
                &cfg.faults,
            )),
            arm: HumanArm::new(cfg.sim_patient.clone(), dt_s, cfg.session.seed),
            sensing: Box::new(
                SimArmSensing::new(
                    cfg.sim_arm,
                    cfg.arm.sim_mounting,
                    cfg.session.seed,
                    real_time,
                    clock,
                    &cfg.faults,
                )
                .context("simulated arm")?,
            ),
        })
    }

    /// The first force-feedback wheel found, and the first two controller IMUs if there are
    /// two (see `telerehab devices`). `clock` is the session's (a real one: real devices stamp
    /// their readings on it).
    #[cfg(target_os = "linux")]
    pub fn first_real_wheel(cfg: &StationConfig, clock: clock::Clock) -> anyhow::Result<Self> {
        use haptic_wheel::evdev_wheel::rejoin::{KernelFinder, RESCAN_EVERY};
        use haptic_wheel::evdev_wheel::{EvdevWheel, monotonic_ns};
        let wheel = EvdevWheel::open_first(cfg.wheel.clone(), clock.clone())
            .context("no usable force-feedback wheel (run `telerehab devices`)")?
            // Unplugged and plugged back in, it is found again (within the replug grace).
            .reopen_with(KernelFinder, RESCAN_EVERY)
            .context("cannot watch for the wheel being plugged back in")?;
        // Arm sensing is optional: an IMU that cannot be opened (permissions, a flat battery)
        // costs the joint angles, not the exercise.
        let arm = crate::session::arm::hid::HidArmSensing::open_first_two(
            cfg.arm.geometry,
            cfg.arm.swivel_rad,
            monotonic_ns,
            clock.clone(),
        )
        .unwrap_or_else(|e| {
            tracing::warn!("no arm sensing this session: {e:#}");
            None
        })
        .map(Box::new);
        Ok(Self::real_wheel(Box::new(wheel), arm, clock))
    }

    /// A real wheel backend (already opened) held by a patient, with optional arm sensing;
    /// `clock` is the clock of the wheel's readings.
    #[cfg(target_os = "linux")]
    pub fn real_wheel(
        wheel: Box<dyn Wheel + Send>,
        arm: Option<Box<crate::session::arm::hid::HidArmSensing>>,
        clock: clock::Clock,
    ) -> Self {
        Body::Evdev {
            wheel: ZeroTorqueOnDrop::new(wheel),
            arm,
            clock,
        }
    }

    /// Where the arm sensing is; `None` without IMUs.
    fn arm_setup(&self) -> Option<SetupStep> {
        match self {
            Body::Sim { sensing, .. } => Some(sensing.setup_step()),
            #[cfg(target_os = "linux")]
            Body::Evdev { arm, .. } => arm.as_ref().map(|a| a.setup_step()),
            Body::Recorded(r) => r.arm_setup(),
        }
    }

    fn wheel(&mut self) -> &mut dyn Wheel {
        match self {
            Body::Sim { wheel, .. } => &mut **wheel,
            #[cfg(target_os = "linux")]
            Body::Evdev { wheel, .. } => &mut **wheel,
            Body::Recorded(r) => &mut **r,
        }
    }

    /// Now, ns, on the clock of the wheel's readings.
    fn now_ns(&self) -> u64 {
        match self {
            Body::Sim { wheel, .. } => wheel.time_ns(),
            #[cfg(target_os = "linux")]
            Body::Evdev { clock, .. } => clock.now_ns(),
            Body::Recorded(r) => r.now_ns(),
        }
    }

    /// The encoder step of the wheel, rad (tunes the velocity estimator).
    fn encoder_step_rad(&self, cfg: &StationConfig) -> f64 {
        match self {
            Body::Sim { .. } => cfg.sim_wheel.encoder_step_rad,
            #[cfg(target_os = "linux")]
            Body::Evdev { wheel, .. } => wheel.profile().ka_rad_per_unit,
            Body::Recorded(r) => r.encoder_step_rad(),
        }
    }
}

/// What the body did this tick (simulation only: a real patient is not observed this way),
/// and what the arm tracker was handed.
struct BodyMotion {
    hand_nm: Option<f64>,
    true_angle_rad: Option<f64>,
    arm: Option<ArmSample>,
    seam: Option<ArmSeam>,
}

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
    course: Vec<Segment>,
    segment: usize,
    segment_start_s: f64,
    course_done: bool,
    driver: PreviewDriver,
    cruise: SpeedController,
    feel: AligningTorque,
    projection: Projection,
    driving: DrivingScore,
    dial: DialScore,
    params: vehicle::VehicleParams,
    slew_nm_per_s: f64,
    dt_s: f64,
    tick: u64,
    /// Ticks the exercise ran (not paused): the exercise clock.
    active_ticks: u64,
    /// The patient paused the exercise.
    paused: bool,
    /// Where the patient aimed last, rad (held while paused).
    last_target_rad: f64,
    velocity_rad_s: f64,
    watchdog: WatchdogState,
    /// The first fault the wheel reported (unplugged past the replug grace, silent, out of
    /// range): the session ends on it, and says why.
    wheel_fault: Option<WheelFault>,
    /// When the wheel went away (unplugged), ns of loop time: it has the replug grace to come
    /// back, the exercise paused and the torque at zero meanwhile.
    wheel_gone_since_ns: Option<u64>,
    /// The wheel came back: the exercise stays paused until the supervisor's fault has
    /// cleared, then resumes with a soft start (never a torque step).
    wheel_settling: bool,
    /// Times the wheel went away and came back within the grace.
    wheel_replugs: u32,
    /// `[haptic] replug_grace_s`, ns.
    replug_grace_ns: u64,
    /// Tells a saturated encoder from a wheel turned to its end.
    plausibility: AnglePlausibility,
    /// The last finite wheel angle read, rad (what the car steers by without a reading).
    last_angle_rad: f64,
    /// The wheel's motor and usable torque, for the ceiling stated in the log and report.
    ceiling: CeilingReport,
    /// A stop has been asked for (recorded on `/raw/wheel`).
    stop_requested: bool,
    /// The IMU samples last recorded on `/raw/imu`, per sensor (a held one is not repeated).
    last_imu: [Option<gyro_imu::device::ImuSample>; 2],
    /// The wheel the plant was built around.
    wheel_facts: WheelFacts,
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
        let half_range_rad = body.wheel().capabilities().half_range_rad;
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
        let mut plant = Self {
            body,
            chain,
            course,
            segment: 0,
            segment_start_s: 0.0,
            course_done: false,
            driver: PreviewDriver::default(),
            cruise: SpeedController {
                target_m_s: 0.0,
                gain_n_per_m_s: 2000.0,
                max_force_n: 8000.0,
            },
            feel: AligningTorque {
                nm_per_kn: h.road_feel_nm_per_kn,
                max_torque_nm: ceiling_nm,
            },
            projection: Projection::default(),
            driving: DrivingScore::default(),
            dial: DialScore::default(),
            params: cfg.vehicle.clone(),
            slew_nm_per_s: h.safety.slew_nm_per_s,
            dt_s: 1.0 / cfg.session.loop_rate_hz,
            tick: 0,
            active_ticks: 0,
            paused: false,
            last_target_rad: 0.0,
            velocity_rad_s: 0.0,
            watchdog: WatchdogState::SoftStart,
            wheel_fault: None,
            wheel_gone_since_ns: None,
            wheel_settling: false,
            wheel_replugs: 0,
            replug_grace_ns,
            plausibility: AnglePlausibility::new(half_range_rad),
            last_angle_rad: 0.0,
            ceiling,
            stop_requested: false,
            last_imu: [None; 2],
            wheel_facts,
        };
        plant.projection = plant.start_projection();
        Ok(plant)
    }

    fn start_projection(&self) -> Projection {
        let seg = &self.course[self.segment];
        match &seg.exercise.road {
            Some(road) => {
                let s = seg.exercise.start_state();
                road.project(s.x_m, s.y_m, 0.0)
            }
            None => Projection::default(),
        }
    }

    /// The loop period, s.
    pub fn dt_s(&self) -> f64 {
        self.dt_s
    }

    /// Every exercise of the course is done.
    pub fn course_done(&self) -> bool {
        self.course_done
    }

    /// Ask the safety supervisor to fade the torque out; [`Plant::stopped`] turns true
    /// when it reached zero.
    pub fn request_stop(&mut self) {
        self.stop_requested = true;
        self.chain.request_stop();
    }

    /// The wheel the plant was built around (for the recording's metadata).
    pub fn wheel_facts(&self) -> &WheelFacts {
        &self.wheel_facts
    }

    /// Pause the exercise (its clock, the car and the scores freeze and the torque fades to
    /// zero; the loop and the recording go on) or resume it (the torque soft-starts).
    pub fn set_paused(&mut self, paused: bool) {
        self.paused = paused;
    }

    /// Ticks the exercise has run, pauses excluded.
    pub fn active_ticks(&self) -> u64 {
        self.active_ticks
    }

    /// The first fault the wheel reported, if any (the haptic loop ends the session on it).
    pub fn wheel_fault(&self) -> Option<WheelFault> {
        self.wheel_fault
    }

    /// The wheel is away (unplugged, within the replug grace) or settling after it came back.
    pub fn wheel_away(&self) -> bool {
        self.wheel_gone_since_ns.is_some() || self.wheel_settling
    }

    /// Times the wheel was unplugged and came back within the replug grace.
    pub fn wheel_replugs(&self) -> u32 {
        self.wheel_replugs
    }

    /// How long an unplugged wheel is waited for, ns.
    pub fn replug_grace_ns(&self) -> u64 {
        self.replug_grace_ns
    }

    /// A read of the wheel failed with `e` at loop time `t_ns`. An unplugged wheel has the
    /// replug grace to come back (the exercise paused meanwhile); any other fault, or the
    /// grace over, ends the session. No allocation: a running wheel's faults are `Copy`.
    fn wheel_failed(&mut self, e: &haptic_wheel::WheelError, t_ns: u64) {
        match e.fault() {
            Some(WheelFault::Unplugged) if self.wheel_fault.is_none() => {
                let since = *self.wheel_gone_since_ns.get_or_insert(t_ns);
                if t_ns - since >= self.replug_grace_ns {
                    self.wheel_fault = Some(WheelFault::Unplugged);
                }
            }
            fault => self.wheel_fault = self.wheel_fault.or(fault),
        }
    }

    /// The wheel answered a read: if it was away it is back, and the exercise resumes once
    /// the supervisor's fault has cleared.
    fn wheel_back(&mut self) {
        if self.wheel_gone_since_ns.take().is_some() {
            self.wheel_settling = true;
            self.wheel_replugs += 1;
        }
    }

    /// The torque ceiling in force on this wheel now (a regimen may have lowered it), N·m and
    /// as a share of its motor.
    pub fn ceiling(&self) -> CeilingReport {
        self.ceiling.with_ceiling(self.chain.ceiling_nm())
    }

    /// The supervisor has faded the torque to zero for good.
    pub fn stopped(&self) -> bool {
        self.watchdog == WatchdogState::Stopped
    }

    /// Move on to the next exercise, or mark the course done after the last one.
    fn next_segment(&mut self, t_s: f64) {
        if self.segment + 1 >= self.course.len() {
            self.course_done = true;
            return;
        }
        self.segment += 1;
        self.segment_start_s = t_s;
        self.projection = self.start_projection();
        // Validated when the session started; a refusal keeps the previous settings.
        let _ = self.chain.apply_regimen(&self.course[self.segment].haptic);
    }

    /// Advance one loop period.
    pub fn tick(&mut self) -> TickRecord {
        let dt = self.dt_s;
        let period_ns = (dt * 1e9).round() as u64;
        let t_ns = self.tick * period_ns;
        // The exercise runs on its own clock, which stops while paused.
        let t_s = (self.active_ticks * period_ns) as f64 * 1e-9;
        self.follow_recorded_pause();
        // The exercise waits while the patient pauses it or the arm set-up asks them to do
        // something else; the torque fades out meanwhile, so the wheel turns freely.
        let setup = self.body.arm_setup().filter(|s| s.in_progress());
        // …and while the wheel is away or settling after it came back.
        let paused = self.paused || setup.is_some() || self.wheel_away();
        self.chain.set_paused(paused);
        // 1. Read the wheel as the host sees it (quantised, delayed).
        let (read, raw_read) = self.read_wheel();
        let reading = match read {
            Ok(r) if r.angle_rad.is_finite() && self.plausibility.accept(&r) => Some(r),
            // A NaN or infinite angle is no reading, nor is a clipped (saturated) one: the
            // supervisor fades the torque out as for a stale one, and the car keeps the last
            // good angle.
            Ok(_) => None,
            Err(e) => {
                self.wheel_failed(&e, t_ns);
                None
            }
        };
        let angle = reading.map_or(self.last_angle_rad, |r| r.angle_rad);
        self.last_angle_rad = angle;

        // 2. The exercise: drive the car with the wheel, or show the dial's desired angle.
        //    `target` is where an ideal patient would hold the wheel: the reference for
        //    assistance and the simulated patient's intention.
        let seg = &mut self.course[self.segment];
        let t_in = t_s - self.segment_start_s;
        let (target, road_feel, vehicle, finished) = match (&mut seg.world, &seg.exercise.road) {
            (Some(world), Some(_)) if paused => {
                let steer = self.params.road_wheel_angle_rad(angle);
                let vehicle = vehicle_sample(world, steer, &self.projection);
                (self.last_target_rad, 0.0, Some(vehicle), false)
            }
            _ if paused => (self.last_target_rad, 0.0, None, false),
            (Some(world), Some(road)) => {
                let steer = self.params.road_wheel_angle_rad(angle);
                let st = world.state();
                self.cruise.target_m_s = seg.exercise.target_speed_m_s(self.projection.s_m);
                world.step(self.cruise.input(st.ux_m_s, steer), dt);
                let st = world.state();
                self.projection = road.project(st.x_m, st.y_m, self.projection.s_m);
                // Drained in place: no allocation on a contact tick.
                for event in world.drain_events() {
                    self.driving.record(&event);
                }
                self.driving
                    .update(&self.projection, st.yaw_rad, seg.exercise.lane_width_m, dt);
                let fyf = world.tyre_forces().front_lateral_n;
                let desired = self.driver.desired_steer_rad(
                    &self.params,
                    &st,
                    &self.projection,
                    road.as_ref(),
                );
                let vehicle = vehicle_sample(world, steer, &self.projection);
                (
                    self.params.hand_wheel_angle_rad(desired),
                    // Self-aligning road feel from the front lateral tyre force (§3.3.4).
                    self.feel.torque_nm(fyf),
                    Some(vehicle),
                    seg.exercise.is_finished(t_in, self.projection.s_m),
                )
            }
            _ => {
                let desired = seg.exercise.desired_angle_rad(t_in).unwrap_or(0.0);
                self.dial.update(desired, angle, dt);
                (desired, 0.0, None, seg.exercise.is_finished(t_in, 0.0))
            }
        };
        self.last_target_rad = target;
        let seg_assisted = seg.assist.is_some();
        let assist_out = match &mut seg.assist {
            Some(a) if !paused => {
                // The assist gets the torque budget the road feel leaves under the chain's
                // ceiling now (a regimen may have lowered it): the chain's limiter would
                // otherwise clip torque the assist believes it delivered.
                let limits = Limits {
                    ceiling_nm: (self.chain.ceiling_nm() - road_feel.abs()).max(0.0),
                    slew_nm_per_s: self.slew_nm_per_s,
                };
                let m = Measurement {
                    angle_rad: angle,
                    vel_rad_s: self.velocity_rad_s,
                };
                a.step(m, target, limits, dt)
            }
            _ => Default::default(),
        };
        let segment_index = self.segment as u32;
        if finished {
            self.next_segment(t_s + dt);
        }

        // 3. Haptic chain: model + road feel + assist → passivity → safety supervisor.
        let tel = self.chain.tick(TickInput {
            now_ns: self.body.now_ns(),
            reading,
            external_nm: road_feel + assist_out.torque_nm,
        });
        self.velocity_rad_s = tel.vel_rad_s;
        self.watchdog = tel.watchdog;
        // The fault after a replug has cleared: resume (from paused, so with a soft start).
        self.wheel_settling &= tel.watchdog != WatchdogState::Paused;
        // Firmware effects play only while the supervisor runs at full scale; a failed
        // command is caught by the next read (stale reading → supervisor fault).
        let wheel = self.body.wheel();
        wheel.set_firmware_effects_active(tel.watchdog == WatchdogState::Running);
        let _ = wheel.set_torque_ceiling_nm(self.chain.ceiling_nm());
        let _ = wheel.command_torque(tel.torque_nm);

        // 4. Whoever holds the wheel moves it (following the arm set-up's prompts first).
        let aim = match setup {
            Some(SetupStep::TurnWheel { .. }) => {
                // Slowly left and right, about ±60°.
                let t = self.tick as f64 * dt;
                1.05 * (std::f64::consts::TAU * 0.2 * t).sin()
            }
            Some(_) => 0.0,
            None => target,
        };
        let motion = self.move_body(
            aim,
            WheelNow {
                t_ns,
                angle_rad: angle,
                rate_rad_s: tel.vel_rad_s,
                dt_s: dt,
            },
        );

        let lane = self.driving.lane();
        let dial = self.dial.summary();
        let rec = TickRecord {
            tick: self.tick,
            t_ns,
            wheel: WheelSample {
                angle_rad: angle,
                velocity_rad_s: tel.vel_rad_s,
                model_nm: tel.model_nm,
                road_feel_nm: road_feel,
                requested_nm: tel.requested_nm,
                commanded_nm: tel.torque_nm,
                clipped: tel.clipped,
                safety_scale: tel.safety_scale,
                watchdog: tel.watchdog.into(),
                passivity_energy_j: tel.passivity_energy_j,
                passivity_damping_nm_s_per_rad: tel.passivity_damping_nm_s_per_rad,
                true_angle_rad: motion.true_angle_rad,
                hand_nm: motion.hand_nm,
                target_rad: target,
                ceiling_nm: self.chain.ceiling_nm(),
                motor_rating_known: !self.ceiling.assumed,
            },
            vehicle,
            score: ScoreSample {
                exercise_index: segment_index,
                rms_lateral_m: lane.rms_m(),
                max_lateral_m: lane.max_abs_m(),
                pct_in_lane: lane.pct_in_lane(),
                cone_hits: self.driving.summary().cone_hits,
                dial_rms_error_deg: dial.rms_error_deg,
                active_s: t_s,
                paused,
            },
            assist: AssistSample {
                active: seg_assisted,
                torque_nm: assist_out.torque_nm,
                reference_rad: assist_out.reference_rad,
                error_rad: assist_out.error_rad,
                assistance_level: assist_out.assistance_level,
                saturated: assist_out.saturated,
            },
            arm: motion.arm,
            timing: Default::default(),
            raw: self.raw_tick(raw_read, tel.now_ns, motion.seam),
        };
        self.tick += 1;
        self.active_ticks += u64::from(!paused);
        rec
    }

    /// A replay pauses where the patient did.
    fn follow_recorded_pause(&mut self) {
        if let Body::Recorded(r) = &self.body {
            self.paused = r.paused();
        }
    }

    /// Read the wheel, its angle on the recording's grid (the device edge) so that
    /// `/raw/wheel` holds exactly what the chain consumes (a wheel that answers is back); also
    /// how the read came out and the reading, as recorded.
    fn read_wheel(
        &mut self,
    ) -> (
        Result<WheelReading, haptic_wheel::WheelError>,
        (RawRead, Option<WheelReading>),
    ) {
        let read = self.body.wheel().read().map(|r| WheelReading {
            angle_rad: on_grid(r.angle_rad, ANGLE_QUANTUM_RAD),
            ..r
        });
        if read.is_ok() {
            self.wheel_back();
        }
        let raw = (
            crate::session::recorded::raw_read(&read),
            read.as_ref().ok().copied(),
        );
        (read, raw)
    }

    /// This tick's raw inputs: how the wheel's read came out and its reading (`read`), the
    /// body clock the chain ran at (`now_ns`), the patient's pause and stop, and what the arm
    /// tracker was handed (`seam`).
    fn raw_tick(
        &mut self,
        read: (RawRead, Option<WheelReading>),
        now_ns: u64,
        seam: Option<ArmSeam>,
    ) -> RawTick {
        let (read, reading) = read;
        RawTick {
            wheel: RawWheelSample {
                read,
                angle_rad: reading.map_or(0.0, |r| r.angle_rad),
                reading_t_ns: reading.map_or(0, |r| r.t_ns),
                now_ns,
                paused: self.paused,
                stop: self.stop_requested,
                arm_stepped: seam.is_some_and(|s| s.stepped.is_some()),
                arm_lost: seam.is_some_and(|s| s.lost),
                arm_regained: seam.is_some_and(|s| s.regained),
                solver_answered: seam.is_some_and(|s| s.solver_answered),
                solver_timed_out: seam.is_some_and(|s| s.solver_timed_out),
            },
            imu: self.new_imu_samples(seam),
        }
    }

    /// The IMU samples the tracker was stepped with this tick that `/raw/imu` does not hold
    /// yet (a sample held over ticks is recorded once).
    fn new_imu_samples(&mut self, seam: Option<ArmSeam>) -> [Option<RawImuSample>; 2] {
        let mut out = [None; 2];
        if let Some((a, b)) = seam.and_then(|s| s.stepped) {
            for (i, s) in [a, b].into_iter().enumerate() {
                if !self.last_imu[i].is_some_and(|last| same_sample(&last, &s)) {
                    self.last_imu[i] = Some(s);
                    out[i] = Some(RawImuSample::of(i as u32, &s));
                }
            }
        }
        out
    }

    /// The simulated patient looks at the road and moves the simulated wheel, and the arm
    /// pose is estimated from the simulated IMUs; a real patient moves a real wheel alone.
    fn move_body(&mut self, target_rad: f64, read: WheelNow) -> BodyMotion {
        let dt = read.dt_s;
        match &mut self.body {
            Body::Sim {
                wheel,
                arm,
                sensing,
            } => {
                let hand = arm.step(
                    target_rad,
                    wheel.true_angle_rad(),
                    wheel.true_velocity_rad_s(),
                    dt,
                );
                wheel.advance(dt, hand);
                let sample =
                    sensing.step(wheel.true_angle_rad(), wheel.true_velocity_rad_s(), read);
                // What the simulation alone observes, on the recording's grid: a replay of
                // the raw inputs takes it from the recording, and the measures must agree.
                BodyMotion {
                    hand_nm: Some(on_grid(hand, TORQUE_QUANTUM_NM)),
                    true_angle_rad: Some(on_grid(wheel.true_angle_rad(), ANGLE_QUANTUM_RAD)),
                    arm: Some(sample),
                    seam: Some(sensing.take_seam()),
                }
            }
            #[cfg(target_os = "linux")]
            Body::Evdev { arm, .. } => BodyMotion {
                hand_nm: None,
                true_angle_rad: None,
                arm: arm.as_mut().map(|a| a.step(read)),
                seam: arm.as_mut().map(|a| a.take_seam()),
            },
            Body::Recorded(r) => {
                let m = r.step(read);
                BodyMotion {
                    hand_nm: m.hand_nm,
                    true_angle_rad: m.true_angle_rad,
                    arm: m.arm,
                    seam: m.seam,
                }
            }
        }
    }

    /// Range of motion of each estimated joint angle so far, rad (order of
    /// `gyro_imu::arm::JointAngles::NAMES`); `None` without arm sensing.
    pub fn range_of_motion_rad(&self) -> Option<[f64; 5]> {
        match &self.body {
            Body::Sim { sensing, .. } => Some(sensing.range_of_motion_rad()),
            #[cfg(target_os = "linux")]
            Body::Evdev { arm, .. } => arm.as_ref().map(|a| a.range_of_motion_rad()),
            Body::Recorded(r) => r.range_of_motion_rad(),
        }
    }

    /// Why arm sensing stopped or never started, if it did.
    pub fn arm_failure(&self) -> Option<&crate::session::arm::ArmFailure> {
        match &self.body {
            Body::Sim { sensing, .. } => sensing.failure(),
            #[cfg(target_os = "linux")]
            Body::Evdev { arm, .. } => arm.as_ref().and_then(|a| a.failure()),
            Body::Recorded(r) => r.arm_failure(),
        }
    }

    /// Command zero torque directly and stop firmware effects (every exit path calls it;
    /// dropping the plant does too).
    pub fn zero_torque(&mut self) {
        self.body.wheel().set_firmware_effects_active(false);
        let _ = self.body.wheel().command_torque(0.0);
    }
}

/// Fastest a hand (or a released wheel) turns a wheel, rad/s (~5700 °/s): a reading further
/// from the last good one than this allows is a glitch, not a movement.
const MAX_PLAUSIBLE_RATE_RAD_S: f64 = 100.0;

/// Tells a saturated (clipped) encoder from a wheel turned to its end: a reading at the end of
/// the range reached by a jump no hand could make is no reading, and neither are the readings
/// that hold there after it; one reached by turning is a reading. Any other jump is a glitch
/// and dropped. Allocation-free.
#[derive(Clone, Copy, Debug)]
struct AnglePlausibility {
    half_range_rad: f64,
    /// The last accepted reading: (t_ns, angle_rad).
    last_good: Option<(u64, f64)>,
    /// The encoder is clipped at its end since a jump there.
    clipped: bool,
}

impl AnglePlausibility {
    fn new(half_range_rad: f64) -> Self {
        Self {
            half_range_rad,
            last_good: None,
            clipped: false,
        }
    }

    /// Whether `r` (a finite angle) is a reading of the wheel's position.
    fn accept(&mut self, r: &WheelReading) -> bool {
        let at_end = r.angle_rad.abs() >= self.half_range_rad * (1.0 - 1e-6);
        let jump = self.last_good.is_some_and(|(t, a)| {
            let dt_s = r.t_ns.saturating_sub(t) as f64 * 1e-9;
            (r.angle_rad - a).abs() > MAX_PLAUSIBLE_RATE_RAD_S * dt_s.max(1e-3)
        });
        self.clipped = at_end && (jump || self.clipped);
        if jump || self.clipped {
            return false;
        }
        self.last_good = Some((r.t_ns, r.angle_rad));
        true
    }
}

/// The car's state on the road as recorded, with the road-wheel angle `steer_rad` the wheel
/// asks for now.
fn vehicle_sample(
    world: &vehicle::World,
    steer_rad: f64,
    projection: &Projection,
) -> VehicleSample {
    let st = world.state();
    VehicleSample {
        x_m: st.x_m,
        y_m: st.y_m,
        yaw_rad: st.yaw_rad,
        ux_m_s: st.ux_m_s,
        uy_m_s: st.uy_m_s,
        r_rad_s: st.r_rad_s,
        steer_rad,
        front_lateral_n: world.tyre_forces().front_lateral_n,
        s_m: projection.s_m,
        lateral_m: projection.lateral_m,
    }
}
