//! Simulated motion and devices: a generic random motion, the patient's arm on the wheel and
//! trunk in the chair, and simulated IMUs with the sensor model of [`crate::sensor`].

pub mod arm;
pub mod motion;
pub mod trunk;

use crate::error::ImuError;

/// The wheel's angular acceleration, rad/s², from its rate now and at the previous tick
/// (`prev_rate_rad_s`, updated; 0 at the first tick), `dt_s` apart; an error naming the
/// inputs when the wheel's angle, rate or the step is not finite, or the step not positive.
/// The arm and the trunk simulations move with the wheel alike.
pub(crate) fn wheel_acceleration(
    prev_rate_rad_s: &mut Option<f64>,
    wheel_rad: f64,
    wheel_rate_rad_s: f64,
    dt_s: f64,
) -> Result<f64, ImuError> {
    if !(wheel_rad.is_finite() && wheel_rate_rad_s.is_finite() && dt_s.is_finite() && dt_s > 0.0) {
        return Err(ImuError::InvalidInput(format!(
            "wheel {wheel_rad} rad, rate {wheel_rate_rad_s} rad/s, dt {dt_s} s must be finite (dt > 0)"
        )));
    }
    let acc = prev_rate_rad_s.map_or(0.0, |p| (wheel_rate_rad_s - p) / dt_s);
    *prev_rate_rad_s = Some(wheel_rate_rad_s);
    Ok(acc)
}
