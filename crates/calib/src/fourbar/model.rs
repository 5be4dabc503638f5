//! The planar four-bar loop of the arm and wheel (thesis §4.2.1, eq. 4.1–4.2): parameters,
//! samples, the closure residual and its Jacobian, and a noise-free simulator.

use serde::{Deserialize, Serialize};

use crate::error::{CalibError, check_finite};

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

/// The unknowns of the planar four-bar (thesis eq. 4.2, plus l1 and the gyro biases).
///
/// Angles are in the frame where the ground link lies along +x from the wheel centre to the
/// shoulder: θj(t) = Θj + φj(t) − bj·t for the gyro-measured links j = 3, 4.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FourbarParams {
    /// Ground link, wheel centre to shoulder (m).
    pub l1_m: f64,
    /// Forearm (coupler), handgrip to elbow (m).
    pub l3_m: f64,
    /// Upper arm (follower), shoulder to elbow (m).
    pub l4_m: f64,
    /// Initial wheel-crank angle Θ2 (rad).
    pub theta2_0_rad: f64,
    /// Initial forearm angle Θ3 (rad).
    pub theta3_0_rad: f64,
    /// Initial upper-arm angle Θ4 (rad).
    pub theta4_0_rad: f64,
    /// Forearm gyro bias b3: the integrated angle φ3 drifts by b3 per unit time (rad/s when
    /// timestamps are given, else rad per sample). 0 when not estimated.
    pub gyro_bias3: f64,
    /// Upper-arm gyro bias b4, as `gyro_bias3`.
    pub gyro_bias4: f64,
}

impl FourbarParams {
    /// Parameters without gyro bias.
    pub fn new(
        l1_m: f64,
        l3_m: f64,
        l4_m: f64,
        theta2_0: f64,
        theta3_0: f64,
        theta4_0: f64,
    ) -> Self {
        Self {
            l1_m,
            l3_m,
            l4_m,
            theta2_0_rad: theta2_0,
            theta3_0_rad: theta3_0,
            theta4_0_rad: theta4_0,
            gyro_bias3: 0.0,
            gyro_bias4: 0.0,
        }
    }

    /// As a vector `[l1, l3, l4, Θ2, Θ3, Θ4, b3, b4]`.
    pub(crate) fn to_vec8(self) -> [f64; 8] {
        [
            self.l1_m,
            self.l3_m,
            self.l4_m,
            self.theta2_0_rad,
            self.theta3_0_rad,
            self.theta4_0_rad,
            self.gyro_bias3,
            self.gyro_bias4,
        ]
    }

    /// From `[l1, l3, l4, Θ2, Θ3, Θ4, b3, b4]`, made canonical: lengths positive (a negative
    /// length is the same link turned by π) and angles wrapped to (−π, π].
    pub(crate) fn from_vec8(p: [f64; 8]) -> Self {
        // A negative ground link is the whole loop turned by π: flip it back so l1 points along +x.
        let turn = if p[0] < 0.0 {
            std::f64::consts::PI
        } else {
            0.0
        };
        let (l3, t3) = canonical_link(p[1], p[4] + turn);
        let (l4, t4) = canonical_link(p[2], p[5] + turn);
        Self {
            l1_m: p[0].abs(),
            l3_m: l3,
            l4_m: l4,
            theta2_0_rad: wrap_angle(p[3] + turn),
            theta3_0_rad: t3,
            theta4_0_rad: t4,
            gyro_bias3: p[6],
            gyro_bias4: p[7],
        }
    }

    /// Check that every field is finite (named in the error).
    pub fn validate(&self) -> Result<(), CalibError> {
        let fields = [
            ("initial.l1_m", self.l1_m),
            ("initial.l3_m", self.l3_m),
            ("initial.l4_m", self.l4_m),
            ("initial.theta2_0_rad", self.theta2_0_rad),
            ("initial.theta3_0_rad", self.theta3_0_rad),
            ("initial.theta4_0_rad", self.theta4_0_rad),
            ("initial.gyro_bias3", self.gyro_bias3),
            ("initial.gyro_bias4", self.gyro_bias4),
        ];
        for (argument, value) in fields {
            check_finite(argument, &[value])?;
        }
        Ok(())
    }
}

fn canonical_link(l: f64, theta: f64) -> (f64, f64) {
    if l < 0.0 {
        (-l, wrap_angle(theta + std::f64::consts::PI))
    } else {
        (l, wrap_angle(theta))
    }
}

/// Wrap an angle to (−π, π] (rad); one definition for the workspace, in `common`.
pub use common::wrap_angle;

/// Measured relative angles of one recording (rad), equal lengths: φ2 from the wheel encoder,
/// φ3, φ4 from the integrated forearm and upper-arm gyros (thesis §4.2.1), and optional
/// timestamps (s, non-decreasing) used by the gyro-bias terms.
#[derive(Debug, Clone, Copy)]
pub struct FourbarSamples<'a> {
    /// Wheel angle relative to the start, φ2 (rad).
    pub phi2: &'a [f64],
    /// Forearm angle relative to the start, φ3 (rad).
    pub phi3: &'a [f64],
    /// Upper-arm angle relative to the start, φ4 (rad).
    pub phi4: &'a [f64],
    /// Sample times (s); `None` means the sample index is the time axis.
    pub time_s: Option<&'a [f64]>,
}

/// Fewest samples any method accepts (6–8 unknowns, 2 equations per sample, with margin).
pub const MIN_SAMPLES: usize = 10;

impl<'a> FourbarSamples<'a> {
    /// Samples without timestamps.
    pub fn new(phi2: &'a [f64], phi3: &'a [f64], phi4: &'a [f64]) -> Self {
        Self {
            phi2,
            phi3,
            phi4,
            time_s: None,
        }
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.phi2.len()
    }

    /// True when there are no samples.
    pub fn is_empty(&self) -> bool {
        self.phi2.is_empty()
    }

    /// Time of sample `k` (s, or the index when no timestamps were given).
    pub(crate) fn time(&self, k: usize) -> f64 {
        match self.time_s {
            Some(t) => t[k] - t[0],
            None => k as f64,
        }
    }

    /// Check lengths, finiteness and the minimum sample count.
    pub fn validate(&self) -> Result<(), CalibError> {
        let n = self.phi2.len();
        for (argument, v) in [("phi3", self.phi3), ("phi4", self.phi4)] {
            if v.len() != n {
                return Err(CalibError::LengthMismatch {
                    argument,
                    got: v.len(),
                    expected: n,
                    reference: "phi2",
                });
            }
        }
        if let Some(t) = self.time_s {
            if t.len() != n {
                return Err(CalibError::LengthMismatch {
                    argument: "time_s",
                    got: t.len(),
                    expected: n,
                    reference: "phi2",
                });
            }
            check_finite("time_s", t)?;
            if let Some(k) = t.windows(2).position(|w| w[1] < w[0]) {
                return Err(CalibError::OutOfRange {
                    argument: "time_s",
                    value: t[k + 1],
                    allowed: "timestamps must be non-decreasing",
                });
            }
        }
        if n < MIN_SAMPLES {
            return Err(CalibError::TooFewSamples {
                argument: "phi2",
                got: n,
                needed: MIN_SAMPLES,
            });
        }
        check_finite("phi2", self.phi2)?;
        check_finite("phi3", self.phi3)?;
        check_finite("phi4", self.phi4)?;
        Ok(())
    }

    /// Peak-to-peak wheel motion (rad).
    pub fn wheel_range_rad(&self) -> f64 {
        let (lo, hi) = self
            .phi2
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
                (lo.min(v), hi.max(v))
            });
        hi - lo
    }
}

/// A four-bar with known lengths, for simulation: wheel centre at the origin, shoulder at
/// `(l1, 0)`, handgrip on the wheel rim, elbow where the forearm and upper-arm circles meet.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FourbarGeometry {
    /// Ground link (m).
    pub l1_m: f64,
    /// Wheel crank (m).
    pub l2_m: f64,
    /// Forearm (m).
    pub l3_m: f64,
    /// Upper arm (m).
    pub l4_m: f64,
    /// Elbow branch: +1 or −1 (which of the two circle intersections).
    pub elbow_branch: f64,
}

impl FourbarGeometry {
    /// Absolute link angles `(θ3, θ4)` (rad) for wheel angle `θ2`, or `None` where the loop
    /// cannot close (hand out of the arm's reach).
    pub fn link_angles(&self, theta2: f64) -> Option<(f64, f64)> {
        let (hx, hy) = (self.l2_m * theta2.cos(), self.l2_m * theta2.sin());
        let (dx, dy) = (self.l1_m - hx, -hy); // hand → shoulder
        let d = dx.hypot(dy);
        if d > self.l3_m + self.l4_m || d < (self.l3_m - self.l4_m).abs() || d == 0.0 {
            return None;
        }
        // distance from the hand along hand→shoulder to the chord between the intersections
        let a = (self.l3_m * self.l3_m - self.l4_m * self.l4_m + d * d) / (2.0 * d);
        let h = (self.l3_m * self.l3_m - a * a).max(0.0).sqrt() * self.elbow_branch;
        let (ux, uy) = (dx / d, dy / d);
        let (ex, ey) = (hx + a * ux - h * uy, hy + a * uy + h * ux);
        Some(((ey - hy).atan2(ex - hx), ey.atan2(ex - self.l1_m)))
    }

    /// Noise-free relative angles `(φ3, φ4)` for the wheel angles `θ2 = theta2_0 + φ2`,
    /// relative to the first sample, with the true initial angles `(Θ3, Θ4)`.
    pub fn simulate(
        &self,
        theta2_0: f64,
        phi2: &[f64],
    ) -> Result<(Vec<f64>, Vec<f64>, f64, f64), CalibError> {
        let unreachable = |k: usize| CalibError::OutOfRange {
            argument: "phi2",
            value: phi2[k],
            allowed: "the loop must close (hand within reach of the arm) at every sample",
        };
        let first = phi2.first().copied().unwrap_or(0.0);
        let (t3_0, t4_0) = self
            .link_angles(theta2_0 + first)
            .ok_or_else(|| unreachable(0))?;
        let mut phi3 = Vec::with_capacity(phi2.len());
        let mut phi4 = Vec::with_capacity(phi2.len());
        let (mut prev3, mut prev4) = (0.0, 0.0);
        for (k, &p2) in phi2.iter().enumerate() {
            let (t3, t4) = self
                .link_angles(theta2_0 + p2)
                .ok_or_else(|| unreachable(k))?;
            // unwrap so the relative angles are continuous, as integrated gyros are
            prev3 += wrap_angle(t3 - t3_0 - prev3);
            prev4 += wrap_angle(t4 - t4_0 - prev4);
            phi3.push(prev3);
            phi4.push(prev4);
        }
        Ok((phi3, phi4, t3_0, t4_0))
    }
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

    #[test]
    fn mismatched_lengths_name_the_argument() {
        let a = [0.0; 12];
        let b = [0.0; 11];
        let err = FourbarSamples::new(&a, &a, &b).validate().unwrap_err();
        assert!(matches!(
            err,
            CalibError::LengthMismatch {
                argument: "phi4",
                got: 11,
                ..
            }
        ));
    }

    #[test]
    fn nan_sample_is_rejected_with_its_index() {
        let a = [0.0; 12];
        let mut b = [0.0; 12];
        b[7] = f64::NAN;
        let err = FourbarSamples::new(&a, &b, &a).validate().unwrap_err();
        assert_eq!(
            err,
            CalibError::NonFinite {
                argument: "phi3",
                index: 7
            }
        );
    }
}
