//! Real-time arm pose from two IMUs and the wheel angle, for the 1 kHz haptic thread.
//!
//! With the wheel angle known the arm–wheel chain has one free degree of freedom (eq. 4.5–4.7),
//! the elbow swivel; forearm pronation is a second unknown. Each IMU runs an
//! [`OrientationFilter`] whose inclination is drift-free (the accelerometer, filtered in an
//! almost-inertial frame); its heading is not needed: [`ArmPoseEstimator`] fits swivel and
//! pronation so that the chain's predicted "up" direction in each segment frame matches the
//! measured one (a 2-parameter damped Gauss–Newton, warm-started from the last tick). Heading
//! drift therefore cannot leak into the joint angles. No allocation per update.

use nalgebra::{Matrix2, UnitQuaternion, Vector2, Vector3};

use crate::arm::{self, ArmGeometry, ArmState, JointAngles, RangeOfMotion};
use crate::device::ImuSample;
use crate::error::ImuError;
use crate::fusion::{FusionConfig, OrientationFilter};
use crate::so3;

/// Sensor-to-segment rotations of the two IMUs, as [`crate::mounting`] finds them.
pub use crate::mounting::Mounting;

/// One estimated arm pose.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArmPose {
    /// Joint angles (rad).
    pub angles: JointAngles,
    /// Elbow swivel about the shoulder–grip line (rad).
    pub swivel_rad: f64,
    /// Segment orientations and joint positions in the wheel frame.
    pub state: ArmState,
    /// RMS mismatch of the measured and fitted "up" directions (rad).
    pub fit_residual_rad: f64,
}

/// Chain-constrained arm pose estimator (see the module docs).
#[derive(Debug, Clone)]
pub struct ArmPoseEstimator {
    geo: ArmGeometry,
    mount: Mounting,
    upper: OrientationFilter,
    fore: OrientationFilter,
    params: Vector2<f64>,
    started: bool,
    rom: RangeOfMotion,
}

impl ArmPoseEstimator {
    /// An estimator for `geometry` with IMU `mounting` and fusion settings `fusion`.
    pub fn new(
        geometry: ArmGeometry,
        mounting: Mounting,
        fusion: FusionConfig,
    ) -> Result<Self, ImuError> {
        geometry.validate()?;
        arm::solve(&geometry, 0.0, 0.0, 0.0)?;
        Ok(Self {
            geo: geometry,
            mount: mounting,
            upper: OrientationFilter::new(fusion)?,
            fore: OrientationFilter::new(fusion)?,
            params: Vector2::zeros(),
            started: false,
            rom: RangeOfMotion::default(),
        })
    }

    /// Feed the wheel angle (rad) and one sample of each IMU, `dt_s` after the last update.
    /// Non-finite samples are ignored by the filters; an out-of-reach wheel angle is an error.
    pub fn update(
        &mut self,
        wheel_rad: f64,
        upper: &ImuSample,
        fore: &ImuSample,
        dt_s: f64,
    ) -> Result<ArmPose, ImuError> {
        if !wheel_rad.is_finite() {
            return Err(ImuError::InvalidInput(format!("wheel angle {wheel_rad}")));
        }
        if !self.started {
            // Start the filters at the chain's pose with the initial swivel (zero unless set)
            // and pronation zero; the accelerometer then fixes inclination on the first sample.
            let s = arm::solve(&self.geo, wheel_rad, self.params.x, 0.0)?;
            self.upper
                .set_orientation(arm::to_quat(&s.upper) * self.mount.upper);
            self.fore
                .set_orientation(arm::to_quat(&s.fore) * self.mount.fore);
            self.started = true;
        }
        let qu = self
            .upper
            .update(&upper.rate_rad_s, upper.acc_m_s2.as_ref(), dt_s);
        let qf = self
            .fore
            .update(&fore.rate_rad_s, fore.acc_m_s2.as_ref(), dt_s);
        // Measured "up" in each segment frame.
        let up_u = self.mount.upper * (qu.inverse() * Vector3::z());
        let up_f = self.mount.fore * (qf.inverse() * Vector3::z());
        // Every solve of the fit is at this tick's wheel angle: the grip point and the elbow's
        // circle are found once ([`arm::reach`]); a step in swivel alone keeps the forearm's
        // twist, a step in pronation alone the elbow, and the pose fitted is the last one
        // solved. The same arithmetic as a plain [`arm::solve`] per trial, bit for bit
        // (`the_fit_is_bit_for_bit_the_fit_by_plain_solves`), with a third of its sines and
        // cosines (issue 47: they were the haptic thread's largest cost at `--speed max`).
        let reach = arm::reach(&self.geo, self.geo.grip(wheel_rad))?;
        let swivel = |x: f64| reach.elbow((x.sin(), x.cos()));
        let twist = |y: f64| so3::exp(&Vector3::new(y, 0.0, 0.0));
        let residual = |s: &ArmState| -> [f64; 6] {
            let pu = s.upper.transpose() * Vector3::z();
            let pf = s.fore.transpose() * Vector3::z();
            [
                pu.x - up_u.x,
                pu.y - up_u.y,
                pu.z - up_u.z,
                pf.x - up_f.x,
                pf.y - up_f.y,
                pf.z - up_f.z,
            ]
        };
        // A trial's elbow or twist is the current one's when its angle has the same bits
        // (`x + 0.0` only differs from `x` at −0).
        let same = |a: f64, b: f64| a.to_bits() == b.to_bits();
        let mut p = self.params;
        let (mut elbow, mut turn) = (swivel(p.x), twist(p.y));
        let mut state = elbow.state(turn);
        let mut r0 = residual(&state);
        for _ in 0..3 {
            let h = 1e-6;
            let (pa, pb) = (p + Vector2::new(h, 0.0), p + Vector2::new(0.0, h));
            let turn_a = if same(pa.y, p.y) { turn } else { twist(pa.y) };
            let r_a = residual(&swivel(pa.x).state(turn_a));
            let elbow_b = if same(pb.x, p.x) { elbow } else { swivel(pb.x) };
            let r_b = residual(&elbow_b.state(twist(pb.y)));
            let (mut jtj, mut jtr) = (Matrix2::zeros(), Vector2::zeros());
            for i in 0..6 {
                let j = Vector2::new((r_a[i] - r0[i]) / h, (r_b[i] - r0[i]) / h);
                jtj += j * j.transpose();
                jtr += j * r0[i];
            }
            jtj += Matrix2::identity() * 1e-4;
            let Some(step) = jtj.try_inverse().map(|m| m * jtr) else {
                break;
            };
            let step = step.map(|x| x.clamp(-0.3, 0.3));
            let cand = p - step;
            let (elbow_c, turn_c) = (swivel(cand.x), twist(cand.y));
            let state_c = elbow_c.state(turn_c);
            let rc = residual(&state_c);
            if norm2(&rc) <= norm2(&r0) {
                p = cand;
                r0 = rc;
                (elbow, turn, state) = (elbow_c, turn_c, state_c);
            } else {
                break;
            }
            if step.norm() < 1e-9 {
                break;
            }
        }
        self.params = p;
        let angles = arm::joint_angles(&state.upper, &state.fore);
        self.rom.update(&angles);
        Ok(ArmPose {
            angles,
            swivel_rad: p.x,
            state,
            fit_residual_rad: (norm2(&r0) / 2.0).sqrt(),
        })
    }

    /// Ranges of motion accumulated since construction or the last [`Self::reset_range_of_motion`].
    pub fn range_of_motion(&self) -> &RangeOfMotion {
        &self.rom
    }

    /// Start from elbow swivel `swivel_rad` (rad, as in [`arm::solve`]) rather than zero: the
    /// swivel the patient holds (e.g. found by the mounting procedure). The filters' initial
    /// heading follows it, so a good value leaves no heading offset to drift from. Only before
    /// the first update.
    pub fn set_initial_swivel(&mut self, swivel_rad: f64) {
        if !self.started && swivel_rad.is_finite() {
            self.params.x = swivel_rad;
        }
    }

    /// Re-acquire the sensors' orientations after a gap in their samples (an IMU unplugged and
    /// plugged back): the next update starts the filters again at the chain's pose for its
    /// wheel angle and the swivel last fitted, as the first update does; the mounting, the
    /// gyro-bias estimates and the range of motion are kept.
    pub fn reacquire(&mut self) {
        self.started = false;
    }

    /// Start a new range-of-motion accumulation (e.g. a new exercise).
    pub fn reset_range_of_motion(&mut self) {
        self.rom = RangeOfMotion::default();
    }

    /// Current sensor-to-earth orientations of the two IMUs (upper, fore); the earth frame's
    /// heading is the wheel frame's at the first update and may drift slowly.
    pub fn sensor_orientations(&self) -> (UnitQuaternion<f64>, UnitQuaternion<f64>) {
        (self.upper.orientation(), self.fore.orientation())
    }

    /// Current gyro-bias estimates (rad/s, sensor frames): (upper, fore).
    pub fn bias_rad_s(&self) -> (Vector3<f64>, Vector3<f64>) {
        (self.upper.bias_rad_s(), self.fore.bias_rad_s())
    }
}

fn norm2(r: &[f64; 6]) -> f64 {
    r.iter().map(|x| x * x).sum()
}

#[cfg(test)]
mod tests;
