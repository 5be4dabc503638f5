//! Steering feel: the self-aligning torque on the hand wheel from the front lateral tyre force
//! (thesis §3.3.4: "force feedback that is proportional to the lateral force on the front
//! wheel").
//!
//! # Scale
//!
//! On a real car the aligning moment is `Fyf · t` about the king pins (pneumatic plus caster
//! trail `t` ≈ 3–5 cm), divided by the steering ratio and helped by power assistance; at the
//! thesis car's limits that is tens of N·m at the rim, far beyond a consumer wheel's ±1.87 N·m.
//! The feel is therefore a gain chosen so the wheel's range maps to normal driving: the default
//! 0.25 N·m at the wheel per kN of `Fyf` gives ≈ 0.95 N·m in a 4 m/s² bend of the Table C.1 car
//! (`Fyf = m·a·b/L` ≈ 3.8 kN), and saturates at `max_torque_nm`. The station's safety clamp
//! still applies on top.

use serde::{Deserialize, Serialize};

use crate::error::{VehicleError, check_range};

/// Self-aligning torque law: `τ = −k · Fyf`, clamped to `±max_torque_nm`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct AligningTorque {
    /// Hand-wheel torque per kN of front lateral force, N·m/kN.
    pub nm_per_kn: f64,
    /// Largest |torque| this law asks for, N·m.
    pub max_torque_nm: f64,
}

impl Default for AligningTorque {
    fn default() -> Self {
        Self {
            nm_per_kn: 0.25,
            max_torque_nm: 1.87,
        }
    }
}

impl AligningTorque {
    /// Check the fields; the message names the field and its range.
    pub fn validate(&self) -> Result<(), VehicleError> {
        check_range(
            "AligningTorque",
            "nm_per_kn",
            self.nm_per_kn,
            0.0,
            5.0,
            "N·m/kN",
        )?;
        check_range(
            "AligningTorque",
            "max_torque_nm",
            self.max_torque_nm,
            0.0,
            20.0,
            "N·m",
        )
    }

    /// Hand-wheel torque for front lateral force `front_lateral_n` (N, positive to the left),
    /// N·m, positive counter-clockwise. A car turning left (Fyf > 0) pulls the wheel back to
    /// the right, towards the centre. A non-finite force gives zero torque.
    pub fn torque_nm(&self, front_lateral_n: f64) -> f64 {
        if !front_lateral_n.is_finite() {
            return 0.0;
        }
        (-self.nm_per_kn * front_lateral_n / 1000.0).clamp(-self.max_torque_nm, self.max_torque_nm)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{DriverInput, Vehicle, VehicleParams, VehicleState};

    #[test]
    fn steering_left_gives_a_centring_torque_of_documented_size() {
        let p = VehicleParams::thesis_linear();
        let mut v = Vehicle::new(
            p.clone(),
            VehicleState {
                ux_m_s: 20.0,
                ..Default::default()
            },
        );
        // δ for a ≈ 4 m/s² steady bend at 20 m/s: r = a/U.
        let r = 4.0 / 20.0;
        let delta = r * (p.wheelbase_m() + p.understeer_gradient_rad_s2_per_m() * 400.0) / 20.0;
        for _ in 0..2000 {
            v.step(
                DriverInput {
                    steer_rad: delta,
                    ..Default::default()
                },
                0.001,
            );
        }
        let fyf = v.tyre_forces().front_lateral_n;
        let tau = AligningTorque::default().torque_nm(fyf);
        assert!(fyf > 0.0 && tau < 0.0);
        assert!((tau + 0.95).abs() < 0.05, "τ = {tau} N·m for Fyf = {fyf} N");
    }

    #[test]
    fn torque_is_clamped_and_nan_safe() {
        let a = AligningTorque::default();
        assert_eq!(a.torque_nm(-1e9), 1.87);
        assert_eq!(a.torque_nm(f64::NAN), 0.0);
        a.validate().unwrap();
        assert!(
            AligningTorque {
                nm_per_kn: -1.0,
                ..a
            }
            .validate()
            .is_err()
        );
    }
}
