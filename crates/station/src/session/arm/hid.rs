//! The real patient's arm: two game-controller IMUs over HID (DualShock 4, DualSense,
//! Joy-Con, Pro Controller; see `telerehab devices`) strapped to the upper arm and forearm,
//! either way round. Polled without blocking on the haptic thread; allocation-free per tick.

use super::{ArmTracker, WheelNow};
use crate::record::ArmSample;
use anyhow::Context;
use gyro_imu::ImuError;
use gyro_imu::arm::ArmGeometry;
use gyro_imu::device::hid::HidImu;
use gyro_imu::device::{Imu, ImuSample};

/// Samples one poll may return per device (a Joy-Con report carries three).
const POLL_CAPACITY: usize = 24;

/// One opened controller and its newest sample.
struct Source {
    imu: HidImu,
    buf: [ImuSample; POLL_CAPACITY],
    latest: Option<ImuSample>,
    failed: bool,
}

impl Source {
    /// Take what arrived since the last tick and hold it until the next arrival (zero-order
    /// hold at the device's rate). A read error (unplugged) stops this source; it is returned
    /// once.
    fn poll(&mut self) -> Result<(), ImuError> {
        if self.failed {
            return Ok(());
        }
        match self.imu.poll(&mut self.buf) {
            Ok(0) => Ok(()),
            Ok(n) => {
                self.latest = Some(mean_sample(&self.buf[..n]));
                Ok(())
            }
            Err(e) => {
                self.failed = true;
                Err(e)
            }
        }
    }
}

/// One sample standing for several that arrived together (a Joy-Con report carries three):
/// the mean rate, so the integral over the interval is kept rather than the newest sample's
/// alone, the mean specific force, and the newest time. `samples` must not be empty.
fn mean_sample(samples: &[ImuSample]) -> ImuSample {
    let last = samples[samples.len() - 1];
    if samples.len() == 1 {
        return last;
    }
    let n = samples.len() as f64;
    let rate = samples
        .iter()
        .map(|s| s.rate_rad_s)
        .sum::<nalgebra::Vector3<f64>>()
        / n;
    let acc = samples
        .iter()
        .map(|s| s.acc_m_s2)
        .try_fold(nalgebra::Vector3::zeros(), |sum, a| a.map(|a| sum + a))
        .map(|sum| sum / n);
    ImuSample {
        t_ns: last.t_ns,
        rate_rad_s: rate,
        acc_m_s2: acc,
    }
}

/// Two controller IMUs and the tracker (which runs the guided procedure first).
pub struct HidArmSensing {
    a: Source,
    b: Source,
    tracker: ArmTracker,
    last: ArmSample,
}

impl HidArmSensing {
    /// Open the first two supported controllers found, for a patient of `geometry`; `None`
    /// (with the reason logged) when fewer than two are present. `clock_ns` is the clock the
    /// device timestamps are anchored to; `clock` times the guided procedure's solver out.
    pub fn open_first_two(
        geometry: ArmGeometry,
        swivel_rad: f64,
        clock_ns: fn() -> u64,
        clock: clock::Clock,
    ) -> anyhow::Result<Option<Self>> {
        let found = match gyro_imu::device::enumerate() {
            Ok(f) => f,
            Err(e) => {
                tracing::info!("no arm sensing: {e}");
                return Ok(None);
            }
        };
        if found.len() < 2 {
            tracing::info!(
                found = found.len(),
                "no arm sensing: it needs two controller IMUs, one on the upper arm and one on the forearm (see `telerehab devices`)"
            );
            return Ok(None);
        }
        let open = |i: usize| -> anyhow::Result<Source> {
            let (imu, warning) = HidImu::open(&found[i], clock_ns)
                .with_context(|| format!("cannot open IMU {}", found[i].name))?;
            if let Some(w) = warning {
                tracing::warn!("IMU {}: using nominal scales ({w})", found[i].name);
            }
            Ok(Source {
                imu,
                buf: [ImuSample {
                    t_ns: 0,
                    rate_rad_s: nalgebra::Vector3::zeros(),
                    acc_m_s2: None,
                }; POLL_CAPACITY],
                latest: None,
                failed: false,
            })
        };
        let (a, b) = (open(0)?, open(1)?);
        tracing::info!(
            first = %found[0].name,
            second = %found[1].name,
            "arm sensing: two IMUs open; the guided procedure finds which is on the upper arm"
        );
        Ok(Some(Self {
            a,
            b,
            // Real IMUs: the solver times out on the session's (real) clock.
            tracker: ArmTracker::guided(geometry, swivel_rad, true, clock)?,
            last: ArmSample::default(),
        }))
    }

    /// Where the arm sensing is.
    pub fn setup_step(&self) -> super::SetupStep {
        self.tracker.step_now()
    }

    /// Poll both devices and update the pose; before both have delivered a sample the
    /// previous sample is kept, and after one stops the pose stays frozen (the tracker says
    /// why in the session report).
    pub fn step(&mut self, wheel: WheelNow) -> ArmSample {
        for source in [&mut self.a, &mut self.b] {
            if let Err(e) = source.poll() {
                self.tracker.lose_sensor(e);
            }
        }
        if let (Some(a), Some(b)) = (self.a.latest, self.b.latest) {
            self.last = self.tracker.update(wheel, &a, &b);
        }
        self.last
    }

    /// This tick's raw inputs of the tracker, taken.
    pub fn take_seam(&mut self) -> super::ArmSeam {
        self.tracker.take_seam()
    }

    /// Why there are no (more) joint angles, if so.
    pub fn failure(&self) -> Option<&super::ArmFailure> {
        self.tracker.failure()
    }

    /// Range of motion of each estimated joint angle this session, rad.
    pub fn range_of_motion_rad(&self) -> [f64; 5] {
        self.tracker.range_of_motion_rad()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    fn sample(t_ns: u64, rate_x: f64, acc_z: Option<f64>) -> ImuSample {
        ImuSample {
            t_ns,
            rate_rad_s: Vector3::new(rate_x, 0.0, 0.0),
            acc_m_s2: acc_z.map(|z| Vector3::new(0.0, 0.0, z)),
        }
    }

    #[test]
    fn samples_arriving_together_keep_their_mean_rate_and_the_newest_time() {
        let joycon_report = [
            sample(10, 1.0, Some(9.0)),
            sample(15, 2.0, Some(10.0)),
            sample(20, 6.0, Some(11.0)),
        ];
        let m = mean_sample(&joycon_report);
        assert_eq!(m.t_ns, 20);
        assert_eq!(m.rate_rad_s.x, 3.0);
        assert_eq!(m.acc_m_s2.unwrap().z, 10.0);
        let one = sample(7, 0.5, None);
        assert_eq!(mean_sample(&[one]), one);
        let gyro_only_in_one = [sample(1, 1.0, Some(9.8)), sample(2, 1.0, None)];
        assert_eq!(mean_sample(&gyro_only_in_one).acc_m_s2, None);
    }
}
