//! The arm–wheel chain (thesis §4.2.2, Fig. 4-4): a spherical shoulder, an elbow with flexion
//! and pronation, the hand gripping the wheel rim, the wheel a revolute joint. With the wheel
//! angle known the chain has one free degree of freedom left (eq. 4.5–4.7): the swivel of the
//! elbow about the shoulder–grip line. Forearm pronation is carried as a second unknown.
//!
//! Frames. World `W` = wheel frame: origin at the wheel centre, x forward (away from the
//! patient), y left, z up. Right arm. Upper-arm frame `U`: x along the humerus (shoulder →
//! elbow), z the elbow flexion axis, y = z × x. Forearm frame `F`: x along the forearm (elbow →
//! grip), the hinge frame `[x_f, z_U × x_f, z_U]` turned by the pronation angle about x_f.

use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

use crate::error::{ImuError, check_range};
use crate::so3;

/// Geometry of the patient's arm and the wheel (m, rad).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ArmGeometry {
    /// Shoulder joint centre in the wheel frame (m).
    pub shoulder_m: [f64; 3],
    /// Shoulder-to-elbow length (m).
    pub upper_arm_m: f64,
    /// Elbow-to-grip length (m).
    pub forearm_m: f64,
    /// Radius of the rim where the hand grips (m).
    pub grip_radius_m: f64,
    /// Rim angle of the grip at wheel angle 0, counter-clockwise as the patient sees it from
    /// the driver's right (rad); 0 = "3 o'clock".
    pub grip_angle_rad: f64,
    /// Tilt of the wheel's top toward the patient from vertical (rad).
    pub wheel_tilt_rad: f64,
}

impl Default for ArmGeometry {
    /// An adult right arm at a desk wheel: shoulder 0.42 m behind, 0.17 m right of and 0.25 m
    /// above the wheel centre; 0.30 m upper arm, 0.33 m forearm to grip; 0.14 m rim.
    fn default() -> Self {
        Self {
            shoulder_m: [-0.42, -0.17, 0.25],
            upper_arm_m: 0.30,
            forearm_m: 0.33,
            grip_radius_m: 0.14,
            grip_angle_rad: 0.0,
            wheel_tilt_rad: 20f64.to_radians(),
        }
    }
}

impl ArmGeometry {
    /// Check every field; the error names the field and its allowed range.
    pub fn validate(&self) -> Result<(), ImuError> {
        for (field, v) in [
            ("shoulder_m[0]", self.shoulder_m[0]),
            ("shoulder_m[1]", self.shoulder_m[1]),
            ("shoulder_m[2]", self.shoulder_m[2]),
        ] {
            check_range(field, v, -2.0, 2.0, "[-2, 2] m")?;
        }
        check_range("upper_arm_m", self.upper_arm_m, 0.1, 0.6, "[0.1, 0.6] m")?;
        check_range("forearm_m", self.forearm_m, 0.1, 0.7, "[0.1, 0.7] m")?;
        check_range(
            "grip_radius_m",
            self.grip_radius_m,
            0.05,
            0.4,
            "[0.05, 0.4] m",
        )?;
        check_range(
            "grip_angle_rad",
            self.grip_angle_rad,
            -std::f64::consts::PI,
            std::f64::consts::PI,
            "[-π, π] rad",
        )?;
        check_range(
            "wheel_tilt_rad",
            self.wheel_tilt_rad,
            -1.2,
            1.2,
            "[-1.2, 1.2] rad",
        )
    }

    /// Shoulder position (m, wheel frame).
    pub fn shoulder(&self) -> Vector3<f64> {
        Vector3::from(self.shoulder_m)
    }

    /// Grip point on the rim at wheel angle `wheel_rad` (m, wheel frame). Positive wheel angle
    /// turns left (counter-clockwise as the patient sees it).
    pub fn grip(&self, wheel_rad: f64) -> Vector3<f64> {
        let right = -Vector3::y();
        let (s, c) = self.wheel_tilt_rad.sin_cos();
        let up = Vector3::new(-s, 0.0, c);
        let phi = self.grip_angle_rad + wheel_rad;
        (right * phi.cos() + up * phi.sin()) * self.grip_radius_m
    }
}

/// The chain's full state at one instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArmState {
    /// Upper-arm-to-world orientation.
    pub upper: Matrix3<f64>,
    /// Forearm-to-world orientation.
    pub fore: Matrix3<f64>,
    /// Elbow position (m).
    pub elbow_m: Vector3<f64>,
    /// Grip (wrist) position (m).
    pub grip_m: Vector3<f64>,
}

/// Smallest elbow flexion the solver accepts (rad): the hinge axis is undefined when straight.
pub const MIN_FLEXION_RAD: f64 = 0.05;

/// Solve the chain for wheel angle `wheel_rad`, elbow swivel `swivel_rad` (0 = elbow straight
/// below the shoulder–grip line, positive = outward/right) and pronation `pronation_rad`.
pub fn solve(
    geo: &ArmGeometry,
    wheel_rad: f64,
    swivel_rad: f64,
    pronation_rad: f64,
) -> Result<ArmState, ImuError> {
    solve_from(
        geo,
        geo.grip(wheel_rad),
        (swivel_rad.sin(), swivel_rad.cos()),
        so3::exp(&Vector3::new(pronation_rad, 0.0, 0.0)),
    )
}

/// [`solve`] with its trigonometry done by the caller: the grip point `grip_m` (m, wheel
/// frame, [`ArmGeometry::grip`]), the swivel's `(sin, cos)` and the forearm's turn about its
/// own axis by the pronation (`twist`, a rotation about x). The simulated arm
/// ([`crate::sim::arm`]) solves the chain three times a tick at angles a step apart and gets
/// these by angle addition; the pose estimator calls [`reach`] once a tick and solves from it.
pub fn solve_from(
    geo: &ArmGeometry,
    grip_m: Vector3<f64>,
    swivel_sin_cos: (f64, f64),
    twist: Matrix3<f64>,
) -> Result<ArmState, ImuError> {
    Ok(reach(geo, grip_m)?.elbow(swivel_sin_cos).state(twist))
}

/// What the chain's solve takes from the grip point alone: the circle the elbow can lie on.
/// [`Reach::elbow`] places the elbow on it at a swivel and [`Elbow::state`] turns the forearm
/// by the pronation; the three steps are [`solve_from`]'s arithmetic, operation for operation,
/// so a caller that solves many swivels and pronations at one wheel angle (the pose
/// estimator's Gauss–Newton fit) gets the same bits as from [`solve`] with a third of the work.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reach {
    shoulder_m: Vector3<f64>,
    grip_m: Vector3<f64>,
    upper_arm_m: f64,
    forearm_m: f64,
    /// The centre of the elbow's circle, m: `shoulder + n·a`.
    centre_m: Vector3<f64>,
    /// The circle's radius, m.
    radius_m: f64,
    /// The circle's unit axes: `e1` the swivel's zero (elbow down), `e2 = e1 × n`.
    e1: Vector3<f64>,
    e2: Vector3<f64>,
}

/// The elbow placed at one swivel: the upper arm's frame and the forearm's hinge frame (before
/// its turn by the pronation), from [`Reach::elbow`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Elbow {
    /// Upper-arm-to-world orientation.
    pub upper: Matrix3<f64>,
    /// The forearm's hinge frame `[x_f, z × x_f, z]` in the world.
    pub hinge: Matrix3<f64>,
    /// Elbow position (m).
    pub elbow_m: Vector3<f64>,
    /// Grip (wrist) position (m).
    pub grip_m: Vector3<f64>,
}

/// The elbow's circle for the grip point `grip_m` (m, wheel frame); an error when the grip is
/// out of the arm's reach (nearer than the lengths' difference, or farther than the arm
/// reaches with [`MIN_FLEXION_RAD`] of flexion).
pub fn reach(geo: &ArmGeometry, grip_m: Vector3<f64>) -> Result<Reach, ImuError> {
    let s = geo.shoulder();
    let w = grip_m;
    let (l1, l2) = (geo.upper_arm_m, geo.forearm_m);
    let d_vec = w - s;
    let d = d_vec.norm();
    // Keep away from a straight elbow: max reach with MIN_FLEXION_RAD of flexion.
    let max = (l1 * l1 + l2 * l2 + 2.0 * l1 * l2 * MIN_FLEXION_RAD.cos()).sqrt();
    let min = (l1 - l2).abs() + 1e-3;
    if !(d < max && d > min) {
        return Err(ImuError::OutOfReach {
            distance_m: d,
            min_m: min,
            max_m: max,
        });
    }
    let n = d_vec / d;
    let a = (l1 * l1 - l2 * l2 + d * d) / (2.0 * d);
    let h = (l1 * l1 - a * a).max(0.0).sqrt();
    let down = -Vector3::z();
    let e1 = (down - n * down.dot(&n))
        .try_normalize(1e-9)
        .unwrap_or_else(|| n.cross(&Vector3::y()).normalize());
    let e2 = e1.cross(&n);
    Ok(Reach {
        shoulder_m: s,
        grip_m: w,
        upper_arm_m: l1,
        forearm_m: l2,
        centre_m: s + n * a,
        radius_m: h,
        e1,
        e2,
    })
}

impl Reach {
    /// The elbow at the swivel whose `(sin, cos)` is given (0 = straight below the
    /// shoulder–grip line, positive = outward).
    pub fn elbow(&self, (swivel_sin, swivel_cos): (f64, f64)) -> Elbow {
        let s = self.shoulder_m;
        let w = self.grip_m;
        let elbow = self.centre_m + (self.e1 * swivel_cos + self.e2 * swivel_sin) * self.radius_m;
        let xu = (elbow - s) / self.upper_arm_m;
        let xf = (w - elbow) / self.forearm_m;
        let z = xu.cross(&xf).normalize();
        Elbow {
            upper: Matrix3::from_columns(&[xu, z.cross(&xu), z]),
            hinge: Matrix3::from_columns(&[xf, z.cross(&xf), z]),
            elbow_m: elbow,
            grip_m: w,
        }
    }
}

impl Elbow {
    /// The chain with the forearm turned about its own axis by `twist` (a rotation about x,
    /// `so3::exp` of the pronation about x).
    pub fn state(&self, twist: Matrix3<f64>) -> ArmState {
        ArmState {
            upper: self.upper,
            fore: self.hinge * twist,
            elbow_m: self.elbow_m,
            grip_m: self.grip_m,
        }
    }
}

/// Joint angles of the arm (rad).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct JointAngles {
    /// Humerus elevation: angle from hanging straight down (rad).
    pub shoulder_elevation_rad: f64,
    /// Plane of elevation: 0 = lateral (abduction), π/2 = forward (flexion) (rad).
    pub shoulder_plane_rad: f64,
    /// Humeral axial rotation relative to the hanging reference, internal positive (rad).
    pub shoulder_rotation_rad: f64,
    /// Elbow flexion: 0 = straight (rad).
    pub elbow_flexion_rad: f64,
    /// Forearm pronation about its long axis relative to the elbow hinge (rad).
    pub forearm_pronation_rad: f64,
}

impl JointAngles {
    /// The angles as an array, in field order.
    pub fn to_array(&self) -> [f64; 5] {
        [
            self.shoulder_elevation_rad,
            self.shoulder_plane_rad,
            self.shoulder_rotation_rad,
            self.elbow_flexion_rad,
            self.forearm_pronation_rad,
        ]
    }

    /// Field names matching [`JointAngles::to_array`].
    pub const NAMES: [&'static str; 5] = [
        "shoulder_elevation_rad",
        "shoulder_plane_rad",
        "shoulder_rotation_rad",
        "elbow_flexion_rad",
        "forearm_pronation_rad",
    ];
}

/// Joint angles from segment orientations in the trunk (= wheel/world) frame.
///
/// Shoulder: swing–twist decomposition of the upper-arm frame against the hanging reference
/// (humerus down, flexion axis pointing right), so elevation is the swing angle, the plane is
/// the swing direction and rotation the twist. Elbow: angle between humerus and forearm, and
/// the forearm's roll about its axis relative to the hinge frame.
pub fn joint_angles(upper: &Matrix3<f64>, fore: &Matrix3<f64>) -> JointAngles {
    let xu: Vector3<f64> = upper.column(0).into();
    let xf: Vector3<f64> = fore.column(0).into();
    let down = -Vector3::z();
    let elevation = down.angle(&xu);
    let plane = xu.x.atan2(-xu.y);
    let swing =
        UnitQuaternion::rotation_between(&down, &xu).unwrap_or_else(UnitQuaternion::identity);
    let reference = Matrix3::from_columns(&[down, Vector3::x(), -Vector3::y()]);
    let twist_m =
        reference.transpose() * swing.to_rotation_matrix().into_inner().transpose() * upper;
    let rotation = twist_m[(2, 1)].atan2(twist_m[(1, 1)]);
    let flexion = xu.angle(&xf);
    let z = upper.column(2).into_owned();
    let hinge_y = z.cross(&xf);
    let fy: Vector3<f64> = fore.column(1).into();
    let pronation = fy.dot(&z).atan2(fy.dot(&hinge_y));
    JointAngles {
        shoulder_elevation_rad: elevation,
        shoulder_plane_rad: plane,
        shoulder_rotation_rad: rotation,
        elbow_flexion_rad: flexion,
        forearm_pronation_rad: pronation,
    }
}

/// Per-session range of motion of each joint angle (rad): running min and max.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RangeOfMotion {
    /// Smallest value seen, per angle in [`JointAngles::NAMES`] order.
    pub min_rad: [f64; 5],
    /// Largest value seen, per angle.
    pub max_rad: [f64; 5],
    /// Samples accumulated.
    pub samples: u64,
}

impl Default for RangeOfMotion {
    fn default() -> Self {
        Self {
            min_rad: [f64::INFINITY; 5],
            max_rad: [f64::NEG_INFINITY; 5],
            samples: 0,
        }
    }
}

impl RangeOfMotion {
    /// Accumulate one pose (non-finite angles are skipped).
    pub fn update(&mut self, a: &JointAngles) {
        let v = a.to_array();
        if v.iter().any(|x| !x.is_finite()) {
            return;
        }
        for ((lo, hi), x) in self.min_rad.iter_mut().zip(self.max_rad.iter_mut()).zip(v) {
            *lo = lo.min(x);
            *hi = hi.max(x);
        }
        self.samples += 1;
    }

    /// The range (max − min, rad) per angle; 0 before any sample.
    pub fn range_rad(&self) -> [f64; 5] {
        let mut r = [0.0; 5];
        if self.samples > 0 {
            for (i, x) in r.iter_mut().enumerate() {
                *x = self.max_rad[i] - self.min_rad[i];
            }
        }
        r
    }
}

/// Rotation matrix to unit quaternion (for callers mixing forms).
pub fn to_quat(m: &Matrix3<f64>) -> UnitQuaternion<f64> {
    UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(*m))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn default_geometry_reaches_the_grip_over_plus_minus_90_deg() {
        let g = ArmGeometry::default();
        g.validate().unwrap();
        for deg in (-90..=90).step_by(10) {
            let st = solve(&g, (deg as f64).to_radians(), 0.3, 0.0).unwrap();
            assert!(((st.elbow_m - g.shoulder()).norm() - g.upper_arm_m).abs() < 1e-12);
            assert!(((st.grip_m - st.elbow_m).norm() - g.forearm_m).abs() < 1e-12);
        }
    }

    #[test]
    fn out_of_reach_is_an_error_not_a_panic() {
        let g = ArmGeometry {
            shoulder_m: [-0.9, -0.2, 0.3],
            ..ArmGeometry::default()
        };
        assert!(matches!(
            solve(&g, 0.0, 0.0, 0.0),
            Err(ImuError::OutOfReach { .. })
        ));
    }

    #[test]
    fn hanging_arm_with_forearm_forward_has_zero_shoulder_angles_and_right_angle_elbow() {
        let upper = Matrix3::from_columns(&[-Vector3::z(), Vector3::x(), -Vector3::y()]);
        let fore = Matrix3::from_columns(&[Vector3::x(), Vector3::z(), -Vector3::y()]);
        let a = joint_angles(&upper, &fore);
        assert!(a.shoulder_elevation_rad.abs() < 1e-12);
        assert!(a.shoulder_rotation_rad.abs() < 1e-12);
        assert!((a.elbow_flexion_rad - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        assert!(a.forearm_pronation_rad.abs() < 1e-12);
    }

    proptest! {
        #[test]
        fn solved_frames_are_rotations_and_pronation_is_recovered(
            wheel in -1.2f64..1.2, swivel in -0.8f64..0.8, pron in -1.0f64..1.0
        ) {
            let st = solve(&ArmGeometry::default(), wheel, swivel, pron).unwrap();
            for m in [st.upper, st.fore] {
                prop_assert!((m.transpose() * m - Matrix3::identity()).norm() < 1e-12);
                prop_assert!((m.determinant() - 1.0).abs() < 1e-12);
            }
            let a = joint_angles(&st.upper, &st.fore);
            prop_assert!((a.forearm_pronation_rad - pron).abs() < 1e-9);
            prop_assert!(a.elbow_flexion_rad > MIN_FLEXION_RAD * 0.99);
        }
    }

    #[test]
    fn range_of_motion_tracks_min_and_max() {
        let mut rom = RangeOfMotion::default();
        assert_eq!(rom.range_rad(), [0.0; 5]);
        for e in [0.2, 0.9, 0.5] {
            rom.update(&JointAngles {
                elbow_flexion_rad: e,
                ..Default::default()
            });
        }
        rom.update(&JointAngles {
            elbow_flexion_rad: f64::NAN,
            ..Default::default()
        });
        assert!((rom.range_rad()[3] - 0.7).abs() < 1e-12);
        assert_eq!(rom.samples, 3);
    }
}
