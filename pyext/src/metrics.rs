//! Movement-measure bindings (`telerehab.metrics`): SPARC, LDLJ, movement segmentation, the
//! speed profile of an angle and a session's measures from crate `metrics`, following the
//! convention in [`crate::check`]: float64 arrays in (angles rad, speeds in any unit, rates
//! Hz), finiteness checked by the crate, which names the signal and the sample index (renamed
//! here to the Python argument), the GIL released around the work.

use metrics::{MAX_PADLEVEL, MetricError, Movement, SegmentParams, SparcParams};
use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;

use crate::check::{finite, value_error, vec1};

/// Add the metrics functions to the native module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(metrics_sparc, m)?)?;
    m.add_function(wrap_pyfunction!(metrics_ldlj, m)?)?;
    m.add_function(wrap_pyfunction!(metrics_segment, m)?)?;
    m.add_function(wrap_pyfunction!(metrics_speed_profile, m)?)?;
    m.add_function(wrap_pyfunction!(metrics_session_measures, m)?)?;
    m.add_function(wrap_pyfunction!(metrics_speed_metric, m)?)?;
    m.add_function(wrap_pyfunction!(metrics_steering_reversals, m)?)?;
    m.add_function(wrap_pyfunction!(metrics_step_responses, m)?)?;
    Ok(())
}

/// The Python name of a signal the crate names in its errors.
fn python_signal(signal: &str) -> String {
    match signal {
        "wheel angle" => "wheel_angle_rad".to_owned(),
        // `joint "elbow"` (Rust's debug quoting) is `joints["elbow"]` in Python.
        s => match s.strip_prefix("joint ") {
            Some(name) => format!("joints[{name}]"),
            None => s.to_owned(),
        },
    }
}

/// A `ValueError` for `e` (its message names the signal and index, or the parameter and its
/// allowed range), with the names the Python caller used.
fn metric_error(mut e: MetricError) -> PyErr {
    match &mut e {
        MetricError::Empty { signal }
        | MetricError::TooShort { signal, .. }
        | MetricError::NonFinite { signal, .. }
        | MetricError::Degenerate { signal, .. } => *signal = python_signal(signal),
        MetricError::BadParameter { field, .. } if *field == "fc_hz" => *field = "fc",
        _ => {}
    }
    value_error(e.to_string())
}

/// The sampling rate check of the crate, for the functions of the crate that do not check it.
fn check_fs(fs: f64) -> PyResult<()> {
    if fs.is_finite() && fs > 0.0 {
        Ok(())
    } else {
        Err(metric_error(MetricError::BadSampleRate { fs_hz: fs }))
    }
}

/// SPARC parameters from the Python arguments; `padlevel` arrives signed so a negative value
/// is a `ValueError` naming it, not an `OverflowError`.
fn sparc_params(padlevel: i64, fc: f64, amp_th: f64) -> PyResult<SparcParams> {
    let padlevel = u32::try_from(padlevel)
        .ok()
        .filter(|&p| p <= MAX_PADLEVEL)
        .ok_or_else(|| {
            metric_error(MetricError::BadParameter {
                context: "SparcParams",
                field: "padlevel",
                value: padlevel as f64,
                allowed: "0 ..= 8",
            })
        })?;
    Ok(SparcParams {
        padlevel,
        fc_hz: fc,
        amp_th,
    })
}

/// SPARC of one movement's speed profile (any unit) sampled at `fs` Hz; see
/// `telerehab.metrics.sparc`.
#[pyfunction]
#[pyo3(signature = (speed, fs, padlevel, fc, amp_th))]
fn metrics_sparc(
    py: Python<'_>,
    speed: PyReadonlyArray1<'_, f64>,
    fs: f64,
    padlevel: i64,
    fc: f64,
    amp_th: f64,
) -> PyResult<f64> {
    let params = sparc_params(padlevel, fc, amp_th)?;
    let v = vec1(&speed);
    py.detach(|| metrics::sparc(&v, fs, params))
        .map_err(metric_error)
}

/// LDLJ of one movement's speed profile (any unit) sampled at `fs` Hz; see
/// `telerehab.metrics.ldlj`.
#[pyfunction]
#[pyo3(signature = (speed, fs))]
fn metrics_ldlj(py: Python<'_>, speed: PyReadonlyArray1<'_, f64>, fs: f64) -> PyResult<f64> {
    let v = vec1(&speed);
    py.detach(|| metrics::ldlj_speed(&v, fs))
        .map_err(metric_error)
}

/// One movement as a tuple `(start_index, end_index, start_s, duration_s, peak_speed, n_peaks,
/// sparc, ldlj, speed_metric, discrete)`; the facade makes it a frozen `Movement`.
type MovementTuple = (
    usize,
    usize,
    f64,
    f64,
    f64,
    usize,
    Option<f64>,
    Option<f64>,
    f64,
    bool,
);

fn movement_tuple(m: Movement) -> MovementTuple {
    (
        m.start_index,
        m.end_index,
        m.start_s,
        m.duration_s,
        m.peak_speed,
        m.n_peaks,
        m.sparc,
        m.ldlj,
        m.speed_metric,
        m.discrete,
    )
}

/// The movements in a speed profile sampled at `fs` Hz; see `telerehab.metrics.segment`.
#[pyfunction]
#[pyo3(signature = (speed, fs, onset_fraction, floor, merge_gap_s, min_duration_s, peak_fraction))]
#[allow(clippy::too_many_arguments)]
fn metrics_segment(
    py: Python<'_>,
    speed: PyReadonlyArray1<'_, f64>,
    fs: f64,
    onset_fraction: f64,
    floor: f64,
    merge_gap_s: f64,
    min_duration_s: f64,
    peak_fraction: f64,
) -> PyResult<Vec<MovementTuple>> {
    let params = SegmentParams {
        onset_fraction,
        floor,
        merge_gap_s,
        min_duration_s,
        peak_fraction,
        ..SegmentParams::default()
    };
    let v = vec1(&speed);
    let movements = py
        .detach(|| metrics::segment(&v, fs, params))
        .map_err(metric_error)?;
    Ok(movements.into_iter().map(movement_tuple).collect())
}

/// Speed profile (rad/s) of an angle (rad) sampled at `fs` Hz; see
/// `telerehab.metrics.speed_profile`. The crate checks nothing here (it is infallible), so the
/// checks are made before the call.
#[pyfunction]
#[pyo3(signature = (angle_rad, fs, lowpass_hz))]
fn metrics_speed_profile<'py>(
    py: Python<'py>,
    angle_rad: PyReadonlyArray1<'py, f64>,
    fs: f64,
    lowpass_hz: f64,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    check_fs(fs)?;
    // +inf, like any value at or above fs/2, means no filter.
    if lowpass_hz.is_nan() || lowpass_hz <= 0.0 {
        return Err(value_error(format!(
            "lowpass_hz must be > 0 Hz (at or above fs/2 no filter is applied), got {lowpass_hz}"
        )));
    }
    let angle = vec1(&angle_rad);
    finite("angle_rad", &angle)?;
    let speed = py.detach(|| metrics::speed_profile(&angle, fs, lowpass_hz));
    Ok(PyArray1::from_vec(py, speed))
}

/// A session's measures as JSON (`SessionMeasures` serialised); see
/// `telerehab.metrics.session_measures`.
#[pyfunction]
#[pyo3(signature = (wheel_angle_rad, fs, joints))]
fn metrics_session_measures(
    py: Python<'_>,
    wheel_angle_rad: PyReadonlyArray1<'_, f64>,
    fs: f64,
    joints: Vec<(String, PyReadonlyArray1<'_, f64>)>,
) -> PyResult<String> {
    let wheel = vec1(&wheel_angle_rad);
    let joints: Vec<(String, Vec<f64>)> = joints
        .iter()
        .map(|(name, samples)| (name.clone(), vec1(samples)))
        .collect();
    let measures = py
        .detach(|| {
            let refs: Vec<(&str, &[f64])> = joints
                .iter()
                .map(|(name, samples)| (name.as_str(), samples.as_slice()))
                .collect();
            metrics::session_measures(&wheel, fs, &refs)
        })
        .map_err(metric_error)?;
    serde_json::to_string(&measures)
        .map_err(|e| PyRuntimeError::new_err(format!("serialising the session measures: {e}")))
}

/// Mean over peak speed of one movement's speed profile; see `telerehab.metrics.speed_metric`.
#[pyfunction]
#[pyo3(signature = (speed))]
fn metrics_speed_metric(speed: PyReadonlyArray1<'_, f64>) -> PyResult<Option<f64>> {
    let v = vec1(&speed);
    if let Some((index, &value)) = v.iter().enumerate().find(|(_, x)| !x.is_finite()) {
        return Err(metric_error(MetricError::NonFinite {
            signal: "speed".to_owned(),
            index,
            value,
        }));
    }
    Ok(metrics::speed_metric(&v))
}

/// Steering reversals of an angle signal with a gap; see
/// `telerehab.metrics.steering_reversals`.
#[pyfunction]
#[pyo3(signature = (angle_rad, gap_rad))]
fn metrics_steering_reversals(
    py: Python<'_>,
    angle_rad: PyReadonlyArray1<'_, f64>,
    gap_rad: f64,
) -> PyResult<usize> {
    let v = vec1(&angle_rad);
    py.detach(|| metrics::steering_reversals(&v, gap_rad))
        .map_err(|e| metric_error(rename_angle(e)))
}

/// One step response as a tuple `(step_index, target_rad, reaction_time_s,
/// initial_direction_error_deg, path_length_ratio)`.
type ResponseTuple = (usize, f64, Option<f64>, Option<f64>, Option<f64>);

/// The wheel's responses to steps of the target; see `telerehab.metrics.step_responses`.
#[pyfunction]
#[pyo3(signature = (angle_rad, fs, step_indices, step_targets_rad))]
fn metrics_step_responses(
    py: Python<'_>,
    angle_rad: PyReadonlyArray1<'_, f64>,
    fs: f64,
    step_indices: Vec<usize>,
    step_targets_rad: Vec<f64>,
) -> PyResult<Vec<ResponseTuple>> {
    if step_indices.len() != step_targets_rad.len() {
        return Err(value_error(format!(
            "step_indices has {} entries but step_targets_rad {}: one target a step",
            step_indices.len(),
            step_targets_rad.len()
        )));
    }
    let steps: Vec<metrics::TargetStep> = step_indices
        .iter()
        .zip(&step_targets_rad)
        .map(|(&index, &target_rad)| metrics::TargetStep { index, target_rad })
        .collect();
    let v = vec1(&angle_rad);
    let responses = py
        .detach(|| metrics::step_responses(&v, fs, &steps, &metrics::ResponseParams::default()))
        .map_err(|e| metric_error(rename_angle(e)))?;
    Ok(responses
        .into_iter()
        .map(|r| {
            (
                r.step.index,
                r.step.target_rad,
                r.reaction_time_s,
                r.initial_direction_error_deg,
                r.path_length_ratio,
            )
        })
        .collect())
}

/// The crate's "wheel angle" is the Python `angle_rad` in these functions.
fn rename_angle(mut e: MetricError) -> MetricError {
    if let MetricError::Empty { signal }
    | MetricError::TooShort { signal, .. }
    | MetricError::NonFinite { signal, .. } = &mut e
        && signal == "wheel angle"
    {
        *signal = "angle_rad".to_owned();
    }
    e
}
