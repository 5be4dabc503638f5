//! The station's and the hub's measurements and drills, run by `telerehab bench` and
//! `telerehab hub chaos|cohort`: what needs the whole product running, not a micro-benchmark.
//!
//! - [`bench`](mod@bench): the window's effect on the haptic loop, the recording's bytes, an hour's soak,
//!   the loop's lateness against the platform's floor.
//! - [`chaos`] (Linux): a compressed clinic day on two hubs sharing one PostgreSQL, with hubs,
//!   stations and the database killed at random; exactly-once or it fails.
//! - [`cohort`] (Linux): the standard assessment's measurement noise over two simulated
//!   cohorts of unchanged patients (docs/RELIABILITY.md).
//!
//! Nothing here is on a patient's path: the station and the hub never depend on this crate.

pub mod bench;
#[cfg(unix)]
pub mod chaos;
#[cfg(unix)]
pub mod cohort;
