//! Camera placement and the projection from world metres to screen pixels.
//!
//! Right-handed world (x, y on the ground, z up). Clip space follows wgpu: x, y in [-1, 1]
//! with y up, depth in [0, 1]. Matrices are column-major `[[f32; 4]; 4]` (`m[col][row]`), the
//! layout WGSL's `mat4x4<f32>` reads from a uniform buffer.

use super::scene::{CameraMode, CarPose};

/// A 4×4 column-major matrix.
pub type Mat4 = [[f32; 4]; 4];

/// Chase camera: distance behind the car's centre, m.
pub const CHASE_BACK_M: f32 = 10.0;
/// Chase camera: eye height above the ground, m.
pub const CHASE_HEIGHT_M: f32 = 3.8;
/// Chase camera: the look-at point is this far ahead of the car's centre, m.
pub const CHASE_LOOK_AHEAD_M: f32 = 16.0;
/// Driver camera: eye height above the ground, m.
pub const DRIVER_EYE_HEIGHT_M: f32 = 1.2;
/// Driver camera: the look-at point is this far ahead of the eye, m.
pub const DRIVER_LOOK_AHEAD_M: f32 = 25.0;
/// Near clip plane, m.
pub const NEAR_M: f32 = 0.3;
/// Far clip plane, m.
pub const FAR_M: f32 = 900.0;

/// A perspective camera.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// Eye position in the world, m.
    pub eye: [f32; 3],
    /// Point looked at, m.
    pub target: [f32; 3],
    /// Vertical field of view, rad.
    pub fov_y_rad: f32,
    /// Width / height of the viewport.
    pub aspect: f32,
}

fn sub(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn dot(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn normalize(a: [f32; 3]) -> [f32; 3] {
    let n = dot(a, a).sqrt();
    [a[0] / n, a[1] / n, a[2] / n]
}

/// Product `a · b` of two column-major matrices.
pub fn mat_mul(a: &Mat4, b: &Mat4) -> Mat4 {
    let mut out = [[0.0; 4]; 4];
    for (c, col) in out.iter_mut().enumerate() {
        for (r, v) in col.iter_mut().enumerate() {
            *v = (0..4).map(|k| a[k][r] * b[c][k]).sum();
        }
    }
    out
}

/// Applies `m` to the column vector `v`.
pub fn transform(m: &Mat4, v: [f32; 4]) -> [f32; 4] {
    let mut out = [0.0; 4];
    for (r, o) in out.iter_mut().enumerate() {
        *o = (0..4).map(|k| m[k][r] * v[k]).sum();
    }
    out
}

impl Camera {
    /// The camera for `mode` following `car` (chase: behind and above; driver: at the eye).
    pub fn follow(mode: CameraMode, car: &CarPose, aspect: f32) -> Self {
        let (s, c) = (car.yaw_rad.sin() as f32, car.yaw_rad.cos() as f32);
        let (x, y) = (car.x_m as f32, car.y_m as f32);
        match mode {
            CameraMode::Chase => Camera {
                eye: [x - c * CHASE_BACK_M, y - s * CHASE_BACK_M, CHASE_HEIGHT_M],
                target: [x + c * CHASE_LOOK_AHEAD_M, y + s * CHASE_LOOK_AHEAD_M, 0.5],
                fov_y_rad: 55f32.to_radians(),
                aspect,
            },
            CameraMode::Driver => Camera {
                eye: [x, y, DRIVER_EYE_HEIGHT_M],
                target: [
                    x + c * DRIVER_LOOK_AHEAD_M,
                    y + s * DRIVER_LOOK_AHEAD_M,
                    0.6,
                ],
                fov_y_rad: 60f32.to_radians(),
                aspect,
            },
        }
    }

    /// Unit vectors (forward, right, up) of the camera in the world frame.
    pub fn basis(&self) -> ([f32; 3], [f32; 3], [f32; 3]) {
        let f = normalize(sub(self.target, self.eye));
        let r = normalize(cross(f, [0.0, 0.0, 1.0]));
        let u = cross(r, f);
        (f, r, u)
    }

    /// World → view matrix (right-handed, camera looks down −z).
    pub fn view(&self) -> Mat4 {
        let (f, r, u) = self.basis();
        let e = self.eye;
        [
            [r[0], u[0], -f[0], 0.0],
            [r[1], u[1], -f[1], 0.0],
            [r[2], u[2], -f[2], 0.0],
            [-dot(r, e), -dot(u, e), dot(f, e), 1.0],
        ]
    }

    /// View → clip perspective matrix with depth in [0, 1] (near → 0, far → 1).
    pub fn projection(&self) -> Mat4 {
        let t = 1.0 / (self.fov_y_rad / 2.0).tan();
        let (n, f) = (NEAR_M, FAR_M);
        [
            [t / self.aspect, 0.0, 0.0, 0.0],
            [0.0, t, 0.0, 0.0],
            [0.0, 0.0, f / (n - f), -1.0],
            [0.0, 0.0, n * f / (n - f), 0.0],
        ]
    }

    /// World → clip matrix, `projection · view`.
    pub fn view_projection(&self) -> Mat4 {
        mat_mul(&self.projection(), &self.view())
    }

    /// Pixel position (x right, y down, origin at the top-left corner) of a world point on a
    /// `width`×`height` image, or `None` when the point is behind the near plane.
    pub fn project_to_pixel(&self, world: [f32; 3], width: u32, height: u32) -> Option<[f32; 2]> {
        let clip = transform(&self.view_projection(), [world[0], world[1], world[2], 1.0]);
        if clip[3] <= NEAR_M {
            return None;
        }
        let (nx, ny) = (clip[0] / clip[3], clip[1] / clip[3]);
        Some([
            (nx + 1.0) * 0.5 * width as f32,
            (1.0 - ny) * 0.5 * height as f32,
        ])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn straight_car() -> CarPose {
        CarPose::default()
    }

    #[test]
    fn look_at_target_projects_to_image_centre() {
        for mode in [CameraMode::Chase, CameraMode::Driver] {
            let cam = Camera::follow(mode, &straight_car(), 16.0 / 9.0);
            let p = cam.project_to_pixel(cam.target, 1280, 720).unwrap();
            assert!(
                (p[0] - 640.0).abs() < 1e-3 && (p[1] - 360.0).abs() < 1e-3,
                "{p:?}"
            );
        }
    }

    #[test]
    fn point_behind_camera_does_not_project() {
        let cam = Camera::follow(CameraMode::Driver, &straight_car(), 1.0);
        assert!(cam.project_to_pixel([-10.0, 0.0, 1.0], 100, 100).is_none());
    }

    #[test]
    fn point_to_the_left_of_the_car_projects_left_of_centre() {
        // Yaw 0 means the car faces +x, so +y is to its left.
        let cam = Camera::follow(CameraMode::Chase, &straight_car(), 16.0 / 9.0);
        let p = cam.project_to_pixel([20.0, 2.0, 0.0], 1280, 720).unwrap();
        assert!(p[0] < 640.0, "{p:?}");
    }

    #[test]
    fn ground_point_ahead_matches_pinhole_angle() {
        // Independent check with the pinhole model: the pixel offset from the image centre is
        // focal_px · tan(angle between the ray and the optical axis).
        let cam = Camera::follow(CameraMode::Driver, &straight_car(), 16.0 / 9.0);
        let (h, w) = (720.0f32, 1280.0f32);
        let focal_px = h / 2.0 / (cam.fov_y_rad / 2.0).tan();
        let pitch = ((cam.eye[2] - cam.target[2]) / DRIVER_LOOK_AHEAD_M).atan();
        for d in [5.0f32, 10.0, 40.0, 120.0] {
            let below = (cam.eye[2] / d).atan();
            let expect_y = h / 2.0 + focal_px * (below - pitch).tan();
            let p = cam
                .project_to_pixel([d, 0.0, 0.0], w as u32, h as u32)
                .unwrap();
            assert!(
                (p[1] - expect_y).abs() < 0.05,
                "d={d}: {} vs {expect_y}",
                p[1]
            );
            assert!((p[0] - w / 2.0).abs() < 1e-3);
        }
    }

    #[test]
    fn rotating_car_and_point_together_leaves_projection_unchanged() {
        let a = CarPose {
            x_m: 3.0,
            y_m: -2.0,
            yaw_rad: 0.0,
            steer_rad: 0.0,
        };
        let b = CarPose { yaw_rad: 1.1, ..a };
        let ca = Camera::follow(CameraMode::Chase, &a, 1.5);
        let cb = Camera::follow(CameraMode::Chase, &b, 1.5);
        let local = [15.0f32, 1.5, 0.0];
        let rot = |yaw: f32| {
            [
                3.0 + local[0] * yaw.cos() - local[1] * yaw.sin(),
                -2.0 + local[0] * yaw.sin() + local[1] * yaw.cos(),
                0.0,
            ]
        };
        let pa = ca.project_to_pixel(rot(0.0), 900, 600).unwrap();
        let pb = cb.project_to_pixel(rot(1.1), 900, 600).unwrap();
        assert!((pa[0] - pb[0]).abs() < 0.01 && (pa[1] - pb[1]).abs() < 0.01);
    }

    #[test]
    fn depth_is_zero_at_near_plane_and_one_at_far_plane() {
        let cam = Camera {
            eye: [0.0, 0.0, 0.0],
            target: [1.0, 0.0, 0.0],
            fov_y_rad: 1.0,
            aspect: 1.0,
        };
        let vp = cam.view_projection();
        let near = transform(&vp, [NEAR_M, 0.0, 0.0, 1.0]);
        let far = transform(&vp, [FAR_M, 0.0, 0.0, 1.0]);
        assert!((near[2] / near[3]).abs() < 1e-5);
        assert!((far[2] / far[3] - 1.0).abs() < 1e-5);
    }
}
