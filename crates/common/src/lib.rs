//! Small pure helpers that several telerehab crates need, written once.
//!
//! - [`check_range`]: is a configuration value finite and inside its allowed range? The error
//!   names the field and the range, so every crate's validation message reads the same
//!   (house style 5); each crate wraps [`OutOfRange`] into its own error enum.
//! - [`Bound`]: an allowed range written once, checked by a validator and stated in a JSON
//!   Schema from the same constant.
//! - [`wrap_angle`]: an angle mapped to (−π, π], rad.
//! - [`quantile`]: the nearest-rank quantile of sorted data.
//! - [`end_stop_nm`]: a steering wheel's end stop as a contact, the one law the simulated
//!   wheel pushes with and the patient's torque estimate models.
//! - [`resident`]: bounded buffers given their memory pages up front, so that a long session's
//!   resident memory stays flat.
//!
//! Pure: no I/O, no threads, no clock, no dependencies.

pub mod resident;

use std::fmt;

/// A value that is not finite or lies outside its closed allowed range `[lo, hi]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OutOfRange {
    /// The field's name as the user writes it (e.g. a TOML key or a dotted path).
    pub field: &'static str,
    /// The rejected value.
    pub value: f64,
    /// Lowest allowed value.
    pub lo: f64,
    /// Highest allowed value.
    pub hi: f64,
}

impl OutOfRange {
    /// The allowed range in words, `"{lo} to {hi} {unit}"` (no trailing space when `unit` is
    /// empty).
    pub fn allowed(&self, unit: &str) -> String {
        let range = format!("{} to {} {unit}", self.lo, self.hi);
        range.trim_end().to_string()
    }
}

impl fmt::Display for OutOfRange {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "`{}` = {} is outside the allowed range {}",
            self.field,
            self.value,
            self.allowed("")
        )
    }
}

impl std::error::Error for OutOfRange {}

/// Check that `value` is finite and inside `[lo, hi]`; otherwise an [`OutOfRange`] naming
/// `field` and the range.
///
/// # Example
///
/// ```
/// assert!(common::check_range("delay_s", 0.2, 0.0, 1.0).is_ok());
/// let err = common::check_range("delay_s", f64::NAN, 0.0, 1.0).unwrap_err();
/// assert_eq!(err.to_string(), "`delay_s` = NaN is outside the allowed range 0 to 1");
/// ```
pub fn check_range(field: &'static str, value: f64, lo: f64, hi: f64) -> Result<(), OutOfRange> {
    if value.is_finite() && value >= lo && value <= hi {
        Ok(())
    } else {
        Err(OutOfRange {
            field,
            value,
            lo,
            hi,
        })
    }
}

/// A closed allowed range `[min, max]` written once: a validator checks it ([`Bound::check`])
/// and a JSON Schema states it (`#[schemars(range(min = B.min, max = B.max))]`) from the same
/// constant, so the form a therapist fills in and the validator cannot drift apart.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bound {
    /// Lowest allowed value.
    pub min: f64,
    /// Highest allowed value.
    pub max: f64,
}

impl Bound {
    /// The range `[min, max]`.
    pub const fn new(min: f64, max: f64) -> Self {
        Self { min, max }
    }

    /// [`check_range`] against this range.
    pub fn check(self, field: &'static str, value: f64) -> Result<(), OutOfRange> {
        check_range(field, value, self.min, self.max)
    }
}

/// Wrap an angle to (−π, π], rad.
///
/// # Example
///
/// ```
/// use std::f64::consts::PI;
/// assert!((common::wrap_angle(3.0 * PI) - PI).abs() < 1e-12);
/// assert!((common::wrap_angle(-PI) - PI).abs() < 1e-12);
/// ```
pub fn wrap_angle(a: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    let w = a.rem_euclid(TAU);
    if w > PI { w - TAU } else { w }
}

/// The nearest-rank `q`-quantile of `sorted` (ascending): the smallest element with at least a
/// fraction `q` of the data at or below it, i.e. element `⌈q·n⌉` (1-based, clamped to
/// `1..=n`). `None` when `sorted` is empty.
///
/// Works for any copyable element (`u64` nanoseconds, `f64` milliseconds...). `q` outside
/// `[0, 1]` is clamped to the first or last element.
///
/// # Example
///
/// ```
/// let d: Vec<u64> = (1..=100).collect();
/// assert_eq!(common::quantile(&d, 0.5), Some(50));
/// assert_eq!(common::quantile(&d, 0.99), Some(99));
/// assert_eq!(common::quantile::<f64>(&[], 0.5), None);
/// ```
pub fn quantile<T: Copy>(sorted: &[T], q: f64) -> Option<T> {
    let n = sorted.len();
    if n == 0 {
        return None;
    }
    // `as usize` saturates: NaN and negative q give 0, clamped to the first element.
    let rank = (q * n as f64).ceil() as usize;
    Some(sorted[rank.clamp(1, n) - 1])
}

/// The least-squares line through `points` (x, y): `(slope, intercept)`. Fewer than two
/// points, or all at one x, give a slope of 0 through the mean of the y values (0 without
/// points).
///
/// ```
/// let (slope, intercept) = common::line_fit(&[(0.0, 1.0), (1.0, 3.0), (2.0, 5.0)]);
/// assert!((slope - 2.0).abs() < 1e-12 && (intercept - 1.0).abs() < 1e-12);
/// assert_eq!(common::line_fit(&[(4.0, 7.0)]), (0.0, 7.0));
/// ```
pub fn line_fit(points: &[(f64, f64)]) -> (f64, f64) {
    if points.is_empty() {
        return (0.0, 0.0);
    }
    let n = points.len() as f64;
    let mx = points.iter().map(|p| p.0).sum::<f64>() / n;
    let my = points.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = points.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let slope = if sxx > 0.0 { sxy / sxx } else { 0.0 };
    (slope, my - slope * mx)
}

/// A steering wheel's end stop on its rim at `angle_rad` moving at `vel_rad_s`, N·m: a spring
/// `k_nm_per_rad` and a damper `b_nm_s_per_rad` beyond `half_range_rad` that push the rim back
/// and never pull it into the stop (a stop is a contact: the damper lets go as the rim leaves).
///
/// ```
/// assert_eq!(common::end_stop_nm(0.9, 3.0, 1.0, 50.0, 0.5), 0.0);
/// assert!((common::end_stop_nm(1.1, 2.0, 1.0, 50.0, 0.5) + 6.0).abs() < 1e-12);
/// assert_eq!(common::end_stop_nm(1.01, -4.0, 1.0, 50.0, 0.5), 0.0);
/// ```
pub fn end_stop_nm(
    angle_rad: f64,
    vel_rad_s: f64,
    half_range_rad: f64,
    k_nm_per_rad: f64,
    b_nm_s_per_rad: f64,
) -> f64 {
    let over = angle_rad.abs() - half_range_rad;
    if over > 0.0 {
        let outward_rad_s = vel_rad_s * angle_rad.signum();
        -angle_rad.signum() * (k_nm_per_rad * over + b_nm_s_per_rad * outward_rad_s).max(0.0)
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_end_stop_pushes_the_rim_back_and_never_pulls_it_in() {
        assert_eq!(end_stop_nm(0.9, 3.0, 1.0, 50.0, 0.5), 0.0);
        assert!(
            (end_stop_nm(1.1, 2.0, 1.0, 50.0, 0.5) + 6.0).abs() < 1e-12,
            "5 + 1 N·m back"
        );
        assert!((end_stop_nm(-1.1, -2.0, 1.0, 50.0, 0.5) - 6.0).abs() < 1e-12);
        // Leaving fast: the damper lets go rather than pull the rim back in.
        assert_eq!(end_stop_nm(1.01, -4.0, 1.0, 50.0, 0.5), 0.0);
    }
    use std::f64::consts::PI;

    #[test]
    fn check_range_accepts_the_closed_interval_and_rejects_the_rest() {
        assert!(check_range("x", 0.0, 0.0, 1.0).is_ok());
        assert!(check_range("x", 1.0, 0.0, 1.0).is_ok());
        for bad in [
            -1e-12,
            1.0 + 1e-12,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ] {
            let err = check_range("x", bad, 0.0, 1.0).unwrap_err();
            assert_eq!(err.field, "x");
            assert_eq!((err.lo, err.hi), (0.0, 1.0));
            assert!(err.value.to_bits() == bad.to_bits(), "{err}");
        }
    }

    #[test]
    fn out_of_range_names_the_field_and_the_range() {
        let err = check_range("speed_m_s", 80.0, 0.5, 40.0).unwrap_err();
        assert_eq!(
            err.to_string(),
            "`speed_m_s` = 80 is outside the allowed range 0.5 to 40"
        );
        assert_eq!(err.allowed("m/s"), "0.5 to 40 m/s");
        assert_eq!(err.allowed(""), "0.5 to 40");
    }

    #[test]
    fn wrap_angle_maps_into_half_open_interval() {
        assert!((wrap_angle(3.0 * PI) - PI).abs() < 1e-12);
        assert!((wrap_angle(-PI) - PI).abs() < 1e-12);
        assert!((wrap_angle(0.5 + 4.0 * PI) - 0.5).abs() < 1e-12);
        assert!((wrap_angle(-0.5 - 4.0 * PI) + 0.5).abs() < 1e-12);
        for k in -100..=100 {
            let w = wrap_angle(f64::from(k) * 0.37);
            assert!(w > -PI && w <= PI, "{k}: {w}");
        }
    }

    #[test]
    fn quantile_uses_nearest_rank() {
        let d: Vec<f64> = (1..=100).map(f64::from).collect();
        assert_eq!(quantile(&d, 0.5), Some(50.0));
        assert_eq!(quantile(&d, 0.99), Some(99.0));
        assert_eq!(quantile(&d, 1.0), Some(100.0));
        assert_eq!(quantile(&d, 0.0), Some(1.0));
        assert_eq!(quantile(&d, -1.0), Some(1.0));
        assert_eq!(quantile(&d, 2.0), Some(100.0));
        assert_eq!(quantile::<f64>(&[], 0.5), None);
    }

    #[test]
    fn quantile_works_on_integers() {
        let d = [10u64, 20, 30];
        assert_eq!(quantile(&d, 0.34), Some(20));
        assert_eq!(quantile(&d, 0.33), Some(10));
        assert_eq!(quantile(&[7u64], 0.99), Some(7));
    }
}
