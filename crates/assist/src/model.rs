//! The thesis's 1-DOF wheel + human model (eq. 5.5–5.10), its input–output linearisation
//! (eq. 5.12–5.32) and pole placement for the linearised chain (eq. 5.29–5.30).
//!
//! The state of eq. 5.9 is `θ = [θ¹, θ², θ³] = [angle, velocity, torque]`: the actuator
//! torque is itself a state and the control input `u` is its *rate* (an integrator in the
//! input channel, thesis p. 74). On a real wheel that is exactly the quantity the haptic
//! layer's slew limit bounds, which is why the rest of the crate keeps this structure.

use crate::error::{AssistError, check_range};
use common::Bound;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// A plant's inertia `J`, kg·m² (above 0).
pub const PLANT_INERTIA_KG_M2: Bound = Bound::new(0.0, 1e3);
/// A plant's damping `B`, N·m·s/rad.
pub const PLANT_DAMPING_NM_S_PER_RAD: Bound = Bound::new(0.0, 1e4);
/// A plant's stiffness `C`, N·m/rad.
pub const PLANT_STIFFNESS_NM_PER_RAD: Bound = Bound::new(0.0, 1e4);
/// Each closed-loop pole of the motion assist, rad/s (real, stable).
pub const POLE_RAD_S: Bound = Bound::new(-500.0, -0.1);

/// A second-order rotational mass–spring–damper, `J θ̈ + B θ̇ + C θ = τ` (eq. 5.5 / 5.6).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PlantParams {
    /// Inertia `J` about the steering axis, kg·m².
    #[schemars(range(max = PLANT_INERTIA_KG_M2.max), extend("exclusiveMinimum" = PLANT_INERTIA_KG_M2.min))]
    pub inertia_kg_m2: f64,
    /// Viscous damping `B`, N·m·s/rad.
    #[schemars(range(min = PLANT_DAMPING_NM_S_PER_RAD.min, max = PLANT_DAMPING_NM_S_PER_RAD.max))]
    pub damping_nm_s_per_rad: f64,
    /// Rotational stiffness `C`, N·m/rad.
    #[schemars(range(min = PLANT_STIFFNESS_NM_PER_RAD.min, max = PLANT_STIFFNESS_NM_PER_RAD.max))]
    pub stiffness_nm_per_rad: f64,
}

impl PlantParams {
    /// Table 5.1 of the thesis: J = 10, B = 25, C = 15 (the combined plant of eq. 5.7).
    pub const THESIS: Self = Self {
        inertia_kg_m2: 10.0,
        damping_nm_s_per_rad: 25.0,
        stiffness_nm_per_rad: 15.0,
    };

    /// A consumer wheel's rim and motor (matches `haptic-wheel`'s simulated wheel).
    pub const CONSUMER_WHEEL: Self = Self {
        inertia_kg_m2: 0.02,
        damping_nm_s_per_rad: 0.02,
        stiffness_nm_per_rad: 0.0,
    };

    /// A relaxed forearm/upper arm reflected to the wheel axis (order of magnitude from the
    /// issue: 0.05–0.2 kg·m², 0.1–0.5 N·m·s/rad; a little passive tone).
    pub const RELAXED_ARM: Self = Self {
        inertia_kg_m2: 0.1,
        damping_nm_s_per_rad: 0.3,
        stiffness_nm_per_rad: 0.1,
    };

    /// Sum of two plants rigidly coupled at the wheel (eq. 5.7: J = J₁ + J₂, …).
    pub fn coupled_with(&self, other: &Self) -> Self {
        Self {
            inertia_kg_m2: self.inertia_kg_m2 + other.inertia_kg_m2,
            damping_nm_s_per_rad: self.damping_nm_s_per_rad + other.damping_nm_s_per_rad,
            stiffness_nm_per_rad: self.stiffness_nm_per_rad + other.stiffness_nm_per_rad,
        }
    }

    /// Check the ranges: J in (0, 1e3], B and C in [0, 1e4]. `prefix` names the owner.
    pub fn validate(&self, fields: [&'static str; 3]) -> Result<(), AssistError> {
        if !(self.inertia_kg_m2.is_finite() && self.inertia_kg_m2 > PLANT_INERTIA_KG_M2.min) {
            return Err(AssistError::InvalidConfig {
                field: fields[0],
                value: self.inertia_kg_m2,
                allowed: "(0, 1000] kg·m²",
            });
        }
        let (j, b, c) = (
            PLANT_INERTIA_KG_M2,
            PLANT_DAMPING_NM_S_PER_RAD,
            PLANT_STIFFNESS_NM_PER_RAD,
        );
        check_range(
            fields[0],
            self.inertia_kg_m2,
            j.min,
            j.max,
            "(0, 1000] kg·m²",
        )?;
        check_range(
            fields[1],
            self.damping_nm_s_per_rad,
            b.min,
            b.max,
            "[0, 10000] N·m·s/rad",
        )?;
        check_range(
            fields[2],
            self.stiffness_nm_per_rad,
            c.min,
            c.max,
            "[0, 10000] N·m/rad",
        )
    }

    /// Torque that makes the plant follow `(angle, vel, acc)` exactly: `J θ̈ + B θ̇ + C θ`
    /// (inverse dynamics of eq. 5.7), N·m.
    pub fn inverse_dynamics(&self, angle_rad: f64, vel_rad_s: f64, acc_rad_s2: f64) -> f64 {
        self.inertia_kg_m2 * acc_rad_s2
            + self.damping_nm_s_per_rad * vel_rad_s
            + self.stiffness_nm_per_rad * angle_rad
    }

    /// Acceleration under torque `torque_nm`: the second row of eq. 5.10, rad/s².
    pub fn acceleration(&self, angle_rad: f64, vel_rad_s: f64, torque_nm: f64) -> f64 {
        (torque_nm - self.damping_nm_s_per_rad * vel_rad_s - self.stiffness_nm_per_rad * angle_rad)
            / self.inertia_kg_m2
    }

    /// The diffeomorphism `z = T(θ) = [h, L_f h, L_f² h]` of eq. 5.27–5.28 for the position
    /// output (eq. 5.11): angle, velocity and model acceleration.
    pub fn to_linear_coordinates(&self, state: [f64; 3]) -> [f64; 3] {
        [
            state[0],
            state[1],
            self.acceleration(state[0], state[1], state[2]),
        ]
    }

    /// `α(θ)` of eq. 5.23–5.25: `α = −L_f³h / L_g L_f² h = −(BC/J) θ¹ + (C − B²/J) θ² + (B/J) θ³`.
    pub fn linearising_alpha(&self, state: [f64; 3]) -> f64 {
        let (j, b, c) = (
            self.inertia_kg_m2,
            self.damping_nm_s_per_rad,
            self.stiffness_nm_per_rad,
        );
        -(b * c / j) * state[0] + (c - b * b / j) * state[1] + (b / j) * state[2]
    }

    /// `β` of eq. 5.26: the inverse of the decoupling matrix `Φ = L_g L_f² h = 1/J` (eq. 5.21).
    pub fn linearising_beta(&self) -> f64 {
        self.inertia_kg_m2
    }
}

/// Gains `[K₀, K₁, K₂]` of eq. 5.30 placing the poles of the linearised error dynamics
/// `e⃛ + K₂ ë + K₁ ė + K₀ e = 0` at `poles_rad_s` (each real and negative), from the
/// coefficients of `(s − p₁)(s − p₂)(s − p₃)` (Vieta). Table 5.1's K = [6000, 1100, 60] is
/// `[-10, -20, -30]`.
pub fn gains_for_poles(poles_rad_s: [f64; 3]) -> Result<[f64; 3], AssistError> {
    const FIELDS: [&str; 3] = [
        "motion.poles_rad_s[0]",
        "motion.poles_rad_s[1]",
        "motion.poles_rad_s[2]",
    ];
    for (p, field) in poles_rad_s.iter().zip(FIELDS) {
        check_range(
            field,
            *p,
            POLE_RAD_S.min,
            POLE_RAD_S.max,
            "[-500, -0.1] rad/s (real, stable)",
        )?;
    }
    let [p1, p2, p3] = poles_rad_s;
    Ok([-p1 * p2 * p3, p1 * p2 + p1 * p3 + p2 * p3, -(p1 + p2 + p3)])
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn det3(m: [[f64; 3]; 3]) -> f64 {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    }

    #[test]
    fn thesis_poles_give_table_5_1_gains() {
        let k = gains_for_poles([-10.0, -20.0, -30.0]).unwrap();
        assert_eq!(k, [6000.0, 1100.0, 60.0]);
    }

    /// Independent check: build the closed loop of the *original* plant (eq. 5.10) under
    /// u = α + β·v (eq. 5.31) in θ coordinates as a 3×3 matrix and evaluate
    /// det(sI − A_cl) at the requested poles; it must vanish there and not elsewhere.
    #[test]
    fn closed_loop_of_original_plant_has_the_requested_poles() {
        for poles in [
            [-10.0, -20.0, -30.0],
            [-3.0, -7.5, -40.0],
            [-15.0, -15.0, -15.0],
        ] {
            let k = gains_for_poles(poles).unwrap();
            for p in [PlantParams::THESIS, PlantParams::CONSUMER_WHEEL] {
                let (j, b, c) = (
                    p.inertia_kg_m2,
                    p.damping_nm_s_per_rad,
                    p.stiffness_nm_per_rad,
                );
                // u as a row vector in θ (zero reference): α(θ) + J·(−K₂ z³ − K₁ θ² − K₀ θ¹),
                // z³ = (θ³ − Bθ² − Cθ¹)/J.
                let z3 = [-c / j, -b / j, 1.0 / j];
                let alpha = [-(b * c / j), c - b * b / j, b / j];
                let mut urow = [0.0; 3];
                for i in 0..3 {
                    urow[i] = alpha[i] - j * k[2] * z3[i];
                }
                urow[0] -= j * k[0];
                urow[1] -= j * k[1];
                let a = [[0.0, 1.0, 0.0], [-c / j, -b / j, 1.0 / j], urow];
                let char_at = |s: f64| {
                    det3([
                        [s - a[0][0], -a[0][1], -a[0][2]],
                        [-a[1][0], s - a[1][1], -a[1][2]],
                        [-a[2][0], -a[2][1], s - a[2][2]],
                    ])
                };
                for s in poles {
                    assert!(char_at(s).abs() < 1e-6 * k[0].max(1.0), "{poles:?} {s}");
                }
                // Leading behaviour: det(sI − A) = s³ + K₂ s² + K₁ s + K₀ exactly.
                for s in [0.0, 1.0, -2.5, 7.0] {
                    let expect = s * s * s + k[2] * s * s + k[1] * s + k[0];
                    assert_relative_eq!(char_at(s), expect, max_relative = 1e-9, epsilon = 1e-6);
                }
            }
        }
    }

    #[test]
    fn unstable_or_non_finite_poles_are_rejected_with_the_field_named() {
        let err = gains_for_poles([-10.0, 5.0, -30.0]).unwrap_err();
        assert!(err.to_string().contains("poles_rad_s[1]"), "{err}");
        assert!(gains_for_poles([f64::NAN, -1.0, -2.0]).is_err());
    }

    #[test]
    fn alpha_matches_derivative_of_inverse_dynamics() {
        // u = C θ̇ + B θ̈ + J θ⃛ (eq. 5.31 with v = θ⃛): with v = 0, α = C θ² + B z³.
        let p = PlantParams::THESIS;
        let s = [0.3, -1.2, 40.0];
        let z = p.to_linear_coordinates(s);
        assert_relative_eq!(
            p.linearising_alpha(s),
            p.stiffness_nm_per_rad * s[1] + p.damping_nm_s_per_rad * z[2],
            max_relative = 1e-12
        );
    }
}
