//! The native module behind the Python package `telerehab` (`telerehab._native`).
//!
//! A thin layer: numpy arrays in, checked for shape and dtype, calls into the pure crates,
//! numpy arrays out. The Python facade in `python/telerehab` is the public API.
//!
//! Modules (private): `check` (the binding convention every function follows: shapes, dtypes,
//! `ValueError`s, the GIL released), `calib` (`telerehab.calib`), `imu` (`telerehab.imu`),
//! `metrics` (`telerehab.metrics`), `session` (`telerehab.session`: recordings
//! read by the `record` crate).

use pyo3::prelude::*;

mod calib;
mod check;
mod imu;
mod metrics;
mod session;

/// The `telerehab._native` module.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    calib::register(m)?;
    imu::register(m)?;
    metrics::register(m)?;
    session::register(m)?;
    Ok(())
}
