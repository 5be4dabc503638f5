//! Roads: a centre line with a lane width, and projection of the car onto it.

use serde::{Deserialize, Serialize};

/// Where a point lies relative to a road's centre line.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Projection {
    /// Distance along the road of the closest centre-line point, m.
    pub s_m: f64,
    /// Signed lateral offset of the point from the centre line, m (positive to the left).
    pub lateral_m: f64,
    /// Heading of the centre line at `s_m`, rad.
    pub heading_rad: f64,
    /// Curvature of the centre line at `s_m`, 1/m (positive turning left).
    pub curvature_1_m: f64,
}

/// A road: a centre line parametrised by distance and a lane width.
///
/// Used by the station as `Box<dyn Road + Send>`.
pub trait Road {
    /// Width of the lane the car should stay in, m.
    fn lane_width_m(&self) -> f64;
    /// Centre-line point `(x, y)` in m, heading in rad and curvature in 1/m at distance `s_m`.
    fn centre(&self, s_m: f64) -> ([f64; 2], f64, f64);
    /// Project the point `(x_m, y_m)` onto the centre line, searching near `hint_s_m`
    /// (the last projection, for amortised O(1) lookups of a car moving forward).
    fn project(&self, x_m: f64, y_m: f64, hint_s_m: f64) -> Projection;
}

/// A sine road along global x: `y = A·sin(2π·x/λ)`, the thesis's sine road (§3.3.4), endless.
///
/// Unlike the library's roads ([`crate::PathRoad`], built by [`crate::ExerciseSpec`]), this
/// road's distance parameter is the global `x`, not arc length (exact for projection and
/// simple for a road along x). Prefer `ExerciseSpec::Sine` (`--exercise sine-road`), which is
/// arc-length parametrised and has a lead-in and lead-out.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SineRoad {
    /// Amplitude `A`, m.
    pub amplitude_m: f64,
    /// Wavelength `λ`, m.
    pub wavelength_m: f64,
    /// Lane width, m.
    pub lane_width_m: f64,
}

impl Default for SineRoad {
    fn default() -> Self {
        Self {
            amplitude_m: 4.0,
            wavelength_m: 120.0,
            lane_width_m: 3.5,
        }
    }
}

impl SineRoad {
    fn y(&self, x: f64) -> (f64, f64, f64) {
        let k = std::f64::consts::TAU / self.wavelength_m;
        let (s, c) = (k * x).sin_cos();
        (
            self.amplitude_m * s,
            self.amplitude_m * k * c,
            -self.amplitude_m * k * k * s,
        )
    }
}

impl Road for SineRoad {
    fn lane_width_m(&self) -> f64 {
        self.lane_width_m
    }

    fn centre(&self, s_m: f64) -> ([f64; 2], f64, f64) {
        let (y, dy, ddy) = self.y(s_m);
        let curvature = ddy / (1.0 + dy * dy).powf(1.5);
        ([s_m, y], dy.atan(), curvature)
    }

    fn project(&self, x_m: f64, y_m: f64, hint_s_m: f64) -> Projection {
        // Newton iterations on d/dx |p - c(x)|² = 0, started at the hint.
        let mut x = if hint_s_m.is_finite() { hint_s_m } else { x_m };
        for _ in 0..8 {
            let (y, dy, ddy) = self.y(x);
            let g = (x - x_m) + (y - y_m) * dy;
            let h = 1.0 + dy * dy + (y - y_m) * ddy;
            let step = if h > 1e-9 { g / h } else { g };
            x -= step;
            if step.abs() < 1e-10 {
                break;
            }
        }
        let ([cx, cy], heading, curvature) = self.centre(x);
        let (sh, ch) = heading.sin_cos();
        let lateral = -(x_m - cx) * sh + (y_m - cy) * ch;
        Projection {
            s_m: x,
            lateral_m: lateral,
            heading_rad: heading,
            curvature_1_m: curvature,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn point_left_of_centre_projects_with_positive_offset() {
        let road = SineRoad::default();
        for &x in &[0.0, 17.0, 30.0, 61.0, 95.0] {
            let ([cx, cy], heading, _) = road.centre(x);
            let (sh, ch) = heading.sin_cos();
            let p = road.project(cx - 0.8 * sh, cy + 0.8 * ch, x + 3.0);
            assert!((p.lateral_m - 0.8).abs() < 1e-6, "{p:?}");
            assert!((p.s_m - x).abs() < 1e-6);
        }
    }
}
