//! Rate-gyro integration on SO(3), sensor models, orientation fusion, the arm–wheel chain and
//! IMU devices (thesis Chapter 4, §3.2.2).
//!
//! Everything except [`device`]'s HID backend is pure: no I/O, no threads, no clock; time comes
//! in as `dt` or timestamps.

pub mod arm;
pub mod bias;
pub mod chain;
pub mod device;
pub mod error;
pub mod fusion;
pub mod integrate;
pub mod mounting;
pub mod pose;
pub mod sensor;
pub mod sim;
pub mod so3;

pub use error::ImuError;
