//! Mounting calibration: where on the segment is each IMU, and turned how? (thesis §4.2.2: the
//! gyros sit at arbitrary places on the links.)
//!
//! A short guided procedure: (1) hold still with the wheel centred — each accelerometer measures
//! the "up" direction in its sensor frame, the chain model ([`crate::arm::solve`]) gives it in
//! the segment frame; (2) turn the wheel back and forth through its range, keeping the elbow
//! relaxed — regressing each gyro's bias-corrected rate on the wheel rate gives the segment's
//! mean rotation axis per unit wheel rate in the sensor frame, which the chain model predicts
//! in the segment frame. Two vector pairs per sensor fix its rotation (TRIAD, gravity first).
//! Forearm pronation that follows the wheel adds an unknown rate about the forearm's long axis;
//! its gain is solved from the fact that rotations preserve the angle between the two vectors.
//! Zero pronation is, by convention, the pronation held in step (1).

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
    gyro_wheel: Vector3<f64>,
    gyro_sum: Vector3<f64>,
    pred_wheel: Vector3<f64>,
}

/// Accumulates the two phases of the mounting procedure for both IMUs.
#[derive(Debug, Clone)]
pub struct MountingCalibrator {
    geo: ArmGeometry,
    swivel_rad: f64,
    upper: Sums,
    fore: Sums,
    wheel_still_sum: f64,
    rate2: f64,
    rate_sum: f64,
    n_motion: usize,
}

/// Diagnostics of a mounting calibration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MountingReport {
    /// The sensor-to-segment rotations.
    pub mounting: Mounting,
    /// Angle between gravity and rotation axis in each segment frame (rad): (upper, fore);
    /// the larger, the better conditioned.
    pub conditioning_rad: (f64, f64),
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
            wheel_still_sum: 0.0,
            rate2: 0.0,
            rate_sum: 0.0,
            n_motion: 0,
        })
    }

    /// Phase 1: a sample while the patient holds still at wheel angle `wheel_rad`.
    pub fn add_still(&mut self, wheel_rad: f64, upper: &ImuSample, fore: &ImuSample) -> Result<(), ImuError> {
        let (Some(au), Some(af)) = (upper.acc_m_s2, fore.acc_m_s2) else {
            return Err(ImuError::Calibration("mounting calibration needs accelerometers on both IMUs".into()));
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

    /// Phase 2: a sample while the wheel turns (angle `wheel_rad`, rate `wheel_rate_rad_s`).
    pub fn add_motion(&mut self, wheel_rad: f64, wheel_rate_rad_s: f64, upper: &ImuSample, fore: &ImuSample) -> Result<(), ImuError> {
        if !(upper.is_finite() && fore.is_finite() && wheel_rad.is_finite() && wheel_rate_rad_s.is_finite()) {
            return Ok(());
        }
        let h = 1e-4;
        let sm = arm::solve(&self.geo, wheel_rad - wheel_rate_rad_s * h, self.swivel_rad, 0.0)?;
        let sp = arm::solve(&self.geo, wheel_rad + wheel_rate_rad_s * h, self.swivel_rad, 0.0)?;
        let pu = so3::log(&(sm.upper.transpose() * sp.upper)) / (2.0 * h);
        let pf = so3::log(&(sm.fore.transpose() * sp.fore)) / (2.0 * h);
        for (s, w, p) in [(&mut self.upper, upper.rate_rad_s, pu), (&mut self.fore, fore.rate_rad_s, pf)] {
            s.gyro_wheel += w * wheel_rate_rad_s;
            s.gyro_sum += w;
            s.pred_wheel += p * wheel_rate_rad_s;
        }
        self.rate2 += wheel_rate_rad_s * wheel_rate_rad_s;
        self.rate_sum += wheel_rate_rad_s;
        self.n_motion += 1;
        Ok(())
    }

    /// Solve both mountings.
    pub fn finish(&self) -> Result<MountingReport, ImuError> {
        if self.upper.n_still < 10 {
            return Err(ImuError::Calibration(format!("only {} still samples (need ≥ 10)", self.upper.n_still)));
        }
        if self.n_motion < 10 || self.rate2 < 1e-6 {
            return Err(ImuError::Calibration("the wheel did not turn during the motion phase".into()));
        }
        let wheel_still = self.wheel_still_sum / self.upper.n_still as f64;
        let st = arm::solve(&self.geo, wheel_still, self.swivel_rad, 0.0)?;
        let solve_one = |s: &Sums, seg: &Matrix3<f64>, fore: bool| -> Result<(UnitQuaternion<f64>, f64, f64), ImuError> {
            let g_s = (s.acc / s.n_still as f64).normalize();
            let bias = s.gyro_still / s.n_still as f64;
            // Regression of the bias-corrected gyro on the wheel rate.
            let a_s = (s.gyro_wheel - bias * self.rate_sum) / self.rate2;
            let g_seg = seg.transpose() * Vector3::z();
            let mut a_seg = s.pred_wheel / self.rate2;
            let mut pron = 0.0;
            if fore && g_seg.x.abs() > 0.1 {
                pron = (a_s.dot(&g_s) - a_seg.dot(&g_seg)) / g_seg.x;
                a_seg += Vector3::x() * pron;
            }
            let cond = g_seg.angle(&a_seg);
            if cond < 10f64.to_radians() || a_s.norm() < 1e-3 {
                return Err(ImuError::Calibration(format!(
                    "{} IMU: rotation axis only {:.1}° from vertical; turn the wheel further",
                    if fore { "forearm" } else { "upper-arm" },
                    cond.to_degrees()
                )));
            }
            Ok((triad(&g_s, &a_s, &g_seg, &a_seg), cond, pron))
        };
        let (mu, cu, _) = solve_one(&self.upper, &st.upper, false)?;
        let (mf, cf, pron) = solve_one(&self.fore, &st.fore, true)?;
        Ok(MountingReport { mounting: Mounting { upper: mu, fore: mf }, conditioning_rad: (cu, cf), pronation_per_wheel: pron })
    }
}

/// The rotation `M` with `M·v1 = w1` exactly and `M·v2` as close to `w2` as possible (TRIAD).
pub fn triad(v1: &Vector3<f64>, v2: &Vector3<f64>, w1: &Vector3<f64>, w2: &Vector3<f64>) -> UnitQuaternion<f64> {
    let frame = |a: &Vector3<f64>, b: &Vector3<f64>| {
        let x = a.normalize();
        let y = x.cross(b).normalize();
        Matrix3::from_columns(&[x, y, x.cross(&y)])
    };
    let m = frame(w1, w2) * frame(v1, v2).transpose();
    UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(m))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sensor::{AccSpec, GyroSpec};
    use crate::sim::arm::{PatientArmConfig, SimArm, sine_road};
    use rand::{Rng, SeedableRng};

    /// Run the guided procedure on a simulated arm; returns the calibration report.
    pub(crate) fn calibrate(arm: &mut SimArm, t0_s: f64, dt: f64) -> MountingReport {
        let mut cal = MountingCalibrator::new(arm.config().geometry, arm.config().swivel_mean_rad).unwrap();
        let n_still = (5.0 / dt) as usize;
        let n_move = (20.0 / dt) as usize;
        for k in 0..n_still + n_move {
            let t = t0_s + k as f64 * dt;
            let (w, wd) = if k < n_still { (0.0, 0.0) } else { sine_road((k - n_still) as f64 * dt, 1.0, 0.25, 0.0, 0.1) };
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
            let mut rv = || Vector3::new(rng.random_range(-3.0..3.0), rng.random_range(-3.0..3.0), rng.random_range(-3.0..3.0));
            let (mu, mf) = (so3::exp_quat(&rv()), so3::exp_quat(&rv()));
            let cfg = PatientArmConfig { swivel_amp_rad: 0.0, swivel_per_wheel: 0.0, ..PatientArmConfig::default() };
            let mut arm = SimArm::new(cfg, GyroSpec::consumer_mems(), Some(AccSpec::consumer_mems()), mu, mf, 40 + trial).unwrap();
            let rep = calibrate(&mut arm, 0.0, 0.005);
            let eu = so3::angle_between(&rep.mounting.upper, &mu).to_degrees();
            let ef = so3::angle_between(&rep.mounting.fore, &mf).to_degrees();
            println!("trial {trial}: upper {eu:.2}°, fore {ef:.2}°, cond {:.0}°/{:.0}°, pron gain {:.3}", rep.conditioning_rad.0.to_degrees(), rep.conditioning_rad.1.to_degrees(), rep.pronation_per_wheel);
            assert!(eu < 2.0 && ef < 2.0, "upper {eu}°, fore {ef}°");
            assert!((rep.pronation_per_wheel - cfg.pronation_per_wheel).abs() < 0.05);
        }
    }

    #[test]
    fn no_motion_is_a_clear_error() {
        let mut cal = MountingCalibrator::new(ArmGeometry::default(), 0.3).unwrap();
        let s = ImuSample { t_ns: 0, rate_rad_s: Vector3::zeros(), acc_m_s2: Some(Vector3::z() * 9.81) };
        for _ in 0..20 {
            cal.add_still(0.0, &s, &s).unwrap();
        }
        assert!(cal.finish().unwrap_err().to_string().contains("did not turn"));
        let gyro_only = ImuSample { acc_m_s2: None, ..s };
        assert!(cal.add_still(0.0, &gyro_only, &gyro_only).is_err());
    }

    #[test]
    fn triad_maps_the_first_vector_exactly() {
        let m = so3::exp_quat(&Vector3::new(0.3, -1.2, 2.0));
        let (v1, v2) = (Vector3::new(0.1, 0.2, 0.97), Vector3::new(1.0, 0.0, 0.1));
        let r = triad(&v1, &v2, &(m * v1), &(m * v2));
        assert!(so3::angle_between(&r, &m) < 1e-12);
    }
}
