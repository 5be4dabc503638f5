//! Motion assist by input–output linearisation (thesis §5.4.1, eq. 5.11–5.32), in three
//! flavours: the thesis's unconstrained law, the same law with a naive output clamp (which
//! winds up), and the saturation-aware law whose integrator state *is* the actuator torque.

use crate::limits::Limits;
use crate::model::PlantParams;

/// The desired trajectory in the linearised coordinates `z_d` of eq. 5.32.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DesiredMotion {
    /// θ¹_d, rad.
    pub angle_rad: f64,
    /// θ²_d, rad/s.
    pub vel_rad_s: f64,
    /// z³_d (desired acceleration), rad/s².
    pub acc_rad_s2: f64,
    /// ż³_d (desired jerk), rad/s³.
    pub jerk_rad_s3: f64,
}

/// How the controller meets the actuator's limits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SaturationHandling {
    /// The thesis design: no limits at all (Fig. 5-4 shows the torque this needs).
    Unconstrained,
    /// Integrate `u` freely and clamp only the output: the internal torque winds up.
    NaiveClamp,
    /// Clamp the torque rate to the slew limit and the torque state to the ceiling before
    /// storing it, so the integrator state always equals the torque actually applied
    /// (back-calculation with infinite tracking gain; Åström & Rundqwist 1989,
    /// "Integrator windup and how to avoid it", ACC).
    AntiWindup,
}

/// The linearising motion controller. State: the torque `θ³` (eq. 5.9).
#[derive(Clone, Debug)]
pub struct LinearisingMotion {
    model: PlantParams,
    gains: [f64; 3],
    handling: SaturationHandling,
    torque_state_nm: f64,
    applied_nm: f64,
}

impl LinearisingMotion {
    /// A controller for `model` with gains `[K₀, K₁, K₂]` (eq. 5.30), torque state zero.
    pub fn new(model: PlantParams, gains: [f64; 3], handling: SaturationHandling) -> Self {
        Self {
            model,
            gains,
            handling,
            torque_state_nm: 0.0,
            applied_nm: 0.0,
        }
    }

    /// The internal torque state θ³, N·m (what winds up under [`SaturationHandling::NaiveClamp`]).
    pub fn torque_state_nm(&self) -> f64 {
        self.torque_state_nm
    }

    /// Force the torque state to what the actuator really applied (bumpless transfer and
    /// back-calculation from a later limiter), N·m.
    pub fn track_applied(&mut self, applied_nm: f64) {
        self.torque_state_nm = applied_nm;
        self.applied_nm = applied_nm;
    }

    /// The torque rate `u = α(θ) + β·v` of eq. 5.31 with `v` of eq. 5.30, N·m/s. The third
    /// coordinate `z³` is the model acceleration of eq. 5.28 computed from the torque state,
    /// so a hand torque the model does not see acts as a disturbance.
    pub fn rate_nm_per_s(&self, angle_rad: f64, vel_rad_s: f64, d: &DesiredMotion) -> f64 {
        let state = [angle_rad, vel_rad_s, self.torque_state_nm];
        let z = self.model.to_linear_coordinates(state);
        let [k0, k1, k2] = self.gains;
        let v = d.jerk_rad_s3
            + k2 * (d.acc_rad_s2 - z[2])
            + k1 * (d.vel_rad_s - z[1])
            + k0 * (d.angle_rad - z[0]);
        self.model.linearising_alpha(state) + self.model.linearising_beta() * v
    }

    /// One tick: compute `u`, integrate the torque state over `dt_s` and return the torque
    /// to apply, N·m. `limits` is ignored by [`SaturationHandling::Unconstrained`].
    pub fn step(
        &mut self,
        angle_rad: f64,
        vel_rad_s: f64,
        desired: &DesiredMotion,
        limits: Limits,
        dt_s: f64,
    ) -> f64 {
        let u = self.rate_nm_per_s(angle_rad, vel_rad_s, desired);
        match self.handling {
            SaturationHandling::Unconstrained => {
                self.torque_state_nm += u * dt_s;
                self.applied_nm = self.torque_state_nm;
            }
            SaturationHandling::NaiveClamp => {
                self.torque_state_nm += u * dt_s;
                self.applied_nm = limits.apply(self.applied_nm, self.torque_state_nm, dt_s).0;
            }
            SaturationHandling::AntiWindup => {
                let u = u.clamp(-limits.slew_nm_per_s, limits.slew_nm_per_s);
                self.torque_state_nm =
                    (self.torque_state_nm + u * dt_s).clamp(-limits.ceiling_nm, limits.ceiling_nm);
                self.applied_nm = self.torque_state_nm;
            }
        }
        self.applied_nm
    }
}
