//! The real patient's arm: two game-controller IMUs over HID (DualShock 4, DualSense,
//! Joy-Con, Pro Controller; see `telerehab devices`) strapped to the upper arm and forearm,
//! either way round. Polled without blocking on the haptic thread; allocation-free per tick.

use super::{ArmTracker, WheelNow};
use crate::session::record::ArmSample;
use anyhow::Context;
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
    /// Take what arrived since the last tick; the newest sample is held until the next one
    /// (zero-order hold at the device's rate). A read error (unplugged) stops this source.
    fn poll(&mut self) {
        if self.failed {
            return;
        }
        match self.imu.poll(&mut self.buf) {
            Ok(0) => {}
            Ok(n) => self.latest = Some(self.buf[n - 1]),
            Err(e) => {
                self.failed = true;
                tracing::warn!(
                    "IMU {} stopped ({e}); the arm pose is frozen for the rest of the session",
                    self.imu.info().name
                );
            }
        }
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
    /// device timestamps are anchored to.
    pub fn open_first_two(
        geometry: ArmGeometry,
        swivel_rad: f64,
        clock_ns: fn() -> u64,
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
            tracker: ArmTracker::guided(geometry, swivel_rad, true)?,
            last: ArmSample::default(),
        }))
    }

    /// Where the arm sensing is.
    pub fn setup_step(&self) -> super::SetupStep {
        self.tracker.step_now()
    }

    /// Poll both devices and update the pose; before both have delivered a sample (or after
    /// one stopped) the previous sample is kept.
    pub fn step(&mut self, wheel: WheelNow) -> ArmSample {
        self.a.poll();
        self.b.poll();
        if let (Some(a), Some(b), false) =
            (self.a.latest, self.b.latest, self.a.failed || self.b.failed)
        {
            self.last = self.tracker.update(wheel, &a, &b);
        }
        self.last
    }

    /// Range of motion of each estimated joint angle this session, rad.
    pub fn range_of_motion_rad(&self) -> [f64; 5] {
        self.tracker.range_of_motion_rad()
    }
}
