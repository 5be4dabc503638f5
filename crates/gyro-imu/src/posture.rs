//! The trunk's angles from its start posture: the Cardan split `R_z(rotation) · R_y(flexion) ·
//! R_x(lean)` of the rotation from the start posture, in the start posture's trunk axes (x
//! forward, y to the left, z up) — the thorax angles of the ISB recommendation (Wu et al.,
//! *J Biomech* 38, 2005, §3.3), here in the yaw–pitch–roll order. Signs: flexion > 0 bends
//! forward, lean > 0 leans to the right, rotation > 0 turns to the left. Pure math, shared by
//! the estimate ([`crate::trunk`]) and the simulated truth ([`crate::sim::trunk`]).

use nalgebra::UnitQuaternion;
use serde::{Deserialize, Serialize};

/// Trunk angles from the start posture (deg); see the module docs for axes and signs.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct TrunkAngles {
    /// Forward flexion (deg, > 0 forward).
    pub flexion_deg: f64,
    /// Lateral lean (deg, > 0 to the right).
    pub lean_deg: f64,
    /// Axial rotation (deg, > 0 to the left).
    pub rotation_deg: f64,
}

impl TrunkAngles {
    /// The angles as `[flexion, lean, rotation]` (deg): the order of [`AXES`].
    pub fn to_array(&self) -> [f64; 3] {
        [self.flexion_deg, self.lean_deg, self.rotation_deg]
    }

    /// The largest excursion on any axis (deg).
    pub fn max_abs_deg(&self) -> f64 {
        self.to_array().iter().fold(0.0, |m, a| m.max(a.abs()))
    }
}

/// The axes' names in the order of [`TrunkAngles::to_array`], as in the measures' keys.
pub const AXES: [&str; 3] = ["flexion", "lean", "rotation"];

/// The rotation (trunk frame now to trunk frame at the start) of `a`:
/// `R_z(rotation) · R_y(flexion) · R_x(lean)`.
pub fn trunk_rotation(a: &TrunkAngles) -> UnitQuaternion<f64> {
    UnitQuaternion::from_euler_angles(
        a.lean_deg.to_radians(),
        a.flexion_deg.to_radians(),
        a.rotation_deg.to_radians(),
    )
}

/// The trunk angles of the trunk orientation `now` from the start posture `start` (both
/// trunk-to-world): the Cardan split of `start⁻¹ · now` (inverse of [`trunk_rotation`]).
pub fn trunk_angles(start: &UnitQuaternion<f64>, now: &UnitQuaternion<f64>) -> TrunkAngles {
    let (lean, flexion, rotation) = (start.inverse() * now).euler_angles();
    TrunkAngles {
        flexion_deg: flexion.to_degrees(),
        lean_deg: lean.to_degrees(),
        rotation_deg: rotation.to_degrees(),
    }
}
