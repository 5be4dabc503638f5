//! A simulated wheel: rim inertia, viscous and Coulomb friction, end stops, encoder and
//! torque quantisation, and a USB command path with delay and seeded jitter. The patient's
//! hand torque comes in through [`SimWheel::advance`].

use crate::profile::DeviceProfile;
use crate::wheel::{ConfigError, MotorUpdates, Wheel, WheelError, WheelReading};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

/// Physical parameters of the simulated wheel.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SimWheelParams {
    /// Rim + motor inertia reflected to the steering axis, kg·m².
    pub inertia_kg_m2: f64,
    /// Viscous friction, N·m·s/rad.
    pub viscous_nm_s_per_rad: f64,
    /// Coulomb friction, N·m.
    pub coulomb_nm: f64,
    /// Encoder step, rad (thesis wheel: `Ka` = 0.002253 rad per DirectX unit, eq. 3.2; the
    /// thesis also reports 0.1 rad raw steps before filtering, §3.3.2 — see
    /// [`SimWheelParams::thesis_raw_encoder`]). Zero: no quantisation.
    pub encoder_step_rad: f64,
    /// Torque command step, N·m (thesis wheel: `Kt` = 1.873e-4 N·m per unit, eq. 3.3).
    pub torque_step_nm: f64,
    /// Largest motor torque, N·m.
    pub max_torque_nm: f64,
    /// Half range of motion, rad (thesis wheel: ±129°).
    pub range_rad: f64,
    /// End-stop stiffness beyond the range, N·m/rad.
    pub end_stop_k_nm_per_rad: f64,
    /// End-stop damping beyond the range, N·m·s/rad.
    pub end_stop_b_nm_s_per_rad: f64,
    /// Host-to-motor delay of a torque command (USB + firmware), s.
    pub usb_delay_s: f64,
    /// Extra uniformly distributed delay `[0, jitter]` per command, s. Commands never
    /// overtake each other.
    pub usb_jitter_s: f64,
    /// Seed of the jitter generator.
    pub seed: u64,
}

impl Default for SimWheelParams {
    fn default() -> Self {
        Self {
            inertia_kg_m2: 0.02,
            viscous_nm_s_per_rad: 0.02,
            coulomb_nm: 0.03,
            encoder_step_rad: crate::THESIS_KA_RAD_PER_UNIT,
            torque_step_nm: crate::THESIS_KT_NM_PER_UNIT,
            max_torque_nm: crate::THESIS_WHEEL_MAX_TORQUE_NM,
            range_rad: 129f64.to_radians(),
            end_stop_k_nm_per_rad: 50.0,
            end_stop_b_nm_s_per_rad: 0.5,
            usb_delay_s: 0.002,
            usb_jitter_s: 0.0005,
            seed: 0x5eed,
        }
    }
}

impl SimWheelParams {
    /// The thesis wheel as its raw encoder saw it: 0.1 rad steps before filtering (§3.3.2).
    pub fn thesis_raw_encoder() -> Self {
        Self {
            encoder_step_rad: 0.1,
            ..Self::default()
        }
    }

    /// Check every field; the error names the field and its allowed range.
    pub fn validate(&self) -> Result<(), ConfigError> {
        let check = |name: &str, v: f64, lo: f64, hi: f64, lo_open: bool| {
            let ok = v.is_finite() && v <= hi && if lo_open { v > lo } else { v >= lo };
            if ok {
                Ok(())
            } else {
                let open = if lo_open { "(" } else { "[" };
                Err(ConfigError(format!(
                    "sim_wheel.{name} = {v}, allowed {open}{lo}, {hi}]"
                )))
            }
        };
        check("inertia_kg_m2", self.inertia_kg_m2, 0.0, 10.0, true)?;
        check(
            "viscous_nm_s_per_rad",
            self.viscous_nm_s_per_rad,
            0.0,
            10.0,
            false,
        )?;
        check("coulomb_nm", self.coulomb_nm, 0.0, 10.0, false)?;
        check("encoder_step_rad", self.encoder_step_rad, 0.0, 1.0, false)?;
        check("torque_step_nm", self.torque_step_nm, 0.0, 1.0, false)?;
        check("max_torque_nm", self.max_torque_nm, 0.0, 30.0, true)?;
        check(
            "range_rad",
            self.range_rad,
            0.0,
            4.0 * std::f64::consts::PI,
            true,
        )?;
        check(
            "end_stop_k_nm_per_rad",
            self.end_stop_k_nm_per_rad,
            0.0,
            1.0e4,
            false,
        )?;
        check(
            "end_stop_b_nm_s_per_rad",
            self.end_stop_b_nm_s_per_rad,
            0.0,
            100.0,
            false,
        )?;
        let max_delay = (DELAY_SLOTS as f64 - 1.0) * 1e-3 / 2.0;
        check("usb_delay_s", self.usb_delay_s, 0.0, max_delay, false)?;
        check("usb_jitter_s", self.usb_jitter_s, 0.0, max_delay, false)?;
        Ok(())
    }
}

/// Capacity of the command delay line. At a 1 kHz command rate it holds 127 ms of commands;
/// when it is full the oldest pending command is dropped (the latest value wins).
const DELAY_SLOTS: usize = 256;

/// Fixed-capacity FIFO of (apply-at time, torque) commands: no allocation after construction.
#[derive(Clone, Debug)]
struct DelayLine {
    slots: [(u64, f64); DELAY_SLOTS],
    head: usize,
    len: usize,
}

impl DelayLine {
    fn new() -> Self {
        Self {
            slots: [(0, 0.0); DELAY_SLOTS],
            head: 0,
            len: 0,
        }
    }

    fn push(&mut self, at_ns: u64, torque_nm: f64) {
        if self.len == DELAY_SLOTS {
            self.head = (self.head + 1) % DELAY_SLOTS;
            self.len -= 1;
        }
        let tail = (self.head + self.len) % DELAY_SLOTS;
        self.slots[tail] = (at_ns, torque_nm);
        self.len += 1;
    }

    fn last_at_ns(&self) -> Option<u64> {
        (self.len > 0).then(|| self.slots[(self.head + self.len - 1) % DELAY_SLOTS].0)
    }

    /// Pop every command due at or before `now_ns`, returning the latest one.
    fn pop_due(&mut self, now_ns: u64) -> Option<f64> {
        let mut latest = None;
        while self.len > 0 && self.slots[self.head].0 <= now_ns {
            latest = Some(self.slots[self.head].1);
            self.head = (self.head + 1) % DELAY_SLOTS;
            self.len -= 1;
        }
        latest
    }

    fn clear(&mut self) {
        self.len = 0;
    }
}

/// The simulated wheel's true state and its device-side view.
#[derive(Clone, Debug)]
pub struct SimWheel {
    params: SimWheelParams,
    angle_rad: f64,
    vel_rad_s: f64,
    motor_nm: f64,
    t_ns: u64,
    delay: DelayLine,
    rng: ChaCha8Rng,
    /// Every finite command is an update written to the (simulated) device.
    updates: MotorUpdates,
}

impl SimWheel {
    /// A wheel at rest at angle zero. Out-of-range parameters are the caller's bug: check
    /// them with [`SimWheelParams::validate`] first (config loading does).
    pub fn new(params: SimWheelParams) -> Self {
        let rng = ChaCha8Rng::seed_from_u64(params.seed);
        Self {
            params,
            angle_rad: 0.0,
            vel_rad_s: 0.0,
            motor_nm: 0.0,
            t_ns: 0,
            delay: DelayLine::new(),
            rng,
            updates: MotorUpdates::default(),
        }
    }

    /// The parameters this wheel was built with.
    pub fn params(&self) -> &SimWheelParams {
        &self.params
    }

    /// True angle, rad (what the patient's hand feels, before encoder quantisation).
    pub fn true_angle_rad(&self) -> f64 {
        self.angle_rad
    }

    /// True angular velocity, rad/s.
    pub fn true_velocity_rad_s(&self) -> f64 {
        self.vel_rad_s
    }

    /// The torque the motor is applying now, N·m.
    pub fn motor_torque_nm(&self) -> f64 {
        self.motor_nm
    }

    /// Simulated time, ns since construction. It is the wheel's own clock, moved only by
    /// [`SimWheel::advance`]'s `dt` (never read from the operating system, nor from the
    /// station's injectable `clock::Clock`): a simulated session gives the same readings
    /// whatever its pacing, and its timestamps are exactly `k·dt`.
    pub fn time_ns(&self) -> u64 {
        self.t_ns
    }

    /// Place the wheel at `angle_rad` with velocity `vel_rad_s` (test and scenario set-up).
    pub fn set_state(&mut self, angle_rad: f64, vel_rad_s: f64) {
        if angle_rad.is_finite() && vel_rad_s.is_finite() {
            self.angle_rad = angle_rad;
            self.vel_rad_s = vel_rad_s;
        }
    }

    /// Advance the wheel's physics by `dt_s` with the patient's hand torque `hand_nm`
    /// (semi-implicit Euler; friction cannot reverse the motion within a step). Torque
    /// commands whose delay has elapsed take effect at the start of the step.
    pub fn advance(&mut self, dt_s: f64, hand_nm: f64) {
        self.advance_held(dt_s, hand_nm, 0.0);
    }

    /// Advance as [`SimWheel::advance`] with the rim held by an arm of inertia
    /// `arm_inertia_kg_m2` (reflected to the axis) whose muscles apply `muscle_nm`: the arm
    /// moves with the rim, so the two accelerate together (eq. 5.7: the inertias add), and the
    /// torque the hand passes to the rim is the muscles' less the arm's own inertial torque,
    /// `τ_h = τ_m − J_arm θ̈`. Returns that hand torque, N·m.
    pub fn advance_held(&mut self, dt_s: f64, muscle_nm: f64, arm_inertia_kg_m2: f64) -> f64 {
        let muscle = if muscle_nm.is_finite() {
            muscle_nm
        } else {
            0.0
        };
        if !(dt_s.is_finite() && dt_s > 0.0) {
            return muscle;
        }
        let arm_j = if arm_inertia_kg_m2.is_finite() {
            arm_inertia_kg_m2.max(0.0)
        } else {
            0.0
        };
        if let Some(t) = self.delay.pop_due(self.t_ns) {
            self.motor_nm = t;
        }
        let p = &self.params;
        let inertia = p.inertia_kg_m2 + arm_j;
        let stop = common::end_stop_nm(
            self.angle_rad,
            self.vel_rad_s,
            p.range_rad,
            p.end_stop_k_nm_per_rad,
            p.end_stop_b_nm_s_per_rad,
        );
        let drive = self.motor_nm + muscle + stop - p.viscous_nm_s_per_rad * self.vel_rad_s;
        let mut vel = self.vel_rad_s + drive / inertia * dt_s;
        let friction_dv = p.coulomb_nm / inertia * dt_s;
        vel = if vel.abs() <= friction_dv {
            0.0
        } else {
            vel - vel.signum() * friction_dv
        };
        let accel = (vel - self.vel_rad_s) / dt_s;
        self.vel_rad_s = vel;
        self.angle_rad += vel * dt_s;
        self.t_ns += (dt_s * 1e9).round() as u64;
        muscle - arm_j * accel
    }
}

fn quantise(v: f64, step: f64) -> f64 {
    if step > 0.0 {
        (v / step).round() * step
    } else {
        v
    }
}

impl Wheel for SimWheel {
    fn read(&mut self) -> Result<WheelReading, WheelError> {
        Ok(WheelReading {
            angle_rad: quantise(self.angle_rad, self.params.encoder_step_rad),
            t_ns: self.t_ns,
        })
    }

    fn command_torque(&mut self, torque_nm: f64) -> Result<(), WheelError> {
        if !torque_nm.is_finite() {
            // The firmware's safe reaction: drop everything in flight, stop the motor.
            self.delay.clear();
            self.motor_nm = 0.0;
            return Err(WheelError::NonFiniteTorque(torque_nm));
        }
        let max = self.params.max_torque_nm;
        let q = quantise(torque_nm.clamp(-max, max), self.params.torque_step_nm);
        let jitter = if self.params.usb_jitter_s > 0.0 {
            self.rng.random::<f64>() * self.params.usb_jitter_s
        } else {
            0.0
        };
        let due = self.t_ns + ((self.params.usb_delay_s + jitter) * 1e9).round() as u64;
        let due = due.max(self.delay.last_at_ns().unwrap_or(0));
        self.delay.push(due, q);
        self.updates.written(self.t_ns);
        Ok(())
    }

    fn motor_updates(&self) -> Option<MotorUpdates> {
        Some(self.updates)
    }

    fn max_torque_nm(&self) -> f64 {
        self.params.max_torque_nm
    }

    fn profile(&self) -> DeviceProfile {
        let mut p = DeviceProfile::simulated(self.params.max_torque_nm, self.params.range_rad);
        if self.params.encoder_step_rad > 0.0 {
            p.ka_rad_per_unit = self.params.encoder_step_rad;
        }
        if self.params.torque_step_nm > 0.0 {
            p.torque_step_nm = self.params.torque_step_nm;
        }
        p
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::wheel::ZeroTorqueOnDrop;

    #[test]
    fn constant_torque_accelerates_at_torque_over_inertia_without_friction() {
        let mut w = SimWheel::new(SimWheelParams {
            viscous_nm_s_per_rad: 0.0,
            coulomb_nm: 0.0,
            torque_step_nm: 0.0,
            usb_delay_s: 0.0,
            usb_jitter_s: 0.0,
            ..Default::default()
        });
        w.command_torque(0.2).unwrap();
        for _ in 0..100 {
            w.advance(0.001, 0.0);
        }
        assert!((w.true_velocity_rad_s() - 0.2 / 0.02 * 0.1).abs() < 1e-9);
    }

    #[test]
    fn torque_below_coulomb_friction_does_not_move_the_wheel() {
        let mut w = SimWheel::new(SimWheelParams::default());
        for _ in 0..1000 {
            w.advance(0.001, 0.02);
        }
        assert_eq!(w.true_angle_rad(), 0.0);
    }

    #[test]
    fn reading_is_quantised_to_the_encoder_step() {
        let mut w = SimWheel::new(SimWheelParams {
            coulomb_nm: 0.0,
            ..Default::default()
        });
        for _ in 0..50 {
            w.advance(0.001, 0.1);
        }
        let r = w.read().unwrap();
        let units = r.angle_rad / crate::THESIS_KA_RAD_PER_UNIT;
        assert!((units - units.round()).abs() < 1e-9);
    }

    #[test]
    fn torque_command_takes_effect_after_the_usb_delay() {
        let mut w = SimWheel::new(SimWheelParams {
            usb_delay_s: 0.004,
            usb_jitter_s: 0.0,
            ..Default::default()
        });
        w.command_torque(1.0).unwrap();
        for _ in 0..4 {
            w.advance(0.001, 0.0);
            assert_eq!(w.motor_torque_nm(), 0.0);
        }
        w.advance(0.001, 0.0);
        assert!((w.motor_torque_nm() - 1.0).abs() < 1e-3);
    }

    #[test]
    fn jittered_commands_never_overtake_each_other() {
        let mut w = SimWheel::new(SimWheelParams {
            usb_delay_s: 0.002,
            usb_jitter_s: 0.003,
            torque_step_nm: 0.0,
            ..Default::default()
        });
        let mut seen = Vec::new();
        for k in 0..500 {
            w.command_torque(k as f64 * 1e-3).unwrap();
            w.advance(0.001, 0.0);
            seen.push(w.motor_torque_nm());
        }
        assert!(seen.windows(2).all(|p| p[1] >= p[0]));
        assert!(
            seen[499] > 0.48,
            "latest command arrives within the delay bound"
        );
    }

    #[test]
    fn same_seed_gives_the_same_trajectory() {
        let run = || {
            let mut w = SimWheel::new(SimWheelParams::default());
            for k in 0..300 {
                w.command_torque((k as f64 * 0.05).sin()).unwrap();
                w.advance(0.001, 0.0);
            }
            w.true_angle_rad()
        };
        assert_eq!(run(), run());
    }

    #[test]
    fn end_stop_holds_the_wheel_near_its_range() {
        let mut w = SimWheel::new(SimWheelParams::default());
        w.command_torque(1.87).unwrap();
        for _ in 0..5000 {
            w.advance(0.001, 0.0);
        }
        let over = w.true_angle_rad() - w.params().range_rad;
        // Static balance: 1.87 N·m against a 50 N·m/rad stop is 0.037 rad of overtravel.
        assert!(over > 0.0 && over < 0.04, "overtravel {over}");
    }

    #[test]
    fn non_finite_command_stops_the_motor_and_flushes_pending_commands() {
        let mut w = SimWheel::new(SimWheelParams::default());
        w.command_torque(1.0).unwrap();
        assert!(w.command_torque(f64::NAN).is_err());
        for _ in 0..10 {
            w.advance(0.001, 0.0);
        }
        assert_eq!(w.motor_torque_nm(), 0.0);
    }

    #[test]
    fn validate_names_the_bad_field() {
        let p = SimWheelParams {
            inertia_kg_m2: 0.0,
            ..Default::default()
        };
        assert!(
            p.validate()
                .unwrap_err()
                .to_string()
                .contains("inertia_kg_m2")
        );
        SimWheelParams::default().validate().unwrap();
        SimWheelParams::thesis_raw_encoder().validate().unwrap();
    }

    // The zero-torque guard of `wheel`, on the simulated wheel (whose motor it stops).
    #[test]
    fn guard_commands_zero_torque_when_dropped() {
        let mut sim = SimWheel::new(SimWheelParams {
            usb_delay_s: 0.0,
            usb_jitter_s: 0.0,
            ..Default::default()
        });
        {
            let mut guard = ZeroTorqueOnDrop::new(&mut sim);
            guard.command_torque(1.0).unwrap();
            guard.wheel().advance(0.001, 0.0);
            assert!(guard.motor_torque_nm() > 0.9);
        }
        sim.advance(0.001, 0.0);
        assert_eq!(sim.motor_torque_nm(), 0.0);
    }

    #[test]
    fn guard_commands_zero_torque_when_a_panic_unwinds() {
        let mut sim = SimWheel::new(SimWheelParams {
            usb_delay_s: 0.0,
            usb_jitter_s: 0.0,
            ..Default::default()
        });
        let res = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            let mut guard = ZeroTorqueOnDrop::new(&mut sim);
            guard.command_torque(1.5).unwrap();
            panic!("haptic thread bug");
        }));
        assert!(res.is_err());
        sim.advance(0.001, 0.0);
        assert_eq!(sim.motor_torque_nm(), 0.0);
    }
}
