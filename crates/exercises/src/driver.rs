//! Simple driver models: a preview steering law (what a driver aims for) and a speed
//! controller (cruise control standing in for the pedals in simulated sessions).

use crate::model::{DriverInput, VehicleParams, VehicleState};
use crate::road::{Projection, Road};
use common::wrap_angle;

/// Preview steering: a pure-pursuit driver aiming at the centre line a look-ahead time ahead.
///
/// The target is the centre-line point at arc length `s + ℓ`, ℓ = max(|U|·`preview_s`,
/// `min_lookahead_m`).
/// The arc from the car through it along the car's course (heading plus side-slip angle) has
/// curvature `κ = 2 sin α / d` (α: angle from the course to the target, d: its distance),
/// which is exact on a circular road. The road-wheel angle is that curvature through the
/// steady-state bicycle model, `δ = (L + K·U²)·κ` (K: understeer gradient), plus optional
/// feedback on the present lateral and heading errors:
/// `− k_lateral·e_y − k_heading·e_ψ`.
#[derive(Clone, Debug)]
pub struct PreviewDriver {
    /// Look-ahead time, s. Shorter reacts faster but can oscillate; longer cuts corners.
    pub preview_s: f64,
    /// Shortest look-ahead distance, m (keeps the aim point ahead at low speed).
    pub min_lookahead_m: f64,
    /// Feedback gain on the present lateral error, rad/m.
    pub k_lateral_rad_per_m: f64,
    /// Feedback gain on the present heading error, rad/rad.
    pub k_heading: f64,
}

impl Default for PreviewDriver {
    fn default() -> Self {
        Self {
            preview_s: 0.6,
            min_lookahead_m: 4.0,
            k_lateral_rad_per_m: 0.02,
            k_heading: 0.1,
        }
    }
}

impl PreviewDriver {
    /// Road-wheel angle the driver wants, rad, given the car state and its projection `here`
    /// onto `road`. Non-finite state gives 0.
    pub fn desired_steer_rad(
        &self,
        params: &VehicleParams,
        state: &VehicleState,
        here: &Projection,
        road: &dyn Road,
    ) -> f64 {
        let u = state.ux_m_s.max(1.0);
        let lookahead_m = (state.ux_m_s.abs() * self.preview_s).max(self.min_lookahead_m.max(0.5));
        let ([tx, ty], _, _) = road.centre(here.s_m + lookahead_m);
        let (dx, dy) = (tx - state.x_m, ty - state.y_m);
        let d = dx.hypot(dy).max(1e-3);
        let course = state.yaw_rad + state.uy_m_s.atan2(state.ux_m_s.abs().max(0.1));
        let alpha = wrap_angle(dy.atan2(dx) - course);
        let kappa = 2.0 * alpha.sin() / d;
        let gain = params.wheelbase_m() + params.understeer_gradient_rad_s2_per_m() * u * u;
        let heading_err = wrap_angle(state.yaw_rad - here.heading_rad);
        let steer =
            gain * kappa - self.k_lateral_rad_per_m * here.lateral_m - self.k_heading * heading_err;
        if steer.is_finite() { steer } else { 0.0 }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn speed_controller_brakes_above_target_and_never_both_pedals() {
        let c = SpeedController {
            target_m_s: 10.0,
            gain_n_per_m_s: 1000.0,
            max_force_n: 3000.0,
        };
        let fast = c.input(15.0, 0.1);
        assert_eq!((fast.drive_force_n, fast.brake_force_n), (0.0, 3000.0));
        let slow = c.input(9.0, 0.0);
        assert_eq!((slow.drive_force_n, slow.brake_force_n), (1000.0, 0.0));
        assert_eq!(fast.steer_rad, 0.1);
    }
}
