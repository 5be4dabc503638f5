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
    let mut rows = take_rows(shape[0]);
    match a.as_slice() {
        // C-contiguous (what the facade passes): one straight copy
        Ok(flat) => rows.extend(flat.chunks_exact(3).map(|r| [r[0], r[1], r[2]])),
        Err(_) => rows.extend(a.as_array().rows().into_iter().map(|r| [r[0], r[1], r[2]])),
    }
    if let Some(i) = rows.iter().position(|r| !r.iter().all(|x| x.is_finite())) {
        return Err(value_error(format!(
            "{name}[{i}] is not finite (NaN or infinity)"
        )));
    }
    Ok(rows)
}

/// Most row buffers kept per thread by [`give_rows`].
const MAX_ROW_BUFFERS: usize = 6;

/// Most bytes kept per thread by [`give_rows`] (three 200 000-sample arrays).
const MAX_ROW_BYTES: usize = 16 << 20;

thread_local! {
    static ROW_BUFFERS: std::cell::RefCell<Vec<Vec<[f64; 3]>>> =
        const { std::cell::RefCell::new(Vec::new()) };
}

/// An empty buffer for `n` rows: one kept by [`give_rows`] on this thread when one is large
/// enough. The copies of the (N, 3) inputs are 144 KiB each at 6 000 samples, past the size
/// the allocator maps fresh from the system, so a new one page-faults in on every call.
fn take_rows(n: usize) -> Vec<[f64; 3]> {
    let kept = ROW_BUFFERS.with(|b| {
        let mut b = b.borrow_mut();
        let i = b.iter().position(|v| v.capacity() >= n)?;
        Some(b.swap_remove(i))
    });
    match kept {
        Some(mut v) => {
            v.clear();
            v
        }
        None => Vec::with_capacity(n),
    }
}

/// Keep `v`'s memory for the next [`rows3`] on this thread (bounded; dropped beyond).
pub fn give_rows(v: Vec<[f64; 3]>) {
    ROW_BUFFERS.with(|b| {
        let mut b = b.borrow_mut();
        let bytes: usize = b.iter().map(|x| x.capacity() * 24).sum();
        if b.len() < MAX_ROW_BUFFERS && bytes + v.capacity() * 24 <= MAX_ROW_BYTES {
            b.push(v);
        }
    });
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
