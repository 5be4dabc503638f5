//! The guided wheel measurement behind `telerehab wheel calibrate`, as pure analysis of what
//! the procedure recorded: the lock-to-lock range and the angle sign from a slow turn, the
//! encoder resolution from the smallest step seen, the torque sign from two gentle pushes with
//! hands off, and the usable torque update rate from how long updates take. The device-driving
//! part is `evdev_wheel::calibrate`; this module does no I/O.

use crate::profile::DeviceProfile;

/// Largest torque the procedure ever commands, N·m: gentle on any wheel (a tenth of a Logitech
/// G29's full force), and never more than a tenth of the wheel's usable torque.
pub const CALIBRATION_MAX_TORQUE_NM: f64 = 0.3;

/// The torque the procedure pushes with on a wheel whose usable maximum is `usable_nm`, N·m.
pub fn gentle_torque_nm(usable_nm: f64) -> f64 {
    CALIBRATION_MAX_TORQUE_NM.min(0.1 * usable_nm.max(0.0))
}

/// What went wrong in a measurement, in words the person at the wheel can act on.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum CalibrationError {
    /// The turn did not reach both locks.
    #[error(
        "the wheel turned over only {0:.0} % of its declared range: turn it slowly all the way to the left lock, then all the way to the right lock"
    )]
    TurnTooSmall(f64),
    /// The wheel did not move under the gentle pushes.
    #[error(
        "the wheel did not move under a gentle push: take your hands off the rim and check that nothing blocks it"
    )]
    NoMotion,
    /// The two pushes moved the wheel the same way.
    #[error("the two pushes moved the wheel the same way: keep your hands off the rim and retry")]
    Inconsistent,
}

/// The turn lock to lock: raw axis values in time order.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TurnResult {
    /// Raw value at the left lock.
    pub left_raw: i32,
    /// Raw value at the right lock.
    pub right_raw: i32,
    /// `+1.0` if a left turn raises the raw value, else `-1.0` (the profile's `angle_sign`).
    pub angle_sign: f64,
    /// Smallest non-zero change between two readings, raw units.
    pub step_units: u32,
}

/// Analyse a turn asked as "left lock first, then right lock": `raw` in time order, the axis's
/// declared range `declared` (min, max). The lock reached first is the left one.
pub fn analyze_turn(raw: &[i32], declared: (i32, i32)) -> Result<TurnResult, CalibrationError> {
    let (Some(&lo), Some(&hi)) = (raw.iter().min(), raw.iter().max()) else {
        return Err(CalibrationError::TurnTooSmall(0.0));
    };
    let span = f64::from(declared.1) - f64::from(declared.0);
    let covered = (f64::from(hi) - f64::from(lo)) / span.max(1.0);
    if covered < 0.2 {
        return Err(CalibrationError::TurnTooSmall(100.0 * covered));
    }
    let first_lo = raw.iter().position(|&v| v == lo).unwrap_or(0);
    let first_hi = raw.iter().position(|&v| v == hi).unwrap_or(0);
    // Left first: if the low extreme came first, a left turn lowers the value.
    let angle_sign = if first_lo < first_hi { -1.0 } else { 1.0 };
    let (left_raw, right_raw) = if angle_sign < 0.0 { (lo, hi) } else { (hi, lo) };
    let step_units = raw
        .windows(2)
        .map(|w| w[1].abs_diff(w[0]))
        .filter(|&d| d > 0)
        .min()
        .unwrap_or(1);
    Ok(TurnResult {
        left_raw,
        right_raw,
        angle_sign,
        step_units,
    })
}

/// The torque sign from the raw displacement under a positive (`pos_delta`) and a negative
/// (`neg_delta`) gentle push, raw units, on a wheel whose `angle_sign` is known: `+1.0` if a
/// positive device force turns the wheel left.
pub fn analyze_push(
    pos_delta: i32,
    neg_delta: i32,
    angle_sign: f64,
    step_units: u32,
) -> Result<f64, CalibrationError> {
    let moved = |d: i32| d.unsigned_abs() >= 2 * step_units.max(1);
    if !moved(pos_delta) && !moved(neg_delta) {
        return Err(CalibrationError::NoMotion);
    }
    if pos_delta.signum() == neg_delta.signum() && moved(pos_delta) && moved(neg_delta) {
        return Err(CalibrationError::Inconsistent);
    }
    // Displacement of the positive push in our angle convention (left positive).
    let d = if moved(pos_delta) {
        f64::from(pos_delta)
    } else {
        -f64::from(neg_delta)
    };
    Ok(if d * angle_sign > 0.0 { 1.0 } else { -1.0 })
}

/// The usable torque update rate from measured update durations (ns), Hz: one update per
/// twice the 99th-percentile duration, never above the driver's policy `policy_hz`.
pub fn usable_update_rate_hz(update_ns: &[u64], policy_hz: f64) -> f64 {
    let mut v = update_ns.to_vec();
    v.sort_unstable();
    let p99 = v
        .get(((v.len() as f64 * 0.99).ceil() as usize).saturating_sub(1))
        .copied()
        .unwrap_or(0)
        .max(1);
    policy_hz.min(1e9 / (2.0 * p99 as f64)).max(1.0)
}

/// The profile the measurement gives: `base` (the built-in, configured or unknown profile the
/// wheel was driven with) with the measured range, signs, resolution and update rate, and the
/// rated torque when one was entered (`rated_torque_nm`, from the maker's sheet).
pub fn measured_profile(
    base: &DeviceProfile,
    declared: (i32, i32),
    turn: &TurnResult,
    torque_sign: f64,
    update_rate_hz: f64,
    rated_torque_nm: Option<f64>,
) -> DeviceProfile {
    let span = (f64::from(declared.1) - f64::from(declared.0)).max(1.0);
    // The declared span is the base profile's full range; the locks reached say how much of it
    // the wheel turns as set up now.
    let rad_per_unit = 2.0 * base.half_range_rad / span;
    let lock_to_lock_rad = f64::from(turn.left_raw.abs_diff(turn.right_raw)) * rad_per_unit;
    let mut p = match rated_torque_nm {
        Some(t) => base.clone().with_rated_torque(t),
        None => base.clone(),
    };
    p.name = format!("{} (measured by telerehab wheel calibrate)", base.name);
    p.half_range_rad = 0.5 * lock_to_lock_rad;
    p.ka_rad_per_unit = rad_per_unit;
    p.angle_sign = turn.angle_sign;
    p.torque_sign = torque_sign;
    p.max_update_rate_hz = update_rate_hz;
    p.torque_step_nm = p.torque_step_nm.min(p.max_torque_nm);
    p
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sweep(from: i32, to: i32, step: i32) -> Vec<i32> {
        let mut v = Vec::new();
        let mut x = from;
        while (step > 0 && x <= to) || (step < 0 && x >= to) {
            v.push(x);
            x += step;
        }
        v
    }

    #[test]
    fn a_turn_left_then_right_gives_the_locks_the_sign_and_the_step() {
        // A G29-like wheel: left lowers the value, 4-unit encoder steps.
        let mut raw = sweep(32_768, 0, -4);
        raw.extend(sweep(0, 65_532, 4));
        raw.extend(sweep(65_532, 32_768, -4));
        let t = analyze_turn(&raw, (0, 65_535)).unwrap();
        assert_eq!(t.angle_sign, -1.0);
        assert_eq!((t.left_raw, t.right_raw), (0, 65_532));
        assert_eq!(t.step_units, 4);
        // The other convention.
        let rev: Vec<i32> = raw.iter().map(|v| 65_535 - v).collect();
        assert_eq!(analyze_turn(&rev, (0, 65_535)).unwrap().angle_sign, 1.0);
    }

    #[test]
    fn a_small_turn_is_refused_with_what_to_do() {
        let raw = sweep(32_000, 33_000, 10);
        let e = analyze_turn(&raw, (0, 65_535)).unwrap_err();
        assert!(e.to_string().contains("left lock"), "{e}");
    }

    #[test]
    fn pushes_give_the_torque_sign_or_say_why_not() {
        // angle_sign −1: a left turn lowers the value; a positive push lowering it turns left.
        assert_eq!(analyze_push(-300, 300, -1.0, 1), Ok(1.0));
        assert_eq!(analyze_push(300, -300, -1.0, 1), Ok(-1.0));
        assert_eq!(analyze_push(300, -300, 1.0, 1), Ok(1.0));
        assert_eq!(analyze_push(0, 1, 1.0, 1), Err(CalibrationError::NoMotion));
        assert_eq!(
            analyze_push(300, 280, 1.0, 1),
            Err(CalibrationError::Inconsistent)
        );
    }

    #[test]
    fn the_update_rate_is_capped_by_the_driver_and_by_slow_updates() {
        assert_eq!(usable_update_rate_hz(&[50_000; 100], 1000.0), 1000.0);
        // 2 ms updates: 250 Hz.
        assert!((usable_update_rate_hz(&[2_000_000; 100], 1000.0) - 250.0).abs() < 1e-9);
    }

    #[test]
    fn the_measured_profile_keeps_the_torque_unless_a_rating_is_entered() {
        let base = DeviceProfile::unknown(crate::DriverFamily::HidPidff);
        let turn = TurnResult {
            left_raw: 16_384,
            right_raw: 49_151,
            angle_sign: -1.0,
            step_units: 1,
        };
        let p = measured_profile(&base, (0, 65_535), &turn, 1.0, 500.0, None);
        assert_eq!(p.torque_source, crate::TorqueSource::Assumed);
        assert!(
            (p.half_range_rad.to_degrees() - 225.0).abs() < 0.1,
            "half of 900°"
        );
        p.validate().unwrap();
        let p = measured_profile(&base, (0, 65_535), &turn, 1.0, 500.0, Some(9.0));
        assert_eq!(p.torque_source, crate::TorqueSource::Clinician);
        assert_eq!(p.usable_max_nm(), 9.0);
        assert!(
            gentle_torque_nm(1.0) <= 0.1 && gentle_torque_nm(20.0) <= CALIBRATION_MAX_TORQUE_NM
        );
    }
}
