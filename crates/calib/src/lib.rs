//! Kinematic calibration of the patient's arm (thesis Chapter 4).
//!
//! Pure: arrays in, estimates out. No I/O, threads or clocks.

pub mod fourbar;
