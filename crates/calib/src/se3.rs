//! Rigid-body motions SE(3): hat, exponential and logarithm maps and the adjoint (thesis §4.3,
//! eq. 4.28–4.46). Twists are ordered `(v, ω)` = `(dx, dy, dz, δx, δy, δz)` as in eq. 4.44.

use nalgebra::{Matrix3, Matrix4, Matrix6, Vector3, Vector6};

/// Skew-symmetric matrix `[w]×` with `[w]× u = w × u`.
pub fn skew(w: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -w.z, w.y, w.z, 0.0, -w.x, -w.y, w.x, 0.0)
}

/// The 4×4 matrix of a twist (eq. 4.32): `[[ω]×, v; 0, 0]`.
pub fn hat(xi: &Vector6<f64>) -> Matrix4<f64> {
    let mut m = Matrix4::zeros();
    m.fixed_view_mut::<3, 3>(0, 0)
        .copy_from(&skew(&xi.fixed_rows::<3>(3).into_owned()));
    m.fixed_view_mut::<3, 1>(0, 3)
        .copy_from(&xi.fixed_rows::<3>(0));
    m
}

/// Rotation part of a transform.
pub fn rotation(t: &Matrix4<f64>) -> Matrix3<f64> {
    t.fixed_view::<3, 3>(0, 0).into_owned()
}

/// Translation part of a transform (m).
pub fn translation(t: &Matrix4<f64>) -> Vector3<f64> {
    t.fixed_view::<3, 1>(0, 3).into_owned()
}

/// Build a transform from a rotation and a translation (m).
pub fn from_parts(r: &Matrix3<f64>, p: &Vector3<f64>) -> Matrix4<f64> {
    let mut t = Matrix4::identity();
    t.fixed_view_mut::<3, 3>(0, 0).copy_from(r);
    t.fixed_view_mut::<3, 1>(0, 3).copy_from(p);
    t
}

/// Inverse of a rigid transform, `[Rᵀ, −Rᵀp; 0, 1]` (exact, no general matrix inversion).
pub fn inverse(t: &Matrix4<f64>) -> Matrix4<f64> {
    let rt = rotation(t).transpose();
    from_parts(&rt, &(-(rt * translation(t))))
}

/// Coefficients `(sin θ/θ, (1−cos θ)/θ², (θ−sin θ)/θ³)` with series near θ = 0.
fn so3_coefficients(theta: f64) -> (f64, f64, f64) {
    let t2 = theta * theta;
    if theta < 1e-4 {
        (
            1.0 - t2 / 6.0 + t2 * t2 / 120.0,
            0.5 - t2 / 24.0 + t2 * t2 / 720.0,
            1.0 / 6.0 - t2 / 120.0 + t2 * t2 / 5040.0,
        )
    } else {
        (
            theta.sin() / theta,
            (1.0 - theta.cos()) / t2,
            (theta - theta.sin()) / (t2 * theta),
        )
    }
}

/// Exponential map se(3) → SE(3) (closed form: Rodrigues for the rotation, the left Jacobian
/// `V = I + (1−cos θ)/θ²·W + (θ−sin θ)/θ³·W²` for the translation).
pub fn exp(xi: &Vector6<f64>) -> Matrix4<f64> {
    let v = xi.fixed_rows::<3>(0).into_owned();
    let w = xi.fixed_rows::<3>(3).into_owned();
    let theta = w.norm();
    let (a, b, c) = so3_coefficients(theta);
    let wx = skew(&w);
    let wx2 = wx * wx;
    let r = Matrix3::identity() + wx * a + wx2 * b;
    let vmat = Matrix3::identity() + wx * b + wx2 * c;
    from_parts(&r, &(vmat * v))
}

/// Logarithm SO(3) → so(3) as a rotation vector (rad), accurate to machine precision at every
/// angle: θ from `atan2(‖vee(R − Rᵀ)‖/2, (tr R − 1)/2)` (an `acos` of the trace alone loses
/// half the digits near θ = 0), the axis from the symmetric part near θ = π.
fn log_so3(r: &Matrix3<f64>) -> Vector3<f64> {
    let s = Vector3::new(
        r[(2, 1)] - r[(1, 2)],
        r[(0, 2)] - r[(2, 0)],
        r[(1, 0)] - r[(0, 1)],
    ) * 0.5;
    let sin = s.norm();
    let cos = (r.trace() - 1.0) * 0.5;
    let theta = sin.atan2(cos);
    if theta < 1e-6 {
        return s * (1.0 + theta * theta / 6.0);
    }
    if theta < std::f64::consts::PI - 1e-3 {
        return s * (theta / sin);
    }
    // near π: (R + Rᵀ)/2 = cos θ·I + (1 − cos θ)·aaᵀ
    let sym = (r + r.transpose()) * 0.5;
    let b = (sym - Matrix3::identity() * cos) / (1.0 - cos);
    let i = (0..3)
        .max_by(|&i, &j| b[(i, i)].total_cmp(&b[(j, j)]))
        .unwrap_or(0);
    let mut axis: Vector3<f64> = b.column(i) / b[(i, i)].max(f64::MIN_POSITIVE).sqrt();
    axis.normalize_mut();
    if axis.dot(&s) < 0.0 {
        axis = -axis;
    }
    axis * theta
}

/// Logarithm SE(3) → se(3) (the `log∨` of eq. 4.46), exact (not the first-order
/// `T′T⁻¹ − I` of eq. 4.43): twist `(v, ω)` with `exp(log(T)) = T`.
pub fn log(t: &Matrix4<f64>) -> Vector6<f64> {
    let w = log_so3(&rotation(t));
    let theta = w.norm();
    let wx = skew(&w);
    // V⁻¹ = I − ½W + (1/θ²)(1 − (θ sin θ)/(2(1 − cos θ)))·W²
    let d = if theta < 1e-4 {
        1.0 / 12.0 + theta * theta / 720.0
    } else {
        (1.0 - theta * theta.sin() / (2.0 * (1.0 - theta.cos()))) / (theta * theta)
    };
    let vinv = Matrix3::identity() - wx * 0.5 + wx * wx * d;
    let v = vinv * translation(t);
    Vector6::new(v.x, v.y, v.z, w.x, w.y, w.z)
}

/// Adjoint of a transform acting on `(v, ω)` twists: `Ad_T = [[R, [p]×R], [0, R]]`, so that
/// `T·exp(ξ)·T⁻¹ = exp(Ad_T ξ)` (eq. 4.45).
pub fn adjoint(t: &Matrix4<f64>) -> Matrix6<f64> {
    let r = rotation(t);
    let pr = skew(&translation(t)) * r;
    let mut ad = Matrix6::zeros();
    ad.fixed_view_mut::<3, 3>(0, 0).copy_from(&r);
    ad.fixed_view_mut::<3, 3>(0, 3).copy_from(&pr);
    ad.fixed_view_mut::<3, 3>(3, 3).copy_from(&r);
    ad
}

/// Why `t` is not a rigid transform (tolerance `tol` on orthonormality), or `None` if it is.
pub fn rigid_defect(t: &Matrix4<f64>, tol: f64) -> Option<&'static str> {
    if t.iter().any(|x| !x.is_finite()) {
        return Some("contains NaN or infinity");
    }
    if t[(3, 0)] != 0.0 || t[(3, 1)] != 0.0 || t[(3, 2)] != 0.0 || t[(3, 3)] != 1.0 {
        return Some("last row is not [0, 0, 0, 1]");
    }
    let r = rotation(t);
    if (r.transpose() * r - Matrix3::identity()).amax() > tol {
        return Some("rotation block is not orthonormal");
    }
    if r.determinant() < 0.0 {
        return Some("rotation block is a reflection (det = −1)");
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn twist() -> impl Strategy<Value = Vector6<f64>> {
        // rotation angle kept below π so the log is unique
        (
            prop::array::uniform3(-2.0..2.0f64),
            prop::array::uniform3(-1.7..1.7f64),
        )
            .prop_map(|(v, w)| Vector6::new(v[0], v[1], v[2], w[0], w[1], w[2]))
            .prop_filter("angle below π", |x| x.fixed_rows::<3>(3).norm() < 3.0)
    }

    proptest! {
        #[test]
        fn log_inverts_exp(xi in twist()) {
            let back = log(&exp(&xi));
            prop_assert!((back - xi).amax() < 1e-10, "{xi} -> {back}");
        }

        #[test]
        fn adjoint_conjugates_twists(a in twist(), b in twist()) {
            let t = exp(&a);
            let lhs = t * exp(&b) * inverse(&t);
            let rhs = exp(&(adjoint(&t) * b));
            prop_assert!((lhs - rhs).amax() < 1e-10);
        }

        #[test]
        fn exp_is_a_rigid_transform(xi in twist()) {
            prop_assert_eq!(rigid_defect(&exp(&xi), 1e-12), None);
            prop_assert!((exp(&xi) * inverse(&exp(&xi)) - Matrix4::identity()).amax() < 1e-12);
        }
    }

    #[test]
    fn exp_of_small_twist_matches_first_order_hat() {
        let xi = Vector6::new(1e-7, -2e-7, 3e-7, 1e-7, 2e-7, -1e-7);
        let first_order = Matrix4::identity() + hat(&xi);
        assert!((exp(&xi) - first_order).amax() < 1e-13);
    }

    #[test]
    fn log_is_accurate_for_tiny_rotations() {
        let xi = Vector6::new(1e-9, 0.0, 0.0, 3e-10, -2e-10, 1e-10);
        assert!((log(&exp(&xi)) - xi).amax() < 1e-22);
    }

    #[test]
    fn log_handles_half_turn() {
        let xi = Vector6::new(0.3, -0.1, 0.2, 0.0, 0.0, std::f64::consts::PI);
        let back = log(&exp(&xi));
        assert!((exp(&back) - exp(&xi)).amax() < 1e-12);
    }

    #[test]
    fn reflection_is_not_rigid() {
        let mut t = Matrix4::identity();
        t[(0, 0)] = -1.0;
        assert_eq!(
            rigid_defect(&t, 1e-9),
            Some("rotation block is a reflection (det = −1)")
        );
    }
}
