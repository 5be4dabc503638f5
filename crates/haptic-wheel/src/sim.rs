//! A simulated wheel: rim inertia, viscous and Coulomb friction, end stops, encoder and
//! torque quantisation. The patient's hand torque comes in through [`SimWheel::advance`].

use crate::wheel::{Wheel, WheelError, WheelReading};
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
    /// Encoder step, rad (thesis wheel: `Ka` = 0.002253 rad per DirectX unit, eq. 3.2).
    pub encoder_step_rad: f64,
    /// Torque command step, N·m (thesis wheel: `Kt` = 1.873e-4 N·m per unit, eq. 3.3).
    pub torque_step_nm: f64,
    /// Largest motor torque, N·m.
    pub max_torque_nm: f64,
    /// Half range of motion, rad (thesis wheel: ±129°).
    pub range_rad: f64,
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
        }
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
}

/// Stiffness and damping of the end stops, N·m/rad and N·m·s/rad.
const END_STOP_K: f64 = 50.0;
const END_STOP_B: f64 = 0.5;

impl SimWheel {
    /// A wheel at rest at angle zero.
    pub fn new(params: SimWheelParams) -> Self {
        Self {
            params,
            angle_rad: 0.0,
            vel_rad_s: 0.0,
            motor_nm: 0.0,
            t_ns: 0,
        }
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

    /// Advance the wheel's physics by `dt_s` with the patient's hand torque `hand_nm`
    /// (semi-implicit Euler; friction cannot reverse the motion within a step).
    pub fn advance(&mut self, dt_s: f64, hand_nm: f64) {
        let p = &self.params;
        let hand = if hand_nm.is_finite() { hand_nm } else { 0.0 };
        let over = self.angle_rad.abs() - p.range_rad;
        let stop = if over > 0.0 {
            -self.angle_rad.signum() * (END_STOP_K * over) - END_STOP_B * self.vel_rad_s
        } else {
            0.0
        };
        let drive = self.motor_nm + hand + stop - p.viscous_nm_s_per_rad * self.vel_rad_s;
        let mut vel = self.vel_rad_s + drive / p.inertia_kg_m2 * dt_s;
        let friction_dv = p.coulomb_nm / p.inertia_kg_m2 * dt_s;
        vel = if vel.abs() <= friction_dv {
            0.0
        } else {
            vel - vel.signum() * friction_dv
        };
        self.vel_rad_s = vel;
        self.angle_rad += vel * dt_s;
        self.t_ns += (dt_s * 1e9).round() as u64;
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
            self.motor_nm = 0.0;
            return Err(WheelError::NonFiniteTorque(torque_nm));
        }
        let max = self.params.max_torque_nm;
        self.motor_nm = quantise(torque_nm.clamp(-max, max), self.params.torque_step_nm);
        Ok(())
    }

    fn max_torque_nm(&self) -> f64 {
        self.params.max_torque_nm
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constant_torque_accelerates_at_torque_over_inertia_without_friction() {
        let mut w = SimWheel::new(SimWheelParams {
            viscous_nm_s_per_rad: 0.0,
            coulomb_nm: 0.0,
            torque_step_nm: 0.0,
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
}
