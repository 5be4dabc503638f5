//! Haptic models rendered on the wheel.

use serde::{Deserialize, Serialize};

/// Torsional spring–mass–damper of thesis eq. 3.5, `τ_h = I·θ̈ + B·θ̇ + K·θ`.
///
/// Rendered as the torque the motor applies against the patient: `τ = −(K·(θ−θ₀) + B·θ̇ + I·θ̈)`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SpringDamper {
    /// Spring constant `K`, N·m/rad.
    pub k_nm_per_rad: f64,
    /// Damping `B`, N·m·s/rad.
    pub b_nm_s_per_rad: f64,
    /// Virtual inertia `I`, kg·m².
    pub i_kg_m2: f64,
    /// Spring rest angle θ₀, rad.
    pub centre_rad: f64,
}

impl Default for SpringDamper {
    fn default() -> Self {
        Self {
            k_nm_per_rad: 0.5,
            b_nm_s_per_rad: 0.05,
            i_kg_m2: 0.0,
            centre_rad: 0.0,
        }
    }
}

impl SpringDamper {
    /// Motor torque for angle `angle_rad`, velocity `vel_rad_s` and acceleration `acc_rad_s2`, N·m.
    pub fn torque_nm(&self, angle_rad: f64, vel_rad_s: f64, acc_rad_s2: f64) -> f64 {
        -(self.k_nm_per_rad * (angle_rad - self.centre_rad)
            + self.b_nm_s_per_rad * vel_rad_s
            + self.i_kg_m2 * acc_rad_s2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spring_pulls_back_towards_centre_and_damper_opposes_motion() {
        let m = SpringDamper {
            k_nm_per_rad: 2.0,
            b_nm_s_per_rad: 0.5,
            i_kg_m2: 0.0,
            centre_rad: 0.0,
        };
        assert_eq!(m.torque_nm(0.5, 0.0, 0.0), -1.0);
        assert_eq!(m.torque_nm(0.0, -2.0, 0.0), 1.0);
    }
}
