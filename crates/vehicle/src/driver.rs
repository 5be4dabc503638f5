//! Simple driver models: a preview steering law (what a driver aims for) and a speed
//! controller (cruise control standing in for the pedals in simulated sessions).

use crate::model::{DriverInput, VehicleParams, VehicleState};
use crate::road::{Projection, Road};

/// Preview steering by pure pursuit: aim at the centre-line point a look-ahead distance
/// ℓ = max(U·t_preview, ℓ_min) further along the road, on the circular arc through the car that
/// is tangent to its heading: curvature κ = 2·y_c/ℓ² (y_c: the goal's lateral offset in the car
/// frame), road-wheel angle δ = atan(L·κ).
#[derive(Clone, Debug)]
pub struct PreviewDriver {
    /// Look-ahead time, s.
    pub preview_s: f64,
    /// Shortest look-ahead distance, m.
    pub min_lookahead_m: f64,
}

impl Default for PreviewDriver {
    fn default() -> Self {
        Self {
            preview_s: 0.6,
            min_lookahead_m: 4.0,
        }
    }
}

impl PreviewDriver {
    /// Road-wheel angle the driver wants, rad, given the car state and its projection.
    pub fn desired_steer_rad(
        &self,
        params: &VehicleParams,
        state: &VehicleState,
        here: &Projection,
        road: &dyn Road,
    ) -> f64 {
        let lookahead_m = (state.ux_m_s.abs() * self.preview_s).max(self.min_lookahead_m);
        let ([gx, gy], _, _) = road.centre(here.s_m + lookahead_m);
        let (sy, cy) = state.yaw_rad.sin_cos();
        let (dx, dy) = (gx - state.x_m, gy - state.y_m);
        let y_car = -sy * dx + cy * dy;
        let dist2 = (dx * dx + dy * dy).max(1e-6);
        let wheelbase = params.cg_to_front_m + params.cg_to_rear_m;
        (wheelbase * 2.0 * y_car / dist2).atan()
    }
}

/// Wrap an angle to (−π, π], rad.
pub fn wrap_angle(a: f64) -> f64 {
    let t = a.rem_euclid(std::f64::consts::TAU);
    if t > std::f64::consts::PI {
        t - std::f64::consts::TAU
    } else {
        t
    }
}

/// Proportional cruise control producing drive and brake forces (eq. C.11's `Fad`, `Fbd`).
#[derive(Clone, Debug)]
pub struct SpeedController {
    /// Target forward speed, m/s.
    pub target_m_s: f64,
    /// Gain, N per m/s of speed error.
    pub gain_n_per_m_s: f64,
    /// Largest drive or brake force, N.
    pub max_force_n: f64,
}

impl SpeedController {
    /// Pedal forces for the current forward speed `ux_m_s`; `steer_rad` is passed through.
    pub fn input(&self, ux_m_s: f64, steer_rad: f64) -> DriverInput {
        let f = (self.gain_n_per_m_s * (self.target_m_s - ux_m_s))
            .clamp(-self.max_force_n, self.max_force_n);
        DriverInput {
            steer_rad,
            drive_force_n: f.max(0.0),
            brake_force_n: (-f).max(0.0),
        }
    }
}
