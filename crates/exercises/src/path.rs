//! Arc-length parametrised roads built from pieces: clothoids (which include straights and
//! circular arcs) and sine waves. Every exercise road of the library is a [`PathRoad`].
//!
//! # Lookups
//!
//! At build time the centre line is tabulated at knots every [`KNOT_SPACING_M`] of arc length
//! (and at every piece start). A lookup at arc length `s` indexes the knot directly
//! (`floor(s / spacing)`: O(1), no search) and integrates the last ≤ 1 m exactly:
//! a clothoid piece's heading is a quadratic in `s`, its position the 6-point Gauss–Legendre
//! quadrature of `(cos ψ, sin ψ)` (error far below 1e-9 m); a sine piece solves its
//! arc-length equation by Newton's method from the knot's abscissa. Projection of a point
//! uses Newton's method started at the caller's hint, so a car moving forward costs O(1) per
//! tick. Beyond either end the road continues as a straight line.

use crate::error::VehicleError;
use crate::road::{Projection, Road};
use std::cell::Cell;

/// Spacing of the precomputed knots along the centre line, m.
pub const KNOT_SPACING_M: f64 = 1.0;

/// 6-point Gauss–Legendre nodes on [−1, 1].
const GL_X: [f64; 6] = [
    -0.932_469_514_203_152,
    -0.661_209_386_466_264_5,
    -0.238_619_186_083_196_9,
    0.238_619_186_083_196_9,
    0.661_209_386_466_264_5,
    0.932_469_514_203_152,
];
/// 6-point Gauss–Legendre weights.
const GL_W: [f64; 6] = [
    0.171_324_492_379_170_3,
    0.360_761_573_048_138_6,
    0.467_913_934_572_691,
    0.467_913_934_572_691,
    0.360_761_573_048_138_6,
    0.171_324_492_379_170_3,
];

/// ∫ₐᵇ f by 6-point Gauss–Legendre.
fn gauss<F: Fn(f64) -> f64>(a: f64, b: f64, f: F) -> f64 {
    let (m, h) = ((a + b) / 2.0, (b - a) / 2.0);
    GL_X.iter()
        .zip(GL_W.iter())
        .map(|(x, w)| w * f(m + h * x))
        .sum::<f64>()
        * h
}

/// The curvature law of one piece.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Shape {
    /// Curvature `k0 + dk·u` at local arc length `u` (straight: both 0; arc: `dk` 0).
    Clothoid { k0_1_m: f64, dk_1_m2: f64 },
    /// `y = A (1 − cos(2π ξ/λ))` in the piece's frame: starts and ends (after whole
    /// half-periods) tangent to the frame's x axis.
    Sine { amplitude_m: f64, wavelength_m: f64 },
}

impl Shape {
    /// For a sine piece: (y, y', y'') at abscissa ξ.
    fn sine_y(amplitude_m: f64, wavelength_m: f64, xi: f64) -> (f64, f64, f64) {
        let k = std::f64::consts::TAU / wavelength_m;
        let (s, c) = (k * xi).sin_cos();
        (
            amplitude_m * (1.0 - c),
            amplitude_m * k * s,
            amplitude_m * k * k * c,
        )
    }
}

#[derive(Clone, Debug)]
struct Piece {
    s0_m: f64,
    len_m: f64,
    /// Pose of the piece start (clothoid) or of its frame origin (sine).
    x0: f64,
    y0: f64,
    psi0: f64,
    shape: Shape,
}

/// A centre-line sample: arc length, pose, and for sine pieces the local abscissa.
#[derive(Clone, Copy, Debug)]
struct Knot {
    s_m: f64,
    piece: usize,
    x: f64,
    y: f64,
    psi: f64,
    xi: f64,
}

/// Centre-line pose at one arc length.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CentrePoint {
    /// Position `[x, y]`, m.
    pub xy_m: [f64; 2],
    /// Heading, rad.
    pub heading_rad: f64,
    /// Curvature, 1/m (positive turning left).
    pub curvature_1_m: f64,
}

/// Builds a [`PathRoad`] piece by piece, starting at a given pose.
#[derive(Clone, Debug)]
pub struct PathBuilder {
    start: [f64; 3],
    shapes: Vec<(Shape, f64)>,
    lane_width_m: f64,
}

impl PathBuilder {
    /// A path starting at `(x_m, y_m)` with heading `heading_rad`, for a lane `lane_width_m` wide.
    pub fn new(x_m: f64, y_m: f64, heading_rad: f64, lane_width_m: f64) -> Self {
        Self {
            start: [x_m, y_m, heading_rad],
            shapes: Vec::new(),
            lane_width_m,
        }
    }

    /// A straight of `length_m`.
    pub fn straight(mut self, length_m: f64) -> Self {
        self.shapes.push((
            Shape::Clothoid {
                k0_1_m: 0.0,
                dk_1_m2: 0.0,
            },
            length_m,
        ));
        self
    }

    /// A circular arc of `radius_m` turning by `angle_rad` (positive: left).
    pub fn arc(mut self, radius_m: f64, angle_rad: f64) -> Self {
        let k = angle_rad.signum() / radius_m;
        self.shapes.push((
            Shape::Clothoid {
                k0_1_m: k,
                dk_1_m2: 0.0,
            },
            angle_rad.abs() * radius_m,
        ));
        self
    }

    /// A clothoid of `length_m` whose curvature goes linearly from `k_start_1_m` to `k_end_1_m`.
    pub fn clothoid(mut self, length_m: f64, k_start_1_m: f64, k_end_1_m: f64) -> Self {
        self.shapes.push((
            Shape::Clothoid {
                k0_1_m: k_start_1_m,
                dk_1_m2: (k_end_1_m - k_start_1_m) / length_m,
            },
            length_m,
        ));
        self
    }

    /// `half_periods` half waves of `y = A (1 − cos(2π ξ/λ))` along the current heading
    /// (first bend to the left for positive `amplitude_m`).
    pub fn sine(mut self, amplitude_m: f64, wavelength_m: f64, half_periods: u32) -> Self {
        let len = sine_arc_length(amplitude_m, wavelength_m, 0.0, wavelength_m / 2.0)
            * f64::from(half_periods);
        self.shapes.push((
            Shape::Sine {
                amplitude_m,
                wavelength_m,
            },
            len,
        ));
        self
    }

    /// Tabulate the path. Errors if a piece has a non-finite or negative length or the path
    /// is empty.
    pub fn build(self) -> Result<PathRoad, VehicleError> {
        if !(self.lane_width_m.is_finite() && self.lane_width_m > 0.0) {
            return Err(VehicleError::InvalidInput(format!(
                "lane width must be positive, got {}",
                self.lane_width_m
            )));
        }
        let [mut x, mut y, mut psi] = self.start;
        let mut s = 0.0;
        let mut pieces = Vec::new();
        for (shape, len) in self.shapes {
            if !(len.is_finite() && len >= 0.0) {
                return Err(VehicleError::InvalidInput(format!(
                    "road piece {shape:?} has length {len} m"
                )));
            }
            if len == 0.0 {
                continue;
            }
            let piece = Piece {
                s0_m: s,
                len_m: len,
                x0: x,
                y0: y,
                psi0: psi,
                shape,
            };
            // Exit pose, integrated knot by knot below; here only to chain the pieces.
            pieces.push(piece);
            let end = PathRoad::piece_end(&pieces[pieces.len() - 1]);
            (x, y, psi) = (end.xy_m[0], end.xy_m[1], end.heading_rad);
            s += len;
        }
        if pieces.is_empty() {
            return Err(VehicleError::InvalidInput("road has no pieces".into()));
        }
        let length_m = s;
        let n = (length_m / KNOT_SPACING_M).floor() as usize + 1;
        let mut knots = Vec::with_capacity(n);
        let mut p = 0;
        let mut prev: Option<Knot> = None;
        for i in 0..n {
            let sk = i as f64 * KNOT_SPACING_M;
            while p + 1 < pieces.len() && pieces[p + 1].s0_m <= sk {
                p += 1;
            }
            let from = match prev {
                Some(k) if k.piece == p => k,
                _ => PathRoad::piece_start_knot(&pieces[p], p),
            };
            let (cp, xi) = PathRoad::eval_from(&pieces[p], &from, sk);
            let knot = Knot {
                s_m: sk,
                piece: p,
                x: cp.xy_m[0],
                y: cp.xy_m[1],
                psi: cp.heading_rad,
                xi,
            };
            knots.push(knot);
            prev = Some(knot);
        }
        Ok(PathRoad {
            pieces,
            knots,
            length_m,
            lane_width_m: self.lane_width_m,
            last_projection: Cell::new(None),
        })
    }
}

/// Arc length of the sine `A (1 − cos(2π ξ/λ))` between abscissae `a` and `b`, m.
fn sine_arc_length(amplitude_m: f64, wavelength_m: f64, a: f64, b: f64) -> f64 {
    // Panels of at most λ/16 keep 6-point Gauss–Legendre far below 1e-10 relative error.
    let panels = (((b - a).abs() / (wavelength_m / 16.0)).ceil() as usize).max(1);
    let h = (b - a) / panels as f64;
    (0..panels)
        .map(|i| {
            let lo = a + h * i as f64;
            gauss(lo, lo + h, |xi| {
                let (_, dy, _) = Shape::sine_y(amplitude_m, wavelength_m, xi);
                (1.0 + dy * dy).sqrt()
            })
        })
        .sum()
}

/// An arc-length parametrised road made of clothoid and sine pieces; see the module docs.
#[derive(Clone, Debug)]
pub struct PathRoad {
    pieces: Vec<Piece>,
    knots: Vec<Knot>,
    length_m: f64,
    lane_width_m: f64,
    /// The arc length (as bits) where the last [`Road::project`] ended and the centre point
    /// there. A car's projection starts from where the last one ended (its hint), so the
    /// point it starts from is this one, found again from the same arc length with no
    /// evaluation: a sine piece's point costs a Newton solve of its arc length, a fifth of the
    /// haptic thread's samples at `--speed max` with the car on a sine road (issue 47). The
    /// point is a function of the arc length alone, so the answer is the same bits.
    last_projection: Cell<Option<(u64, CentrePoint)>>,
}

impl PathRoad {
    /// Total length of the built pieces, m (lookups beyond it continue straight).
    pub fn length_m(&self) -> f64 {
        self.length_m
    }

    fn piece_start_knot(piece: &Piece, index: usize) -> Knot {
        Knot {
            s_m: piece.s0_m,
            piece: index,
            x: piece.x0,
            y: piece.y0,
            psi: piece.psi0,
            xi: 0.0,
        }
    }

    fn piece_end(piece: &Piece) -> CentrePoint {
        // Chain in ≤ 1 m hops from the start so long pieces stay exact.
        let mut k = Self::piece_start_knot(piece, 0);
        let end = piece.s0_m + piece.len_m;
        loop {
            let next = (k.s_m + KNOT_SPACING_M).min(end);
            let (cp, xi) = Self::eval_from(piece, &k, next);
            if next >= end {
                return cp;
            }
            k = Knot {
                s_m: next,
                piece: 0,
                x: cp.xy_m[0],
                y: cp.xy_m[1],
                psi: cp.heading_rad,
                xi,
            };
        }
    }

    /// Evaluate `piece` at global arc length `s` starting from a knot of the same piece.
    fn eval_from(piece: &Piece, from: &Knot, s: f64) -> (CentrePoint, f64) {
        match piece.shape {
            Shape::Clothoid { k0_1_m, dk_1_m2 } => {
                let u0 = from.s_m - piece.s0_m;
                let k_from = k0_1_m + dk_1_m2 * u0;
                let psi = |v: f64| from.psi + k_from * v + 0.5 * dk_1_m2 * v * v;
                let v = s - from.s_m;
                let dx = gauss(0.0, v, |w| psi(w).cos());
                let dy = gauss(0.0, v, |w| psi(w).sin());
                (
                    CentrePoint {
                        xy_m: [from.x + dx, from.y + dy],
                        heading_rad: psi(v),
                        curvature_1_m: k0_1_m + dk_1_m2 * (s - piece.s0_m),
                    },
                    0.0,
                )
            }
            Shape::Sine {
                amplitude_m: a,
                wavelength_m: l,
            } => {
                // Newton on S(ξ) = s − from.s: arc length from the knot's abscissa.
                let target = s - from.s_m;
                let (_, dy0, _) = Shape::sine_y(a, l, from.xi);
                let mut xi = from.xi + target / (1.0 + dy0 * dy0).sqrt();
                for _ in 0..20 {
                    let (_, dy, _) = Shape::sine_y(a, l, xi);
                    let f = sine_arc_length(a, l, from.xi, xi) - target;
                    let step = f / (1.0 + dy * dy).sqrt();
                    xi -= step;
                    if step.abs() < 1e-12 {
                        break;
                    }
                }
                let (yl, dy, ddy) = Shape::sine_y(a, l, xi);
                let (sp, cp) = piece.psi0.sin_cos();
                (
                    CentrePoint {
                        xy_m: [piece.x0 + cp * xi - sp * yl, piece.y0 + sp * xi + cp * yl],
                        heading_rad: piece.psi0 + dy.atan(),
                        curvature_1_m: ddy / (1.0 + dy * dy).powf(1.5),
                    },
                    xi,
                )
            }
        }
    }

    /// Centre-line pose at arc length `s_m` (straight continuation outside `[0, length]`).
    pub fn point(&self, s_m: f64) -> CentrePoint {
        let s = if s_m.is_finite() { s_m } else { 0.0 };
        if s < 0.0 {
            let p = &self.pieces[0];
            let (sh, ch) = p.psi0.sin_cos();
            return CentrePoint {
                xy_m: [p.x0 + ch * s, p.y0 + sh * s],
                heading_rad: p.psi0,
                curvature_1_m: 0.0,
            };
        }
        if s > self.length_m {
            let end = self.point(self.length_m);
            let (sh, ch) = end.heading_rad.sin_cos();
            let d = s - self.length_m;
            return CentrePoint {
                xy_m: [end.xy_m[0] + ch * d, end.xy_m[1] + sh * d],
                heading_rad: end.heading_rad,
                curvature_1_m: 0.0,
            };
        }
        let i = ((s / KNOT_SPACING_M) as usize).min(self.knots.len() - 1);
        let knot = &self.knots[i];
        let mut p = knot.piece;
        while p + 1 < self.pieces.len() && self.pieces[p + 1].s0_m <= s {
            p += 1;
        }
        let from = if p == knot.piece {
            *knot
        } else {
            Self::piece_start_knot(&self.pieces[p], p)
        };
        Self::eval_from(&self.pieces[p], &from, s).0
    }
}

impl Road for PathRoad {
    fn lane_width_m(&self) -> f64 {
        self.lane_width_m
    }

    fn centre(&self, s_m: f64) -> ([f64; 2], f64, f64) {
        let c = self.point(s_m);
        (c.xy_m, c.heading_rad, c.curvature_1_m)
    }

    fn project(&self, x_m: f64, y_m: f64, hint_s_m: f64) -> Projection {
        let dist2 = |c: &CentrePoint| (c.xy_m[0] - x_m).powi(2) + (c.xy_m[1] - y_m).powi(2);
        // Start from the hint; without a usable one, scan the knots once.
        let mut s = if hint_s_m.is_finite() {
            hint_s_m
        } else {
            let mut best = (f64::INFINITY, 0.0);
            for k in &self.knots {
                let d = (k.x - x_m).powi(2) + (k.y - y_m).powi(2);
                if d < best.0 {
                    best = (d, k.s_m);
                }
            }
            best.1
        };
        // Newton on g(s) = (p − c(s))·t(s) = 0, g'(s) = −(1 − κ·lateral); steps capped, and
        // halved when they would move away from the point (robust near cusps). A car moving
        // forward converges in two or three lookups.
        let mut c = match self.last_projection.get() {
            Some((bits, c)) if bits == s.to_bits() => c,
            _ => self.point(s),
        };
        for _ in 0..16 {
            let (sh, ch) = c.heading_rad.sin_cos();
            let (dx, dy) = (x_m - c.xy_m[0], y_m - c.xy_m[1]);
            let along = dx * ch + dy * sh;
            let lateral = -dx * sh + dy * ch;
            let denom = (1.0 - c.curvature_1_m * lateral).max(0.2);
            let step = (along / denom).clamp(-5.0, 5.0);
            if step.abs() < 1e-8 {
                break;
            }
            let next = self.point(s + step);
            if dist2(&next) <= dist2(&c) + 1e-12 {
                s += step;
                c = next;
            } else {
                s += step / 2.0;
                c = self.point(s);
            }
        }
        // `c` is `self.point(s)` here: each step above sets both together.
        self.last_projection.set(Some((s.to_bits(), c)));
        let (sh, ch) = c.heading_rad.sin_cos();
        Projection {
            s_m: s,
            lateral_m: -(x_m - c.xy_m[0]) * sh + (y_m - c.xy_m[1]) * ch,
            heading_rad: c.heading_rad,
            curvature_1_m: c.curvature_1_m,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use std::f64::consts::PI;

    /// The remembered last projection (issue 47) is kept from sliding back, as a ratio in the
    /// same run: a car's projections along a sine road, each from the last one's answer, with
    /// the road remembering against the same projections with the memory cleared before each
    /// (best of 9 alternating rounds of 4 000). A car's projection evaluates the centre line
    /// three or four times, one of them where the last ended. 2026-12-08, loaded machine:
    /// 0.66–0.67 in release, 0.37–0.66 in the debug build CI runs; the bound leaves room for
    /// noise.
    /// (The clock is read here, in the test, never in the library.)
    #[test]
    #[allow(clippy::disallowed_methods)]
    fn a_cars_projection_from_where_the_last_ended_costs_less_than_afresh() {
        use std::time::Instant;
        const RATIO_LIMIT: f64 = 0.85;
        let road = PathBuilder::new(0.0, 0.0, 0.0, 3.5)
            .sine(1.5, 40.0, 6)
            .build()
            .unwrap();
        let car: Vec<(f64, f64)> = (0..4000)
            .map(|k| {
                let s = k as f64 * 0.01;
                let c = road.point(s);
                let (sh, ch) = c.heading_rad.sin_cos();
                let off = 0.5 * (s * 0.3).sin();
                (c.xy_m[0] - off * sh, c.xy_m[1] + off * ch)
            })
            .collect();
        let (mut kept, mut afresh) = (f64::MAX, f64::MAX);
        for _ in 0..9 {
            let t = Instant::now();
            let mut hint = 0.0;
            for &(x, y) in &car {
                hint = std::hint::black_box(road.project(x, y, hint)).s_m;
            }
            kept = kept.min(t.elapsed().as_secs_f64());
            let t = Instant::now();
            let mut hint = 0.0;
            for &(x, y) in &car {
                road.last_projection.set(None);
                hint = std::hint::black_box(road.project(x, y, hint)).s_m;
            }
            afresh = afresh.min(t.elapsed().as_secs_f64());
        }
        let ratio = kept / afresh;
        println!("a car's projection, remembered start: {ratio:.2} of afresh");
        assert!(
            ratio < RATIO_LIMIT,
            "a car's projection costs {ratio:.2} of one afresh"
        );
    }

    /// A car's projections with the road remembering where the last one ended are those of
    /// a road that remembers nothing, bit for bit, along sine, clothoid, arc and straight
    /// pieces, with hints that are the last answer (as a car's), elsewhere, or none.
    #[test]
    fn a_projection_from_where_the_last_ended_is_the_same_bits_as_afresh() {
        let road = PathBuilder::new(0.0, 0.0, 0.3, 3.5)
            .straight(12.0)
            .sine(1.5, 40.0, 3)
            .clothoid(20.0, 0.0, 0.02)
            .arc(50.0, 0.6)
            .sine(0.8, 25.0, 2)
            .build()
            .unwrap();
        let mut s_hint = 0.0;
        for k in 0..40_000 {
            let s = k as f64 * 0.004;
            let c = road.point(s);
            let (sh, ch) = c.heading_rad.sin_cos();
            let off = 0.9 * (s * 0.37).sin();
            let (x, y) = (c.xy_m[0] - off * sh, c.xy_m[1] + off * ch);
            let hint = match k % 50 {
                7 => f64::NAN,
                23 => s_hint + 3.0,
                _ => s_hint,
            };
            let afresh = road.clone();
            afresh.last_projection.set(None);
            let (a, b) = (road.project(x, y, hint), afresh.project(x, y, hint));
            let bits = |p: &Projection| {
                [p.s_m, p.lateral_m, p.heading_rad, p.curvature_1_m].map(f64::to_bits)
            };
            assert_eq!(bits(&a), bits(&b), "step {k} at {s} m");
            s_hint = a.s_m;
        }
    }

    #[test]
    fn straight_then_quarter_circle_lands_where_geometry_says() {
        let r = 50.0;
        let road = PathBuilder::new(0.0, 0.0, 0.0, 3.5)
            .straight(10.5)
            .arc(r, PI / 2.0)
            .build()
            .unwrap();
        assert!((road.length_m() - (10.5 + r * PI / 2.0)).abs() < 1e-12);
        let end = road.point(road.length_m());
        assert!((end.xy_m[0] - (10.5 + r)).abs() < 1e-9, "{end:?}");
        assert!((end.xy_m[1] - r).abs() < 1e-9);
        assert!((end.heading_rad - PI / 2.0).abs() < 1e-12);
        let mid = road.point(10.5 + r * PI / 4.0);
        assert!((mid.curvature_1_m - 1.0 / r).abs() < 1e-12);
        assert!((mid.xy_m[0] - (10.5 + r * (PI / 4.0).sin())).abs() < 1e-9);
    }

    #[test]
    fn clothoid_heading_is_integral_of_linear_curvature() {
        let road = PathBuilder::new(0.0, 0.0, 0.0, 3.5)
            .clothoid(200.0, 0.0, 0.02)
            .build()
            .unwrap();
        for &s in &[0.0, 37.3, 100.0, 200.0] {
            let c = road.point(s);
            let k = 0.02 * s / 200.0;
            assert!((c.curvature_1_m - k).abs() < 1e-15);
            assert!((c.heading_rad - 0.5 * 0.02 / 200.0 * s * s).abs() < 1e-12);
        }
        // Fresnel check at small s: x ≈ s − s⁵ a²/40 with ψ = a s²/2.
        let c = road.point(10.0);
        let a = 0.02 / 200.0;
        assert!((c.xy_m[0] - (10.0 - a * a * 1e5 / 40.0)).abs() < 1e-9);
    }

    #[test]
    fn sine_piece_matches_closed_form_and_ends_tangent() {
        let (a, l) = (4.0, 120.0);
        let road = PathBuilder::new(0.0, 0.0, 0.0, 3.5)
            .sine(a, l, 4)
            .build()
            .unwrap();
        // Arc length per period of y = A cos(kx): check against a fine trapezoid sum.
        let n = 200_000;
        let h = l / n as f64;
        let k = 2.0 * PI / l;
        let trap: f64 = (0..n)
            .map(|i| {
                let x = (i as f64 + 0.5) * h;
                (1.0 + (a * k * (k * x).sin()).powi(2)).sqrt() * h
            })
            .sum();
        assert!(
            (road.length_m() - 2.0 * trap).abs() < 1e-6,
            "{}",
            road.length_m()
        );
        for &s in &[0.0, 13.0, 61.7, 150.0, road.length_m()] {
            let c = road.point(s);
            let (x, y) = (c.xy_m[0], c.xy_m[1]);
            assert!((y - a * (1.0 - (k * x).cos())).abs() < 1e-9, "s={s}: {c:?}");
        }
        let end = road.point(road.length_m());
        assert!(end.heading_rad.abs() < 1e-9 && (end.xy_m[0] - 2.0 * l).abs() < 1e-6);
    }

    #[test]
    fn lookups_beyond_the_ends_continue_straight() {
        let road = PathBuilder::new(1.0, 2.0, 0.5, 3.5)
            .arc(30.0, 0.4)
            .build()
            .unwrap();
        let before = road.point(-10.0);
        assert!((before.xy_m[0] - (1.0 - 10.0 * 0.5f64.cos())).abs() < 1e-12);
        let end = road.point(road.length_m());
        let after = road.point(road.length_m() + 5.0);
        assert!((after.heading_rad - 0.9).abs() < 1e-12 && after.curvature_1_m == 0.0);
        assert!((after.xy_m[1] - end.xy_m[1] - 5.0 * 0.9f64.sin()).abs() < 1e-9);
    }

    #[test]
    fn empty_or_bad_paths_are_errors() {
        assert!(PathBuilder::new(0.0, 0.0, 0.0, 3.5).build().is_err());
        assert!(
            PathBuilder::new(0.0, 0.0, 0.0, 3.5)
                .straight(f64::NAN)
                .build()
                .is_err()
        );
        assert!(
            PathBuilder::new(0.0, 0.0, 0.0, 0.0)
                .straight(1.0)
                .build()
                .is_err()
        );
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 128, rng_seed: proptest::test_runner::RngSeed::Fixed(3), ..ProptestConfig::default() })]

        /// A point placed at a known offset from the centre line projects back to it,
        /// from a hint a few metres off.
        #[test]
        fn projection_recovers_offset_and_arc_length(
            s in 5.0f64..390.0, off in -3.0f64..3.0, hint_off in -4.0f64..4.0,
        ) {
            let road = PathBuilder::new(0.0, 0.0, 0.0, 3.5)
                .straight(20.0).clothoid(60.0, 0.0, 0.03).arc(33.3, 0.8)
                .clothoid(60.0, 0.03, -0.02).sine(3.0, 80.0, 3)
                .build().unwrap();
            let c = road.point(s);
            let (sh, ch) = c.heading_rad.sin_cos();
            let p = road.project(c.xy_m[0] - off * sh, c.xy_m[1] + off * ch, s + hint_off);
            prop_assert!((p.s_m - s).abs() < 1e-6, "{p:?} vs s={s}");
            prop_assert!((p.lateral_m - off).abs() < 1e-6);
        }

        /// Heading is the derivative direction of position (finite difference).
        #[test]
        fn heading_is_tangent_of_centre_line(s in 1.0f64..380.0) {
            let road = PathBuilder::new(0.0, 0.0, 0.3, 3.5)
                .clothoid(100.0, 0.0, -0.04).arc(25.0, -1.0).sine(2.0, 60.0, 5)
                .build().unwrap();
            let h = 1e-4;
            let (a, b) = (road.point(s - h), road.point(s + h));
            let dir = (b.xy_m[1] - a.xy_m[1]).atan2(b.xy_m[0] - a.xy_m[0]);
            let here = road.point(s).heading_rad;
            prop_assert!(common::wrap_angle(dir - here).abs() < 1e-6);
            let step = ((b.xy_m[0] - a.xy_m[0]).powi(2) + (b.xy_m[1] - a.xy_m[1]).powi(2)).sqrt();
            prop_assert!((step - 2.0 * h).abs() < 1e-9, "not arc length: {step}");
        }
    }
}
