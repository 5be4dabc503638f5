//! Mounting calibration: where on the segment is each IMU, and turned how? (thesis §4.2.2: the
//! gyros sit at arbitrary places on the links.)
//!
//! A short guided procedure: (1) hold still with the wheel centred — each accelerometer measures
//! the "up" direction in its sensor frame, the chain model ([`crate::arm::solve`]) gives it in
//! the segment frame; (2) turn the wheel back and forth through its range, keeping the elbow
//! relaxed — each bias-corrected gyro sample is paired with the segment's body rate the chain
//! model predicts for the measured wheel angle and rate. The sensor-to-segment rotation is the
//! solution of Wahba's problem over all these pairs, gravity weighted 10× the whole sweep.
//! Forearm pronation that follows the wheel (`p·θ`, unknown gain `p`) changes the forearm's
//! predicted rate to `Rx(−p·θ)·ω_hinge + p·θ̇·e_x`; `p` is found by a 1-D search on Wahba's
//! loss. Zero pronation is, by convention, the pronation held in step (1).

use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};

use crate::arm::{self, ArmGeometry};
use crate::device::ImuSample;
use crate::error::ImuError;
use crate::pose::Mounting;
use crate::so3;

#[derive(Debug, Clone, Copy, Default)]
struct Sums {
    acc: Vector3<f64>,
    gyro_still: Vector3<f64>,
    n_still: usize,
    /// Σ ω_pred·ω_sᵀ over the sweep (segment × sensor).
    b0: Matrix3<f64>,
    /// Σ |ω_pred|².
    s_hh: f64,
}

/// One forearm sweep sample: bias-corrected sensor rate, the hinge frame's predicted body rate
/// at zero pronation, wheel angle and rate.
type ForeSample = (Vector3<f64>, Vector3<f64>, f64, f64);

/// Accumulates the two phases of the mounting procedure for both IMUs.
#[derive(Debug, Clone)]
pub struct MountingCalibrator {
    geo: ArmGeometry,
    swivel_rad: f64,
    upper: Sums,
    fore: Sums,
    fore_sweep: Vec<ForeSample>,
    wheel_still_sum: f64,
    rate2: f64,
    n_motion: usize,
}

/// Diagnostics of a mounting calibration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MountingReport {
    /// The sensor-to-segment rotations.
    pub mounting: Mounting,
    /// Angle between the aligned measured gravity and the model's (rad): (upper, fore).
    pub gravity_misfit_rad: (f64, f64),
    /// Estimated forearm pronation per unit wheel angle during the sweep.
    pub pronation_per_wheel: f64,
}

impl MountingCalibrator {
    /// A calibrator for `geometry`, assuming the elbow swivel `swivel_rad` during the procedure.
    pub fn new(geometry: ArmGeometry, swivel_rad: f64) -> Result<Self, ImuError> {
        geometry.validate()?;
        arm::solve(&geometry, 0.0, swivel_rad, 0.0)?;
        Ok(Self {
            geo: geometry,
            swivel_rad,
            upper: Sums::default(),
            fore: Sums::default(),
            fore_sweep: Vec::new(),
            wheel_still_sum: 0.0,
            rate2: 0.0,
            n_motion: 0,
        })
    }

    /// Make room for `n` motion samples now, so that [`MountingCalibrator::add_motion`] does
    /// not allocate on a real-time thread.
    pub fn reserve_motion(&mut self, n: usize) {
        self.fore_sweep
            .reserve(n.saturating_sub(self.fore_sweep.len()));
    }

    /// Phase 1: a sample while the patient holds still at wheel angle `wheel_rad`.
    pub fn add_still(
        &mut self,
        wheel_rad: f64,
        upper: &ImuSample,
        fore: &ImuSample,
    ) -> Result<(), ImuError> {
        let (Some(au), Some(af)) = (upper.acc_m_s2, fore.acc_m_s2) else {
            return Err(ImuError::Calibration(
                "mounting calibration needs accelerometers on both IMUs".into(),
            ));
        };
        if !(upper.is_finite() && fore.is_finite() && wheel_rad.is_finite()) {
            return Ok(());
        }
        self.upper.acc += au;
        self.fore.acc += af;
        self.upper.gyro_still += upper.rate_rad_s;
        self.fore.gyro_still += fore.rate_rad_s;
        self.upper.n_still += 1;
        self.fore.n_still += 1;
        self.wheel_still_sum += wheel_rad;
        Ok(())
    }

    /// Phase 2 (after phase 1): a sample while the wheel turns (angle `wheel_rad`, rate
    /// `wheel_rate_rad_s`).
    pub fn add_motion(
        &mut self,
        wheel_rad: f64,
        wheel_rate_rad_s: f64,
        upper: &ImuSample,
        fore: &ImuSample,
    ) -> Result<(), ImuError> {
        if self.upper.n_still == 0 {
            return Err(ImuError::Calibration(
                "hold still first: the motion phase needs the gyro bias from the still phase"
                    .into(),
            ));
        }
        if !(upper.is_finite()
            && fore.is_finite()
            && wheel_rad.is_finite()
            && wheel_rate_rad_s.is_finite())
        {
            return Ok(());
        }
        let h = 1e-4;
        let sm = arm::solve(
            &self.geo,
            wheel_rad - wheel_rate_rad_s * h,
            self.swivel_rad,
            0.0,
        )?;
        let sp = arm::solve(
            &self.geo,
            wheel_rad + wheel_rate_rad_s * h,
            self.swivel_rad,
            0.0,
        )?;
        let pu = so3::log(&(sm.upper.transpose() * sp.upper)) / (2.0 * h);
        let pf = so3::log(&(sm.fore.transpose() * sp.fore)) / (2.0 * h);
        let u = &mut self.upper;
        let wu = upper.rate_rad_s - u.gyro_still / u.n_still as f64;
        u.b0 += pu * wu.transpose();
        u.s_hh += pu.norm_squared();
        let wf = fore.rate_rad_s - self.fore.gyro_still / self.fore.n_still as f64;
        self.fore_sweep.push((wf, pf, wheel_rad, wheel_rate_rad_s));
        self.rate2 += wheel_rate_rad_s * wheel_rate_rad_s;
        self.n_motion += 1;
        Ok(())
    }

    /// Solve both mountings.
    pub fn finish(&self) -> Result<MountingReport, ImuError> {
        if self.upper.n_still < 10 {
            return Err(ImuError::Calibration(format!(
                "only {} still samples (need ≥ 10)",
                self.upper.n_still
            )));
        }
        if self.n_motion < 10 || self.rate2 < 1e-6 || self.upper.s_hh < 1e-9 {
            return Err(ImuError::Calibration(
                "the wheel did not turn during the motion phase".into(),
            ));
        }
        let wheel_still = self.wheel_still_sum / self.upper.n_still as f64;
        let st = arm::solve(&self.geo, wheel_still, self.swivel_rad, 0.0)?;
        let (mu, eu, _) = self.solve_one(&self.upper, &st.upper, false)?;
        let (mf, ef, pron) = self.solve_one(&self.fore, &st.fore, true)?;
        Ok(MountingReport {
            mounting: Mounting {
                upper: mu,
                fore: mf,
            },
            gravity_misfit_rad: (eu, ef),
            pronation_per_wheel: pron,
        })
    }

    /// Wahba's problem on the rate pairs plus the gravity pair (weighted 10× the whole sweep).
    /// For the forearm the pronation `p·θ` is unknown: the predicted body rate is
    /// `Rx(−p·θ)·ω_hinge + p·θ̇·e_x`, and `p` is found by a 1-D search on Wahba's loss.
    fn solve_one(
        &self,
        s: &Sums,
        seg: &Matrix3<f64>,
        fore: bool,
    ) -> Result<(UnitQuaternion<f64>, f64, f64), ImuError> {
        let g_s = (s.acc / s.n_still as f64).normalize();
        let wheel_still = self.wheel_still_sum / s.n_still as f64;
        let rx = |a: f64| so3::exp(&Vector3::new(a, 0.0, 0.0));
        // Gravity weight: 10× the sweep's predicted rate energy at zero pronation (fixed in p,
        // so the loss compares like with like across p).
        let w_g = 10.0
            * if fore {
                self.fore_sweep
                    .iter()
                    .map(|x| x.1.norm_squared())
                    .sum::<f64>()
            } else {
                s.s_hh
            }
            .max(1e-9);
        // Returns (loss, rotation, model gravity) for pronation gain p.
        let solve_p = |p: f64| -> (f64, Matrix3<f64>, Vector3<f64>) {
            let g_seg = rx(-p * wheel_still) * seg.transpose() * Vector3::z();
            let (b, s_pp) = if fore {
                let mut b = Matrix3::zeros();
                let mut s_pp = 0.0;
                for (w, h, th, thd) in &self.fore_sweep {
                    let pred = rx(-p * th) * h + Vector3::x() * (p * thd);
                    b += pred * w.transpose();
                    s_pp += pred.norm_squared();
                }
                (b, s_pp)
            } else {
                (s.b0, s.s_hh)
            };
            let (m, sigma) = wahba(&(b + g_seg * g_s.transpose() * w_g));
            (s_pp - 2.0 * sigma, m, g_seg)
        };
        let mut best_p = 0.0;
        if fore {
            let mut best = f64::INFINITY;
            for i in -30..=30 {
                let p = i as f64 * 0.05;
                let c = solve_p(p).0;
                if c < best {
                    best = c;
                    best_p = p;
                }
            }
            // Golden-section refinement within ±0.05.
            let (mut lo, mut hi) = (best_p - 0.05, best_p + 0.05);
            let r = (5f64.sqrt() - 1.0) / 2.0;
            for _ in 0..30 {
                let (a, b) = (hi - r * (hi - lo), lo + r * (hi - lo));
                if solve_p(a).0 < solve_p(b).0 {
                    hi = b;
                } else {
                    lo = a;
                }
            }
            best_p = 0.5 * (lo + hi);
        }
        let (_, m, g_seg) = solve_p(best_p);
        let q = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(m));
        let misfit = (q * g_s).angle(&g_seg);
        Ok((q, misfit, best_p))
    }
}

/// The rotation `M` maximising `tr(Mᵀ·B)` (Wahba's problem, by SVD) and that maximum.
fn wahba(b: &Matrix3<f64>) -> (Matrix3<f64>, f64) {
    let svd = b.svd(true, true);
    let (u, v_t) = (
        svd.u.unwrap_or_else(Matrix3::identity),
        svd.v_t.unwrap_or_else(Matrix3::identity),
    );
    let d = (u * v_t).determinant().signum();
    let m = u * Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, d)) * v_t;
    let sv = svd.singular_values;
    (m, sv[0] + sv[1] + d * sv[2])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sensor::{AccSpec, GyroSpec};
    use crate::sim::arm::{PatientArmConfig, SimArm, sine_road};
    use rand::{Rng, SeedableRng};

    /// Run the guided procedure on a simulated arm; returns the calibration report.
    pub(crate) fn calibrate(arm: &mut SimArm, t0_s: f64, dt: f64) -> MountingReport {
        let mut cal =
            MountingCalibrator::new(arm.config().geometry, arm.config().swivel_mean_rad).unwrap();
        let n_still = (5.0 / dt) as usize;
        let n_move = (20.0 / dt) as usize;
        for k in 0..n_still + n_move {
            let t = t0_s + k as f64 * dt;
            let (w, wd) = if k < n_still {
                (0.0, 0.0)
            } else {
                sine_road((k - n_still) as f64 * dt, 1.0, 0.25, 0.0, 0.1)
            };
            arm.step((t * 1e9) as u64, w, wd, dt).unwrap();
            let (u, f) = arm.latest().unwrap();
            if k < n_still {
                cal.add_still(w, &u, &f).unwrap();
            } else {
                cal.add_motion(w, wd, &u, &f).unwrap();
            }
        }
        cal.finish().unwrap()
    }

    #[test]
    fn random_mountings_are_recovered_within_2_deg() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        for trial in 0..4 {
            let mut rv = || {
                Vector3::new(
                    rng.random_range(-3.0..3.0),
                    rng.random_range(-3.0..3.0),
                    rng.random_range(-3.0..3.0),
                )
            };
            let (mu, mf) = (so3::exp_quat(&rv()), so3::exp_quat(&rv()));
            let cfg = PatientArmConfig {
                swivel_amp_rad: 0.0,
                swivel_per_wheel: 0.0,
                ..PatientArmConfig::default()
            };
            let mut arm = SimArm::new(
                cfg,
                GyroSpec::consumer_mems(),
                Some(AccSpec::consumer_mems()),
                mu,
                mf,
                40 + trial,
            )
            .unwrap();
            let rep = calibrate(&mut arm, 0.0, 0.005);
            let eu = so3::angle_between(&rep.mounting.upper, &mu).to_degrees();
            let ef = so3::angle_between(&rep.mounting.fore, &mf).to_degrees();
            println!(
                "trial {trial}: upper {eu:.2}°, fore {ef:.2}°, pron gain {:.3}",
                rep.pronation_per_wheel
            );
            assert!(eu < 2.0 && ef < 2.0, "upper {eu}°, fore {ef}°");
            assert!((rep.pronation_per_wheel - cfg.pronation_per_wheel).abs() < 0.05);
        }
    }

    #[test]
    fn no_motion_is_a_clear_error() {
        let mut cal = MountingCalibrator::new(ArmGeometry::default(), 0.3).unwrap();
        let s = ImuSample {
            t_ns: 0,
            rate_rad_s: Vector3::zeros(),
            acc_m_s2: Some(Vector3::z() * 9.81),
        };
        for _ in 0..20 {
            cal.add_still(0.0, &s, &s).unwrap();
        }
        assert!(
            cal.finish()
                .unwrap_err()
                .to_string()
                .contains("did not turn")
        );
        let gyro_only = ImuSample {
            acc_m_s2: None,
            ..s
        };
        assert!(cal.add_still(0.0, &gyro_only, &gyro_only).is_err());
    }
}
