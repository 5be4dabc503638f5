//! The simulated plant: a simulated wheel held by a simulated patient who steers a car along
//! the road. One [`SimPlant::tick`] is one haptic-loop period; it allocates nothing.

use crate::config::StationConfig;
use crate::session::record::{ScoreSample, TickRecord, VehicleSample, WheelSample};
use assist::HumanArm;
use haptic_wheel::{SimWheel, TorqueLimiter, Wheel};
use vehicle::{
    LaneScore, PreviewDriver, Projection, Road, SineRoad, SpeedController, Vehicle, VehicleState,
};

/// Velocity from quantised angles: finite difference through a first-order low-pass.
#[derive(Clone, Debug)]
struct VelocityEstimator {
    last_rad: Option<f64>,
    vel_rad_s: f64,
    tau_s: f64,
}

impl VelocityEstimator {
    fn update(&mut self, angle_rad: f64, dt_s: f64) -> f64 {
        if let Some(last) = self.last_rad {
            let raw = (angle_rad - last) / dt_s;
            let alpha = dt_s / (self.tau_s + dt_s);
            self.vel_rad_s += alpha * (raw - self.vel_rad_s);
        }
        self.last_rad = Some(angle_rad);
        self.vel_rad_s
    }
}

/// Simulated wheel, patient, car and road, stepped together.
pub struct SimPlant {
    wheel: SimWheel,
    arm: HumanArm,
    car: Vehicle,
    road: Box<dyn Road + Send>,
    driver: PreviewDriver,
    cruise: SpeedController,
    limiter: TorqueLimiter,
    velocity: VelocityEstimator,
    score: LaneScore,
    projection: Projection,
    cfg: crate::config::HapticConfig,
    dt_s: f64,
    tick: u64,
    hand_nm: f64,
    target_rad: f64,
}

impl SimPlant {
    /// Build the plant for `cfg`; all noise is seeded from `cfg.session.seed`.
    pub fn new(cfg: &StationConfig) -> Self {
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
        Self {
            wheel: SimWheel::new(cfg.sim_wheel.clone()),
            arm: HumanArm::new(cfg.sim_patient.clone(), dt_s, cfg.session.seed),
            car,
            road,
            driver: PreviewDriver::default(),
            cruise: SpeedController {
                target_m_s: cfg.session.speed_m_s,
                gain_n_per_m_s: 2000.0,
                max_force_n: 8000.0,
            },
            limiter: TorqueLimiter::new(cfg.haptic.ceiling_nm, cfg.haptic.slew_nm_per_s),
            velocity: VelocityEstimator {
                last_rad: None,
                vel_rad_s: 0.0,
                tau_s: 0.02,
            },
            score: LaneScore::default(),
            projection,
            cfg: cfg.haptic.clone(),
            dt_s,
            tick: 0,
            hand_nm: 0.0,
            target_rad: 0.0,
        }
    }

    /// The loop period, s.
    pub fn dt_s(&self) -> f64 {
        self.dt_s
    }

    /// The torque the motor is applying now, N·m.
    pub fn motor_torque_nm(&self) -> f64 {
        self.wheel.motor_torque_nm()
    }

    /// Advance one loop period. `torque_scale` (0–1) multiplies the haptic request (the
    /// fade-out ramps it to zero when the session stops).
    pub fn tick(&mut self, torque_scale: f64) -> TickRecord {
        let dt = self.dt_s;
        // 1. Read the wheel as the host sees it.
        let reading = self.wheel.read().unwrap_or_default();
        let angle = reading.angle_rad;
        let vel = self.velocity.update(angle, dt);

        // 2. Step the car with the wheel as its steering input.
        let steer = angle / self.cfg.steering_ratio;
        let st = *self.car.state();
        let input = self.cruise.input(st.ux_m_s, steer);
        self.car.step(input, dt);
        let st = *self.car.state();
        self.projection = self.road.project(st.x_m, st.y_m, self.projection.s_m);
        self.score
            .update(self.projection.lateral_m, self.road.lane_width_m(), dt);

        // 3. Haptic model: centring spring–damper (eq. 3.5) + road feel from the front
        //    lateral tyre force (§3.3.4), then the safety chain.
        let fyf = self.car.tyre_forces().front_lateral_n;
        let requested = (self.cfg.centring.torque_nm(angle, vel, 0.0)
            - self.cfg.road_feel_nm_per_kn * fyf / 1000.0)
            * torque_scale;
        let limited = self.limiter.apply(requested, dt);
        // The simulated device refuses only non-finite values, which the limiter never emits.
        let _ = self.wheel.command_torque(limited.torque_nm);

        // 4. The simulated patient looks at the road and moves the wheel.
        let desired_steer =
            self.driver
                .desired_steer_rad(self.car.params(), &st, &self.projection, &*self.road);
        self.target_rad = desired_steer * self.cfg.steering_ratio;
        self.hand_nm = self.arm.step(
            self.target_rad,
            self.wheel.true_angle_rad(),
            self.wheel.true_velocity_rad_s(),
            dt,
        );
        self.wheel.advance(dt, self.hand_nm);

        let rec = TickRecord {
            tick: self.tick,
            t_ns: self.tick * (dt * 1e9).round() as u64,
            wheel: WheelSample {
                angle_rad: angle,
                velocity_rad_s: vel,
                requested_nm: requested,
                commanded_nm: limited.torque_nm,
                clipped: limited.clipped,
                true_angle_rad: self.wheel.true_angle_rad(),
                hand_nm: self.hand_nm,
                target_rad: self.target_rad,
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
            timing: Default::default(),
        };
        self.tick += 1;
        rec
    }

    /// Command zero torque directly (used on every exit path).
    pub fn zero_torque(&mut self) {
        let _ = self.wheel.command_torque(0.0);
    }
}
