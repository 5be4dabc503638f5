//! The plant the haptic loop drives: a wheel and whoever holds it (a simulated patient on a
//! simulated wheel, or a real patient on a real force-feedback wheel), the car on the road,
//! and between them the haptic chain and the assist controller — the same code for both.
//! One [`Plant::tick`] is one haptic-loop period; it allocates nothing.

use crate::config::StationConfig;
use crate::session::arm::SimArmSensing;
use crate::session::record::{
    ArmSample, AssistSample, ScoreSample, TickRecord, VehicleSample, WheelSample, watchdog_label,
};
use anyhow::Context;
use assist::{Assist, HumanArm, Limits, Measurement};
use haptic_wheel::{
    HapticChain, HapticChainConfig, SimWheel, TickInput, WatchdogState, Wheel, ZeroTorqueOnDrop,
};
use vehicle::{
    LaneScore, PreviewDriver, Projection, Road, SineRoad, SpeedController, Vehicle, VehicleState,
};

/// Who holds the wheel.
// One body per session, built once and never moved on the hot path: its size does not matter.
#[allow(clippy::large_enum_variant)]
pub enum Body {
    /// A simulated wheel held by a simulated patient who wears simulated IMUs.
    Sim {
        /// The simulated wheel (zero torque when dropped).
        wheel: ZeroTorqueOnDrop<SimWheel>,
        /// The simulated patient's arm control.
        arm: HumanArm,
        /// The simulated arm kinematics, IMUs and pose estimator.
        sensing: Box<SimArmSensing>,
    },
    /// A real force-feedback wheel (Linux kernel FF API) held by the patient.
    #[cfg(target_os = "linux")]
    Evdev {
        /// The device (zero torque, effects erased and gain restored when dropped).
        wheel: ZeroTorqueOnDrop<haptic_wheel::evdev_wheel::EvdevWheel>,
    },
}

impl Body {
    /// The simulated body of `cfg`, seeded from `cfg.session.seed`.
    pub fn simulated(cfg: &StationConfig) -> anyhow::Result<Self> {
        let dt_s = 1.0 / cfg.session.loop_rate_hz;
        let mut wheel_params = cfg.sim_wheel.clone();
        wheel_params.seed = cfg.session.seed;
        Ok(Body::Sim {
            wheel: ZeroTorqueOnDrop::new(SimWheel::new(wheel_params)),
            arm: HumanArm::new(cfg.sim_patient.clone(), dt_s, cfg.session.seed),
            sensing: Box::new(
                SimArmSensing::new(cfg.sim_arm, cfg.session.seed).context("simulated arm")?,
            ),
        })
    }

    /// The first force-feedback wheel found (see `telerehab devices`).
    #[cfg(target_os = "linux")]
    pub fn first_real_wheel() -> anyhow::Result<Self> {
        use haptic_wheel::evdev_wheel::{EvdevWheel, EvdevWheelConfig};
        let wheel = EvdevWheel::open_first(EvdevWheelConfig::default())
            .context("no usable force-feedback wheel (run `telerehab devices`)")?;
        Ok(Body::Evdev {
            wheel: ZeroTorqueOnDrop::new(wheel),
        })
    }

    fn wheel(&mut self) -> &mut dyn Wheel {
        match self {
            Body::Sim { wheel, .. } => &mut **wheel,
            #[cfg(target_os = "linux")]
            Body::Evdev { wheel } => &mut **wheel,
        }
    }

    /// Now, ns, on the clock of the wheel's readings.
    fn now_ns(&self) -> u64 {
        match self {
            Body::Sim { wheel, .. } => wheel.time_ns(),
            #[cfg(target_os = "linux")]
            Body::Evdev { .. } => haptic_wheel::evdev_wheel::monotonic_ns(),
        }
    }

    /// The encoder step of the wheel, rad (tunes the velocity estimator).
    fn encoder_step_rad(&self, cfg: &StationConfig) -> f64 {
        match self {
            Body::Sim { .. } => cfg.sim_wheel.encoder_step_rad,
            #[cfg(target_os = "linux")]
            Body::Evdev { wheel } => wheel.profile().ka_rad_per_unit,
        }
    }
}

/// What the body did this tick (simulation only: a real patient is not observed this way).
struct BodyMotion {
    hand_nm: Option<f64>,
    true_angle_rad: Option<f64>,
    arm: Option<ArmSample>,
}

/// Wheel, body, car and road, stepped together through the haptic chain.
pub struct Plant {
    body: Body,
    chain: HapticChain,
    assist: Option<Assist>,
    car: Vehicle,
    road: Box<dyn Road + Send>,
    driver: PreviewDriver,
    cruise: SpeedController,
    score: LaneScore,
    projection: Projection,
    road_feel_nm_per_kn: f64,
    steering_ratio: f64,
    ceiling_nm: f64,
    slew_nm_per_s: f64,
    dt_s: f64,
    tick: u64,
    velocity_rad_s: f64,
    watchdog: WatchdogState,
}

impl Plant {
    /// The fully simulated plant of a validated `cfg`; all noise is seeded from
    /// `cfg.session.seed`.
    pub fn simulated(cfg: &StationConfig) -> anyhow::Result<Self> {
        Self::new(cfg, Body::simulated(cfg)?)
    }

    /// The plant of a validated `cfg` around `body`.
    pub fn new(cfg: &StationConfig, body: Body) -> anyhow::Result<Self> {
        let dt_s = 1.0 / cfg.session.loop_rate_hz;
        let road: Box<dyn Road + Send> = Box::new(SineRoad {
            amplitude_m: 6.0,
            wavelength_m: 100.0,
            lane_width_m: 3.5,
        });
        // Start on the centre line, aligned with the road, at the target speed.
        let ([x0, y0], heading0, _) = road.centre(0.0);
        let car = Vehicle::new(
            cfg.vehicle.clone(),
            VehicleState {
                x_m: x0,
                y_m: y0,
                yaw_rad: heading0,
                ux_m_s: cfg.session.speed_m_s,
                ..Default::default()
            },
        );
        let projection = road.project(x0, y0, 0.0);
        let mut body = body;
        let h = &cfg.haptic;
        let chain_cfg = HapticChainConfig {
            safety: h.safety,
            model: Some(h.centring),
            passivity: h.passivity_enabled.then_some(h.passivity),
            ..HapticChainConfig::for_encoder_step(body.encoder_step_rad(cfg))
        };
        let device_max = body.wheel().max_torque_nm();
        let chain = HapticChain::new(chain_cfg, device_max).context("haptic chain")?;
        let assist = cfg
            .assist
            .as_ref()
            .map(Assist::new)
            .transpose()
            .context("assist")?;
        Ok(Self {
            body,
            chain,
            assist,
            car,
            road,
            driver: PreviewDriver::default(),
            cruise: SpeedController {
                target_m_s: cfg.session.speed_m_s,
                gain_n_per_m_s: 2000.0,
                max_force_n: 8000.0,
            },
            score: LaneScore::default(),
            projection,
            road_feel_nm_per_kn: h.road_feel_nm_per_kn,
            steering_ratio: h.steering_ratio,
            ceiling_nm: h.safety.ceiling_nm.unwrap_or(device_max).min(device_max),
            slew_nm_per_s: h.safety.slew_nm_per_s,
            dt_s,
            tick: 0,
            velocity_rad_s: 0.0,
            watchdog: WatchdogState::SoftStart,
        })
    }

    /// The loop period, s.
    pub fn dt_s(&self) -> f64 {
        self.dt_s
    }

    /// Ask the safety supervisor to fade the torque out; [`SimPlant::stopped`] turns true
    /// when it reached zero.
    pub fn request_stop(&mut self) {
        self.chain.request_stop();
    }

    /// The supervisor has faded the torque to zero for good.
    pub fn stopped(&self) -> bool {
        self.watchdog == WatchdogState::Stopped
    }

    /// Advance one loop period.
    pub fn tick(&mut self) -> TickRecord {
        let dt = self.dt_s;
        // 1. Read the wheel as the host sees it (quantised, delayed).
        let reading = self.body.wheel().read().ok();
        let angle = reading.map_or(0.0, |r| r.angle_rad);

        // 2. Step the car with the wheel as its steering input.
        let steer = angle / self.steering_ratio;
        let st = *self.car.state();
        let input = self.cruise.input(st.ux_m_s, steer);
        self.car.step(input, dt);
        let st = *self.car.state();
        self.projection = self.road.project(st.x_m, st.y_m, self.projection.s_m);
        self.score
            .update(self.projection.lateral_m, self.road.lane_width_m(), dt);
        let fyf = self.car.tyre_forces().front_lateral_n;
        // Self-aligning road feel: proportional to the front lateral tyre force (§3.3.4).
        let road_feel = -self.road_feel_nm_per_kn * fyf / 1000.0;

        // 3. Where an ideal driver would hold the wheel: the reference for assistance and the
        //    simulated patient's intention.
        let desired_steer =
            self.driver
                .desired_steer_rad(self.car.params(), &st, &self.projection, &*self.road);
        let target = desired_steer * self.steering_ratio;
        let assist_out = match &mut self.assist {
            Some(a) => {
                // The assist gets the torque budget the road feel leaves (the chain's limiter
                // would otherwise clip torque the assist believes it delivered).
                let limits = Limits {
                    ceiling_nm: (self.ceiling_nm - road_feel.abs()).max(0.0),
                    slew_nm_per_s: self.slew_nm_per_s,
                };
                let m = Measurement {
                    angle_rad: angle,
                    vel_rad_s: self.velocity_rad_s,
                };
                a.step(m, target, limits, dt)
            }
            None => Default::default(),
        };

        // 4. Haptic chain: model + road feel + assist → passivity → safety supervisor.
        let tel = self.chain.tick(TickInput {
            now_ns: self.body.now_ns(),
            reading,
            external_nm: road_feel + assist_out.torque_nm,
        });
        self.velocity_rad_s = tel.vel_rad_s;
        self.watchdog = tel.watchdog;
        // A failed command is caught by the next read (stale reading → supervisor fault).
        let _ = self.body.wheel().command_torque(tel.torque_nm);

        // 5. Whoever holds the wheel moves it.
        let t_ns = self.tick * (dt * 1e9).round() as u64;
        let motion = self.move_body(target, angle, t_ns, dt);

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
                watchdog: watchdog_label(tel.watchdog),
                passivity_energy_j: tel.passivity_energy_j,
                passivity_damping_nm_s_per_rad: tel.passivity_damping_nm_s_per_rad,
                true_angle_rad: motion.true_angle_rad,
                hand_nm: motion.hand_nm,
                target_rad: target,
            },
            vehicle: VehicleSample {
                x_m: st.x_m,
                y_m: st.y_m,
                yaw_rad: st.yaw_rad,
                ux_m_s: st.ux_m_s,
                uy_m_s: st.uy_m_s,
                r_rad_s: st.r_rad_s,
                steer_rad: steer,
                front_lateral_n: fyf,
                s_m: self.projection.s_m,
                lateral_m: self.projection.lateral_m,
            },
            score: ScoreSample {
                rms_lateral_m: self.score.rms_m(),
                max_lateral_m: self.score.max_abs_m(),
                pct_in_lane: self.score.pct_in_lane(),
            },
            assist: AssistSample {
                torque_nm: assist_out.torque_nm,
                reference_rad: assist_out.reference_rad,
                error_rad: assist_out.error_rad,
                assistance_level: assist_out.assistance_level,
                saturated: assist_out.saturated,
            },
            arm: motion.arm,
            timing: Default::default(),
        };
        self.tick += 1;
        rec
    }

    /// The simulated patient looks at the road and moves the simulated wheel, and the arm
    /// pose is estimated from the simulated IMUs; a real patient moves a real wheel alone.
    fn move_body(&mut self, target_rad: f64, read_rad: f64, t_ns: u64, dt: f64) -> BodyMotion {
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
                let sample = sensing.step(
                    t_ns,
                    wheel.true_angle_rad(),
                    wheel.true_velocity_rad_s(),
                    read_rad,
                    dt,
                );
                BodyMotion {
                    hand_nm: Some(hand),
                    true_angle_rad: Some(wheel.true_angle_rad()),
                    arm: Some(sample),
                }
            }
            #[cfg(target_os = "linux")]
            Body::Evdev { .. } => BodyMotion {
                hand_nm: None,
                true_angle_rad: None,
                arm: None,
            },
        }
    }

    /// Range of motion of each estimated joint angle so far, rad (order of
    /// `gyro_imu::arm::JointAngles::NAMES`); `None` without arm sensing.
    pub fn range_of_motion_rad(&self) -> Option<[f64; 5]> {
        match &self.body {
            Body::Sim { sensing, .. } => Some(sensing.range_of_motion_rad()),
            #[cfg(target_os = "linux")]
            Body::Evdev { .. } => None,
        }
    }

    /// Command zero torque directly (every exit path calls it; dropping the plant does too).
    pub fn zero_torque(&mut self) {
        let _ = self.body.wheel().command_torque(0.0);
    }
}
