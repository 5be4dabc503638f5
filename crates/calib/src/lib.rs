//! Kinematic calibration of the patient's arm (thesis Chapter 4).
//!
//! - [`arm3d`]: the spatial arm loop (eq. 4.1 in 3-D): shoulder position and segment lengths
//!   from the IMU segment directions and the grip point, in closed form, batch and online.
//! - [`fourbar`]: the planar arm–wheel four-bar (§4.2.1): global closed form, the thesis's
//!   Gauss–Newton, robust Levenberg–Marquardt with gyro-bias terms, and an online estimator.
//! - [`serial`]: serial-chain SE(3) calibration of initial frames (§4.3).
//! - [`se3`]: the rigid-motion maps both use.
//! - [`error`]: the errors, [`CalibError`].
//!
//! Pure: arrays in, estimates out. No I/O, threads or clocks. (The four-bar fit keeps the
//! memory of its per-sample buffers per thread between calls, bounded, so long recordings do
//! not page-fault it in again on every call.)

pub mod arm3d;
pub mod error;
pub mod fourbar;
pub mod se3;
pub mod serial;

pub use arm3d::{
    Arm3dCalibration, Arm3dParams, ArmLoopOptions, ArmLoopSamples, HeadingModel, OnlineArm3d,
    OnlineArm3dOptions, calibrate_arm_3d,
};
pub use error::CalibError;
pub use fourbar::online::{OnlineFourbar, OnlineOptions};
pub use fourbar::{
    FourbarCalibration, FourbarMethod, FourbarOptions, FourbarParams, FourbarSamples, calibrate,
};
pub use serial::{SerialCalibration, SerialOptions, calibrate_serial_chain};
