//! The rotation group SO(3): exponential and logarithm maps, in matrix and quaternion form
//! (Rodrigues' formula, thesis eq. 4.9–4.12).

use nalgebra::{Matrix3, Quaternion, Rotation3, UnitQuaternion, Vector3};

/// `exp([φ]×)` for a rotation vector `phi_rad` (axis × angle, rad), by Rodrigues' formula
/// (thesis eq. 4.12), with a series expansion near zero angle.
pub fn exp(phi_rad: &Vector3<f64>) -> Matrix3<f64> {
    let t2 = phi_rad.norm_squared();
    // sin θ/θ and (1 − cos θ)/θ²: Taylor series below 0.1 rad (exact to f64 precision there,
    // the usual per-sample angle of a gyro), libm above.
    let (a, b) = if t2 < 0.01 {
        (
            1.0 - t2
                * (1.0 / 6.0)
                * (1.0 - t2 * (1.0 / 20.0) * (1.0 - t2 * (1.0 / 42.0) * (1.0 - t2 * (1.0 / 72.0)))),
            0.5 - t2
                * (1.0 / 24.0)
                * (1.0 - t2 * (1.0 / 30.0) * (1.0 - t2 * (1.0 / 56.0) * (1.0 - t2 * (1.0 / 90.0)))),
        )
    } else {
        let theta = t2.sqrt();
        let (sin, cos) = theta.sin_cos();
        (sin / theta, (1.0 - cos) / t2)
    };
    // I + a [φ]× + b [φ]×², written out so it compiles to straight-line code.
    let (x, y, z) = (phi_rad.x, phi_rad.y, phi_rad.z);
    let (xx, yy, zz, xy, xz, yz) = (x * x, y * y, z * z, x * y, x * z, y * z);
    Matrix3::new(
        1.0 - b * (yy + zz),
        b * xy - a * z,
        b * xz + a * y,
        b * xy + a * z,
        1.0 - b * (xx + zz),
        b * yz - a * x,
        b * xz - a * y,
        b * yz + a * x,
        1.0 - b * (xx + yy),
    )
}

/// The rotation vector (axis × angle, rad, angle in [0, π]) of a rotation matrix: the inverse
/// of [`exp`]. Accurate near 0 and near π.
pub fn log(r: &Matrix3<f64>) -> Vector3<f64> {
    log_quat(&UnitQuaternion::from_rotation_matrix(
        &Rotation3::from_matrix_unchecked(*r),
    ))
}

/// The exponential map in quaternion form: the unit quaternion of rotation vector `phi_rad`,
/// `[cos(θ/2), sin(θ/2)·φ/θ]` (equivalent to eq. 4.12).
pub fn exp_quat(phi_rad: &Vector3<f64>) -> UnitQuaternion<f64> {
    let t2 = phi_rad.norm_squared();
    // cos(θ/2) and sin(θ/2)/θ: Taylor series below 0.2 rad (exact to f64 precision), libm above.
    let (w, s) = if t2 < 0.04 {
        let x2 = t2 * 0.25;
        (
            1.0 - x2
                * 0.5
                * (1.0
                    - x2 * (1.0 / 12.0)
                        * (1.0
                            - x2 * (1.0 / 30.0)
                                * (1.0 - x2 * (1.0 / 56.0) * (1.0 - x2 * (1.0 / 90.0))))),
            0.5 * (1.0
                - x2 * (1.0 / 6.0)
                    * (1.0
                        - x2 * (1.0 / 20.0)
                            * (1.0
                                - x2 * (1.0 / 42.0)
                                    * (1.0 - x2 * (1.0 / 72.0) * (1.0 - x2 * (1.0 / 110.0)))))),
        )
    } else {
        let theta = t2.sqrt();
        let (sin, cos) = (0.5 * theta).sin_cos();
        (cos, sin / theta)
    };
    UnitQuaternion::new_unchecked(Quaternion::new(
        w,
        s * phi_rad.x,
        s * phi_rad.y,
        s * phi_rad.z,
    ))
}

/// The rotation vector (rad, angle in [0, π]) of a unit quaternion.
pub fn log_quat(q: &UnitQuaternion<f64>) -> Vector3<f64> {
    let (w, v) = if q.w < 0.0 {
        (-q.w, -q.imag())
    } else {
        (q.w, q.imag())
    };
    let s = v.norm();
    if s < 1e-12 {
        return v * 2.0;
    }
    let angle = 2.0 * s.atan2(w);
    v * (angle / s)
}

/// The rotation angle (rad, in [0, π]) between two orientations.
pub fn angle_between(a: &UnitQuaternion<f64>, b: &UnitQuaternion<f64>) -> f64 {
    log_quat(&(a.inverse() * b)).norm()
}

/// Re-normalise a nearly unit quaternion without a square root (one Newton step on
/// `|q|² = 1`, exact to second order in the error).
#[inline]
pub fn renormalize(q: &Quaternion<f64>) -> UnitQuaternion<f64> {
    UnitQuaternion::new_unchecked(q * (1.5 - 0.5 * q.norm_squared()))
}

/// Re-orthonormalise a nearly orthonormal matrix (the closest rotation, by one symmetric
/// Newton step `R ← R·(3I − RᵀR)/2`, exact to second order in the error).
pub fn reorthonormalize(r: &Matrix3<f64>) -> Matrix3<f64> {
    let e = r.transpose() * r;
    r * (Matrix3::identity() * 3.0 - e) * 0.5
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn quarter_turn_about_z_maps_x_to_y() {
        let r = exp(&Vector3::new(0.0, 0.0, std::f64::consts::FRAC_PI_2));
        let y = r * Vector3::x();
        assert!((y - Vector3::y()).norm() < 1e-15);
        assert!((r.transpose() * r - Matrix3::identity()).norm() < 1e-15);
    }

    proptest! {
        #[test]
        fn exp_is_orthonormal_and_matches_quaternion_and_log_inverts_it(
            x in -3.0f64..3.0, y in -3.0f64..3.0, z in -3.0f64..3.0, scale in prop_oneof![Just(1e-9), Just(1e-4), Just(1.0)]
        ) {
            let phi = Vector3::new(x, y, z) * scale;
            prop_assume!(phi.norm() < std::f64::consts::PI - 1e-6);
            let r = exp(&phi);
            prop_assert!((r.transpose() * r - Matrix3::identity()).norm() < 1e-14);
            prop_assert!((r.determinant() - 1.0).abs() < 1e-14);
            let q = exp_quat(&phi);
            prop_assert!((q.to_rotation_matrix().into_inner() - r).norm() < 1e-14);
            prop_assert!((log(&r) - phi).norm() < 1e-9 * (1.0 + phi.norm()));
            prop_assert!((log_quat(&q) - phi).norm() < 1e-12);
        }
    }

    #[test]
    fn series_and_libm_branches_agree_at_the_switch_points() {
        for t in [0.0999999, 0.1000001, 0.1999999, 0.2000001, 1e-5, 0.05] {
            let phi = Vector3::new(t, 0.0, 0.0);
            let r = exp(&phi);
            assert!(
                (r[(1, 1)] - t.cos()).abs() < 1e-16 && (r[(2, 1)] - t.sin()).abs() < 1e-16,
                "{t}"
            );
            let q = exp_quat(&phi);
            assert!(
                (q.w - (t / 2.0).cos()).abs() < 1e-16 && (q.i - (t / 2.0).sin()).abs() < 1e-16,
                "{t}"
            );
        }
    }

    #[test]
    fn reorthonormalize_shrinks_the_orthonormality_error() {
        let r = exp(&Vector3::new(0.3, -0.2, 0.9))
            + Matrix3::new(1e-4, 0.0, 2e-4, 0.0, -1e-4, 0.0, 0.0, 3e-4, 0.0);
        let e0 = (r.transpose() * r - Matrix3::identity()).norm();
        let n = reorthonormalize(&r);
        let e1 = (n.transpose() * n - Matrix3::identity()).norm();
        assert!(e0 > 1e-4 && e1 < 1e-7, "{e0} -> {e1}");
    }
}
