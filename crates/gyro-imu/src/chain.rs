//! Absolute-to-relative orientation changes along a serial chain (thesis eq. 4.16–4.24).
//!
//! Gyro `i` integrates `R_i`, the rotation of its current frame `{i'}` relative to its own
//! initial frame `{i}` (eq. 4.13). With `ᵏ⁻¹A_k` the initial relative orientation of link `k`,
//! `⁰A_i = ⁰A_1·¹A_2 ⋯ ⁱ⁻¹A_i` (eq. 4.16):
//! - the change expressed in the common frame `{0}` is `R̃_i = ⁰A_i·R_i·⁰A_iᵀ` (eq. 4.16–4.19);
//! - the current orientation of link `i` is `⁰R_i = R̃_i·⁰A_i = ⁰A_i·R_i`, which the chain writes
//!   `⁰R_i = ⁰A_1·Rq_1·¹A_2·Rq_2 ⋯ ⁱ⁻¹A_i·Rq_i` (eq. 4.22–4.23);
//! - so the relative (joint) changes follow recursively,
//!   `Rq_i = (⁰A_1·Rq_1 ⋯ Rq_{i−1}·ⁱ⁻¹A_i)ᵀ·⁰R_i` (eq. 4.24).

use nalgebra::Matrix3;

use crate::error::ImuError;

/// `R̃_i = ⁰A_i·R_i·⁰A_iᵀ`: a gyro's integrated change `r_i` expressed in frame `{0}` (eq. 4.16).
pub fn change_in_base(a0_i: &Matrix3<f64>, r_i: &Matrix3<f64>) -> Matrix3<f64> {
    a0_i * r_i * a0_i.transpose()
}

/// Relative orientation changes `Rq_i` of every joint of a chain (eq. 4.24).
///
/// `initial_rel[k]` is `ᵏA_{k+1}` (initial orientation of link `k+1` in link `k`'s frame);
/// `gyro_changes[k]` is the integrated change `R_{k+1}` of the gyro on link `k+1` (eq. 4.13).
/// Writes `Rq_{k+1}` into `out[k]`; no allocation.
pub fn relative_changes(
    initial_rel: &[Matrix3<f64>],
    gyro_changes: &[Matrix3<f64>],
    out: &mut [Matrix3<f64>],
) -> Result<(), ImuError> {
    let n = initial_rel.len();
    if gyro_changes.len() != n || out.len() != n {
        return Err(ImuError::InvalidInput(format!(
            "chain lengths differ: {} initial orientations, {} gyro changes, {} outputs",
            n,
            gyro_changes.len(),
            out.len()
        )));
    }
    let mut a0 = Matrix3::identity(); // ⁰A_i
    let mut prefix = Matrix3::identity(); // ⁰A_1·Rq_1 ⋯ Rq_{i−1}
    for k in 0..n {
        a0 *= initial_rel[k];
        let r0 = change_in_base(&a0, &gyro_changes[k]) * a0; // ⁰R_i (eq. 4.16, 4.22)
        let pre: Matrix3<f64> = prefix * initial_rel[k];
        out[k] = pre.transpose() * r0; // eq. 4.24
        prefix = pre * out[k];
    }
    Ok(())
}

/// Current orientations `⁰R_i` of every link from initial relative orientations and joint
/// changes (forward kinematics, eq. 4.22). Writes into `out`; no allocation.
pub fn forward(
    initial_rel: &[Matrix3<f64>],
    joint_changes: &[Matrix3<f64>],
    out: &mut [Matrix3<f64>],
) -> Result<(), ImuError> {
    let n = initial_rel.len();
    if joint_changes.len() != n || out.len() != n {
        return Err(ImuError::InvalidInput("chain lengths differ".into()));
    }
    let mut acc = Matrix3::identity();
    for k in 0..n {
        acc = acc * initial_rel[k] * joint_changes[k];
        out[k] = acc;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::so3;
    use nalgebra::Vector3;
    use proptest::prelude::*;

    fn rot(v: [f64; 3]) -> Matrix3<f64> {
        so3::exp(&Vector3::from(v))
    }

    proptest! {
        #[test]
        fn relative_changes_invert_the_forward_chain(
            a in proptest::array::uniform9(-1.5f64..1.5), q in proptest::array::uniform9(-1.5f64..1.5)
        ) {
            let init = [rot([a[0], a[1], a[2]]), rot([a[3], a[4], a[5]]), rot([a[6], a[7], a[8]])];
            let joints = [rot([q[0], q[1], q[2]]), rot([q[3], q[4], q[5]]), rot([q[6], q[7], q[8]])];
            let mut now = [Matrix3::zeros(); 3];
            forward(&init, &joints, &mut now).unwrap();
            // What each gyro integrates: its frame's change relative to its initial frame.
            let mut a0: Matrix3<f64> = Matrix3::identity();
            let mut gyro = [Matrix3::zeros(); 3];
            for k in 0..3 {
                a0 *= init[k];
                gyro[k] = a0.transpose() * now[k];
            }
            let mut rq = [Matrix3::zeros(); 3];
            relative_changes(&init, &gyro, &mut rq).unwrap();
            for k in 0..3 {
                prop_assert!((rq[k] - joints[k]).norm() < 1e-12);
            }
        }
    }

    #[test]
    fn mismatched_lengths_are_an_error() {
        let mut out = [Matrix3::zeros(); 2];
        assert!(
            relative_changes(
                &[Matrix3::identity(); 2],
                &[Matrix3::identity(); 3],
                &mut out
            )
            .is_err()
        );
    }
}
