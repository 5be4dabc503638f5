//! Trunk compensation from an IMU on the sternum: the trunk's flexion, lateral lean and
//! rotation from the start posture, and how far and how long it moved.
//!
//! **Method.** The sternum IMU's orientation comes from the same 6-D fusion as the arm's
//! ([`crate::fusion`], VQF: Laidig & Seel 2023), whose heading is arbitrary but steady (the
//! gyro bias is estimated at rest and during tilting motion). The trunk's orientation is the
//! sensor's composed with the mounting, `T = Q_sensor · M⁻¹` (as for the arm's segments,
//! [`crate::mounting`]). Relative to the start posture `T₀` the rotation `T₀⁻¹ · T` is split
//! into the trunk's Cardan angles ([`crate::posture`]: flexion, lateral lean, axial rotation,
//! as the ISB recommends for the thorax); a relative rotation is free of the fusion's
//! arbitrary heading (it cancels in `T₀⁻¹ · T`).
//!
//! Everything is allocation-free per sample.

use nalgebra::UnitQuaternion;
use serde::{Deserialize, Serialize};

use crate::device::ImuSample;
use crate::error::{ImuError, check_range};
use crate::fusion::{FusionConfig, OrientationFilter};
pub use crate::posture::{AXES, TrunkAngles, trunk_angles, trunk_rotation};

/// Time the fusion needs before its inclination can be trusted (s): one accelerometer
/// time constant of the default fusion (`FusionConfig::tau_acc_s`, 3 s). The start posture is
/// taken no earlier, and not before the fusion has seen the trunk at rest once: until then the
/// gyro's turn-on bias (0.5°/s on consumer MEMS) is unknown, and the rotation about the
/// vertical, which only rest corrects, would drift by it (a session starts with the arm
/// sensors' hold-still step, which gives that rest).
pub const SETTLE_S: f64 = 3.0;

/// The trunk angles from the sternum IMU, tick by tick.
#[derive(Debug, Clone, Copy)]
pub struct TrunkEstimator {
    filter: OrientationFilter,
    /// Trunk-from-sensor: the inverse of the sensor-to-trunk mounting.
    mount_inv: UnitQuaternion<f64>,
    start: Option<UnitQuaternion<f64>>,
    running_s: f64,
    /// The fusion has declared rest at least once (its gyro bias is known).
    rested: bool,
    /// The start posture follows the trunk while it rests (after the start or a restart),
    /// until it first moves.
    start_open: bool,
    /// The last update (re)took the start posture.
    took_start: bool,
}

impl TrunkEstimator {
    /// An estimator for a sensor mounted at the sensor-to-trunk rotation `mount` (identity: the
    /// sensor's x points forward, y to the patient's left, z up), with fusion settings `fusion`.
    pub fn new(mount: UnitQuaternion<f64>, fusion: FusionConfig) -> Result<Self, ImuError> {
        Ok(Self {
            filter: OrientationFilter::new(fusion)?,
            mount_inv: mount.inverse(),
            start: None,
            running_s: 0.0,
            rested: false,
            start_open: true,
            took_start: false,
        })
    }

    /// The fusion settings for the sternum: the defaults, except that the rest detector's
    /// low-pass is 2 s instead of 0.5 s. A seated trunk is never quite still: it sways slowly
    /// (~0.1 Hz), and a rest bias taken from a short low-pass learns the sway's rate as gyro
    /// bias, which then turns the trunk's rotation about the vertical (measured with the
    /// `trunk_truth` test: rotation error 1.5–1.8° RMS with 0.5 s, 1.4–1.6° with 2 s).
    pub fn fusion_config() -> FusionConfig {
        let mut cfg = FusionConfig::default();
        cfg.rest.filter_tau_s = 2.0;
        cfg
    }

    /// Feed one sternum sample, `dt_s` after the previous one. Returns the trunk angles from
    /// the start posture, or `None` while the fusion settles ([`SETTLE_S`]: time, and a first
    /// rest); the posture then (or after [`Self::restart`]) is the start posture, following the
    /// trunk while it rests.
    pub fn update(&mut self, sample: &ImuSample, dt_s: f64) -> Option<TrunkAngles> {
        let q = self
            .filter
            .update(&sample.rate_rad_s, sample.acc_m_s2.as_ref(), dt_s);
        if dt_s.is_finite() && dt_s > 0.0 {
            self.running_s += dt_s;
        }
        let rest = self.filter.is_rest();
        self.rested |= rest;
        self.took_start = false;
        if self.running_s < SETTLE_S || !self.rested {
            return None;
        }
        let trunk = q * self.mount_inv;
        if self.start_open && (rest || self.start.is_none()) {
            self.start = Some(trunk);
            self.took_start = true;
        }
        self.start_open &= rest;
        let start = self.start.unwrap_or(trunk);
        Some(trunk_angles(&start, &trunk))
    }

    /// Take the next posture as the start posture (at an exercise's start); while the trunk
    /// rests the start follows it (the bias improves meanwhile), until it first moves.
    pub fn restart(&mut self) {
        self.start = None;
        self.start_open = true;
    }

    /// Whether the last [`Self::update`] (re)took the start posture: a comparison with the
    /// truth takes its start at the same sample.
    pub fn took_start(&self) -> bool {
        self.took_start
    }

    /// The fusion's gyro-bias estimate (rad/s, sensor frame).
    pub fn bias_rad_s(&self) -> nalgebra::Vector3<f64> {
        self.filter.bias_rad_s()
    }

    /// Whether the fusion's rest detector declares rest.
    pub fn is_rest(&self) -> bool {
        self.filter.is_rest()
    }

    /// Whether a start posture has been taken (angles are being given).
    pub fn is_tracking(&self) -> bool {
        self.start.is_some()
    }
}

/// How far and how long the trunk moved over a stretch (an exercise, a movement): per axis the
/// largest and the mean absolute excursion, and the share of time any axis was beyond the
/// threshold.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrunkExcursion {
    threshold_deg: f64,
    time_s: f64,
    beyond_s: f64,
    /// Time-weighted sum of |angle| per axis (deg·s).
    abs_sum_deg_s: [f64; 3],
    max_abs_deg: [f64; 3],
}

/// A summary of a [`TrunkExcursion`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TrunkSummary {
    /// Largest |angle| per axis (deg), in the order of [`AXES`].
    pub max_deg: [f64; 3],
    /// Time-weighted mean |angle| per axis (deg).
    pub mean_deg: [f64; 3],
    /// Share of the time any axis was beyond the threshold, in [0, 1].
    pub beyond_share: f64,
    /// Time covered (s).
    pub time_s: f64,
}

impl TrunkExcursion {
    /// An empty excursion counting time beyond `threshold_deg` (in (0, 90] deg) as
    /// compensating.
    pub fn new(threshold_deg: f64) -> Result<Self, ImuError> {
        check_range("threshold_deg", threshold_deg, 0.1, 90.0, "[0.1, 90] deg")?;
        Ok(Self {
            threshold_deg,
            time_s: 0.0,
            beyond_s: 0.0,
            abs_sum_deg_s: [0.0; 3],
            max_abs_deg: [0.0; 3],
        })
    }

    /// Add the angles `a` held for `dt_s` (non-finite input is skipped).
    pub fn add(&mut self, a: &TrunkAngles, dt_s: f64) {
        let v = a.to_array();
        if !(dt_s.is_finite() && dt_s > 0.0 && v.iter().all(|x| x.is_finite())) {
            return;
        }
        self.time_s += dt_s;
        for (i, x) in v.iter().enumerate() {
            self.abs_sum_deg_s[i] += x.abs() * dt_s;
            self.max_abs_deg[i] = self.max_abs_deg[i].max(x.abs());
        }
        if a.max_abs_deg() > self.threshold_deg {
            self.beyond_s += dt_s;
        }
    }

    /// Whether the trunk went beyond the threshold on any axis: a compensating movement.
    pub fn compensating(&self) -> bool {
        self.max_abs_deg.iter().any(|m| *m > self.threshold_deg)
    }

    /// Forget everything (the next movement starts).
    pub fn clear(&mut self) {
        self.time_s = 0.0;
        self.beyond_s = 0.0;
        self.abs_sum_deg_s = [0.0; 3];
        self.max_abs_deg = [0.0; 3];
    }

    /// The summary; `None` when nothing was added.
    pub fn summary(&self) -> Option<TrunkSummary> {
        (self.time_s > 0.0).then(|| TrunkSummary {
            max_deg: self.max_abs_deg,
            mean_deg: self.abs_sum_deg_s.map(|s| s / self.time_s),
            beyond_share: self.beyond_s / self.time_s,
            time_s: self.time_s,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn trunk_angles_undo_trunk_rotation_from_any_start_posture() {
        let start = UnitQuaternion::from_euler_angles(0.1, -0.2, 2.5);
        let a = TrunkAngles {
            flexion_deg: 25.0,
            lean_deg: -12.0,
            rotation_deg: 40.0,
        };
        let back = trunk_angles(&start, &(start * trunk_rotation(&a)));
        for (x, y) in back.to_array().iter().zip(a.to_array()) {
            assert!((x - y).abs() < 1e-9, "{back:?}");
        }
        // A pure forward bend of the trunk tips its top (z) toward its front (x).
        let bent = trunk_rotation(&TrunkAngles {
            flexion_deg: 30.0,
            ..TrunkAngles::default()
        }) * nalgebra::Vector3::z();
        assert!(bent.x > 0.49 && bent.y.abs() < 1e-12);
    }

    #[test]
    fn an_excursion_has_its_maxima_means_share_beyond_and_compensation() {
        let mut e = TrunkExcursion::new(10.0).unwrap();
        assert!(e.summary().is_none());
        let small = TrunkAngles {
            flexion_deg: 4.0,
            lean_deg: -2.0,
            rotation_deg: 6.0,
        };
        let big = TrunkAngles {
            rotation_deg: -15.0,
            ..small
        };
        e.add(&small, 3.0);
        assert!(!e.compensating());
        e.add(&big, 1.0);
        e.add(&small, f64::NAN);
        let s = e.summary().unwrap();
        assert_eq!(s.max_deg, [4.0, 2.0, 15.0]);
        assert!((s.mean_deg[2] - (18.0 + 15.0) / 4.0).abs() < 1e-12);
        assert!((s.beyond_share - 0.25).abs() < 1e-12 && e.compensating());
        e.clear();
        assert!(e.summary().is_none() && !e.compensating());
        assert!(
            TrunkExcursion::new(0.0)
                .unwrap_err()
                .to_string()
                .contains("threshold_deg")
        );
    }
}
