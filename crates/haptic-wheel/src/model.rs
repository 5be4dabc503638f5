//! Haptic models rendered on the wheel: the spring–mass–damper of thesis eq. 3.5 and a
//! Hannaford–Ryu time-domain passivity observer/controller that keeps stiff models stable
//! on a delayed, sampled wheel.

use crate::effects::WheelState;
use crate::wheel::{ConfigError, WheelError};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Largest spring constant `K` of a [`SpringDamper`], N·m/rad (smallest: 0).
pub const MAX_K_NM_PER_RAD: f64 = 200.0;
/// Largest damping `B` of a [`SpringDamper`], N·m·s/rad (smallest: 0).
pub const MAX_B_NM_S_PER_RAD: f64 = 10.0;
/// Largest virtual inertia `I` of a [`SpringDamper`], kg·m² (smallest: 0).
pub const MAX_I_KG_M2: f64 = 1.0;
/// Largest |rest angle| θ₀ of a [`SpringDamper`], rad (two turns either way).
pub const MAX_CENTRE_RAD: f64 = 4.0 * PI;

/// Torsional spring–mass–damper of thesis eq. 3.5, `τ_h = I·θ̈ + B·θ̇ + K·θ`.
///
/// Rendered as the torque the motor applies against the patient: `τ = −(K·(θ−θ₀) + B·θ̇ + I·θ̈)`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct SpringDamper {
    /// Spring constant `K`, N·m/rad.
    #[schemars(range(min = 0.0, max = MAX_K_NM_PER_RAD))]
    pub k_nm_per_rad: f64,
    /// Damping `B`, N·m·s/rad.
    #[schemars(range(min = 0.0, max = MAX_B_NM_S_PER_RAD))]
    pub b_nm_s_per_rad: f64,
    /// Virtual inertia `I`, kg·m².
    #[schemars(range(min = 0.0, max = MAX_I_KG_M2))]
    pub i_kg_m2: f64,
    /// Spring rest angle θ₀, rad.
    #[schemars(range(min = -MAX_CENTRE_RAD, max = MAX_CENTRE_RAD))]
    pub centre_rad: f64,
}

impl Default for SpringDamper {
    fn default() -> Self {
        Self {
            k_nm_per_rad: 0.5,
            b_nm_s_per_rad: 0.05,
            i_kg_m2: 0.0,
            centre_rad: 0.0,
        }
    }
}

impl SpringDamper {
    /// Check every field; the error names the field and its allowed range.
    pub fn validate(&self) -> Result<(), ConfigError> {
        let check = |name: &str, v: f64, hi: f64| {
            if v.is_finite() && (0.0..=hi).contains(&v) {
                Ok(())
            } else {
                Err(ConfigError(format!(
                    "model.{name} = {v}, allowed [0, {hi}]"
                )))
            }
        };
        check("k_nm_per_rad", self.k_nm_per_rad, MAX_K_NM_PER_RAD)?;
        check("b_nm_s_per_rad", self.b_nm_s_per_rad, MAX_B_NM_S_PER_RAD)?;
        check("i_kg_m2", self.i_kg_m2, MAX_I_KG_M2)?;
        if !(self.centre_rad.is_finite() && self.centre_rad.abs() <= MAX_CENTRE_RAD) {
            return Err(ConfigError(format!(
                "model.centre_rad = {}, allowed [-4π, 4π]",
                self.centre_rad
            )));
        }
        Ok(())
    }

    /// Energy stored in the model at `state`, J: the spring's potential (its force capped at
    /// `ceiling_nm`, as the safety clamp caps it) plus the virtual inertia's kinetic energy.
    pub fn storage_j(&self, state: &WheelState, ceiling_nm: f64) -> f64 {
        crate::effects::saturated_spring_potential_j(
            self.k_nm_per_rad,
            ceiling_nm,
            state.angle_rad - self.centre_rad,
        ) + 0.5 * self.i_kg_m2 * state.vel_rad_s * state.vel_rad_s
    }

    /// Motor torque for a wheel state, N·m (see [`SpringDamper::torque_nm`]).
    pub fn torque_for(&self, s: &WheelState) -> f64 {
        self.torque_nm(s.angle_rad, s.vel_rad_s, s.acc_rad_s2)
    }

    /// Motor torque for angle `angle_rad`, velocity `vel_rad_s` and acceleration `acc_rad_s2`, N·m.
    pub fn torque_nm(&self, angle_rad: f64, vel_rad_s: f64, acc_rad_s2: f64) -> f64 {
        -(self.k_nm_per_rad * (angle_rad - self.centre_rad)
            + self.b_nm_s_per_rad * vel_rad_s
            + self.i_kg_m2 * acc_rad_s2)
    }
}

/// Tuning of the [`PassivityController`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PassivityParams {
    /// Largest adaptive damping the controller may add, N·m·s/rad. The damper acts through
    /// the same delay as everything else: keep `max · delay / wheel inertia` well below 1
    /// (0.5 N·m·s/rad · 5 ms / 0.02 kg·m² = 0.125). A cap of 2 turned the stiff-spring
    /// test case into a limit cycle of its own.
    pub max_damping_nm_s_per_rad: f64,
    /// Below this speed the controller adds no damping (α = −E/(T·v²) explodes near v = 0
    /// and quantised velocity there is mostly noise), rad/s.
    pub min_speed_rad_s: f64,
    /// Ticks between sending a torque and it acting on the wheel beyond the one-tick
    /// sample-and-hold (USB + firmware latency in loop ticks; 0..=63). The observer pairs
    /// each velocity with the torque that was acting, so delay-induced energy shows up.
    pub port_delay_ticks: usize,
}

impl Default for PassivityParams {
    fn default() -> Self {
        Self {
            max_damping_nm_s_per_rad: 0.5,
            min_speed_rad_s: 0.02,
            port_delay_ticks: 2,
        }
    }
}

impl PassivityParams {
    /// Check every field; the error names the field and its allowed range.
    pub fn validate(&self) -> Result<(), ConfigError> {
        let d = self.max_damping_nm_s_per_rad;
        if !(d.is_finite() && (0.0..=10.0).contains(&d)) {
            return Err(ConfigError(format!(
                "passivity.max_damping_nm_s_per_rad = {d}, allowed [0, 10]"
            )));
        }
        let v = self.min_speed_rad_s;
        if !(v.is_finite() && v > 0.0 && v <= 10.0) {
            return Err(ConfigError(format!(
                "passivity.min_speed_rad_s = {v}, allowed (0, 10]"
            )));
        }
        if self.port_delay_ticks >= PORT_HISTORY {
            return Err(ConfigError(format!(
                "passivity.port_delay_ticks = {}, allowed [0, {}]",
                self.port_delay_ticks,
                PORT_HISTORY - 1
            )));
        }
        Ok(())
    }
}

const PORT_HISTORY: usize = 64;

/// One tick of the passivity controller.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PassivityOutput {
    /// Torque after the adaptive damper, N·m.
    pub torque_nm: f64,
    /// Damping added this tick α, N·m·s/rad (0 when the observed energy is non-negative).
    pub damping_nm_s_per_rad: f64,
    /// Observed energy E, J: the net energy the virtual environment has absorbed from the
    /// wheel port. Negative means it has generated energy (active, may oscillate).
    pub energy_j: f64,
}

/// Hannaford–Ryu time-domain passivity observer and controller (IEEE T-RA 2002) at the
/// impedance port of the wheel, for the passive part of the rendered environment (the
/// eq. 3.5 model and the condition effects).
///
/// Observer: `E[n] = Σ (−τ_port[k]·Δθ[k] − ΔU[k])`, the energy the environment has
/// dissipated. `τ_port` is the passive torque acting on the wheel during tick `k` (sent
/// `1 + port_delay_ticks` ticks earlier, so the delay's energy leak is seen), `Δθ` the
/// measured angle change over the tick (position-based: no velocity-estimator lag in the
/// energy), and `ΔU` the change of the environment's own stored energy (spring potential,
/// virtual inertia) caused by the motion. A passive environment keeps `E ≥ 0`; a
/// deflected spring releasing its own energy is not counted as generation.
///
/// Controller: when `E` plus the dissipation already sent but not yet acting is negative,
/// add a damper `α = −E/(T·v²)` to the outgoing torque, capped at
/// `max_damping_nm_s_per_rad` and disabled below `min_speed_rad_s`.
///
/// Call [`step`](Self::step) with the environment's torque, then
/// [`commit`](Self::commit) with the torque actually sent after the safety limiter.
#[derive(Clone, Debug)]
pub struct PassivityController {
    params: PassivityParams,
    energy_j: f64,
    pending_j: f64,
    sent: [(f64, f64); PORT_HISTORY],
    next: usize,
    credit_j: f64,
    last_angle_rad: Option<f64>,
}

impl PassivityController {
    /// A controller with validated `params`, zero energy and no torque history.
    pub fn new(params: PassivityParams) -> Result<Self, WheelError> {
        params.validate()?;
        Ok(Self {
            params,
            energy_j: 0.0,
            pending_j: 0.0,
            sent: [(0.0, 0.0); PORT_HISTORY],
            next: 0,
            credit_j: 0.0,
            last_angle_rad: None,
        })
    }

    /// The observed energy, J.
    pub fn energy_j(&self) -> f64 {
        self.energy_j
    }

    /// Forget the history (e.g. after the wheel was re-centred with the motor off).
    pub fn reset(&mut self) {
        self.energy_j = 0.0;
        self.pending_j = 0.0;
        self.sent = [(0.0, 0.0); PORT_HISTORY];
        self.next = 0;
        self.credit_j = 0.0;
        self.last_angle_rad = None;
    }

    /// Observe the last tick and damp `torque_nm` if the environment has gone active.
    /// `angle_rad` is the measured angle, `vel_rad_s` the estimated velocity,
    /// `storage_change_j` the change of the environment's stored energy due to the motion
    /// over the tick (its storage at the new state minus at the old, same environment), and
    /// `dt_s` the tick length. Non-finite inputs observe nothing and pass the torque through
    /// (the limiter rejects it).
    pub fn step(
        &mut self,
        torque_nm: f64,
        angle_rad: f64,
        vel_rad_s: f64,
        storage_change_j: f64,
        dt_s: f64,
    ) -> PassivityOutput {
        if !(angle_rad.is_finite()
            && vel_rad_s.is_finite()
            && storage_change_j.is_finite()
            && dt_s.is_finite()
            && dt_s > 0.0)
        {
            return PassivityOutput {
                torque_nm,
                damping_nm_s_per_rad: 0.0,
                energy_j: self.energy_j,
            };
        }
        // The torque acting during the tick that just ended was sent 1 + D ticks ago.
        let back = 1 + self.params.port_delay_ticks;
        let idx = (self.next + PORT_HISTORY - back) % PORT_HISTORY;
        let (port_nm, credit_j) = self.sent[idx];
        let d_angle = self.last_angle_rad.map_or(0.0, |a| angle_rad - a);
        self.last_angle_rad = Some(angle_rad);
        self.energy_j += -port_nm * d_angle - storage_change_j;
        self.pending_j = (self.pending_j - credit_j).max(0.0);

        let expected = self.energy_j + self.pending_j;
        let v2 = vel_rad_s * vel_rad_s;
        let alpha = if expected < 0.0 && vel_rad_s.abs() >= self.params.min_speed_rad_s {
            (-expected / (dt_s * v2)).min(self.params.max_damping_nm_s_per_rad)
        } else {
            0.0
        };
        self.credit_j = alpha * v2 * dt_s;
        PassivityOutput {
            torque_nm: torque_nm - alpha * vel_rad_s,
            damping_nm_s_per_rad: alpha,
            energy_j: self.energy_j,
        }
    }

    /// Record the passive torque actually sent to the wheel this tick, N·m (the
    /// environment's share of what left the safety chain).
    pub fn commit(&mut self, sent_nm: f64) {
        let sent = if sent_nm.is_finite() { sent_nm } else { 0.0 };
        self.pending_j += self.credit_j;
        self.sent[self.next] = (sent, self.credit_j);
        self.credit_j = 0.0;
        self.next = (self.next + 1) % PORT_HISTORY;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spring_pulls_back_towards_centre_and_damper_opposes_motion() {
        let m = SpringDamper {
            k_nm_per_rad: 2.0,
            b_nm_s_per_rad: 0.5,
            i_kg_m2: 0.0,
            centre_rad: 0.0,
        };
        assert_eq!(m.torque_nm(0.5, 0.0, 0.0), -1.0);
        assert_eq!(m.torque_nm(0.0, -2.0, 0.0), 1.0);
    }
}
