//! Simple driver models: a preview steering law (what a driver aims for) and a speed
//! controller (cruise control standing in for the pedals in simulated sessions).

use crate::model::{DriverInput, VehicleParams, VehicleState};
use crate::road::{Projection, Road};

/// Preview steering: aims the car at the centre line a look-ahead time ahead.
///
/// δ = L·κ(s + ℓ) + k_y·(−e_y(ℓ)) + k_ψ·(−e_ψ): curvature feed-forward plus correction of the
/// predicted lateral and heading errors at the preview distance ℓ = U·t_preview.
#[derive(Clone, Debug)]
pub struct PreviewDriver {
    /// Look-ahead time, s.
    pub preview_s: f64,
    /// Lateral-error gain, rad/m.
    pub k_lateral_rad_per_m: f64,
    /// Heading-error gain, rad/rad.
    pub k_heading: f64,
}

impl Default for PreviewDriver {
    fn default() -> Self {
        Self {
            preview_s: 0.8,
            k_lateral_rad_per_m: 0.04,
            k_heading: 0.5,
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
        let lookahead_m = state.ux_m_s.max(1.0) * self.preview_s;
        let (sy, cy) = state.yaw_rad.sin_cos();
        let px = state.x_m + cy * lookahead_m;
        let py = state.y_m + sy * lookahead_m;
        let ahead = road.project(px, py, here.s_m + lookahead_m);
        let heading_err = wrap_angle(state.yaw_rad - ahead.heading_rad);
        let wheelbase = params.cg_to_front_m + params.cg_to_rear_m;
        wheelbase * ahead.curvature_1_m
            - self.k_lateral_rad_per_m * ahead.lateral_m
            - self.k_heading * heading_err
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
