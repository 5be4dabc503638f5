//! The simulated plant: a simulated wheel held by a simulated patient who steers a car along
//! the road, with the haptic chain and the assist controller between them exactly as they run
//! against a real wheel. One [`SimPlant::tick`] is one haptic-loop period; it allocates nothing.

use crate::config::StationConfig;
use crate::session::record::{
    AssistSample, ScoreSample, TickRecord, VehicleSample, WheelSample, watchdog_label,
};
use anyhow::Context;
use assist::{Assist, HumanArm, Limits, Measurement};
use haptic_wheel::{
    HapticChain, HapticChainConfig, SimWheel, TickInput, WatchdogState, Wheel, ZeroTorqueOnDrop,
};
use vehicle::{
    LaneScore, PreviewDriver, Projection, Road, SineRoad, SpeedController, Vehicle, VehicleState,
};

/// Simulated wheel, patient, car and road, stepped together through the haptic chain.
pub struct SimPlant {
    wheel: ZeroTorqueOnDrop<SimWheel>,
    chain: HapticChain,
    assist: Option<Assist>,
    arm: HumanArm,
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

impl SimPlant {
    /// Build the plant for a validated `cfg`; all noise is seeded from `cfg.session.seed`.
    pub fn new(cfg: &StationConfig) -> anyhow::Result<Self> {
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
        let mut wheel_params = cfg.sim_wheel.clone();
        wheel_params.seed = cfg.session.seed;
        let wheel = ZeroTorqueOnDrop::new(SimWheel::new(wheel_params));
        let h = &cfg.haptic;
        let chain_cfg = HapticChainConfig {
            safety: h.safety,
            model: Some(h.centring),
            passivity: h.passivity_enabled.then_some(h.passivity),
            ..HapticChainConfig::for_encoder_step(cfg.sim_wheel.encoder_step_rad)
        };
        let device_max = wheel.max_torque_nm();
        let chain = HapticChain::new(chain_cfg, device_max).context("haptic chain")?;
        let assist = cfg
            .assist
            .as_ref()
            .map(Assist::new)
            .transpose()
            .context("assist")?;
        Ok(Self {
            wheel,
            chain,
            assist,
            arm: HumanArm::new(cfg.sim_patient.clone(), dt_s, cfg.session.seed),
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
        let reading = self.wheel.read().ok();
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
            now_ns: self.wheel.time_ns(),
            reading,
            external_nm: road_feel + assist_out.torque_nm,
        });
        self.velocity_rad_s = tel.vel_rad_s;
        self.watchdog = tel.watchdog;
        // The simulated device refuses only non-finite values, which the chain never emits.
        let _ = self.wheel.command_torque(tel.torque_nm);

        // 5. The simulated patient looks at the road and moves the wheel.
        let hand = self.arm.step(
            target,
            self.wheel.true_angle_rad(),
            self.wheel.true_velocity_rad_s(),
            dt,
        );
        self.wheel.advance(dt, hand);

        let rec = TickRecord {
            tick: self.tick,
            t_ns: self.tick * (dt * 1e9).round() as u64,
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
                true_angle_rad: self.wheel.true_angle_rad(),
                hand_nm: hand,
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
            timing: Default::default(),
        };
        self.tick += 1;
        rec
    }

    /// Command zero torque directly (every exit path calls it; dropping the plant does too).
    pub fn zero_torque(&mut self) {
        let _ = self.wheel.command_torque(0.0);
    }
}
