//! Rate-gyro integration on SO(3) and the arm's orientation chain (thesis Chapter 4).
//!
//! Pure math here; devices live behind the `Imu` trait in later modules.

pub mod so3;
