//! The raw inputs of a session, recorded so that its pure part (vehicle, haptic model and
//! effects, assist, safety chain, arm fusion and pose, scores) can be re-run from them bit for
//! bit — a real-device session as well as a simulated one (`telerehab replay`).
//!
//! Two block channels ([`super::blocks`]):
//!
//! - `/raw/wheel`, every tick ([`RawWheelSample`]): the wheel's read as the device gave it
//!   (its angle, its timestamp, or the fault it reported), the body clock the haptic chain
//!   measured its period on, the patient's pause and stop, and what the arm tracker was
//!   handed that tick besides samples (stepped or not, a sensor lost, the mounting solver's
//!   answer or time-out, which arrive from another thread and the wall clock).
//! - `/raw/imu`, every IMU sample the arm tracker consumed ([`RawImuSample`]): which sensor,
//!   its device timestamp, gyro and accelerometer; a sample held over ticks (zero-order hold
//!   between a device's reports) is recorded once.
//!
//! Bit for bit: the device edge puts every float input on the recording's grid
//! ([`on_grid`]: 1 µrad for a wheel angle, 100 µrad/s for a gyro rate and 100 µm/s² for a
//! specific force: 10 to 200 times finer than a wheel encoder or a controller IMU resolves)
//! before the pure code sees it, so what was consumed is exactly what reads back; timestamps
//! are whole nanoseconds.

use super::blocks::{quantise, unquantise};
use haptic_wheel::DeviceProfile;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// Quantum of an angle input, rad (the `/raw/wheel` column `angle_rad`).
pub const ANGLE_QUANTUM_RAD: f64 = 1e-6;
/// Quantum of a gyro input, rad/s.
pub const RATE_QUANTUM_RAD_S: f64 = 1e-4;
/// Quantum of an accelerometer input, m/s².
pub const ACC_QUANTUM_M_S2: f64 = 1e-4;
/// Quantum of a torque, N·m (the simulated hand's, which a replay takes from `/wheel`).
pub const TORQUE_QUANTUM_NM: f64 = 1e-6;

/// Quantum of a pedal's travel (the `/raw/wheel` columns `throttle`, `brake`: unitless).
pub const PEDAL_QUANTUM: f64 = 1e-9;

/// `x` on the recording's grid of `quantum`: the value a block records and reads back
/// (NaN and infinities kept). Idempotent, so a value on the grid records as itself.
pub fn on_grid(x: f64, quantum: f64) -> f64 {
    unquantise(quantise(x, quantum), quantum).unwrap_or(x)
}

/// What a tick's read of the wheel returned.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
#[schemars(inline)]
pub enum RawRead {
    /// A reading (its angle may still be NaN or infinite: the chain treats it as none).
    #[default]
    Ok,
    /// The wheel was unplugged.
    Unplugged,
    /// The wheel stopped reporting while a torque was commanded.
    Silent,
    /// The wheel reported an angle outside its range.
    OutOfRange,
    /// Another read error (no fault: the chain sees a missing reading).
    Error,
}

/// One tick's raw inputs (channel `/raw/wheel`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct RawWheelSample {
    /// What the wheel's read returned.
    pub read: RawRead,
    /// The reading's angle as the device gave it, rad (0 without a reading; NaN kept).
    pub angle_rad: f64,
    /// When the reading was taken, ns on the body clock (0 without a reading).
    pub reading_t_ns: u64,
    /// Now on the body clock when the haptic chain ran, ns (its period is measured on it).
    pub now_ns: u64,
    /// The patient had the exercise paused.
    pub paused: bool,
    /// A stop had been asked for (the patient, a signal, or the session's own end).
    pub stop: bool,
    /// The arm tracker was stepped this tick (both IMUs had delivered).
    pub arm_stepped: bool,
    /// An IMU stopped answering this tick.
    pub arm_lost: bool,
    /// The lost IMU answered again this tick.
    pub arm_regained: bool,
    /// The mounting solver's answer was in hand (while the set-up waited for it).
    pub solver_answered: bool,
    /// The mounting solver timed out this tick.
    pub solver_timed_out: bool,
    /// The accelerator pedal, 0 (released) to 1 (absent from recordings older than pedals:
    /// released).
    #[serde(default)]
    pub throttle: f64,
    /// The brake pedal, 0 (released) to 1 (absent from older recordings: released).
    #[serde(default)]
    pub brake: f64,
    /// The wheel refused this tick's force command (the ceiling's or the torque's write
    /// failed); absent from recordings older than it: taken.
    #[serde(default)]
    pub write_failed: bool,
}

/// One IMU sample as the arm tracker consumed it (channel `/raw/imu`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct RawImuSample {
    /// Which sensor: 0 or 1, in the order the devices were opened (the guided procedure finds
    /// which is on the upper arm; simulated: 0 upper arm, 1 forearm).
    pub sensor: u32,
    /// The sample's device timestamp, ns on the clock its driver anchors it to.
    pub device_t_ns: u64,
    /// Gyro, sensor x, rad/s.
    pub gyro_x_rad_s: f64,
    /// Gyro, sensor y, rad/s.
    pub gyro_y_rad_s: f64,
    /// Gyro, sensor z, rad/s.
    pub gyro_z_rad_s: f64,
    /// Specific force, sensor x, m/s² (absent without an accelerometer).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(with = "f64")]
    pub acc_x_m_s2: Option<f64>,
    /// Specific force, sensor y, m/s² (absent without an accelerometer).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(with = "f64")]
    pub acc_y_m_s2: Option<f64>,
    /// Specific force, sensor z, m/s² (absent without an accelerometer).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(with = "f64")]
    pub acc_z_m_s2: Option<f64>,
}

impl RawImuSample {
    /// The sample of `sensor` as recorded.
    pub fn of(sensor: u32, s: &gyro_imu::device::ImuSample) -> Self {
        Self {
            sensor,
            device_t_ns: s.t_ns,
            gyro_x_rad_s: s.rate_rad_s.x,
            gyro_y_rad_s: s.rate_rad_s.y,
            gyro_z_rad_s: s.rate_rad_s.z,
            acc_x_m_s2: s.acc_m_s2.map(|a| a.x),
            acc_y_m_s2: s.acc_m_s2.map(|a| a.y),
            acc_z_m_s2: s.acc_m_s2.map(|a| a.z),
        }
    }

    /// The sample the tracker consumed (an accelerometer reading needs all three axes).
    pub fn sample(&self) -> gyro_imu::device::ImuSample {
        let acc = match (self.acc_x_m_s2, self.acc_y_m_s2, self.acc_z_m_s2) {
            (Some(x), Some(y), Some(z)) => Some(nalgebra::Vector3::new(x, y, z)),
            _ => None,
        };
        gyro_imu::device::ImuSample {
            t_ns: self.device_t_ns,
            rate_rad_s: nalgebra::Vector3::new(
                self.gyro_x_rad_s,
                self.gyro_y_rad_s,
                self.gyro_z_rad_s,
            ),
            acc_m_s2: acc,
        }
    }
}

/// `s` on the recording's grid (gyro to 100 µrad/s, accelerometer to 100 µm/s²): what the arm
/// tracker consumes, so that `/raw/imu` holds exactly that.
pub fn imu_on_grid(s: &gyro_imu::device::ImuSample) -> gyro_imu::device::ImuSample {
    gyro_imu::device::ImuSample {
        t_ns: s.t_ns,
        rate_rad_s: s.rate_rad_s.map(|x| on_grid(x, RATE_QUANTUM_RAD_S)),
        acc_m_s2: s.acc_m_s2.map(|a| a.map(|x| on_grid(x, ACC_QUANTUM_M_S2))),
    }
}

/// Whether two samples are the same bit for bit (a NaN equals itself here).
pub fn same_sample(a: &gyro_imu::device::ImuSample, b: &gyro_imu::device::ImuSample) -> bool {
    let bits = |v: &nalgebra::Vector3<f64>| [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()];
    a.t_ns == b.t_ns
        && bits(&a.rate_rad_s) == bits(&b.rate_rad_s)
        && a.acc_m_s2.map(|v| bits(&v)) == b.acc_m_s2.map(|v| bits(&v))
}

/// One tick's raw inputs: the `/raw/wheel` sample and the IMU samples new this tick.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RawTick {
    /// The tick's `/raw/wheel` sample.
    pub wheel: RawWheelSample,
    /// The sample of sensor 0 and of sensor 1 the tracker consumed, when new this tick.
    pub imu: [Option<RawImuSample>; 2],
}

/// Who held the wheel, as the session's metadata says (key `body`, JSON): what a replay of
/// the raw inputs needs besides them to rebuild the pure part.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BodyFacts {
    /// `simulated` or `real`.
    pub kind: BodyKindName,
    /// The wheel's profile as the plant read it (angle scale, motor rating and its source).
    pub wheel_profile: DeviceProfile,
    /// The wheel's usable maximum torque the backend reported, N·m.
    pub wheel_max_torque_nm: f64,
    /// The encoder step the velocity estimator was tuned for, rad.
    pub encoder_step_rad: f64,
    /// The arm tracker, if the session had arm sensing.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub arm: Option<ArmFacts>,
    /// How long the session waited for an unplugged wheel to come back, ns (`[haptic]
    /// replug_grace_s` as the plant applied it). `None` in recordings made before it was
    /// recorded: a real wheel then had no grace, a simulated one the configured grace.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub replug_grace_ns: Option<u64>,
}

/// Simulated or real.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum BodyKindName {
    /// The simulated wheel, patient and IMUs.
    Simulated,
    /// A real wheel held by the patient, maybe with controller IMUs.
    Real,
}

/// How the arm tracker was built.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ArmFacts {
    /// The guided mounting procedure first (`false`: the IMUs sat square on the segments and
    /// tracking began at once, simulation only).
    pub guided: bool,
    /// The arm geometry the tracker assumed.
    pub geometry: gyro_imu::arm::ArmGeometry,
    /// The elbow swivel assumed at the start, rad.
    pub swivel_rad: f64,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::blocks::quantum_of;
    use nalgebra::Vector3;

    #[test]
    fn the_grid_is_the_recorded_quantum_and_a_value_on_it_records_as_itself() {
        assert_eq!(ANGLE_QUANTUM_RAD, quantum_of("angle_rad"));
        assert_eq!(RATE_QUANTUM_RAD_S, quantum_of("gyro_x_rad_s"));
        assert_eq!(ACC_QUANTUM_M_S2, quantum_of("acc_x_m_s2"));
        assert_eq!(TORQUE_QUANTUM_NM, quantum_of("hand_nm"));
        assert_eq!(PEDAL_QUANTUM, quantum_of("throttle"));
        assert_eq!(PEDAL_QUANTUM, quantum_of("brake"));
        for x in [
            0.123_456_789_1,
            -3.000_000_4,
            9.81,
            1e-7,
            -0.0,
            12_345.678_9,
        ] {
            for q in [ANGLE_QUANTUM_RAD, RATE_QUANTUM_RAD_S] {
                let g = on_grid(x, q);
                assert!((g - x).abs() <= 0.5 * q * (1.0 + 1e-9), "{x} → {g}");
                assert_eq!(on_grid(g, q).to_bits(), g.to_bits(), "{x}");
            }
        }
        assert!(on_grid(f64::NAN, 1e-6).is_nan());
        assert_eq!(on_grid(f64::NEG_INFINITY, 1e-6), f64::NEG_INFINITY);
    }

    #[test]
    fn an_imu_sample_round_trips_through_its_raw_row() {
        let s = gyro_imu::device::ImuSample {
            t_ns: 1_234_567_891,
            rate_rad_s: Vector3::new(0.1, -0.2, f64::NAN),
            acc_m_s2: Some(Vector3::new(0.0, 1.5, 9.81)),
        };
        let g = imu_on_grid(&s);
        let back = RawImuSample::of(1, &g).sample();
        assert!(same_sample(&back, &g));
        let no_acc = gyro_imu::device::ImuSample {
            acc_m_s2: None,
            ..g
        };
        assert_eq!(RawImuSample::of(0, &no_acc).sample().acc_m_s2, None);
        assert!(!same_sample(&no_acc, &g));
    }
}
