//! Offline runs of the model for analysts (`telerehab vehicle`): a table of timed driver
//! inputs in, the state at each of those times out.

use crate::error::VehicleError;
use crate::model::{DriverInput, Vehicle, VehicleParams, VehicleState};

/// A driver input that applies from `t_s` until the next row's time (zero-order hold).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TimedInput {
    /// Time at which this input starts to apply, s.
    pub t_s: f64,
    /// Road-wheel angle δ and the forces `Fad`, `Fbd` of eq. C.11.
    pub input: DriverInput,
}

/// Run the model through `rows` with integration steps of at most `dt_s`.
///
/// Returns one state per row: the state at that row's time, before its input acts (the first
/// is `initial`). Between rows the model takes equal steps no longer than `dt_s` that land
/// exactly on the next row's time. Errors name the row (0-based, data rows only) when a time
/// is not finite or not increasing, or an input is not finite.
pub fn simulate(
    params: &VehicleParams,
    initial: VehicleState,
    rows: &[TimedInput],
    dt_s: f64,
) -> Result<Vec<VehicleState>, VehicleError> {
    params.validate()?;
    if !(dt_s.is_finite() && dt_s > 0.0 && dt_s <= 0.1) {
        return Err(VehicleError::InvalidInput(format!(
            "dt must be in (0, 0.1] s, got {dt_s}"
        )));
    }
    if !initial.is_finite() {
        return Err(VehicleError::InvalidInput(format!(
            "initial state must be finite, got {initial:?}"
        )));
    }
    let mut car = Vehicle::new(params.clone(), initial);
    let mut out = Vec::with_capacity(rows.len());
    for (i, row) in rows.iter().enumerate() {
        if !row.t_s.is_finite() {
            return Err(VehicleError::InvalidInput(format!(
                "row {i}: time is not finite"
            )));
        }
        if !row.input.is_finite() {
            return Err(VehicleError::InvalidInput(format!(
                "row {i}: input is not finite: {:?}",
                row.input
            )));
        }
        out.push(*car.state());
        if let Some(next) = rows.get(i + 1) {
            let span = next.t_s - row.t_s;
            if span.is_nan() || span <= 0.0 {
                return Err(VehicleError::InvalidInput(format!(
                    "row {}: time {} s is not after the previous row's {} s",
                    i + 1,
                    next.t_s,
                    row.t_s
                )));
            }
            let n = (span / dt_s).ceil().max(1.0) as usize;
            let h = span / n as f64;
            for _ in 0..n {
                car.try_step(row.input, h)?;
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn braking_rows_reproduce_constant_deceleration_at_each_row_time() {
        let p = VehicleParams::default();
        let rows: Vec<TimedInput> = (0..=10)
            .map(|i| TimedInput {
                t_s: f64::from(i) * 0.25,
                input: DriverInput {
                    brake_force_n: 1860.0,
                    ..Default::default()
                },
            })
            .collect();
        let start = VehicleState {
            ux_m_s: 10.0,
            ..Default::default()
        };
        let out = simulate(&p, start, &rows, 0.001).unwrap();
        assert_eq!(out.len(), rows.len());
        for (row, s) in rows.iter().zip(&out) {
            assert!((s.ux_m_s - (10.0 - row.t_s)).abs() < 1e-9, "{row:?} {s:?}");
        }
    }

    #[test]
    fn non_increasing_time_names_the_row() {
        let rows = [
            TimedInput {
                t_s: 0.0,
                input: DriverInput::default(),
            },
            TimedInput {
                t_s: 0.0,
                input: DriverInput::default(),
            },
        ];
        let e = simulate(
            &VehicleParams::default(),
            VehicleState::default(),
            &rows,
            0.001,
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("row 1"), "{e}");
        assert!(
            simulate(
                &VehicleParams::default(),
                VehicleState::default(),
                &rows,
                0.0
            )
            .is_err()
        );
    }
}
