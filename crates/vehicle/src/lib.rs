//! Vehicle dynamics, roads and scoring for the driving exercise.
//!
//! The model is the 3-DOF yaw-plane vehicle of the thesis (Jadhav 2004, Appendix C):
//! body-frame velocities `Ux`, `Uy`, yaw rate `r` (eq. C.1–C.3), driver input mapped to wheel
//! forces by eq. C.12, linear lateral tyre forces (eq. C.13–C.14) and the global pose by eq. C.15.
//!
//! Pure: no I/O, no threads, no clock. Time comes in as `dt` in seconds.

pub mod driver;
pub mod model;
pub mod road;
pub mod score;

pub use driver::{PreviewDriver, SpeedController};
pub use model::{DriverInput, Vehicle, VehicleParams, VehicleState};
pub use road::{Projection, Road, SineRoad};
pub use score::LaneScore;
