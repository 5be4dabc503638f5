//! The exercise library: every exercise a patient does on the wheel, and what it is built on —
//! the vehicle, its roads, the rotary dial task, the strength test ([`strength`]), the haptic
//! sweep ([`sweep`]), the standard assessment ([`assessment`]) and their scores. (This crate was
//! called `vehicle` until issue 43 named it for what it holds.)
//!
//! The model is the 3-DOF yaw-plane vehicle of the thesis (Jadhav 2004, Appendix C):
//! body-frame velocities `Ux`, `Uy`, yaw rate `r` (eq. C.1–C.3), driver input mapped to wheel
//! forces by eq. C.12, lateral tyre forces (eq. C.13–C.14, linear or saturating) and the global
//! pose by eq. C.15 ([`model`]). [`world`] runs the same car as a rapier2d rigid body among
//! road edges, barriers and cones. [`exercise`] is the therapist's parametric library of roads
//! and the rotary dial task; [`score`] grades them; [`feel`] gives the steering-wheel torque.
//!
//! Also: [`road`] (a centre line and projection onto it) and [`path`] (arc-length roads from
//! clothoids and sine waves), [`dial`] (the rotary dial task's signal), [`driver`] (preview
//! steering and the speed controller standing in for the pedals), [`offline`] (the model run
//! offline for `telerehab vehicle`), [`error`] ([`VehicleError`]); test-only: `reference`, an
//! independent solution of eq. C.1–C.15, and `drive_tests`, whole exercises driven and scored
//! (the one place the driver, the world and the exercise library meet).
//!
//! Pure: no I/O, no threads, no clock. Time comes in as `dt` in seconds.

pub mod assessment;
pub mod dial;
#[cfg(test)]
mod drive_tests;
pub mod driver;
pub mod error;
pub mod exercise;
pub mod feel;
pub mod model;
pub mod offline;
pub mod path;
pub mod pedals;
#[cfg(test)]
mod reference;
pub mod road;
pub mod score;
pub mod strength;
pub mod sweep;
pub mod world;

pub use assessment::{AssessmentPart, AssessmentSpec};
pub use dial::DialSignal;
pub use driver::{PreviewDriver, SpeedController};
pub use error::VehicleError;
pub use exercise::{EXERCISE_NAMES, Exercise, ExerciseSpec, LaneShift, TargetSteps};
pub use feel::AligningTorque;
pub use model::{DriverInput, TyreForces, TyreModel, Vehicle, VehicleParams, VehicleState};
pub use offline::{TimedInput, simulate};
pub use path::{PathBuilder, PathRoad};
pub use pedals::{PedalDrive, Pedals, SimFoot};
pub use road::{Projection, Road, SineRoad};
pub use score::{DialScore, DialSummary, DrivingScore, DrivingSummary, LaneScore};
pub use strength::{StrengthSide, StrengthStop, StrengthSummary, StrengthTest};
pub use sweep::{SweepLevel, SweepParameter};
pub use world::{Side, TrackLayout, World, WorldEvent};

#[cfg(test)]
mod tests {
    /// The station moves these into its haptic thread.
    #[test]
    fn world_exercise_and_roads_are_send() {
        fn send<T: Send>() {}
        send::<crate::World>();
        send::<crate::Exercise>();
        send::<crate::PathRoad>();
        send::<Box<dyn crate::Road + Send>>();
    }
}
