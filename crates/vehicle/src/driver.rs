//! Simple driver models: a preview steering law (what a driver aims for) and a speed
//! controller (cruise control standing in for the pedals in simulated sessions).

use crate::model::{DriverInput, VehicleParams, VehicleState};
use crate::road::{Projection, Road};

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

/// Wrap an angle to (−π, π], rad (one definition for the workspace, in `common`).
pub use common::wrap_angle;

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
    use crate::exercise::{EXERCISE_NAMES, Exercise, ExerciseSpec, SineSpec};
    use crate::model::Vehicle;
    use crate::score::{DrivingScore, DrivingSummary};

    /// Drive `ex` with the preview driver and cruise control on the pure model at 200 Hz.
    fn drive(ex: &Exercise, driver: &PreviewDriver) -> DrivingSummary {
        let p = VehicleParams::default();
        let road = ex.road.as_ref().expect("road exercise");
        let mut car = Vehicle::new(p.clone(), ex.start_state());
        let mut score = DrivingScore::default();
        let dt = 0.005;
        let mut s_hint = 0.0;
        let mut t = 0.0;
        while t < 600.0 {
            let st = *car.state();
            let here = road.project(st.x_m, st.y_m, s_hint);
            s_hint = here.s_m;
            if ex.is_finished(t, here.s_m) {
                score.complete(t);
                break;
            }
            score.update(&here, st.yaw_rad, road.lane_width_m(), dt);
            let steer = driver.desired_steer_rad(&p, &st, &here, road.as_ref());
            let cruise = SpeedController {
                target_m_s: ex.target_speed_m_s(here.s_m),
                gain_n_per_m_s: 3000.0,
                max_force_n: 8000.0,
            };
            car.step(cruise.input(st.ux_m_s, steer), dt);
            t += dt;
        }
        score.summary()
    }

    #[test]
    fn preview_driver_completes_every_road_exercise_mostly_in_lane() {
        for name in EXERCISE_NAMES.iter() {
            let ex = ExerciseSpec::from_name(name).unwrap().build().unwrap();
            if ex.road.is_none() {
                continue;
            }
            let s = drive(&ex, &PreviewDriver::default());
            eprintln!("{name}: {s:?}");
            assert!(s.completion_time_s.is_some(), "{name} not completed: {s:?}");
            assert!(s.pct_in_lane >= 95.0, "{name}: {s:?}");
            assert!(s.rms_lateral_m < 0.25, "{name}: {s:?}");
        }
    }

    #[test]
    fn larger_sine_amplitude_scores_monotonically_worse() {
        let mut last = 0.0;
        for amplitude_m in [1.0, 3.0, 6.0, 10.0, 15.0] {
            let spec = ExerciseSpec::Sine(SineSpec {
                amplitude_m,
                ..Default::default()
            });
            let s = drive(&spec.build().unwrap(), &PreviewDriver::default());
            eprintln!("A = {amplitude_m}: {s:?}");
            assert!(
                s.rms_lateral_m > last,
                "A = {amplitude_m}: {s:?} not worse than {last}"
            );
            last = s.rms_lateral_m;
        }
    }

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
