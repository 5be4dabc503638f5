//! Calibration bindings: the planar four-bar (batch and online), the spatial arm loop
//! (`calib::arm3d`) and the serial-chain SE(3) calibration of crate `calib`, following the
//! convention in [`crate::check`]. Arrays are copied out of numpy before the GIL is released,
//! so other Python threads may run (and even mutate the inputs) during the work.

use calib::fourbar::FourbarStdErrors;
use calib::{
    CalibError, FourbarCalibration, FourbarMethod, FourbarOptions, FourbarParams, FourbarSamples,
    OnlineFourbar, OnlineOptions, SerialCalibration, SerialOptions,
};
use nalgebra::Matrix4;
use numpy::{PyArray3, PyReadonlyArray1, PyReadonlyArray2, PyReadonlyArray3, PyReadonlyArray4};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::check::{give_rows, rows3, same_len, value_error, vec1};

/// Add the calibration functions to the native module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(calibrate_planar_fourbar, m)?)?;
    m.add_function(wrap_pyfunction!(calibrate_serial_chain, m)?)?;
    m.add_class::<PlanarFourbarResult>()?;
    m.add_class::<OnlinePlanarFourbar>()?;
    m.add_class::<SerialChainResult>()?;
    m.add_function(wrap_pyfunction!(calibrate_arm_3d, m)?)?;
    m.add_class::<Arm3dResult>()?;
    Ok(())
}

/// The Python name of a `calib` argument: the facade's names carry their unit.
fn python_name(argument: &'static str) -> &'static str {
    match argument {
        "phi2" => "phi2_rad",
        "phi3" => "phi3_rad",
        "phi4" => "phi4_rad",
        "l2" => "l2_m",
        "grip_points" => "grip_points_m",
        other => other,
    }
}

/// A `ValueError` for `e`, naming the argument as Python knows it.
fn calib_error(mut e: CalibError) -> PyErr {
    match &mut e {
        CalibError::NonFinite { argument, .. }
        | CalibError::TooFewSamples { argument, .. }
        | CalibError::OutOfRange { argument, .. }
        | CalibError::NotUnitVector { argument, .. }
        | CalibError::NotRigidTransform { argument, .. } => *argument = python_name(argument),
        CalibError::LengthMismatch {
            argument,
            reference,
            ..
        } => {
            *argument = python_name(argument);
            *reference = python_name(reference);
        }
        _ => {}
    }
    value_error(e.to_string())
}

/// A calibrated planar four-bar (lengths m, angles rad in the frame where the ground link
/// lies along +x from wheel centre to shoulder) and how far to trust it.
#[pyclass(frozen, module = "telerehab._native")]
pub struct PlanarFourbarResult {
    #[pyo3(get)]
    l1: f64,
    #[pyo3(get)]
    l3: f64,
    #[pyo3(get)]
    l4: f64,
    #[pyo3(get)]
    theta2_0: f64,
    #[pyo3(get)]
    theta3_0: f64,
    #[pyo3(get)]
    theta4_0: f64,
    #[pyo3(get)]
    gyro_bias3: f64,
    #[pyo3(get)]
    gyro_bias4: f64,
    #[pyo3(get)]
    method: &'static str,
    #[pyo3(get)]
    iterations: u32,
    #[pyo3(get)]
    converged: bool,
    #[pyo3(get)]
    rms_residual: f64,
    #[pyo3(get)]
    condition_number: f64,
    #[pyo3(get)]
    outlier_fraction: f64,
    #[pyo3(get)]
    wheel_range: Option<f64>,
    #[pyo3(get)]
    warnings: Vec<String>,
    std_errors: FourbarStdErrors,
}

impl From<FourbarCalibration> for PlanarFourbarResult {
    fn from(c: FourbarCalibration) -> Self {
        let p = c.params;
        Self {
            l1: p.l1_m,
            l3: p.l3_m,
            l4: p.l4_m,
            theta2_0: p.theta2_0_rad,
            theta3_0: p.theta3_0_rad,
            theta4_0: p.theta4_0_rad,
            gyro_bias3: p.gyro_bias3,
            gyro_bias4: p.gyro_bias4,
            method: c.method,
            iterations: c.iterations,
            converged: c.converged,
            rms_residual: c.rms_residual_m,
            condition_number: c.condition_number,
            outlier_fraction: c.outlier_fraction,
            wheel_range: c.wheel_range_rad,
            warnings: c.warnings,
            std_errors: c.std_errors,
        }
    }
}

#[pymethods]
impl PlanarFourbarResult {
    /// 1σ standard errors by parameter name (same units as the parameters).
    #[getter]
    fn std_errors<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let s = &self.std_errors;
        let d = PyDict::new(py);
        d.set_item("l1", s.l1_m)?;
        d.set_item("l3", s.l3_m)?;
        d.set_item("l4", s.l4_m)?;
        d.set_item("theta2_0", s.theta2_0_rad)?;
        d.set_item("theta3_0", s.theta3_0_rad)?;
        d.set_item("theta4_0", s.theta4_0_rad)?;
        if let Some(b) = s.gyro_bias3 {
            d.set_item("gyro_bias3", b)?;
        }
        if let Some(b) = s.gyro_bias4 {
            d.set_item("gyro_bias4", b)?;
        }
        Ok(d)
    }

    fn __repr__(&self) -> String {
        format!(
            "PlanarFourbarResult(l1={:.6}, l3={:.6}, l4={:.6}, theta2_0={:.6}, theta3_0={:.6}, \
             theta4_0={:.6}, method='{}', iterations={}, rms_residual={:.3e}, \
             condition_number={:.1}, warnings={:?})",
            self.l1,
            self.l3,
            self.l4,
            self.theta2_0,
            self.theta3_0,
            self.theta4_0,
            self.method,
            self.iterations,
            self.rms_residual,
            self.condition_number,
            self.warnings
        )
    }
}

fn parse_method(method: &str) -> PyResult<FourbarMethod> {
    match method {
        "auto" => Ok(FourbarMethod::Auto),
        "global" => Ok(FourbarMethod::Global),
        "thesis" => Ok(FourbarMethod::Thesis),
        "lm" => Ok(FourbarMethod::Lm),
        other => Err(value_error(format!(
            "method must be one of 'auto', 'global', 'lm', 'thesis', got {other:?}"
        ))),
    }
}

fn parse_initial(initial: Option<Vec<f64>>) -> PyResult<Option<FourbarParams>> {
    let Some(v) = initial else { return Ok(None) };
    if v.len() != 6 && v.len() != 8 {
        return Err(value_error(format!(
            "initial must have 6 values (l1, l3, l4, theta2_0, theta3_0, theta4_0) or 8 (plus \
             gyro_bias3, gyro_bias4), got {}",
            v.len()
        )));
    }
    let mut p = FourbarParams::new(v[0], v[1], v[2], v[3], v[4], v[5]);
    if v.len() == 8 {
        p.gyro_bias3 = v[6];
        p.gyro_bias4 = v[7];
    }
    Ok(Some(p))
}

/// Native four-bar calibration; see `telerehab.calib.calibrate_planar_fourbar`.
#[pyfunction]
#[pyo3(signature = (phi2_rad, phi3_rad, phi4_rad, l2_m, initial, method, time_s, gyro_bias, robust, max_iterations, tolerance, smoothing_half_window, errors_in_variables))]
#[allow(clippy::too_many_arguments)]
fn calibrate_planar_fourbar(
    py: Python<'_>,
    phi2_rad: PyReadonlyArray1<'_, f64>,
    phi3_rad: PyReadonlyArray1<'_, f64>,
    phi4_rad: PyReadonlyArray1<'_, f64>,
    l2_m: f64,
    initial: Option<Vec<f64>>,
    method: &str,
    time_s: Option<PyReadonlyArray1<'_, f64>>,
    gyro_bias: bool,
    robust: bool,
    max_iterations: u32,
    tolerance: f64,
    smoothing_half_window: usize,
    errors_in_variables: bool,
) -> PyResult<PlanarFourbarResult> {
    let options = FourbarOptions {
        method: parse_method(method)?,
        initial: parse_initial(initial)?,
        gyro_bias,
        robust,
        max_iterations,
        tolerance,
        smoothing_half_window,
        errors_in_variables,
    };
    let (p2, p3, p4) = (vec1(&phi2_rad), vec1(&phi3_rad), vec1(&phi4_rad));
    let t = time_s.as_ref().map(vec1);
    let result = py.detach(|| {
        let samples = FourbarSamples {
            time_s: t.as_deref(),
            ..FourbarSamples::new(&p2, &p3, &p4)
        };
        calib::calibrate(&samples, l2_m, &options)
    });
    result.map(Into::into).map_err(calib_error)
}

/// Online (recursive least-squares with forgetting) four-bar calibration.
#[pyclass(module = "telerehab._native")]
pub struct OnlinePlanarFourbar {
    inner: OnlineFourbar,
}

#[pymethods]
impl OnlinePlanarFourbar {
    #[new]
    #[pyo3(signature = (l2_m, forgetting))]
    fn new(l2_m: f64, forgetting: f64) -> PyResult<Self> {
        OnlineFourbar::new(l2_m, OnlineOptions { forgetting })
            .map(|inner| Self { inner })
            .map_err(calib_error)
    }

    /// Absorb equal-length 1-D arrays of samples, in order. Stops at the first non-finite
    /// sample (earlier samples stay absorbed) and raises ValueError naming it.
    fn update_many(
        &mut self,
        py: Python<'_>,
        phi2_rad: PyReadonlyArray1<'_, f64>,
        phi3_rad: PyReadonlyArray1<'_, f64>,
        phi4_rad: PyReadonlyArray1<'_, f64>,
    ) -> PyResult<()> {
        let (p2, p3, p4) = (vec1(&phi2_rad), vec1(&phi3_rad), vec1(&phi4_rad));
        same_len("phi3_rad", p3.len(), "phi2_rad", p2.len())?;
        same_len("phi4_rad", p4.len(), "phi2_rad", p2.len())?;
        let inner = &mut self.inner;
        py.detach(|| {
            for k in 0..p2.len() {
                inner.update(p2[k], p3[k], p4[k])?;
            }
            Ok(())
        })
        .map_err(calib_error)
    }

    /// The current estimate, or None while the data do not yet determine it.
    #[getter]
    fn estimate(&self) -> Option<PlanarFourbarResult> {
        self.inner.estimate().ok().map(Into::into)
    }

    /// Samples absorbed so far.
    #[getter]
    fn samples(&self) -> u64 {
        self.inner.samples()
    }
}

/// Calibrated frames of a serial chain and how far to trust them.
#[pyclass(frozen, module = "telerehab._native")]
pub struct SerialChainResult {
    frames: Vec<Matrix4<f64>>,
    #[pyo3(get)]
    iterations: u32,
    #[pyo3(get)]
    converged: bool,
    #[pyo3(get)]
    rms_residual: f64,
    #[pyo3(get)]
    rms_translation: f64,
    #[pyo3(get)]
    rms_rotation: f64,
    #[pyo3(get)]
    condition_number: f64,
    #[pyo3(get)]
    rank: usize,
    #[pyo3(get)]
    warnings: Vec<String>,
}

impl From<SerialCalibration> for SerialChainResult {
    fn from(c: SerialCalibration) -> Self {
        Self {
            frames: c.frames,
            iterations: c.iterations,
            converged: c.converged,
            rms_residual: c.rms_residual,
            rms_translation: c.rms_translation_m,
            rms_rotation: c.rms_rotation_rad,
            condition_number: c.condition_number,
            rank: c.rank,
            warnings: c.warnings,
        }
    }
}

#[pymethods]
impl SerialChainResult {
    /// The calibrated frames F0 … Fn, shape (n+1, 4, 4).
    #[getter]
    fn frames<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray3<f64>> {
        let mut flat = Vec::with_capacity(16 * self.frames.len());
        for f in &self.frames {
            for i in 0..4 {
                for j in 0..4 {
                    flat.push(f[(i, j)]);
                }
            }
        }
        let arr = numpy::ndarray::Array3::from_shape_vec((self.frames.len(), 4, 4), flat)
            .expect("16 values per frame");
        PyArray3::from_owned_array(py, arr)
    }

    fn __repr__(&self) -> String {
        format!(
            "SerialChainResult(frames=<{} frames>, iterations={}, rms_residual={:.3e}, \
             condition_number={:.1}, rank={}, warnings={:?})",
            self.frames.len(),
            self.iterations,
            self.rms_residual,
            self.condition_number,
            self.rank,
            self.warnings
        )
    }
}

fn matrices(a: numpy::ndarray::ArrayViewD<'_, f64>) -> Vec<Matrix4<f64>> {
    let flat: Vec<f64> = a.iter().copied().collect();
    flat.chunks_exact(16).map(Matrix4::from_row_slice).collect()
}

fn check_trailing_4x4(name: &str, shape: &[usize], expected: &str) -> PyResult<()> {
    if shape.len() < 2 || shape[shape.len() - 2..] != [4, 4] {
        return Err(value_error(format!(
            "{name} must have shape {expected}, got {shape:?}"
        )));
    }
    Ok(())
}

/// Native serial-chain calibration; see `telerehab.calib.calibrate_serial_chain`.
#[pyfunction]
#[pyo3(signature = (nominal_frames, joint_motions, measured_end_poses, max_iterations, tolerance))]
fn calibrate_serial_chain(
    py: Python<'_>,
    nominal_frames: PyReadonlyArray3<'_, f64>,
    joint_motions: PyReadonlyArray4<'_, f64>,
    measured_end_poses: PyReadonlyArray3<'_, f64>,
    max_iterations: u32,
    tolerance: f64,
) -> PyResult<SerialChainResult> {
    let fs = nominal_frames.as_array().shape().to_vec();
    let qs = joint_motions.as_array().shape().to_vec();
    let ts = measured_end_poses.as_array().shape().to_vec();
    check_trailing_4x4("nominal_frames", &fs, "(n+1, 4, 4)")?;
    check_trailing_4x4("joint_motions", &qs, "(m, n, 4, 4)")?;
    check_trailing_4x4("measured_end_poses", &ts, "(m, 4, 4)")?;
    let n = fs[0].saturating_sub(1);
    if qs[0] != ts[0] || qs[1] != n {
        return Err(value_error(format!(
            "joint_motions must have shape (m, n, 4, 4) = ({}, {n}, 4, 4) to match \
             measured_end_poses {ts:?} and nominal_frames {fs:?}, got {qs:?}",
            ts[0]
        )));
    }
    let frames = matrices(nominal_frames.as_array().into_dyn());
    let motions = matrices(joint_motions.as_array().into_dyn());
    let measured = matrices(measured_end_poses.as_array().into_dyn());
    let options = SerialOptions {
        max_iterations,
        tolerance,
        ..SerialOptions::default()
    };
    py.detach(|| calib::calibrate_serial_chain(&frames, &motions, &measured, &options))
        .map(Into::into)
        .map_err(calib_error)
}

/// A calibrated spatial arm (m, rad, wheel frame) and how far to trust it.
#[pyclass(frozen, module = "telerehab._native")]
pub struct Arm3dResult {
    #[pyo3(get)]
    shoulder_m: [f64; 3],
    #[pyo3(get)]
    upper_arm_m: f64,
    #[pyo3(get)]
    forearm_m: f64,
    #[pyo3(get)]
    heading_offset: [f64; 2],
    #[pyo3(get)]
    heading_drift: [f64; 2],
    #[pyo3(get)]
    heading_model: &'static str,
    #[pyo3(get)]
    iterations: u32,
    #[pyo3(get)]
    converged: bool,
    #[pyo3(get)]
    rms_residual: f64,
    #[pyo3(get)]
    condition_number: f64,
    #[pyo3(get)]
    direction_noise: [f64; 2],
    #[pyo3(get)]
    grip_spread_m: f64,
    #[pyo3(get)]
    warnings: Vec<String>,
    std_errors: calib::arm3d::Arm3dStdErrors,
}

impl From<calib::Arm3dCalibration> for Arm3dResult {
    fn from(c: calib::Arm3dCalibration) -> Self {
        let p = c.params;
        Self {
            shoulder_m: p.shoulder_m,
            upper_arm_m: p.upper_arm_m,
            forearm_m: p.forearm_m,
            heading_offset: p.heading_offset_rad,
            heading_drift: p.heading_drift_rad_s,
            heading_model: c.heading.name(),
            iterations: c.iterations,
            converged: c.converged,
            rms_residual: c.rms_residual_m,
            condition_number: c.condition_number,
            direction_noise: c.direction_noise_rad,
            grip_spread_m: c.grip_spread_m,
            warnings: c.warnings,
            std_errors: c.std_errors,
        }
    }
}

#[pymethods]
impl Arm3dResult {
    /// 1σ standard errors by parameter name (same units as the parameters).
    #[getter]
    fn std_errors<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let s = &self.std_errors;
        let d = PyDict::new(py);
        d.set_item("shoulder_m", s.shoulder_m)?;
        d.set_item("upper_arm_m", s.upper_arm_m)?;
        d.set_item("forearm_m", s.forearm_m)?;
        if let Some(h) = s.heading_offset_rad {
            d.set_item("heading_offset", h)?;
        }
        if let Some(h) = s.heading_drift_rad_s {
            d.set_item("heading_drift", h)?;
        }
        Ok(d)
    }

    fn __repr__(&self) -> String {
        format!(
            "Arm3dResult(shoulder_m={:?}, upper_arm_m={:.6}, forearm_m={:.6}, \
             heading_model='{}', rms_residual={:.3e}, condition_number={:.1}, warnings={:?})",
            self.shoulder_m,
            self.upper_arm_m,
            self.forearm_m,
            self.heading_model,
            self.rms_residual,
            self.condition_number,
            self.warnings
        )
    }
}

/// Native spatial arm calibration; see `telerehab.calib.calibrate_arm_3d`.
#[pyfunction]
#[pyo3(signature = (upper_dirs, fore_dirs, grip_points_m, time_s, heading, errors_in_variables, max_iterations))]
#[allow(clippy::too_many_arguments)]
fn calibrate_arm_3d(
    py: Python<'_>,
    upper_dirs: PyReadonlyArray2<'_, f64>,
    fore_dirs: PyReadonlyArray2<'_, f64>,
    grip_points_m: PyReadonlyArray2<'_, f64>,
    time_s: Option<PyReadonlyArray1<'_, f64>>,
    heading: &str,
    errors_in_variables: bool,
    max_iterations: u32,
) -> PyResult<Arm3dResult> {
    let heading = match heading {
        "exact" => calib::HeadingModel::Exact,
        "offset" => calib::HeadingModel::Offset,
        "offset_and_drift" => calib::HeadingModel::OffsetAndDrift,
        other => {
            return Err(value_error(format!(
                "heading must be one of 'exact', 'offset', 'offset_and_drift', got {other:?}"
            )));
        }
    };
    let options = calib::ArmLoopOptions {
        heading,
        errors_in_variables,
        max_iterations,
    };
    let u = rows3("upper_dirs", &upper_dirs)?;
    let f = rows3("fore_dirs", &fore_dirs)?;
    let g = rows3("grip_points_m", &grip_points_m)?;
    same_len("fore_dirs", f.len(), "upper_dirs", u.len())?;
    same_len("grip_points_m", g.len(), "upper_dirs", u.len())?;
    let t = time_s.as_ref().map(vec1);
    let result = py.detach(|| {
        let samples = calib::ArmLoopSamples {
            time_s: t.as_deref(),
            ..calib::ArmLoopSamples::new(&u, &f, &g)
        };
        calib::calibrate_arm_3d(&samples, &options)
    });
    for rows in [u, f, g] {
        give_rows(rows);
    }
    result.map(Into::into).map_err(calib_error)
}
