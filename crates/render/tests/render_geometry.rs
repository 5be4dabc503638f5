//! The road drawn matches the exercise geometry: points of the lane (centre guide, edge
//! lines, asphalt, grass beside the road) are projected with the camera math and the rendered
//! frame is checked to show the right surface at those pixels.

mod common;

use render::camera::Camera;
use render::mesh::{DASH_LENGTH_M, DASH_PERIOD_M, EDGE_LINE_INSET_M};
use render::{CameraMode, CarPose, Hud, Renderer, Road, RoadPoint, Scene, ScreenState, demo};

const W: u32 = 1280;
const H: u32 = 720;

fn renderer_or_skip() -> Option<Renderer> {
    common::renderer_or_skip(W, H)
}

type Px = [u8; 3];

/// Yellow of the centre guide, also when anti-aliasing blends it with asphalt (asphalt has
/// red below blue; the gravel shoulder's red exceeds its blue by only 40).
fn is_dash(p: Px) -> bool {
    p[0] > 140 && i32::from(p[0]) >= i32::from(p[2]) + 60
}
fn is_edge_line(p: Px) -> bool {
    p.iter().all(|&c| c > 200)
}
fn is_asphalt(p: Px) -> bool {
    let (r, g, b) = (i32::from(p[0]), i32::from(p[1]), i32::from(p[2]));
    (80..=140).contains(&r) && (r - g).abs() < 15 && (b - r) >= 0 && (b - r) < 25
}
fn is_grass(p: Px) -> bool {
    p[1] > p[0] + 10 && p[1] > p[2] + 25
}

/// True when any pixel within ±1 px of `xy` satisfies `pred`.
fn near(rgba: &[u8], xy: [f32; 2], pred: impl Fn(Px) -> bool) -> bool {
    let (cx, cy) = (xy[0].floor() as i64, xy[1].floor() as i64);
    (-1..=1).any(|dy| {
        (-1..=1).any(|dx| {
            let (x, y) = (cx + dx, cy + dy);
            if x < 0 || y < 0 || x >= i64::from(W) || y >= i64::from(H) {
                return false;
            }
            let i = ((y as usize) * W as usize + x as usize) * 4;
            pred([rgba[i], rgba[i + 1], rgba[i + 2]])
        })
    })
}

/// The 3×3 pixels around `xy`, for failure messages.
fn patch(rgba: &[u8], xy: [f32; 2]) -> Vec<Px> {
    let (cx, cy) = (xy[0].floor() as i64, xy[1].floor() as i64);
    let mut out = Vec::new();
    for y in (cy - 1)..=(cy + 1) {
        for x in (cx - 1)..=(cx + 1) {
            if x >= 0 && y >= 0 && x < i64::from(W) && y < i64::from(H) {
                let i = ((y as usize) * W as usize + x as usize) * 4;
                out.push([rgba[i], rgba[i + 1], rgba[i + 2]]);
            }
        }
    }
    out
}

/// Point at arc length `s` along the centre polyline, with its left normal.
fn at_arc(centre: &[RoadPoint], s: f64) -> ([f64; 2], [f64; 2]) {
    let mut acc = 0.0;
    for w in centre.windows(2) {
        let (a, b) = (w[0], w[1]);
        let len = (b.x_m - a.x_m).hypot(b.y_m - a.y_m);
        if acc + len >= s {
            let t = (s - acc) / len;
            let (dx, dy) = ((b.x_m - a.x_m) / len, (b.y_m - a.y_m) / len);
            return (
                [a.x_m + t * (b.x_m - a.x_m), a.y_m + t * (b.y_m - a.y_m)],
                [-dy, dx],
            );
        }
        acc += len;
    }
    panic!("arc {s} beyond the road");
}

fn arc_of_x(centre: &[RoadPoint], x: f64) -> f64 {
    let mut acc = 0.0;
    for w in centre.windows(2) {
        let (a, b) = (w[0], w[1]);
        let len = (b.x_m - a.x_m).hypot(b.y_m - a.y_m);
        if b.x_m >= x {
            return acc + len * (x - a.x_m) / (b.x_m - a.x_m);
        }
        acc += len;
    }
    acc
}

/// The straight demo road with no HUD and the car 20 m along it, `y_m` left of the centre.
fn straight_with_car_at(y_m: f64) -> Scene {
    let mut scene = demo::straight(0.0);
    scene.hud = Hud::default();
    scene.car = CarPose {
        x_m: 20.0,
        y_m,
        yaw_rad: 0.0,
        steer_rad: 0.0,
    };
    scene
}

fn running(road: Road, car: CarPose, camera: CameraMode) -> Scene {
    Scene {
        road,
        car,
        camera,
        dial: None,
        hud: Hud::default(),
        screen: ScreenState::Running,
        arm: None,
    }
}

/// Checks centre dashes, dash gaps, edge lines, asphalt and grass at projected points between
/// `from` and `to` m of arc ahead of the car. Returns (dashes checked, gaps checked).
fn check_road(r: &mut Renderer, scene: &Scene, from: f64, to: f64) -> (usize, usize) {
    let rgba = r.render_to_rgba(scene).unwrap();
    let cam = Camera::follow(scene.camera, &scene.car, W as f32 / H as f32);
    let centre = &scene.road.centre;
    let half_w = centre[0].lane_width_m / 2.0;
    let s_car = arc_of_x(centre, scene.car.x_m);
    let (mut checked, mut gaps) = (0, 0);
    let mut k = ((s_car + from) / DASH_PERIOD_M).ceil();
    while k * DASH_PERIOD_M < s_car + to {
        let s_dash = k * DASH_PERIOD_M + DASH_LENGTH_M / 2.0;
        let s_gap = k * DASH_PERIOD_M + (DASH_PERIOD_M + DASH_LENGTH_M) / 2.0;
        let (p, n) = at_arc(centre, s_dash);
        let proj = |lat: f64, pp: [f64; 2], nn: [f64; 2]| {
            cam.project_to_pixel(
                [
                    (pp[0] + nn[0] * lat) as f32,
                    (pp[1] + nn[1] * lat) as f32,
                    0.0,
                ],
                W,
                H,
            )
            .unwrap()
        };
        let at = |s: f64| s - s_car;
        let c = proj(0.0, p, n);
        assert!(
            near(&rgba, c, is_dash),
            "no centre dash {:.1} m ahead at {c:?}: {:?}",
            at(s_dash),
            patch(&rgba, c)
        );
        let edge = half_w - EDGE_LINE_INSET_M;
        assert!(
            near(&rgba, proj(edge, p, n), is_edge_line),
            "no left edge line {:.1} m ahead",
            at(s_dash)
        );
        assert!(
            near(&rgba, proj(-edge, p, n), is_edge_line),
            "no right edge line {:.1} m ahead",
            at(s_dash)
        );
        assert!(
            near(&rgba, proj(half_w / 2.0, p, n), is_asphalt),
            "no asphalt {:.1} m ahead",
            at(s_dash)
        );
        assert!(
            near(&rgba, proj(-half_w / 2.0, p, n), is_asphalt),
            "no asphalt {:.1} m ahead",
            at(s_dash)
        );
        assert!(
            near(&rgba, proj(half_w + 3.0, p, n), is_grass),
            "no grass left {:.1} m ahead",
            at(s_dash)
        );
        assert!(
            near(&rgba, proj(-half_w - 3.0, p, n), is_grass),
            "no grass right {:.1} m ahead",
            at(s_dash)
        );
        // Controls: the same checks must fail where the surface is different.
        assert!(
            !near(&rgba, proj(half_w / 2.0, p, n), is_dash),
            "dash colour off the centre line"
        );
        // The gap between dashes, where it is resolved on screen (at least 4 px from both
        // neighbouring dash ends; far away the foreshortened gap shrinks below that).
        let (pg, ng) = at_arc(centre, s_gap);
        let g = proj(0.0, pg, ng);
        let end_a = {
            let (q, m) = at_arc(centre, k * DASH_PERIOD_M + DASH_LENGTH_M);
            proj(0.0, q, m)
        };
        let end_b = {
            let (q, m) = at_arc(centre, (k + 1.0) * DASH_PERIOD_M);
            proj(0.0, q, m)
        };
        let dist = |a: [f32; 2], b: [f32; 2]| (a[0] - b[0]).hypot(a[1] - b[1]);
        if dist(g, end_a) >= 4.0 && dist(g, end_b) >= 4.0 {
            assert!(
                !near(&rgba, g, is_dash),
                "dash drawn in a gap {:.1} m ahead: {:?}",
                at(s_gap),
                patch(&rgba, g)
            );
            assert!(
                near(&rgba, g, is_asphalt),
                "no asphalt in the gap {:.1} m ahead: {:?}",
                at(s_gap),
                patch(&rgba, g)
            );
            gaps += 1;
        }
        checked += 1;
        k += 1.0;
    }
    (checked, gaps)
}

#[test]
fn straight_lane_markings_land_where_the_camera_projects_them() {
    let Some(mut r) = renderer_or_skip() else {
        return;
    };
    let mut scene = straight_with_car_at(0.0);
    for camera in [CameraMode::Chase, CameraMode::Driver] {
        scene.camera = camera;
        let (n, gaps) = check_road(&mut r, &scene, 5.0, 40.0);
        assert!(
            n >= 3 && gaps >= 1,
            "{camera:?}: only {n} dashes and {gaps} gaps checked"
        );
    }
}

#[test]
fn sine_road_markings_follow_the_curve() {
    let Some(mut r) = renderer_or_skip() else {
        return;
    };
    for t in [1.0, 3.7, 6.2] {
        let demo = demo::sine_road(t);
        let scene = running(demo.road, demo.car, CameraMode::Chase);
        let (n, gaps) = check_road(&mut r, &scene, 12.0, 38.0);
        assert!(
            n >= 2 && gaps >= 1,
            "t={t}: only {n} dashes and {gaps} gaps checked"
        );
    }
}

#[test]
fn car_offset_from_centre_moves_the_lane_on_screen() {
    // With the car 1 m left of the centre line the centre guide must appear right of the
    // image centre, where the camera math puts it.
    let Some(mut r) = renderer_or_skip() else {
        return;
    };
    let mut scene = straight_with_car_at(1.0);
    scene.camera = CameraMode::Driver;
    let (n, _) = check_road(&mut r, &scene, 10.0, 40.0);
    assert!(n >= 3);
    let cam = Camera::follow(scene.camera, &scene.car, W as f32 / H as f32);
    let p = cam.project_to_pixel([40.0, 0.0, 0.0], W, H).unwrap();
    assert!(p[0] > W as f32 / 2.0 + 20.0, "{p:?}");
}
