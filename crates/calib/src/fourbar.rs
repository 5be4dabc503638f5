//! The planar four-bar loop of the arm and wheel (thesis §4.2.1, eq. 4.1).

/// Closure residual of the planar loop `l2·e^{iθ2} + l3·e^{iθ3} − l4·e^{iθ4} − l1 = 0`
/// (thesis eq. 4.1 with Θ1 = 0: ground link along +x from wheel centre to shoulder).
/// Lengths in m, angles in rad; returns `[re, im]` in m.
pub fn loop_residual(l: [f64; 4], theta2: f64, theta3: f64, theta4: f64) -> [f64; 2] {
    let [l1, l2, l3, l4] = l;
    [
        l2 * theta2.cos() + l3 * theta3.cos() - l4 * theta4.cos() - l1,
        l2 * theta2.sin() + l3 * theta3.sin() - l4 * theta4.sin(),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closed_rectangle_has_zero_residual() {
        use std::f64::consts::FRAC_PI_2;
        // l2 up, l3 across, l4 up from the shoulder: a rectangle closes when l3 = l1, l2 = l4.
        let r = loop_residual([0.5, 0.2, 0.5, 0.2], FRAC_PI_2, 0.0, FRAC_PI_2);
        assert!(r[0].abs() < 1e-15 && r[1].abs() < 1e-15);
    }
}
