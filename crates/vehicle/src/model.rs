//! The 3-DOF yaw-plane vehicle model of thesis Appendix C.

use serde::{Deserialize, Serialize};

/// Physical parameters of the virtual car. Defaults are thesis Table C.1.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct VehicleParams {
    /// Front axle cornering stiffness `Cf` (both tyres), N/rad.
    pub cornering_stiffness_front_n_per_rad: f64,
    /// Rear axle cornering stiffness `Cr` (both tyres), N/rad.
    pub cornering_stiffness_rear_n_per_rad: f64,
    /// Distance from the centre of gravity to the front axle `a`, m.
    pub cg_to_front_m: f64,
    /// Distance from the centre of gravity to the rear axle `b`, m.
    pub cg_to_rear_m: f64,
    /// Track width `d`, m.
    pub track_width_m: f64,
    /// Vehicle mass `m`, kg.
    pub mass_kg: f64,
    /// Yaw moment of inertia `Iz`, kg·m².
    pub yaw_inertia_kg_m2: f64,
    /// Below this forward speed the slip-angle terms of eq. C.13–C.14 use this speed instead
    /// of `Ux` (they divide by `Ux`), m/s.
    pub min_slip_speed_m_s: f64,
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
        }
    }
}

/// Driver input `u_d = [δ, Fad, Fbd]` of eq. C.11.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct DriverInput {
    /// Road-wheel steering angle δ, rad (positive to the left).
    pub steer_rad: f64,
    /// Drive force `Fad`, N (≥ 0).
    pub drive_force_n: f64,
    /// Brake force `Fbd`, N (≥ 0).
    pub brake_force_n: f64,
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

/// Tyre forces at one instant, N.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TyreForces {
    /// Front lateral force `Fyf` (eq. C.13), N.
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
    /// A car with `params` starting at `state`.
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

    /// The parameters.
    pub fn params(&self) -> &VehicleParams {
        &self.params
    }

    /// Tyre forces computed in the last step.
    pub fn tyre_forces(&self) -> TyreForces {
        self.tyres
    }

    /// Advance by `dt_s` seconds with a classical fourth-order Runge–Kutta step.
    pub fn step(&mut self, input: DriverInput, dt_s: f64) {
        let s0 = self.state;
        let k1 = derivative(&self.params, &s0, &input);
        let k2 = derivative(&self.params, &add(&s0, &k1.0, dt_s / 2.0), &input);
        let k3 = derivative(&self.params, &add(&s0, &k2.0, dt_s / 2.0), &input);
        let k4 = derivative(&self.params, &add(&s0, &k3.0, dt_s), &input);
        let mut d = [0.0; 6];
        for (i, di) in d.iter_mut().enumerate() {
            *di = (k1.0[i] + 2.0 * k2.0[i] + 2.0 * k3.0[i] + k4.0[i]) / 6.0;
        }
        self.state = add(&s0, &d, dt_s);
        self.tyres = derivative(&self.params, &self.state, &input).1;
    }
}

/// State as a vector `[x, y, θ, Ux, Uy, r]`.
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

/// Time derivative of the state (eq. C.1–C.3, C.12–C.15) and the tyre forces.
fn derivative(p: &VehicleParams, s: &VehicleState, u: &DriverInput) -> ([f64; 6], TyreForces) {
    let (a, b, d) = (p.cg_to_front_m, p.cg_to_rear_m, p.track_width_m);
    let delta = u.steer_rad;
    // eq. C.12: brake split equally over four wheels, drive on the rear axle.
    let fxrf = -u.brake_force_n / 4.0;
    let fxlf = fxrf;
    let fxrr = u.drive_force_n / 2.0 - u.brake_force_n / 4.0;
    let fxlr = fxrr;
    let fxf = fxrf + fxlf; // eq. C.4
    let fxr = fxrr + fxlr; // eq. C.5
    let dfxf = fxrf - fxlf; // eq. C.6
    let dfxr = fxrr - fxlr; // eq. C.7
    // eq. C.13–C.14, with the speed floored so the slip terms stay finite at standstill.
    let ux_slip = s.ux_m_s.abs().max(p.min_slip_speed_m_s);
    let fyf =
        -p.cornering_stiffness_front_n_per_rad * ((s.uy_m_s + s.r_rad_s * a) / ux_slip - delta);
    let fyr = -p.cornering_stiffness_rear_n_per_rad * ((s.uy_m_s - s.r_rad_s * b) / ux_slip);
    let (sd, cd) = delta.sin_cos();
    let m = p.mass_kg;
    let dux = (fxr + fxf * cd - fyf * sd) / m + s.r_rad_s * s.uy_m_s; // eq. C.1
    let duy = (fyr + fxf * sd + fyf * cd) / m - s.r_rad_s * s.ux_m_s; // eq. C.2
    let dr = (a * fxf * sd + a * fyf * cd - b * fyr + dfxr * d / 2.0 + dfxf * cd * d / 2.0)
        / p.yaw_inertia_kg_m2; // eq. C.3
    let (sy, cy) = s.yaw_rad.sin_cos();
    let dx = cy * s.ux_m_s - sy * s.uy_m_s; // eq. C.15
    let dy = sy * s.ux_m_s + cy * s.uy_m_s;
    (
        [dx, dy, s.r_rad_s, dux, duy, dr],
        TyreForces {
            front_lateral_n: fyf,
            rear_lateral_n: fyr,
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn straight_coasting_keeps_speed_and_heading() {
        let mut v = Vehicle::new(
            VehicleParams::default(),
            VehicleState {
                ux_m_s: 15.0,
                ..Default::default()
            },
        );
        for _ in 0..1000 {
            v.step(DriverInput::default(), 0.001);
        }
        let s = v.state();
        assert!((s.ux_m_s - 15.0).abs() < 1e-12);
        assert!((s.x_m - 15.0).abs() < 1e-9);
        assert!(s.y_m.abs() < 1e-12 && s.yaw_rad.abs() < 1e-12);
    }

    #[test]
    fn steady_state_yaw_rate_matches_linear_bicycle_model() {
        // Steady-state yaw-rate gain of the linear bicycle model:
        // r/δ = U / (L + K_us U²), K_us = m (b Cr − a Cf) / (L Cf Cr).
        let p = VehicleParams::default();
        let u = 15.0;
        let delta = 0.01;
        let mut v = Vehicle::new(
            p.clone(),
            VehicleState {
                ux_m_s: u,
                ..Default::default()
            },
        );
        // Hold speed with the drive force that balances the small drag of the lateral force.
        for _ in 0..20_000 {
            v.step(
                DriverInput {
                    steer_rad: delta,
                    ..Default::default()
                },
                0.001,
            );
        }
        let l = p.cg_to_front_m + p.cg_to_rear_m;
        let (cf, cr) = (
            p.cornering_stiffness_front_n_per_rad,
            p.cornering_stiffness_rear_n_per_rad,
        );
        let k_us = p.mass_kg * (p.cg_to_rear_m * cr - p.cg_to_front_m * cf) / (l * cf * cr);
        let s = v.state();
        let expected = s.ux_m_s * delta / (l + k_us * s.ux_m_s * s.ux_m_s);
        assert!(
            (s.r_rad_s - expected).abs() / expected < 0.01,
            "yaw rate {} vs bicycle model {}",
            s.r_rad_s,
            expected
        );
    }
}
