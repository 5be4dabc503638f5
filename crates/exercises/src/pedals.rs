//! Driving the car's speed with the pedals: the patient's throttle and brake become the drive
//! and brake forces of eq. C.11 (`Fad`, `Fbd`), under a speed governor at the exercise's own
//! speed; and a simulated foot that works the pedals as a patient would, so that tests and
//! simulated sessions drive them.

use crate::driver::SpeedController;
use crate::model::DriverInput;

/// Where the pedals are, each a fraction of its travel in [0, 1] (0: released).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Pedals {
    /// Accelerator, 0..=1.
    pub throttle: f64,
    /// Brake, 0..=1.
    pub brake: f64,
}

impl Pedals {
    /// Each pedal clamped to [0, 1]; a NaN (a device gone wrong) reads as released.
    pub fn clamped(self) -> Self {
        let one = |x: f64| {
            if x.is_finite() {
                x.clamp(0.0, 1.0)
            } else {
                0.0
            }
        };
        Self {
            throttle: one(self.throttle),
            brake: one(self.brake),
        }
    }
}

/// The pedals' forces on the car: full throttle gives `max_force_n` of drive, full brake as
/// much braking. The drive force is governed so that the car never goes faster than the
/// exercise's speed at that point of the road (the road and the haptic feel were built for
/// it), however far the throttle is pressed: above it the governor's force, which falls to
/// zero at the limit, is the most the throttle gets.
#[derive(Clone, Debug)]
pub struct PedalDrive {
    /// The governor: its `target_m_s` is the top speed, its gain and force limit the pedals'.
    pub governor: SpeedController,
}

impl PedalDrive {
    /// Forces for `pedals` at forward speed `ux_m_s` under the governor's top speed;
    /// `steer_rad` is passed through.
    pub fn input(&self, pedals: Pedals, ux_m_s: f64, steer_rad: f64) -> DriverInput {
        let p = pedals.clamped();
        let max = self.governor.max_force_n;
        let governed = self.governor.input(ux_m_s, steer_rad);
        DriverInput {
            steer_rad,
            drive_force_n: (p.throttle * max).min(governed.drive_force_n),
            brake_force_n: p.brake * max,
        }
    }
}

/// A simulated patient's foot on the pedals: it aims at the exercise's speed, pressing the
/// throttle in proportion to how much too slow the car is and the brake when it is too fast,
/// with a first-order lag standing in for the time a foot takes to move (never both pedals at
/// once). Positions are on an 8-bit grid, as a consumer pedal's converter reports them.
#[derive(Clone, Debug)]
pub struct SimFoot {
    /// Pedal travel per m/s of speed error.
    pub gain_per_m_s: f64,
    /// Time constant of the foot, s.
    pub lag_s: f64,
    /// Speed the foot aims below the target, as a fraction of it (a careful driver keeps a
    /// little under the limit).
    pub margin: f64,
    position: f64,
}

impl Default for SimFoot {
    fn default() -> Self {
        Self {
            gain_per_m_s: 0.25,
            lag_s: 0.3,
            margin: 0.05,
            position: 0.0,
        }
    }
}

/// Steps of a consumer pedal's 8-bit converter.
pub const PEDAL_STEPS: f64 = 255.0;

impl SimFoot {
    /// Where the foot puts the pedals after `dt_s` at speed `ux_m_s`, aiming at `target_m_s`.
    pub fn step(&mut self, ux_m_s: f64, target_m_s: f64, dt_s: f64) -> Pedals {
        let aim = target_m_s * (1.0 - self.margin);
        // Positive: throttle; negative: brake.
        let wanted = (self.gain_per_m_s * (aim - ux_m_s)).clamp(-1.0, 1.0);
        let wanted = if wanted.is_finite() { wanted } else { 0.0 };
        let a = (dt_s / self.lag_s.max(dt_s)).clamp(0.0, 1.0);
        self.position += a * (wanted - self.position);
        let on_grid = |x: f64| (x * PEDAL_STEPS).round() / PEDAL_STEPS;
        Pedals {
            throttle: on_grid(self.position.max(0.0)),
            brake: on_grid((-self.position).max(0.0)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Vehicle, VehicleParams, VehicleState};

    fn drive() -> PedalDrive {
        PedalDrive {
            governor: SpeedController {
                target_m_s: 12.0,
                gain_n_per_m_s: 2000.0,
                max_force_n: 8000.0,
            },
        }
    }

    #[test]
    fn full_throttle_never_takes_the_car_past_the_exercise_speed() {
        let params = VehicleParams::default();
        let mut car = Vehicle::new(params, VehicleState::default());
        let d = drive();
        let mut top = 0.0_f64;
        for _ in 0..60_000 {
            let ux = car.state().ux_m_s;
            let full = Pedals {
                throttle: 1.0,
                brake: 0.0,
            };
            car.step(d.input(full, ux, 0.0), 0.001);
            top = top.max(car.state().ux_m_s);
        }
        assert!(top > 11.0, "the car gets up to speed: {top} m/s");
        assert!(top <= 12.0 + 1e-6, "governed at 12 m/s: {top} m/s");
    }

    #[test]
    fn released_pedals_let_the_car_roll_and_the_brake_stops_it() {
        let d = drive();
        let none = d.input(Pedals::default(), 8.0, 0.1);
        assert_eq!((none.drive_force_n, none.brake_force_n), (0.0, 0.0));
        assert_eq!(none.steer_rad, 0.1);
        let brake = d.input(
            Pedals {
                throttle: 0.0,
                brake: 0.5,
            },
            8.0,
            0.0,
        );
        assert_eq!(brake.brake_force_n, 4000.0);
        // A NaN from a broken pedal reads as released, never as a force.
        let nan = d.input(
            Pedals {
                throttle: f64::NAN,
                brake: f64::NAN,
            },
            8.0,
            0.0,
        );
        assert_eq!((nan.drive_force_n, nan.brake_force_n), (0.0, 0.0));
    }

    #[test]
    fn the_simulated_foot_speeds_up_from_rest_and_brakes_when_too_fast() {
        let mut foot = SimFoot::default();
        let mut p = Pedals::default();
        for _ in 0..1000 {
            p = foot.step(0.0, 12.0, 0.001);
        }
        assert!(p.throttle > 0.9 && p.brake == 0.0, "{p:?}");
        for _ in 0..2000 {
            p = foot.step(20.0, 12.0, 0.001);
        }
        assert!(p.brake > 0.9 && p.throttle == 0.0, "{p:?}");
        let on_grid = (p.brake * PEDAL_STEPS).fract();
        assert!(on_grid.abs() < 1e-9, "8-bit pedal positions: {}", p.brake);
    }
}
