//! The exponential map on SO(3) (Rodrigues' formula, thesis eq. 4.12).

use nalgebra::{Matrix3, Vector3};

/// `exp([φ]×)` for a rotation vector `phi_rad` (axis × angle, rad), by Rodrigues' formula
/// (thesis eq. 4.12), with a series expansion near zero angle.
pub fn exp(phi_rad: &Vector3<f64>) -> Matrix3<f64> {
    let theta2 = phi_rad.norm_squared();
    let k = phi_rad.cross_matrix();
    let (a, b) = if theta2 < 1e-12 {
        (1.0 - theta2 / 6.0, 0.5 - theta2 / 24.0)
    } else {
        let theta = theta2.sqrt();
        (theta.sin() / theta, (1.0 - theta.cos()) / theta2)
    };
    Matrix3::identity() + k * a + k * k * b
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quarter_turn_about_z_maps_x_to_y() {
        let r = exp(&Vector3::new(0.0, 0.0, std::f64::consts::FRAC_PI_2));
        let y = r * Vector3::x();
        assert!((y - Vector3::y()).norm() < 1e-15);
        assert!((r.transpose() * r - Matrix3::identity()).norm() < 1e-15);
    }
}
