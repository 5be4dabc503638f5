//! Rate-gyro integration on SO(3), sensor models, orientation fusion, the arm–wheel chain and
//! IMU devices (thesis Chapter 4, §3.2.2).
//!
//! Everything except [`device`]'s HID backend is pure: no I/O, no threads, no clock; time comes
//! in as `dt` or timestamps.
//!
//! # Module map
//!
//! - [`so3`]: exponential and logarithm maps; [`integrate`]: strapdown gyro integration
//!   (eq. 4.8–4.13); [`bias`]: rest detection and gyro bias; [`sensor`]: sensor error models.
//! - [`fusion`]: gyro + accelerometer orientation with online bias (VQF's 6-D part).
//! - [`chain`]: orientation changes along a serial chain (eq. 4.16–4.24); [`arm`]: the
//!   arm–wheel chain and its joint angles; [`pose`]: the real-time arm pose from two IMUs and
//!   the wheel angle.
//! - [`mounting`]: where each IMU sits on its segment; [`procedure`]: the guided mounting
//!   procedure, tick by tick.
//! - [`posture`]: the trunk's angles from its start posture; [`trunk`]: those angles from a
//!   sternum IMU, and their excursions (trunk compensation).
//! - [`device`]: the `Imu` trait, samples, the game-controller report parsers and (feature
//!   `hid`) the hidapi backend; [`sim`]: simulated motion, arm, trunk and IMUs.
//! - [`error`]: the errors, [`ImuError`].
//!
//! # Example: the haptic thread's arm pose from a simulated patient
//!
//! ```
//! use gyro_imu::arm::ArmGeometry;
//! use gyro_imu::fusion::FusionConfig;
//! use gyro_imu::pose::{ArmPoseEstimator, Mounting};
//! use gyro_imu::sim::arm::{PatientArmConfig, SimArm, sine_road};
//! use nalgebra::UnitQuaternion;
//!
//! let id = UnitQuaternion::identity(); // sensor axes = segment axes (else: `mounting`)
//! let cfg = PatientArmConfig::default();
//! let mut arm = SimArm::consumer_mems(cfg, id, id, 1)?;
//! let mounting = Mounting { upper: id, fore: id };
//! let mut est = ArmPoseEstimator::new(cfg.geometry, mounting, FusionConfig::default())?;
//! let dt = 0.001;
//! for k in 0..2000 {
//!     let t = k as f64 * dt;
//!     let (wheel, wheel_rate) = sine_road(t, 0.8, 0.2, 0.25, 0.45); // from the wheel each tick
//!     arm.step((t * 1e9) as u64, wheel, wheel_rate, dt)?;
//!     let (upper, fore) = arm.latest().expect("one sample per step");
//!     let pose = est.update(wheel, &upper, &fore, dt)?; // no allocation
//!     assert!(pose.angles.elbow_flexion_rad.is_finite());
//! }
//! let rom = est.range_of_motion().range_rad(); // per-session ranges of motion
//! assert!(rom[3] > 0.0);
//! # Ok::<(), gyro_imu::ImuError>(())
//! ```

pub mod arm;
pub mod bias;
pub mod chain;
pub mod device;
pub mod error;
pub mod fusion;
pub mod integrate;
pub mod mounting;
pub mod pose;
pub mod posture;
pub mod procedure;
pub mod sensor;
pub mod sim;
pub mod so3;
pub mod trunk;

pub use error::ImuError;
