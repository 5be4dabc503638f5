//! The 3-DOF yaw-plane vehicle model of thesis Appendix C.
//!
//! States are the body-frame velocities `Ux`, `Uy`, yaw rate `r` (eq. C.1–C.3) and the global
//! pose `X`, `Y`, `θ` (eq. C.15). Driver input `[δ, Fad, Fbd]` (eq. C.11) is mapped to the four
//! longitudinal wheel forces by eq. C.12 (= eq. 3.13), and the lateral tyre forces are eq.
//! C.13–C.14.
//!
//! # What the paper leaves open, and what this model does
//!
//! * **Low speed.** The slip terms of eq. C.13–C.14 divide by `Ux`. The divisor is
//!   `max(|Ux|, min_slip_speed_m_s)`: above that speed (1 m/s by default) the equations are the
//!   paper's exactly; below it the tyres act as a stiff lateral damper that brings the car to
//!   rest instead of dividing by zero.
//! * **Reversing.** The lateral slip is written as the lateral velocity of the contact patch
//!   in the wheel frame, `(Uy + a·r) − δ·Ux`, over `|Ux|`. For `Ux > 0` this is eq. C.13
//!   unchanged; for `Ux < 0` the tyre force still opposes the sliding, so a reversing car is
//!   stable and steers the right way. A negative `drive_force_n` is a reverse gear.
//! * **Brakes never drive the car backwards.** Each wheel's brake force is
//!   `−Fbd/4 · sat(Ux / brake_blend_speed_m_s)` (eq. C.12 scaled by a unit saturation): it
//!   opposes the motion in either direction and fades to zero at standstill.
//! * **Tyre saturation.** `tyre_model = "linear"` is eq. C.13–C.14 exactly. `"saturating"` is
//!   the Fiala brush tyre with the same cornering stiffness at small slip and a peak of
//!   `μ·Fz` per axle (static axle loads `Fz = m·g·b/L` front, `m·g·a/L` rear).
//! * **Steering ratio.** `δ` is the road-wheel angle; the hand-wheel angle is `δ·steering_ratio`
//!   ([`VehicleParams::road_wheel_angle_rad`]). Inputs are clamped to the actuator limits
//!   (`max_road_wheel_angle_rad`, `max_drive_force_n`, `max_brake_force_n`).
//! * **Stiffness.** At low speed the tyre terms are stiff; [`Vehicle::step`] splits a long `dt`
//!   into enough RK4 sub-steps to stay well inside RK4's stability region, so an offline run at
//!   `dt = 10 ms` is as stable as the 1 kHz loop.
//!
//! Table C.1's longitudinal stiffnesses `Cxf`, `Cxr` are not used: the model has no wheel-spin
//! states, the wheel forces are commanded directly by eq. C.12.

use serde::{Deserialize, Serialize};

use crate::error::{VehicleError, check_range};

/// Standard gravity, m/s².
pub const GRAVITY_M_S2: f64 = 9.81;

/// How the lateral tyre forces depend on slip.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum TyreModel {
    /// The paper's linear tyres, eq. C.13–C.14: `Fy = −C·α`, unbounded.
    Linear,
    /// Fiala brush tyre: slope `C` at small slip, saturating at `μ·Fz`.
    #[default]
    Saturating,
}

/// Physical parameters of the virtual car. Defaults are thesis Table C.1 plus the documented
/// choices of the module docs. TOML keys are the field names.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct VehicleParams {
    /// Front axle cornering stiffness `Cf` (both tyres), N/rad. Table C.1: 145 000.
    pub cornering_stiffness_front_n_per_rad: f64,
    /// Rear axle cornering stiffness `Cr` (both tyres), N/rad. Table C.1: 145 000.
    pub cornering_stiffness_rear_n_per_rad: f64,
    /// Distance from the centre of gravity to the front axle `a`, m. Table C.1: 1.37.
    pub cg_to_front_m: f64,
    /// Distance from the centre of gravity to the rear axle `b`, m. Table C.1: 1.43.
    pub cg_to_rear_m: f64,
    /// Track width `d`, m. Table C.1: 1.5.
    pub track_width_m: f64,
    /// Vehicle mass `m`, kg. Table C.1: 1860.
    pub mass_kg: f64,
    /// Yaw moment of inertia `Iz`, kg·m². Table C.1: 3100.
    pub yaw_inertia_kg_m2: f64,
    /// Below this forward speed the slip-angle terms of eq. C.13–C.14 use this speed instead
    /// of `|Ux|` (they divide by `Ux`), m/s.
    pub min_slip_speed_m_s: f64,
    /// Lateral tyre law: `"linear"` (the paper) or `"saturating"` (Fiala).
    pub tyre_model: TyreModel,
    /// Tyre–road friction coefficient `μ` for the saturating tyre, dimensionless.
    pub friction_coefficient: f64,
    /// Hand-wheel angle per road-wheel angle, dimensionless (±129° of wheel → ±0.225 rad at 10).
    pub steering_ratio: f64,
    /// Largest road-wheel angle `|δ|`, rad.
    pub max_road_wheel_angle_rad: f64,
    /// Largest drive force `|Fad|`, N (a negative drive force is a reverse gear).
    pub max_drive_force_n: f64,
    /// Largest brake force `Fbd`, N.
    pub max_brake_force_n: f64,
    /// Below this |forward speed| the brake force fades linearly to zero, m/s.
    pub brake_blend_speed_m_s: f64,
    /// Body length for collisions, m.
    pub body_length_m: f64,
    /// Body width for collisions, m.
    pub body_width_m: f64,
}

impl Default for VehicleParams {
    fn default() -> Self {
        Self {
            cornering_stiffness_front_n_per_rad: 145_000.0,
            cornering_stiffness_rear_n_per_rad: 145_000.0,
            cg_to_front_m: 1.37,
            cg_to_rear_m: 1.43,
            track_width_m: 1.5,
            mass_kg: 1860.0,
            yaw_inertia_kg_m2: 3100.0,
            min_slip_speed_m_s: 1.0,
            tyre_model: TyreModel::default(),
            friction_coefficient: 0.9,
            steering_ratio: 10.0,
            max_road_wheel_angle_rad: 0.6,
            max_drive_force_n: 8000.0,
            max_brake_force_n: 15_000.0,
            brake_blend_speed_m_s: 0.1,
            body_length_m: 4.6,
            body_width_m: 1.8,
        }
    }
}

impl VehicleParams {
    /// The paper's car exactly: Table C.1 with the linear tyres of eq. C.13–C.14.
    pub fn thesis_linear() -> Self {
        Self {
            tyre_model: TyreModel::Linear,
            ..Self::default()
        }
    }

    /// Check every field; the error names the field and its allowed range.
    pub fn validate(&self) -> Result<(), VehicleError> {
        let c = "VehicleParams";
        check_range(
            c,
            "cornering_stiffness_front_n_per_rad",
            self.cornering_stiffness_front_n_per_rad,
            1e3,
            1e7,
            "N/rad",
        )?;
        check_range(
            c,
            "cornering_stiffness_rear_n_per_rad",
            self.cornering_stiffness_rear_n_per_rad,
            1e3,
            1e7,
            "N/rad",
        )?;
        check_range(c, "cg_to_front_m", self.cg_to_front_m, 0.1, 10.0, "m")?;
        check_range(c, "cg_to_rear_m", self.cg_to_rear_m, 0.1, 10.0, "m")?;
        check_range(c, "track_width_m", self.track_width_m, 0.3, 5.0, "m")?;
        check_range(c, "mass_kg", self.mass_kg, 50.0, 1e5, "kg")?;
        check_range(
            c,
            "yaw_inertia_kg_m2",
            self.yaw_inertia_kg_m2,
            10.0,
            1e6,
            "kg·m²",
        )?;
        check_range(
            c,
            "min_slip_speed_m_s",
            self.min_slip_speed_m_s,
            0.1,
            10.0,
            "m/s",
        )?;
        check_range(
            c,
            "friction_coefficient",
            self.friction_coefficient,
            0.05,
            2.0,
            "",
        )?;
        check_range(c, "steering_ratio", self.steering_ratio, 1.0, 50.0, "")?;
        check_range(
            c,
            "max_road_wheel_angle_rad",
            self.max_road_wheel_angle_rad,
            0.01,
            1.2,
            "rad",
        )?;
        check_range(
            c,
            "max_drive_force_n",
            self.max_drive_force_n,
            0.0,
            1e5,
            "N",
        )?;
        check_range(
            c,
            "max_brake_force_n",
            self.max_brake_force_n,
            0.0,
            1e5,
            "N",
        )?;
        check_range(
            c,
            "brake_blend_speed_m_s",
            self.brake_blend_speed_m_s,
            0.01,
            2.0,
            "m/s",
        )?;
        check_range(c, "body_length_m", self.body_length_m, 0.5, 20.0, "m")?;
        check_range(c, "body_width_m", self.body_width_m, 0.3, 5.0, "m")?;
        Ok(())
    }

    /// Wheelbase `L = a + b`, m.
    pub fn wheelbase_m(&self) -> f64 {
        self.cg_to_front_m + self.cg_to_rear_m
    }

    /// Road-wheel angle δ for a hand-wheel angle, rad (divides by `steering_ratio`).
    pub fn road_wheel_angle_rad(&self, hand_wheel_rad: f64) -> f64 {
        hand_wheel_rad / self.steering_ratio
    }

    /// Hand-wheel angle for a road-wheel angle δ, rad (multiplies by `steering_ratio`).
    pub fn hand_wheel_angle_rad(&self, road_wheel_rad: f64) -> f64 {
        road_wheel_rad * self.steering_ratio
    }

    /// Understeer gradient of the linear bicycle model, `K = m (b Cr − a Cf) / (L Cf Cr)`,
    /// rad/(m/s²). Table C.1 gives 2.75e-4 (slightly understeering).
    pub fn understeer_gradient_rad_s2_per_m(&self) -> f64 {
        let (cf, cr) = (
            self.cornering_stiffness_front_n_per_rad,
            self.cornering_stiffness_rear_n_per_rad,
        );
        self.mass_kg * (self.cg_to_rear_m * cr - self.cg_to_front_m * cf)
            / (self.wheelbase_m() * cf * cr)
    }

    /// Steady-state yaw rate of the linear bicycle model at speed `u_m_s` and road-wheel angle
    /// `steer_rad`: `r = U δ / (L + K U²)`, rad/s.
    pub fn steady_state_yaw_rate_rad_s(&self, u_m_s: f64, steer_rad: f64) -> f64 {
        u_m_s * steer_rad
            / (self.wheelbase_m() + self.understeer_gradient_rad_s2_per_m() * u_m_s * u_m_s)
    }

    /// Static normal loads on the front and rear axle, N.
    pub fn axle_loads_n(&self) -> (f64, f64) {
        let w = self.mass_kg * GRAVITY_M_S2 / self.wheelbase_m();
        (w * self.cg_to_rear_m, w * self.cg_to_front_m)
    }
}

/// Driver input `u_d = [δ, Fad, Fbd]` of eq. C.11.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct DriverInput {
    /// Road-wheel steering angle δ, rad (positive to the left).
    pub steer_rad: f64,
    /// Drive force `Fad`, N (negative: reverse gear).
    pub drive_force_n: f64,
    /// Brake force `Fbd`, N (≥ 0; negative values count as 0).
    pub brake_force_n: f64,
}

impl DriverInput {
    /// `true` when every field is finite.
    pub fn is_finite(&self) -> bool {
        self.steer_rad.is_finite()
            && self.drive_force_n.is_finite()
            && self.brake_force_n.is_finite()
    }

    /// The input clamped to the car's actuator limits.
    pub fn clamped(&self, p: &VehicleParams) -> DriverInput {
        DriverInput {
            steer_rad: self
                .steer_rad
                .clamp(-p.max_road_wheel_angle_rad, p.max_road_wheel_angle_rad),
            drive_force_n: self
                .drive_force_n
                .clamp(-p.max_drive_force_n, p.max_drive_force_n),
            brake_force_n: self.brake_force_n.clamp(0.0, p.max_brake_force_n),
        }
    }
}

/// State of the car: global pose (eq. C.15) and body-frame velocities (eq. C.9).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct VehicleState {
    /// Global x of the centre of gravity, m.
    pub x_m: f64,
    /// Global y of the centre of gravity, m.
    pub y_m: f64,
    /// Heading θ, rad (counter-clockwise from global x).
    pub yaw_rad: f64,
    /// Forward velocity `Ux`, m/s.
    pub ux_m_s: f64,
    /// Lateral velocity `Uy`, m/s.
    pub uy_m_s: f64,
    /// Yaw rate `r`, rad/s.
    pub r_rad_s: f64,
}

impl VehicleState {
    /// `true` when every field is finite.
    pub fn is_finite(&self) -> bool {
        [
            self.x_m,
            self.y_m,
            self.yaw_rad,
            self.ux_m_s,
            self.uy_m_s,
            self.r_rad_s,
        ]
        .iter()
        .all(|v| v.is_finite())
    }

    /// Speed over ground `sqrt(Ux² + Uy²)`, m/s.
    pub fn speed_m_s(&self) -> f64 {
        self.ux_m_s.hypot(self.uy_m_s)
    }
}

/// Tyre forces at one instant, N.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TyreForces {
    /// Front lateral force `Fyf` (eq. C.13), N, in the front-wheel frame.
    pub front_lateral_n: f64,
    /// Rear lateral force `Fyr` (eq. C.14), N.
    pub rear_lateral_n: f64,
}

/// The vehicle: parameters plus state, advanced by [`Vehicle::step`].
#[derive(Clone, Debug)]
pub struct Vehicle {
    params: VehicleParams,
    state: VehicleState,
    tyres: TyreForces,
}

impl Vehicle {
    /// A car with `params` starting at `state`. Use [`VehicleParams::validate`] first on
    /// parameters that come from a file.
    pub fn new(params: VehicleParams, state: VehicleState) -> Self {
        Self {
            params,
            state,
            tyres: TyreForces::default(),
        }
    }

    /// The current state.
    pub fn state(&self) -> &VehicleState {
        &self.state
    }

    /// Replace the state (e.g. to restart an exercise).
    pub fn set_state(&mut self, state: VehicleState) {
        self.state = state;
    }

    /// The parameters.
    pub fn params(&self) -> &VehicleParams {
        &self.params
    }

    /// Tyre forces computed in the last step.
    pub fn tyre_forces(&self) -> TyreForces {
        self.tyres
    }

    /// Advance by `dt_s` seconds (classical RK4, sub-stepped when the tyres are stiff).
    ///
    /// Never panics: a non-finite input field counts as zero (coast, wheels straight) and a
    /// non-positive or non-finite `dt_s` leaves the car where it is. Use
    /// [`Vehicle::try_step`] to be told about such input instead.
    pub fn step(&mut self, input: DriverInput, dt_s: f64) {
        let input = DriverInput {
            steer_rad: finite_or_zero(input.steer_rad),
            drive_force_n: finite_or_zero(input.drive_force_n),
            brake_force_n: finite_or_zero(input.brake_force_n),
        };
        if dt_s.is_finite() && dt_s > 0.0 {
            self.advance(input, dt_s);
        }
    }

    /// Advance by `dt_s` seconds, rejecting non-finite input, a bad time step or a state that
    /// has become non-finite.
    pub fn try_step(&mut self, input: DriverInput, dt_s: f64) -> Result<(), VehicleError> {
        if !input.is_finite() {
            return Err(VehicleError::InvalidInput(format!(
                "driver input must be finite, got {input:?}"
            )));
        }
        if !(dt_s.is_finite() && dt_s > 0.0 && dt_s <= 1.0) {
            return Err(VehicleError::InvalidInput(format!(
                "time step must be in (0, 1] s, got {dt_s}"
            )));
        }
        if !self.state.is_finite() {
            return Err(VehicleError::InvalidInput(format!(
                "vehicle state is not finite: {:?}",
                self.state
            )));
        }
        self.advance(input, dt_s);
        Ok(())
    }

    fn advance(&mut self, input: DriverInput, dt_s: f64) {
        let input = input.clamped(&self.params);
        let n = substeps(&self.params, &self.state, &input, dt_s);
        let h = dt_s / n as f64;
        for _ in 0..n {
            self.state = rk4(&self.params, &self.state, &input, h);
        }
        self.tyres = derivative(&self.params, &self.state, &input).1;
    }
}

fn finite_or_zero(v: f64) -> f64 {
    if v.is_finite() { v } else { 0.0 }
}

/// Number of RK4 sub-steps for `dt_s`: keeps `h·λ ≤ 2` for the fastest mode estimate λ
/// (lateral, yaw and brake-blend damping), inside RK4's real-axis stability limit of 2.78.
fn substeps(p: &VehicleParams, s: &VehicleState, u: &DriverInput, dt_s: f64) -> usize {
    let speed = s.ux_m_s.abs().max(p.min_slip_speed_m_s);
    let (a, b) = (p.cg_to_front_m, p.cg_to_rear_m);
    let (cf, cr) = (
        p.cornering_stiffness_front_n_per_rad,
        p.cornering_stiffness_rear_n_per_rad,
    );
    let lambda = (cf + cr) / (p.mass_kg * speed)
        + (a * a * cf + b * b * cr) / (p.yaw_inertia_kg_m2 * speed)
        + u.brake_force_n / (p.mass_kg * p.brake_blend_speed_m_s);
    ((dt_s * lambda / 2.0).ceil() as usize).clamp(1, 10_000)
}

/// One classical RK4 step of length `h` of the full state (eq. C.1–C.3 and C.15).
pub(crate) fn rk4(p: &VehicleParams, s0: &VehicleState, u: &DriverInput, h: f64) -> VehicleState {
    let k1 = derivative(p, s0, u).0;
    let k2 = derivative(p, &add(s0, &k1, h / 2.0), u).0;
    let k3 = derivative(p, &add(s0, &k2, h / 2.0), u).0;
    let k4 = derivative(p, &add(s0, &k3, h), u).0;
    let mut d = [0.0; 6];
    for (i, di) in d.iter_mut().enumerate() {
        *di = (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]) / 6.0;
    }
    add(s0, &d, h)
}

/// State plus `h` times a derivative `[Ẋ, Ẏ, θ̇, U̇x, U̇y, ṙ]`.
fn add(s: &VehicleState, d: &[f64; 6], h: f64) -> VehicleState {
    VehicleState {
        x_m: s.x_m + h * d[0],
        y_m: s.y_m + h * d[1],
        yaw_rad: s.yaw_rad + h * d[2],
        ux_m_s: s.ux_m_s + h * d[3],
        uy_m_s: s.uy_m_s + h * d[4],
        r_rad_s: s.r_rad_s + h * d[5],
    }
}

/// Lateral force of one axle for the slip `tan α` (small-angle slip of eq. C.13–C.14), N.
fn lateral_force_n(p: &VehicleParams, stiffness: f64, load_n: f64, tan_alpha: f64) -> f64 {
    match p.tyre_model {
        TyreModel::Linear => -stiffness * tan_alpha,
        TyreModel::Saturating => {
            // Fiala brush model (Pacejka, "Tyre and Vehicle Dynamics", §3.2): cubic up to
            // full sliding at tan α_sl = 3 μ Fz / C, then μ Fz.
            let mu_fz = p.friction_coefficient * load_n;
            let t = tan_alpha;
            if t.abs() < 3.0 * mu_fz / stiffness {
                -stiffness * t + stiffness * stiffness / (3.0 * mu_fz) * t.abs() * t
                    - stiffness.powi(3) / (27.0 * mu_fz * mu_fz) * t.powi(3)
            } else {
                -mu_fz * t.signum()
            }
        }
    }
}

/// Body-frame force along x, along y and yaw moment, and the tyre forces, for the velocity
/// part of `s` (eq. C.1–C.3 right-hand sides times `m`, `m`, `Iz`, without the `m r U` terms).
pub(crate) fn body_forces(
    p: &VehicleParams,
    s: &VehicleState,
    u: &DriverInput,
) -> ([f64; 3], TyreForces) {
    let (a, b, d) = (p.cg_to_front_m, p.cg_to_rear_m, p.track_width_m);
    let delta = u.steer_rad;
    // eq. C.12 (= 3.13): brake split equally over the four wheels, drive on the rear axle; the
    // brake opposes the motion and fades out below `brake_blend_speed_m_s`.
    let brake_dir = (s.ux_m_s / p.brake_blend_speed_m_s).clamp(-1.0, 1.0);
    let brake_wheel = -u.brake_force_n / 4.0 * brake_dir;
    let fxrf = brake_wheel;
    let fxlf = brake_wheel;
    let fxrr = u.drive_force_n / 2.0 + brake_wheel;
    let fxlr = fxrr;
    let fxf = fxrf + fxlf; // eq. C.4
    let fxr = fxrr + fxlr; // eq. C.5
    let dfxf = fxrf - fxlf; // eq. C.6
    let dfxr = fxrr - fxlr; // eq. C.7
    // eq. C.13–C.14 with the divisor floored and signed for reversing (module docs).
    let ux_slip = s.ux_m_s.abs().max(p.min_slip_speed_m_s);
    let (fzf, fzr) = p.axle_loads_n();
    let tan_af = ((s.uy_m_s + s.r_rad_s * a) - delta * s.ux_m_s) / ux_slip;
    let tan_ar = (s.uy_m_s - s.r_rad_s * b) / ux_slip;
    let fyf = lateral_force_n(p, p.cornering_stiffness_front_n_per_rad, fzf, tan_af);
    let fyr = lateral_force_n(p, p.cornering_stiffness_rear_n_per_rad, fzr, tan_ar);
    let (sd, cd) = delta.sin_cos();
    let fx = fxr + fxf * cd - fyf * sd; // eq. C.1 forces
    let fy = fyr + fxf * sd + fyf * cd; // eq. C.2 forces
    let mz = a * fxf * sd + a * fyf * cd - b * fyr + dfxr * d / 2.0 + dfxf * cd * d / 2.0; // eq. C.3
    (
        [fx, fy, mz],
        TyreForces {
            front_lateral_n: fyf,
            rear_lateral_n: fyr,
        },
    )
}

/// Time derivative of the state (eq. C.1–C.3, C.12–C.15) and the tyre forces.
pub(crate) fn derivative(
    p: &VehicleParams,
    s: &VehicleState,
    u: &DriverInput,
) -> ([f64; 6], TyreForces) {
    let ([fx, fy, mz], tyres) = body_forces(p, s, u);
    let m = p.mass_kg;
    let dux = fx / m + s.r_rad_s * s.uy_m_s; // eq. C.1
    let duy = fy / m - s.r_rad_s * s.ux_m_s; // eq. C.2
    let dr = mz / p.yaw_inertia_kg_m2; // eq. C.3
    let (sy, cy) = s.yaw_rad.sin_cos();
    let dx = cy * s.ux_m_s - sy * s.uy_m_s; // eq. C.15
    let dy = sy * s.ux_m_s + cy * s.uy_m_s;
    ([dx, dy, s.r_rad_s, dux, duy, dr], tyres)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn moving(ux: f64) -> VehicleState {
        VehicleState {
            ux_m_s: ux,
            ..Default::default()
        }
    }

    fn run(v: &mut Vehicle, input: DriverInput, seconds: f64, dt: f64) {
        for _ in 0..(seconds / dt).round() as usize {
            v.step(input, dt);
        }
    }

    #[test]
    fn defaults_are_table_c1_and_valid() {
        let p = VehicleParams::default();
        assert_eq!(p.cornering_stiffness_front_n_per_rad, 145_000.0);
        assert_eq!(p.cornering_stiffness_rear_n_per_rad, 145_000.0);
        assert!((p.wheelbase_m() - 2.8).abs() < 1e-12);
        assert_eq!(
            (p.track_width_m, p.mass_kg, p.yaw_inertia_kg_m2),
            (1.5, 1860.0, 3100.0)
        );
        p.validate().unwrap();
        VehicleParams::thesis_linear().validate().unwrap();
    }

    #[test]
    fn validate_names_field_and_range() {
        let p = VehicleParams {
            mass_kg: f64::NAN,
            ..Default::default()
        };
        let msg = p.validate().unwrap_err().to_string();
        assert!(
            msg.contains("mass_kg") && msg.contains("50") && msg.contains("kg"),
            "{msg}"
        );
    }

    #[test]
    fn params_toml_uses_field_names_and_rejects_unknown_keys() {
        let p: VehicleParams =
            toml::from_str("tyre_model = \"linear\"\nmass_kg = 1500.0\n").unwrap();
        assert_eq!(p.tyre_model, TyreModel::Linear);
        assert_eq!(p.mass_kg, 1500.0);
        assert_eq!(p.yaw_inertia_kg_m2, 3100.0);
        assert!(toml::from_str::<VehicleParams>("mass = 1.0").is_err());
        assert!(toml::from_str::<VehicleParams>("tyre_model = \"magic\"").is_err());
    }

    #[test]
    fn straight_coasting_keeps_speed_and_heading() {
        let mut v = Vehicle::new(VehicleParams::default(), moving(15.0));
        run(&mut v, DriverInput::default(), 1.0, 0.001);
        let s = v.state();
        assert!((s.ux_m_s - 15.0).abs() < 1e-12);
        assert!((s.x_m - 15.0).abs() < 1e-9);
        assert!(s.y_m.abs() < 1e-12 && s.yaw_rad.abs() < 1e-12);
    }

    #[test]
    fn understeer_gradient_of_table_c1() {
        // K = m (b Cr − a Cf)/(L Cf Cr) = 1860·0.06·145000/(2.8·145000²) = 2.749e-4 rad/(m/s²).
        let k = VehicleParams::default().understeer_gradient_rad_s2_per_m();
        assert!((k - 1860.0 * 0.06 / (2.8 * 145_000.0)).abs() < 1e-15);
        assert!((k - 2.7488e-4).abs() < 1e-7, "{k}");
    }

    #[test]
    fn steady_state_yaw_rate_matches_linear_bicycle_model() {
        for &(u, delta) in &[(10.0, 0.01), (15.0, 0.01), (25.0, 0.005)] {
            let p = VehicleParams::thesis_linear();
            let mut v = Vehicle::new(p.clone(), moving(u));
            let input = DriverInput {
                steer_rad: delta,
                ..Default::default()
            };
            run(&mut v, input, 10.0, 0.001);
            let s = *v.state();
            // Speed bleeds off slowly through the steered front tyre's drag; compare at the
            // current speed.
            let expected = p.steady_state_yaw_rate_rad_s(s.ux_m_s, delta);
            assert!(
                (s.r_rad_s - expected).abs() / expected < 2e-3,
                "U={u}: yaw rate {} vs bicycle model {expected}",
                s.r_rad_s
            );
        }
    }

    #[test]
    fn saturating_tyre_matches_linear_at_small_slip_and_caps_at_mu_fz() {
        let lin = VehicleParams::thesis_linear();
        let sat = VehicleParams::default();
        let (fzf, _) = sat.axle_loads_n();
        let c = sat.cornering_stiffness_front_n_per_rad;
        let small = 1e-4;
        let fl = lateral_force_n(&lin, c, fzf, small);
        let fs = lateral_force_n(&sat, c, fzf, small);
        assert!((fl - fs).abs() / fl.abs() < 1e-3);
        for &t in &[0.2, 0.5, 1.0, 10.0] {
            let f = lateral_force_n(&sat, c, fzf, t);
            assert!(f.abs() <= sat.friction_coefficient * fzf + 1e-9);
            assert!(f < 0.0);
        }
    }

    #[test]
    fn straight_line_braking_decelerates_at_fbd_over_m_and_stops_without_reversing() {
        let p = VehicleParams::default();
        let mut v = Vehicle::new(p.clone(), moving(20.0));
        let brake = DriverInput {
            brake_force_n: 9300.0,
            ..Default::default()
        };
        run(&mut v, brake, 1.0, 0.001);
        // a = Fbd / m = 5 m/s² exactly while |Ux| > blend speed.
        assert!((v.state().ux_m_s - 15.0).abs() < 1e-9, "{:?}", v.state());
        assert!((v.state().x_m - (20.0 - 2.5)).abs() < 1e-9);
        run(&mut v, brake, 5.0, 0.001);
        let s = v.state();
        assert!(s.ux_m_s >= 0.0 && s.ux_m_s < 1e-3, "{s:?}");
        // Stopping distance v²/(2a) = 40 m, plus a few cm of the blend zone.
        assert!((s.x_m - 40.0).abs() < 0.05, "{s:?}");
    }

    #[test]
    fn reverse_gear_backs_up_and_steers_stably() {
        let mut v = Vehicle::new(VehicleParams::default(), VehicleState::default());
        let input = DriverInput {
            steer_rad: 0.1,
            drive_force_n: -2000.0,
            brake_force_n: 0.0,
        };
        run(&mut v, input, 5.0, 0.001);
        let s = *v.state();
        assert!(s.ux_m_s < -4.0, "{s:?}");
        // Reversing with the wheel to the left turns the nose right (negative yaw rate).
        assert!(s.r_rad_s < 0.0 && s.r_rad_s > -1.0, "{s:?}");
        assert!(s.uy_m_s.abs() < 1.0);
    }

    #[test]
    fn large_step_is_substepped_and_stays_stable_at_standstill() {
        let mut v = Vehicle::new(VehicleParams::default(), moving(0.5));
        v.set_state(VehicleState {
            uy_m_s: 0.3,
            r_rad_s: 0.2,
            ..*v.state()
        });
        run(&mut v, DriverInput::default(), 2.0, 0.05);
        let s = v.state();
        assert!(
            s.is_finite() && s.uy_m_s.abs() < 1e-3 && s.r_rad_s.abs() < 1e-3,
            "{s:?}"
        );
    }

    #[test]
    fn try_step_rejects_nan_and_bad_dt_while_step_coasts() {
        let mut v = Vehicle::new(VehicleParams::default(), moving(10.0));
        let bad = DriverInput {
            steer_rad: f64::NAN,
            ..Default::default()
        };
        assert!(
            v.try_step(bad, 0.001)
                .unwrap_err()
                .to_string()
                .contains("finite")
        );
        assert!(v.try_step(DriverInput::default(), -1.0).is_err());
        v.step(bad, 0.001);
        assert!(v.state().is_finite() && v.state().r_rad_s == 0.0);
    }

    #[test]
    fn inputs_are_clamped_to_actuator_limits() {
        let p = VehicleParams::default();
        let c = DriverInput {
            steer_rad: 3.0,
            drive_force_n: 1e9,
            brake_force_n: -5.0,
        }
        .clamped(&p);
        assert_eq!(c.steer_rad, p.max_road_wheel_angle_rad);
        assert_eq!(c.drive_force_n, p.max_drive_force_n);
        assert_eq!(c.brake_force_n, 0.0);
        assert!((p.road_wheel_angle_rad(129f64.to_radians()) - 0.225).abs() < 1e-3);
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 64, rng_seed: proptest::test_runner::RngSeed::Fixed(7), ..ProptestConfig::default() })]

        /// Without drive force, tyres and brakes only dissipate: kinetic energy
        /// ½ m (Ux² + Uy²) + ½ Iz r² never grows. (The small-angle slip of eq. C.13 can inject
        /// O(δ³) power when the slip lies between δ and tan δ; the per-step tolerance covers that
        /// at |δ| ≤ 0.1 rad.)
        #[test]
        fn kinetic_energy_never_grows_without_drive(
            ux in 2.0f64..30.0, uy in -1.0f64..1.0, r in -0.5f64..0.5,
            steer in -0.1f64..0.1, brake in 0.0f64..5000.0,
            saturating in proptest::bool::ANY,
        ) {
            let p = VehicleParams {
                tyre_model: if saturating { TyreModel::Saturating } else { TyreModel::Linear },
                ..Default::default()
            };
            let energy = |s: &VehicleState| 0.5 * p.mass_kg * (s.ux_m_s.powi(2) + s.uy_m_s.powi(2))
                + 0.5 * p.yaw_inertia_kg_m2 * s.r_rad_s.powi(2);
            let mut v = Vehicle::new(p.clone(), VehicleState { ux_m_s: ux, uy_m_s: uy, r_rad_s: r, ..Default::default() });
            let input = DriverInput { steer_rad: steer, drive_force_n: 0.0, brake_force_n: brake };
            let mut e = energy(v.state());
            for _ in 0..500 {
                v.step(input, 0.002);
                let e2 = energy(v.state());
                prop_assert!(e2 <= e * (1.0 + 1e-8) + 1e-9, "energy grew {e} -> {e2}");
                e = e2;
            }
        }

        /// Mirror symmetry: steering right is the mirror image of steering left.
        #[test]
        fn mirrored_input_gives_mirrored_motion(ux in 3.0f64..30.0, steer in 0.0f64..0.3) {
            let p = VehicleParams::default();
            let mut l = Vehicle::new(p.clone(), VehicleState { ux_m_s: ux, ..Default::default() });
            let mut r = l.clone();
            for _ in 0..300 {
                l.step(DriverInput { steer_rad: steer, ..Default::default() }, 0.005);
                r.step(DriverInput { steer_rad: -steer, ..Default::default() }, 0.005);
            }
            let (a, b) = (l.state(), r.state());
            prop_assert!((a.x_m - b.x_m).abs() < 1e-9 && (a.y_m + b.y_m).abs() < 1e-9);
            prop_assert!((a.yaw_rad + b.yaw_rad).abs() < 1e-12 && (a.r_rad_s + b.r_rad_s).abs() < 1e-12);
        }
    }
}
