//! The patient's arm and the wheel as a Foxglove 3-D scene (`/arm/scene`,
//! `foxglove.SceneUpdate`), so Foxglove's 3-D panel shows the arm move.
//!
//! Posed from what `/arm` records: the grip on the rim, and the forearm's and upper arm's long
//! axes from their IMUs; the segments are drawn at the nominal lengths of
//! [`gyro_imu::arm::ArmGeometry::default`] (the lengths calibrated from the session are on
//! `/arm_calibration` at its end). Frame `wheel`: the wheel frame of `gyro_imu::arm`, metres.

use super::types::ArmSample;
use foxglove::messages::{
    Color, LinePrimitive, Point3, Pose, Quaternion, SceneEntity, SceneUpdate, SpherePrimitive,
    Timestamp, Vector3, line_primitive::Type as LineType,
};
use gyro_imu::arm::ArmGeometry;

/// Scene updates per second of session time.
pub const SCENE_RATE_HZ: u64 = 20;
/// The scene's frame.
pub const FRAME: &str = "wheel";

/// Okabe–Ito blue (the arm) and orange (the wheel): distinguishable with every common colour
/// vision deficiency.
const ARM: Color = Color {
    r: 0.0,
    g: 0.447,
    b: 0.698,
    a: 1.0,
};
const WHEEL: Color = Color {
    r: 0.902,
    g: 0.624,
    b: 0.0,
    a: 1.0,
};

fn point(v: [f64; 3]) -> Point3 {
    Point3 {
        x: v[0],
        y: v[1],
        z: v[2],
    }
}

fn sphere(at: [f64; 3], diameter_m: f64, color: Color) -> SpherePrimitive {
    SpherePrimitive {
        pose: Some(Pose {
            position: Some(Vector3 {
                x: at[0],
                y: at[1],
                z: at[2],
            }),
            orientation: Some(Quaternion {
                x: 0.0,
                y: 0.0,
                z: 0.0,
                w: 1.0,
            }),
        }),
        size: Some(Vector3 {
            x: diameter_m,
            y: diameter_m,
            z: diameter_m,
        }),
        color: Some(color),
    }
}

fn line(kind: LineType, points: Vec<Point3>, thickness_m: f64, color: Color) -> LinePrimitive {
    LinePrimitive {
        r#type: kind as i32,
        pose: Some(Pose {
            position: Some(Vector3 {
                x: 0.0,
                y: 0.0,
                z: 0.0,
            }),
            orientation: Some(Quaternion {
                x: 0.0,
                y: 0.0,
                z: 0.0,
                w: 1.0,
            }),
        }),
        thickness: thickness_m,
        scale_invariant: false,
        points,
        color: Some(color),
        ..Default::default()
    }
}

/// The scene for the arm sample `arm`, stamped `unix_ns` (the message's log time), or `None`
/// before the arm is tracked (its axes are still zero).
pub fn arm_scene(arm: &ArmSample, unix_ns: u64) -> Option<SceneUpdate> {
    let norm = |v: [f64; 3]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    if norm(arm.upper_axis) < 0.5 || norm(arm.fore_axis) < 0.5 {
        return None;
    }
    let geometry = ArmGeometry::default();
    let grip = arm.grip_m;
    let elbow: [f64; 3] = std::array::from_fn(|i| grip[i] - arm.fore_axis[i] * geometry.forearm_m);
    let shoulder: [f64; 3] =
        std::array::from_fn(|i| elbow[i] - arm.upper_axis[i] * geometry.upper_arm_m);
    let rim = (0..48)
        .map(|k| {
            let phi = f64::from(k) / 48.0 * std::f64::consts::TAU;
            let g = ArmGeometry {
                grip_angle_rad: 0.0,
                ..geometry
            }
            .grip(phi);
            Point3 {
                x: g.x,
                y: g.y,
                z: g.z,
            }
        })
        .collect();
    let timestamp = Some(Timestamp::new(
        (unix_ns / 1_000_000_000) as u32,
        (unix_ns % 1_000_000_000) as u32,
    ));
    let entity = |id: &str| SceneEntity {
        timestamp,
        frame_id: FRAME.into(),
        id: id.into(),
        frame_locked: true,
        ..Default::default()
    };
    Some(SceneUpdate {
        deletions: Vec::new(),
        entities: vec![
            SceneEntity {
                lines: vec![
                    line(LineType::LineLoop, rim, 0.02, WHEEL),
                    line(
                        LineType::LineList,
                        vec![point([0.0; 3]), point(grip)],
                        0.015,
                        WHEEL,
                    ),
                ],
                ..entity("wheel")
            },
            SceneEntity {
                lines: vec![line(
                    LineType::LineStrip,
                    vec![point(shoulder), point(elbow), point(grip)],
                    0.05,
                    ARM,
                )],
                spheres: vec![
                    sphere(shoulder, 0.08, ARM),
                    sphere(elbow, 0.07, ARM),
                    sphere(grip, 0.06, ARM),
                ],
                ..entity("arm")
            },
        ],
    })
}
