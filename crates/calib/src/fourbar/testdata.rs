//! The simulated four-bar recording that the tests, the benchmark and the noise-study example
//! share: one arm, one wheel motion, noise-free, so each of them adds its own noise.
//!
//! The arm is the one of the thesis's noise study (Table 4.1): l1 = 0.45, l2 = 0.15,
//! l3 = 0.35, l4 = 0.30 m, elbow up, wheel crank at π/2; the wheel swings ±`amp_deg` at 0.2 Hz,
//! sampled at 100 Hz.

use super::{FourbarGeometry, FourbarParams, FourbarSamples};

/// Wheel crank length l2 of [`GEOMETRY`] (m), the known length [`super::calibrate`] takes.
pub const L2: f64 = 0.15;

/// The simulated arm–wheel loop (m).
pub const GEOMETRY: FourbarGeometry = FourbarGeometry {
    l1_m: 0.45,
    l2_m: L2,
    l3_m: 0.35,
    l4_m: 0.30,
    elbow_branch: 1.0,
};

/// Wheel crank angle at the start of the recording, θ2(0) (rad).
pub const THETA2_0: f64 = std::f64::consts::FRAC_PI_2;

/// A noise-free recording of relative angles (rad) with its timestamps (s) and the true
/// parameters.
#[derive(Debug, Clone)]
pub struct Recording {
    /// Wheel angle relative to the start, φ2 (rad).
    pub phi2: Vec<f64>,
    /// Forearm angle relative to the start, φ3 (rad).
    pub phi3: Vec<f64>,
    /// Upper-arm angle relative to the start, φ4 (rad).
    pub phi4: Vec<f64>,
    /// Sample times (s), 100 Hz from 0.
    pub time_s: Vec<f64>,
    /// The parameters that generated the recording.
    pub truth: FourbarParams,
}

/// `n` samples of [`GEOMETRY`] with the wheel swinging ±`amp_deg` degrees at 0.2 Hz, 100 Hz.
///
/// # Panics
///
/// If the arm cannot reach the wheel at some sample; it can for the swings used in the tests,
/// benchmark and example (±15° and ±60°).
pub fn recording(n: usize, amp_deg: f64) -> Recording {
    let time_s: Vec<f64> = (0..n).map(|k| k as f64 * 0.01).collect();
    let phi2: Vec<f64> = time_s
        .iter()
        .map(|t| amp_deg.to_radians() * (std::f64::consts::TAU * 0.2 * t).sin())
        .collect();
    let (phi3, phi4, t3, t4) = GEOMETRY
        .simulate(THETA2_0, &phi2)
        .expect("the test arm closes its loop");
    let truth = FourbarParams::new(
        GEOMETRY.l1_m,
        GEOMETRY.l3_m,
        GEOMETRY.l4_m,
        THETA2_0,
        t3,
        t4,
    );
    Recording {
        phi2,
        phi3,
        phi4,
        time_s,
        truth,
    }
}

impl Recording {
    /// The recording as calibration input, with its timestamps.
    pub fn samples(&self) -> FourbarSamples<'_> {
        FourbarSamples {
            time_s: Some(&self.time_s),
            ..FourbarSamples::new(&self.phi2, &self.phi3, &self.phi4)
        }
    }
}
