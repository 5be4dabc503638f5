//! The binding convention every native function follows (`calib`, `imu` and `metrics` alike):
//!
//! - arrays arrive typed as float64 numpy arrays (the facade converts first); shapes and
//!   finiteness are re-checked here so each native function is safe on its own;
//! - every bad input is a `ValueError` that names the Python argument (with its unit suffix,
//!   e.g. `phi2_rad`, `dt_s`) and what was expected;
//! - inputs are copied out of numpy, then the GIL is released around the work (`py.detach`);
//! - results with more than one value are frozen `#[pyclass]`es with unit-suffixed fields, or
//!   plain tuples that the facade wraps in a frozen dataclass (`telerehab.metrics.Movement`).

use numpy::{PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// A `ValueError` with `msg`.
pub fn value_error(msg: impl Into<String>) -> PyErr {
    PyValueError::new_err(msg.into())
}

/// Argument `name` (shape `(N, 3)`) as rows, or a `ValueError` naming it.
pub fn rows3(name: &str, a: &PyReadonlyArray2<'_, f64>) -> PyResult<Vec<[f64; 3]>> {
    let shape = a.shape();
    if shape[1] != 3 {
        return Err(value_error(format!(
            "{name} must have shape (N, 3), got {shape:?}"
        )));
    }
    let rows: Vec<[f64; 3]> = a
        .as_array()
        .rows()
        .into_iter()
        .map(|r| [r[0], r[1], r[2]])
        .collect();
    if let Some(i) = rows.iter().position(|r| !r.iter().all(|x| x.is_finite())) {
        return Err(value_error(format!(
            "{name}[{i}] is not finite (NaN or infinity)"
        )));
    }
    Ok(rows)
}

/// Argument `name` (shape `(N,)`) as a vector; finiteness is left to the pure crates, which
/// check it and name the argument.
pub fn vec1(a: &PyReadonlyArray1<'_, f64>) -> Vec<f64> {
    a.as_array().to_vec()
}

/// Check that every sample of argument `name` (shape `(N,)`) is finite, for the crate
/// functions that do not check it themselves.
pub fn finite(name: &str, x: &[f64]) -> PyResult<()> {
    match x.iter().position(|v| !v.is_finite()) {
        Some(i) => Err(value_error(format!(
            "{name}[{i}] is not finite (NaN or infinity)"
        ))),
        None => Ok(()),
    }
}

/// Check that `len` equals the reference length `n` of argument `reference`.
pub fn same_len(name: &str, len: usize, reference: &str, n: usize) -> PyResult<()> {
    if len == n {
        Ok(())
    } else {
        Err(value_error(format!(
            "{name} has {len} rows but {reference} has {n}"
        )))
    }
}
