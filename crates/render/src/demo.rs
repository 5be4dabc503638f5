//! Reference scenes for screenshots, golden-image tests and benchmarks: a straight road, a
//! sine road (thesis §3.3.4), a cone slalom between barriers, and the dial task (§3.3.3).
//!
//! These place the car on a scripted path at time `t_s`; they are not a simulation (the
//! station's session drives the real scenes).

use i18n::tr;
use std::f64::consts::TAU;

use super::scene::{
    ArmInset, CameraMode, CarPose, Dial, Hud, LiveScore, Road, RoadPoint, Scene, ScreenState,
};

/// Speed of the scripted car, m/s.
pub const SPEED_M_S: f64 = 12.0;
/// Sine road amplitude, m.
pub const SINE_AMPLITUDE_M: f64 = 4.0;
/// Sine road wavelength, m.
pub const SINE_WAVELENGTH_M: f64 = 90.0;
/// Cone spacing of the slalom, m.
pub const CONE_SPACING_M: f64 = 18.0;
/// Length of the demo roads, m.
pub const ROAD_LENGTH_M: f64 = 1200.0;

fn devices() -> Vec<String> {
    vec![tr!("hud-wheel-simulated"), tr!("hud-arm-simulated")]
}

fn road_hud(name: &str, t_s: f64) -> Hud {
    Hud {
        exercise: name.into(),
        time_left_s: (120.0 - t_s).max(0.0),
        score: LiveScore::Road {
            rms_lateral_m: 0.31,
            in_lane_pct: 96.0,
        },
        speed_m_s: SPEED_M_S,
        assist_level: 0.4,
        devices: devices(),
        notice: None,
    }
}

/// Centre line `y = f(x)` sampled every 2 m from x = −50 m.
fn road_from(f: impl Fn(f64) -> f64, lane_width_m: f64) -> Vec<RoadPoint> {
    (0..((ROAD_LENGTH_M + 50.0) / 2.0) as usize)
        .map(|i| {
            let x = -50.0 + i as f64 * 2.0;
            RoadPoint {
                x_m: x,
                y_m: f(x),
                lane_width_m,
            }
        })
        .collect()
}

/// The car at `x` on the path `y = f(x)` (heading along the path, steering from curvature).
fn car_on(f: impl Fn(f64) -> f64, x: f64) -> CarPose {
    let h = 0.5;
    let (y0, y1, y2) = (f(x - h), f(x), f(x + h));
    let dy = (y2 - y0) / (2.0 * h);
    let ddy = (y2 - 2.0 * y1 + y0) / (h * h);
    let curvature = ddy / (1.0 + dy * dy).powf(1.5);
    let wheelbase_m = 2.7;
    CarPose {
        x_m: x,
        y_m: y1,
        yaw_rad: dy.atan(),
        steer_rad: (wheelbase_m * curvature).atan(),
    }
}

/// A straight 3.6 m lane with the car slightly left of centre.
pub fn straight(t_s: f64) -> Scene {
    let f = |_x: f64| 0.0;
    let mut car = car_on(f, SPEED_M_S * t_s);
    car.y_m = 0.4 * (t_s * 0.7).sin();
    Scene {
        road: Road {
            centre: road_from(f, 3.6),
            ..Road::default()
        },
        car,
        camera: CameraMode::Chase,
        dial: None,
        hud: road_hud(&tr!("exercise-straight-road"), t_s),
        screen: ScreenState::Running,
        arm: None,
    }
}

/// The default adult arm (`gyro_imu::arm::ArmGeometry::default`) holding the wheel at
/// `wheel_rad`, elbow swivelled 0.35 rad out; `measured`: its lengths are the patient's own.
pub fn arm(wheel_rad: f64, measured: bool) -> ArmInset {
    let geo = gyro_imu::arm::ArmGeometry::default();
    let (upper_axis, fore_axis, grip_m) = match gyro_imu::arm::solve(&geo, wheel_rad, 0.35, 0.0) {
        Ok(state) => {
            let x = |m: nalgebra::Matrix3<f64>| [m[(0, 0)], m[(1, 0)], m[(2, 0)]];
            (x(state.upper), x(state.fore), state.grip_m.into())
        }
        // Out of reach (a wheel angle no arm holds): the arm straight ahead.
        Err(_) => ([1.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0; 3]),
    };
    ArmInset {
        grip_m,
        upper_axis,
        fore_axis,
        upper_arm_m: geo.upper_arm_m,
        forearm_m: geo.forearm_m,
        rim_radius_m: geo.grip_radius_m,
        wheel_tilt_rad: geo.wheel_tilt_rad,
        measured,
    }
}

/// `y = A sin(2π x / λ)`, the thesis's sine road, with the car on its centre line and the
/// arm inset (the wheel turned with the road's bends).
pub fn sine_road(t_s: f64) -> Scene {
    let f = |x: f64| SINE_AMPLITUDE_M * (TAU * x / SINE_WAVELENGTH_M).sin();
    let car = car_on(f, SPEED_M_S * t_s);
    Scene {
        arm: Some(arm(car.steer_rad * 10.0, false)),
        road: Road {
            centre: road_from(f, 3.6),
            ..Road::default()
        },
        car,
        camera: CameraMode::Chase,
        dial: None,
        hud: road_hud(&tr!("exercise-sine-road"), t_s),
        screen: ScreenState::Running,
    }
}

/// Cones on the centre line of a wide lane between barriers; the car weaves between them.
pub fn slalom(t_s: f64) -> Scene {
    let cones: Vec<[f64; 2]> = (1..((ROAD_LENGTH_M / CONE_SPACING_M) as usize))
        .map(|k| [k as f64 * CONE_SPACING_M, 0.0])
        .collect();
    let barrier = |y: f64| {
        (0..=24)
            .map(|k| [-50.0 + k as f64 * 50.0, y])
            .collect::<Vec<_>>()
    };
    let weave = |x: f64| 1.6 * (std::f64::consts::PI * x / CONE_SPACING_M).sin();
    Scene {
        road: Road {
            centre: road_from(|_| 0.0, 7.0),
            barriers: vec![barrier(5.5), barrier(-5.5)],
            cones,
        },
        car: car_on(weave, 8.0 + SPEED_M_S * 0.7 * t_s),
        camera: CameraMode::Chase,
        dial: None,
        hud: road_hud(&tr!("exercise-slalom"), t_s),
        screen: ScreenState::Running,
        arm: None,
    }
}

/// The dial task: the red needle follows a 0.2 Hz sine of ±60°, the black one lags it.
pub fn dial(t_s: f64) -> Scene {
    let desired = 60f64.to_radians() * (TAU * 0.2 * t_s).sin();
    let actual = 55f64.to_radians() * (TAU * 0.2 * (t_s - 0.35)).sin();
    Scene {
        dial: Some(Dial {
            desired_rad: desired,
            actual_rad: actual,
        }),
        hud: Hud {
            exercise: tr!("exercise-dial-sine"),
            time_left_s: (90.0 - t_s).max(0.0),
            score: LiveScore::Dial { rms_error_deg: 8.4 },
            speed_m_s: 0.0,
            assist_level: 0.25,
            devices: devices(),
            notice: None,
        },
        screen: ScreenState::Running,
        ..Scene::default()
    }
}

/// The named demo scene at `t_s`: "straight", "sine-road", "slalom" or "dial".
pub fn by_name(name: &str, t_s: f64) -> Option<Scene> {
    Some(match name {
        "straight" => straight(t_s),
        "sine-road" => sine_road(t_s),
        "slalom" => slalom(t_s),
        "dial" => dial(t_s),
        _ => return None,
    })
}

/// Names accepted by [`by_name`].
pub const NAMES: [&str; 4] = ["straight", "sine-road", "slalom", "dial"];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_demo_scene_validates_over_a_minute() {
        for name in NAMES {
            for k in 0..60 {
                let s = by_name(name, k as f64).unwrap();
                s.validate()
                    .unwrap_or_else(|e| panic!("{name} at {k} s: {e}"));
            }
        }
    }

    #[test]
    fn sine_road_car_sits_on_the_centre_line() {
        let s = sine_road(3.3);
        let expect = SINE_AMPLITUDE_M * (TAU * s.car.x_m / SINE_WAVELENGTH_M).sin();
        assert!((s.car.y_m - expect).abs() < 1e-12);
    }

    #[test]
    fn unknown_name_gives_none() {
        assert!(by_name("loop", 0.0).is_none());
    }
}
