//! CPU-side triangle geometry of the 3D world: ground, road, markings, cones, barriers, car.
//!
//! Everything is rebuilt each frame from the [`Scene`], limited to what lies within
//! [`VIEW_RADIUS_M`] of the car, so a long exercise costs no more per frame than a short one.
//! Faces are flat-shaded here (a fixed sun), which keeps the shader small and the look calm.

use bytemuck::{Pod, Zeroable};

use super::palette;
use super::scene::{CameraMode, CarPose, Scene};

/// Geometry farther than this from the car is not generated, m (fog hides the cut).
pub const VIEW_RADIUS_M: f64 = 420.0;
/// Edge lines: inset from the lane edge to the line's centre, m.
pub const EDGE_LINE_INSET_M: f64 = 0.2;
/// Width of the painted edge lines, m.
pub const EDGE_LINE_WIDTH_M: f64 = 0.2;
/// Width of the dashed centre guide, m.
pub const CENTRE_DASH_WIDTH_M: f64 = 0.2;
/// Length of a centre dash, m.
pub const DASH_LENGTH_M: f64 = 3.0;
/// Dash period (dash plus gap), m.
pub const DASH_PERIOD_M: f64 = 9.0;
/// Gravel shoulder beyond each lane edge, m.
pub const SHOULDER_M: f64 = 0.8;
/// Half-size of the ground square around the car, m.
pub const GROUND_HALF_M: f32 = 1200.0;

/// Heights of the flat layers above the ground, m: stacked so depth testing orders them.
const Z_ROAD: f32 = 0.0;
const Z_SHOULDER: f32 = -0.01;
const Z_MARK: f32 = 0.012;
const Z_SHADOW: f32 = 0.02;
const Z_GROUND: f32 = -0.05;

/// Vertex of the world shader (`shaders/world.wgsl`).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct Vertex {
    /// World position, m.
    pub pos: [f32; 3],
    /// 0 = flat colour, 1 = ground checker computed in the shader.
    pub pattern: f32,
    /// Linear-blend RGBA colour in display (sRGB-encoded) space, 0–1.
    pub color: [f32; 4],
}

/// Direction towards the sun used for flat shading (unit length).
const SUN: [f32; 3] = [-0.408, 0.408, 0.816];

fn shade(color: [f32; 4], normal: [f32; 3]) -> [f32; 4] {
    let n = normal;
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt().max(1e-6);
    let lambert = ((n[0] * SUN[0] + n[1] * SUN[1] + n[2] * SUN[2]) / len).max(0.0);
    let k = 0.62 + 0.38 * lambert;
    [color[0] * k, color[1] * k, color[2] * k, color[3]]
}

/// Triangle list under construction.
#[derive(Debug, Default)]
pub struct MeshBuilder {
    /// Vertices, three per triangle.
    pub vertices: Vec<Vertex>,
}

impl MeshBuilder {
    fn tri(&mut self, a: [f32; 3], b: [f32; 3], c: [f32; 3], color: [f32; 4], pattern: f32) {
        for pos in [a, b, c] {
            self.vertices.push(Vertex {
                pos,
                pattern,
                color,
            });
        }
    }

    /// Quad a-b-c-d (any winding; culling is off).
    fn quad(&mut self, q: [[f32; 3]; 4], color: [f32; 4], pattern: f32) {
        self.tri(q[0], q[1], q[2], color, pattern);
        self.tri(q[0], q[2], q[3], color, pattern);
    }

    /// A shaded quad whose normal is computed from its corners.
    fn lit_quad(&mut self, q: [[f32; 3]; 4], color: [f32; 4]) {
        let e1 = [q[1][0] - q[0][0], q[1][1] - q[0][1], q[1][2] - q[0][2]];
        let e2 = [q[3][0] - q[0][0], q[3][1] - q[0][1], q[3][2] - q[0][2]];
        let mut n = [
            e1[1] * e2[2] - e1[2] * e2[1],
            e1[2] * e2[0] - e1[0] * e2[2],
            e1[0] * e2[1] - e1[1] * e2[0],
        ];
        // Faces are seen from outside or above; make the normal point up or towards the sun's
        // half-space consistently by flipping downward-facing tops.
        if n[2] < -1e-6 {
            n = [-n[0], -n[1], -n[2]];
        }
        self.quad(q, shade(color, n), 0.0);
    }
}

/// Left-hand unit normals of a polyline (averaged at interior points).
fn polyline_normals(pts: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let n = pts.len();
    let seg_dir = |i: usize| {
        let (a, b) = (pts[i], pts[i + 1]);
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let len = dx.hypot(dy);
        if len > 1e-9 {
            [dx / len, dy / len]
        } else {
            [1.0, 0.0]
        }
    };
    (0..n)
        .map(|i| {
            let d = if i == 0 {
                seg_dir(0)
            } else if i == n - 1 {
                seg_dir(n - 2)
            } else {
                let (a, b) = (seg_dir(i - 1), seg_dir(i));
                let s = [a[0] + b[0], a[1] + b[1]];
                let len = s[0].hypot(s[1]);
                if len > 1e-9 {
                    [s[0] / len, s[1] / len]
                } else {
                    b
                }
            };
            [-d[1], d[0]]
        })
        .collect()
}

/// A ground point `p + n·offset` as an f32 world position at height `z`.
fn offset(p: [f64; 2], n: [f64; 2], off: f64, z: f32) -> [f32; 3] {
    [(p[0] + n[0] * off) as f32, (p[1] + n[1] * off) as f32, z]
}

/// The road's centre line split into visible runs of consecutive points near the car.
struct RoadView {
    pts: Vec<[f64; 2]>,
    normals: Vec<[f64; 2]>,
    half_w: Vec<f64>,
    /// Arc length from the first centre point, m.
    arc: Vec<f64>,
    /// Segment `i` (points i, i+1) is near the car.
    near: Vec<bool>,
}

impl RoadView {
    fn new(scene: &Scene) -> Self {
        let c = &scene.road.centre;
        let pts: Vec<[f64; 2]> = c.iter().map(|p| [p.x_m, p.y_m]).collect();
        let normals = polyline_normals(&pts);
        let half_w = c.iter().map(|p| p.lane_width_m / 2.0).collect();
        let mut arc = Vec::with_capacity(pts.len());
        let mut s = 0.0;
        for i in 0..pts.len() {
            if i > 0 {
                s += (pts[i][0] - pts[i - 1][0]).hypot(pts[i][1] - pts[i - 1][1]);
            }
            arc.push(s);
        }
        let car = [scene.car.x_m, scene.car.y_m];
        let close = |p: [f64; 2]| (p[0] - car[0]).hypot(p[1] - car[1]) < VIEW_RADIUS_M;
        let near = (0..pts.len().saturating_sub(1))
            .map(|i| close(pts[i]) || close(pts[i + 1]))
            .collect();
        RoadView {
            pts,
            normals,
            half_w,
            arc,
            near,
        }
    }

    /// A band between lateral offsets `inner(h)` and `outer(h)` along every near segment,
    /// where `h` is the lane's half width at each point.
    fn band(
        &self,
        mesh: &mut MeshBuilder,
        inner: impl Fn(f64) -> f64,
        outer: impl Fn(f64) -> f64,
        z: f32,
        color: [f32; 4],
    ) {
        for i in 0..self.near.len() {
            if !self.near[i] {
                continue;
            }
            let j = i + 1;
            mesh.quad(
                [
                    offset(self.pts[i], self.normals[i], inner(self.half_w[i]), z),
                    offset(self.pts[j], self.normals[j], inner(self.half_w[j]), z),
                    offset(self.pts[j], self.normals[j], outer(self.half_w[j]), z),
                    offset(self.pts[i], self.normals[i], outer(self.half_w[i]), z),
                ],
                color,
                0.0,
            );
        }
    }

    /// Dashes of the centre guide: on for [`DASH_LENGTH_M`] every [`DASH_PERIOD_M`] of arc.
    fn dashes(&self, mesh: &mut MeshBuilder, color: [f32; 4]) {
        let hw = CENTRE_DASH_WIDTH_M / 2.0;
        for i in 0..self.near.len() {
            if !self.near[i] {
                continue;
            }
            let (s0, s1) = (self.arc[i], self.arc[i + 1]);
            if s1 - s0 < 1e-9 {
                continue;
            }
            let lerp = |s: f64| {
                let t = (s - s0) / (s1 - s0);
                let p = [
                    self.pts[i][0] + t * (self.pts[i + 1][0] - self.pts[i][0]),
                    self.pts[i][1] + t * (self.pts[i + 1][1] - self.pts[i][1]),
                ];
                let n = [
                    self.normals[i][0] + t * (self.normals[i + 1][0] - self.normals[i][0]),
                    self.normals[i][1] + t * (self.normals[i + 1][1] - self.normals[i][1]),
                ];
                (p, n)
            };
            let mut k = (s0 / DASH_PERIOD_M).floor();
            while k * DASH_PERIOD_M < s1 {
                let a = (k * DASH_PERIOD_M).max(s0);
                let b = (k * DASH_PERIOD_M + DASH_LENGTH_M).min(s1);
                if b > a {
                    let (pa, na) = lerp(a);
                    let (pb, nb) = lerp(b);
                    mesh.quad(
                        [
                            offset(pa, na, -hw, Z_MARK),
                            offset(pb, nb, -hw, Z_MARK),
                            offset(pb, nb, hw, Z_MARK),
                            offset(pa, na, hw, Z_MARK),
                        ],
                        color,
                        0.0,
                    );
                }
                k += 1.0;
            }
        }
    }
}

fn road(mesh: &mut MeshBuilder, scene: &Scene) {
    if !scene.has_road() {
        return;
    }
    let v = RoadView::new(scene);
    // Bands are given as lateral offsets (m, left positive) from the local half width.
    let (inset, lw) = (EDGE_LINE_INSET_M, EDGE_LINE_WIDTH_M / 2.0);
    let s = SHOULDER_M;
    // Shoulders, then the asphalt, then paint on top.
    v.band(mesh, |h| h, |h| h + s, Z_SHOULDER, palette::SHOULDER);
    v.band(mesh, |h| -h - s, |h| -h, Z_SHOULDER, palette::SHOULDER);
    v.band(mesh, |h| -h, |h| h, Z_ROAD, palette::ASPHALT);
    v.band(
        mesh,
        |h| h - inset - lw,
        |h| h - inset + lw,
        Z_MARK,
        palette::EDGE_LINE,
    );
    v.band(
        mesh,
        |h| -h + inset - lw,
        |h| -h + inset + lw,
        Z_MARK,
        palette::EDGE_LINE,
    );
    v.dashes(mesh, palette::CENTRE_DASH);
}

fn near_car(car: &CarPose, p: [f64; 2]) -> bool {
    (p[0] - car.x_m).hypot(p[1] - car.y_m) < VIEW_RADIUS_M
}

/// A traffic cone: an eight-sided pyramid on a square base, thesis-style slalom marker.
fn cone(mesh: &mut MeshBuilder, p: [f64; 2]) {
    const SIDES: usize = 8;
    let (r, h, base) = (0.2f32, 0.75f32, 0.3f32);
    let (x, y) = (p[0] as f32, p[1] as f32);
    let z0 = 0.04;
    mesh.quad(
        [
            [x - base, y - base, z0],
            [x + base, y - base, z0],
            [x + base, y + base, z0],
            [x - base, y + base, z0],
        ],
        palette::CONE_BASE,
        0.0,
    );
    let apex = [x, y, h];
    for k in 0..SIDES {
        let a0 = k as f32 / SIDES as f32 * std::f32::consts::TAU;
        let a1 = (k + 1) as f32 / SIDES as f32 * std::f32::consts::TAU;
        let p0 = [x + r * a0.cos(), y + r * a0.sin(), z0];
        let p1 = [x + r * a1.cos(), y + r * a1.sin(), z0];
        let am = (a0 + a1) / 2.0;
        let normal = [am.cos() * h, am.sin() * h, r];
        // A white reflective band between 45 % and 65 % of the height.
        let at = |pp: [f32; 3], t: f32| {
            [
                pp[0] + (apex[0] - pp[0]) * t,
                pp[1] + (apex[1] - pp[1]) * t,
                pp[2] + (apex[2] - pp[2]) * t,
            ]
        };
        let (b0, b1) = (0.45, 0.65);
        mesh.quad(
            [p0, p1, at(p1, b0), at(p0, b0)],
            shade(palette::CONE, normal),
            0.0,
        );
        mesh.quad(
            [at(p0, b0), at(p1, b0), at(p1, b1), at(p0, b1)],
            shade(palette::CONE_BAND, normal),
            0.0,
        );
        mesh.tri(
            at(p0, b1),
            at(p1, b1),
            apex,
            shade(palette::CONE, normal),
            0.0,
        );
    }
}

/// A low concrete wall along a polyline.
fn barrier(mesh: &mut MeshBuilder, car: &CarPose, line: &[[f64; 2]]) {
    let (h, half_t) = (0.9f32, 0.15f64);
    for w in line.windows(2) {
        let (a, b) = (w[0], w[1]);
        if !near_car(car, a) && !near_car(car, b) {
            continue;
        }
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let len = dx.hypot(dy);
        if len < 1e-9 {
            continue;
        }
        let n = [-dy / len, dx / len];
        let (al, ar) = (offset(a, n, half_t, 0.0), offset(a, n, -half_t, 0.0));
        let (bl, br) = (offset(b, n, half_t, 0.0), offset(b, n, -half_t, 0.0));
        let up = |p: [f32; 3]| [p[0], p[1], h];
        let base = |p: [f32; 3]| [p[0], p[1], 0.15];
        mesh.lit_quad([al, bl, base(bl), base(al)], palette::BARRIER_BASE);
        mesh.lit_quad([ar, br, base(br), base(ar)], palette::BARRIER_BASE);
        mesh.lit_quad([base(al), base(bl), up(bl), up(al)], palette::BARRIER);
        mesh.lit_quad([base(ar), base(br), up(br), up(ar)], palette::BARRIER);
        mesh.lit_quad([up(al), up(bl), up(br), up(ar)], palette::BARRIER_TOP);
        mesh.lit_quad([al, ar, up(ar), up(al)], palette::BARRIER);
        mesh.lit_quad([bl, br, up(br), up(bl)], palette::BARRIER);
    }
}

/// An oriented box given in the car frame (x forward, y left, z up), placed in the world.
struct CarFrame {
    x: f32,
    y: f32,
    c: f32,
    s: f32,
}

impl CarFrame {
    fn world(&self, local: [f32; 3]) -> [f32; 3] {
        [
            self.x + local[0] * self.c - local[1] * self.s,
            self.y + local[0] * self.s + local[1] * self.c,
            local[2],
        ]
    }

    /// Box with centre `ctr`, half extents `he`, rotated by `yaw` about its own vertical axis.
    fn cuboid(
        &self,
        mesh: &mut MeshBuilder,
        ctr: [f32; 3],
        he: [f32; 3],
        yaw: f32,
        color: [f32; 4],
    ) {
        let (cy, sy) = (yaw.cos(), yaw.sin());
        let corner = |sx: f32, sy_: f32, sz: f32| {
            let lx = sx * he[0];
            let ly = sy_ * he[1];
            self.world([
                ctr[0] + lx * cy - ly * sy,
                ctr[1] + lx * sy + ly * cy,
                ctr[2] + sz * he[2],
            ])
        };
        let faces: [[(f32, f32, f32); 4]; 6] = [
            [(1., -1., -1.), (1., 1., -1.), (1., 1., 1.), (1., -1., 1.)],
            [
                (-1., -1., -1.),
                (-1., 1., -1.),
                (-1., 1., 1.),
                (-1., -1., 1.),
            ],
            [(-1., 1., -1.), (1., 1., -1.), (1., 1., 1.), (-1., 1., 1.)],
            [
                (-1., -1., -1.),
                (1., -1., -1.),
                (1., -1., 1.),
                (-1., -1., 1.),
            ],
            [(-1., -1., 1.), (1., -1., 1.), (1., 1., 1.), (-1., 1., 1.)],
            [
                (-1., -1., -1.),
                (1., -1., -1.),
                (1., 1., -1.),
                (-1., 1., -1.),
            ],
        ];
        let centre = self.world([ctr[0], ctr[1], ctr[2]]);
        for f in faces {
            let q = f.map(|(a, b, c)| corner(a, b, c));
            let mid = [
                (q[0][0] + q[2][0]) / 2.0 - centre[0],
                (q[0][1] + q[2][1]) / 2.0 - centre[1],
                (q[0][2] + q[2][2]) / 2.0 - centre[2],
            ];
            mesh.quad(q, shade(color, mid), 0.0);
        }
    }
}

/// The patient's car: body, cabin, wheels (front ones steered), tail lights and a soft shadow.
fn car(mesh: &mut MeshBuilder, pose: &CarPose) {
    let f = CarFrame {
        x: pose.x_m as f32,
        y: pose.y_m as f32,
        c: pose.yaw_rad.cos() as f32,
        s: pose.yaw_rad.sin() as f32,
    };
    let shadow = [
        [2.3, 1.0, Z_SHADOW],
        [-2.3, 1.0, Z_SHADOW],
        [-2.3, -1.0, Z_SHADOW],
        [2.3, -1.0, Z_SHADOW],
    ]
    .map(|p| f.world(p));
    mesh.quad(shadow, palette::SHADOW, 0.0);
    f.cuboid(
        mesh,
        [0.0, 0.0, 0.68],
        [2.15, 0.9, 0.34],
        0.0,
        palette::CAR_BODY,
    );
    f.cuboid(
        mesh,
        [-0.35, 0.0, 1.27],
        [1.15, 0.78, 0.26],
        0.0,
        palette::CAR_CABIN,
    );
    f.cuboid(
        mesh,
        [-0.35, 0.0, 1.545],
        [1.0, 0.72, 0.015],
        0.0,
        palette::CAR_BODY,
    );
    let steer = pose.steer_rad as f32;
    for (x, y, yaw) in [
        (1.35, 0.82, steer),
        (1.35, -0.82, steer),
        (-1.35, 0.82, 0.0),
        (-1.35, -0.82, 0.0),
    ] {
        f.cuboid(mesh, [x, y, 0.34], [0.34, 0.13, 0.34], yaw, palette::TYRE);
    }
    for y in [0.62, -0.62] {
        f.cuboid(
            mesh,
            [-2.16, y, 0.82],
            [0.02, 0.2, 0.07],
            0.0,
            palette::TAIL_LIGHT,
        );
    }
}

/// A large ground square centred under the car; the shader draws the checker on it.
fn ground(mesh: &mut MeshBuilder, pose: &CarPose) {
    // Snap to the checker period so the pattern does not crawl as the square follows the car.
    let snap = |v: f64| ((v / 16.0).round() * 16.0) as f32;
    let (x, y, h) = (snap(pose.x_m), snap(pose.y_m), GROUND_HALF_M);
    mesh.quad(
        [
            [x - h, y - h, Z_GROUND],
            [x + h, y - h, Z_GROUND],
            [x + h, y + h, Z_GROUND],
            [x - h, y + h, Z_GROUND],
        ],
        palette::GRASS_A,
        1.0,
    );
}

/// All world triangles of `scene` into `mesh` (cleared first).
pub fn build_world(mesh: &mut MeshBuilder, scene: &Scene) {
    mesh.vertices.clear();
    ground(mesh, &scene.car);
    road(mesh, scene);
    for line in &scene.road.barriers {
        barrier(mesh, &scene.car, line);
    }
    for &p in &scene.road.cones {
        if near_car(&scene.car, p) {
            cone(mesh, p);
        }
    }
    if scene.camera == CameraMode::Chase && scene.has_road() {
        car(mesh, &scene.car);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::RoadPoint;

    fn straight(len: usize) -> Scene {
        let mut s = Scene::default();
        s.road.centre = (0..len)
            .map(|i| RoadPoint {
                x_m: i as f64 * 5.0,
                y_m: 0.0,
                lane_width_m: 4.0,
            })
            .collect();
        s
    }

    #[test]
    fn normals_of_straight_line_point_left() {
        let n = polyline_normals(&[[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]);
        for v in n {
            assert!((v[0]).abs() < 1e-12 && (v[1] - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn asphalt_spans_exactly_the_lane_width() {
        let s = straight(3);
        let mut m = MeshBuilder::default();
        road(&mut m, &s);
        let asphalt: Vec<_> = m
            .vertices
            .iter()
            .filter(|v| v.color == palette::ASPHALT)
            .collect();
        assert_eq!(asphalt.len(), 2 * 6);
        let ys: Vec<f32> = asphalt.iter().map(|v| v.pos[1]).collect();
        let (lo, hi) = ys
            .iter()
            .fold((f32::MAX, f32::MIN), |(a, b), &y| (a.min(y), b.max(y)));
        assert!(
            (lo + 2.0).abs() < 1e-6 && (hi - 2.0).abs() < 1e-6,
            "{lo} {hi}"
        );
    }

    #[test]
    fn dashes_follow_the_period() {
        let s = straight(21); // 100 m of road
        let mut m = MeshBuilder::default();
        road(&mut m, &s);
        let dash: Vec<_> = m
            .vertices
            .iter()
            .filter(|v| v.color == palette::CENTRE_DASH)
            .collect();
        // Dashes start at 0, 9, …, 99 m: 12 of them, some split across 5 m segments.
        let mut starts: Vec<f32> = dash.iter().map(|v| v.pos[0]).collect();
        starts.sort_by(f32::total_cmp);
        starts.dedup_by(|a, b| (*a - *b).abs() < 1e-4);
        for k in 0..11 {
            let x = k as f32 * 9.0;
            assert!(
                starts.iter().any(|&s| (s - x).abs() < 1e-4),
                "no dash edge at {x}"
            );
            assert!(
                starts.iter().any(|&s| (s - x - 3.0).abs() < 1e-4),
                "no dash end at {}",
                x + 3.0
            );
        }
        assert!(
            starts.iter().all(|&x| x.rem_euclid(9.0) <= 3.0 + 1e-4),
            "{starts:?}"
        );
    }

    #[test]
    fn far_road_is_not_generated() {
        let mut s = straight(400); // 2 km
        s.car.x_m = 0.0;
        let mut m = MeshBuilder::default();
        road(&mut m, &s);
        let max_x = m.vertices.iter().map(|v| v.pos[0]).fold(f32::MIN, f32::max);
        assert!(max_x < (VIEW_RADIUS_M + 10.0) as f32, "{max_x}");
    }

    #[test]
    fn driver_view_has_no_car_body() {
        let mut s = straight(3);
        s.camera = CameraMode::Driver;
        let mut m = MeshBuilder::default();
        build_world(&mut m, &s);
        let driver = m.vertices.len();
        s.camera = CameraMode::Chase;
        build_world(&mut m, &s);
        // Shadow quad + 3 body boxes + 4 wheels + 2 tail lights, 6 faces × 2 triangles each.
        assert_eq!(m.vertices.len() - driver, 6 + (3 + 4 + 2) * 36);
    }
}
