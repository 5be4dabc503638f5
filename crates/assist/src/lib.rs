//! Active motion and force assist (thesis Chapter 5), and the simulated human that the
//! controllers are designed and tested against.
//!
//! Pure: controllers are structs with a `step(..., dt)` method; no I/O, threads or clocks.

pub mod human;

pub use human::{HumanArm, HumanArmParams};
