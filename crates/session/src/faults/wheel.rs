//! [`FaultyWheel`]: the simulated wheel failing as the session's faults say, at the device
//! seam where a real wheel's faults act.

use crate::config::faults::{FaultKind, FaultSpec, windows};
use haptic_wheel::{Wheel, WheelError, WheelFault, WheelReading};

/// A wheel that fails as `faults` say, on the session time of its own readings.
pub struct FaultyWheel<W> {
    inner: W,
    faults: Vec<(FaultKind, u64, u64)>,
    /// The reading a stall repeats.
    frozen: Option<WheelReading>,
    /// Haptic stalls already played (by start time, ns).
    stalled: Vec<u64>,
    /// The time of the last reading, ns: the tick's commands act at it (read once a tick).
    read_at_ns: u64,
}

impl<W: Wheel> FaultyWheel<W> {
    /// `inner`, failing as the wheel faults among `faults` say (other kinds are ignored: an
    /// arm, hub or disk fault at the same time must not hide a wheel fault).
    pub fn new(inner: W, faults: &[FaultSpec]) -> Self {
        let wheel_faults = windows(faults)
            .into_iter()
            .filter(|(k, _, _)| {
                k.acts_on_readings()
                    || matches!(k, FaultKind::HapticStall | FaultKind::WheelWriteFail)
            })
            .collect();
        Self {
            inner,
            faults: wheel_faults,
            frozen: None,
            // Room for every stall up front: the haptic thread never allocates.
            stalled: Vec::with_capacity(faults.len()),
            read_at_ns: 0,
        }
    }

    /// The wheel refuses commands at `t_ns` (a `wheel-write-fail` window).
    fn refusing(&self, t_ns: u64) -> bool {
        self.faults.iter().any(|(k, start, end)| {
            *k == FaultKind::WheelWriteFail && (*start..*end).contains(&t_ns)
        })
    }

    /// The fault of the wheel's readings acting at `t_ns`, if any.
    fn acting(&self, t_ns: u64) -> Option<FaultKind> {
        self.faults
            .iter()
            .find(|(k, start, end)| k.acts_on_readings() && (*start..*end).contains(&t_ns))
            .map(|(k, _, _)| *k)
    }
}

/// A wheel that can run on its own for a while, as a simulated wheel does while the loop
/// that drives it is stalled.
pub trait Stallable {
    /// Let `dt_s` pass with nobody commanding or holding the wheel.
    fn run_unattended(&mut self, dt_s: f64);
    /// The end of the wheel's range, rad (what a saturated encoder reads).
    fn half_range_rad(&self) -> f64;
}

impl Stallable for haptic_wheel::SimWheel {
    fn half_range_rad(&self) -> f64 {
        // From the parameters, as the profile says it (`DeviceProfile::simulated`), without
        // building the profile (it holds strings: the haptic thread must not allocate).
        self.params().range_rad
    }

    fn run_unattended(&mut self, dt_s: f64) {
        // In 1 ms steps, as the physics would have run.
        let steps = (dt_s / 1e-3).round() as u64;
        for _ in 0..steps {
            self.advance(1e-3, 0.0);
        }
    }
}

/// The wrapped wheel's own methods (a simulated wheel's physics) go straight through.
impl<W> std::ops::Deref for FaultyWheel<W> {
    type Target = W;
    fn deref(&self) -> &W {
        &self.inner
    }
}

impl<W> std::ops::DerefMut for FaultyWheel<W> {
    fn deref_mut(&mut self) -> &mut W {
        &mut self.inner
    }
}

impl<W: Wheel + Stallable> Wheel for FaultyWheel<W> {
    fn read(&mut self) -> Result<WheelReading, WheelError> {
        let mut reading = self.inner.read()?;
        // A haptic stall: the loop comes back after the stall's length, the wheel having
        // moved on under its last command meanwhile (the supervisor sees the gap).
        let stall = self.faults.iter().find(|(k, start, _)| {
            *k == FaultKind::HapticStall && reading.t_ns >= *start && !self.stalled.contains(start)
        });
        if let Some(&(_, start, end)) = stall {
            self.stalled.push(start);
            self.inner.run_unattended((end - start) as f64 * 1e-9);
            reading = self.inner.read()?;
        }
        self.read_at_ns = reading.t_ns;
        match self.acting(reading.t_ns) {
            Some(FaultKind::WheelUnplug) => Err(WheelError::Fault(WheelFault::Unplugged)),
            Some(FaultKind::WheelNan) => Ok(WheelReading {
                angle_rad: f64::NAN,
                ..reading
            }),
            Some(FaultKind::WheelStall) => Ok(*self.frozen.get_or_insert(reading)),
            // A stuck encoder: the angle holds, the readings stay fresh.
            Some(FaultKind::WheelFrozen) => Ok(WheelReading {
                angle_rad: self.frozen.get_or_insert(reading).angle_rad,
                ..reading
            }),
            // A saturated encoder: the end of the wheel's range.
            Some(FaultKind::WheelSaturated) => Ok(WheelReading {
                angle_rad: self.inner.half_range_rad(),
                ..reading
            }),
            Some(_) | None => {
                self.frozen = None;
                Ok(reading)
            }
        }
    }

    fn command_torque(&mut self, torque_nm: f64) -> Result<(), WheelError> {
        // An unplugged wheel takes no command: the motor is unpowered (the simulated one
        // is told zero, as a wheel that lost USB power drops its force).
        let now = self.read_at_ns;
        if self.acting(now) == Some(FaultKind::WheelUnplug) {
            let _ = self.inner.command_torque(0.0);
            return Err(WheelError::Fault(WheelFault::Unplugged));
        }
        if self.refusing(now) {
            // The command never reaches the motor, which keeps its last force.
            return Err(WheelError::write_refused());
        }
        self.inner.command_torque(torque_nm)
    }
    fn set_torque_ceiling_nm(&mut self, ceiling_nm: f64) -> Result<(), WheelError> {
        if self.refusing(self.read_at_ns) {
            return Err(WheelError::write_refused());
        }
        self.inner.set_torque_ceiling_nm(ceiling_nm)
    }

    fn motor_updates(&self) -> Option<haptic_wheel::MotorUpdates> {
        self.inner.motor_updates()
    }

    fn max_torque_nm(&self) -> f64 {
        self.inner.max_torque_nm()
    }

    fn profile(&self) -> haptic_wheel::DeviceProfile {
        self.inner.profile()
    }

    fn set_firmware_effects_active(&mut self, active: bool) {
        self.inner.set_firmware_effects_active(active);
    }

    fn capabilities(&self) -> haptic_wheel::WheelCapabilities {
        self.inner.capabilities()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use haptic_wheel::{SimWheel, SimWheelParams};

    #[test]
    fn the_wheel_fails_in_its_window_only() {
        let sim = SimWheel::new(SimWheelParams::default());
        let faults = [
            FaultSpec::parse("wheel-nan@0+0.002").unwrap(),
            FaultSpec::parse("wheel-stall@0.005+0.002").unwrap(),
            FaultSpec::parse("wheel-unplug@0.010").unwrap(),
        ];
        let mut w = FaultyWheel::new(sim, &faults);
        let mut seen = Vec::new();
        for _ in 0..12 {
            let r = w.read();
            seen.push(match r {
                Ok(r) if r.angle_rad.is_nan() => "nan".to_owned(),
                Ok(r) => format!("ok@{}", r.t_ns / 1_000_000),
                Err(_) => "unplugged".to_owned(),
            });
            let _ = w.command_torque(0.0);
            w.advance(0.001, 0.0);
        }
        assert_eq!(
            seen,
            [
                "nan",
                "nan",
                "ok@2",
                "ok@3",
                "ok@4",
                "ok@5",
                "ok@5",
                "ok@7",
                "ok@8",
                "ok@9",
                "unplugged",
                "unplugged"
            ]
        );
    }

    #[test]
    fn an_arm_hub_or_disk_fault_at_the_same_time_does_not_hide_a_wheel_fault() {
        // Each of these lasts for good from 1 ms on; the wheel's NaN readings from 3 ms on
        // must still come.
        for other in [
            "imu-unplug@0.001",
            "hub-down@0.001",
            "disk-full@0.001",
            "imu-nan@0.001+1",
        ] {
            let faults = [
                FaultSpec::parse(other).unwrap(),
                FaultSpec::parse("wheel-nan@0.003+0.002").unwrap(),
            ];
            let mut w = FaultyWheel::new(SimWheel::new(SimWheelParams::default()), &faults);
            let nan: Vec<bool> = (0..6)
                .map(|_| {
                    let nan = w.read().unwrap().angle_rad.is_nan();
                    w.advance(0.001, 0.0);
                    nan
                })
                .collect();
            assert_eq!(
                nan,
                [false, false, false, true, true, false],
                "with {other}"
            );
        }
    }

    #[test]
    fn a_frozen_encoder_holds_its_angle_on_fresh_readings_and_a_saturated_one_reads_its_end() {
        let sim = SimWheel::new(SimWheelParams::default());
        let half_range = sim.half_range_rad();
        let faults = [
            FaultSpec::parse("wheel-frozen@0.1+0.05").unwrap(),
            FaultSpec::parse("wheel-saturated@0.18+0.005").unwrap(),
        ];
        let mut w = FaultyWheel::new(sim, &faults);
        let mut seen = Vec::new();
        for _ in 0..200 {
            let r = w.read().unwrap();
            seen.push((r.t_ns / 1_000_000, r.angle_rad));
            // The hand turns the wheel.
            w.advance(0.001, 1.0);
        }
        let frozen = seen[100].1;
        assert!(seen[100..150].iter().all(|&(_, a)| a == frozen), "held");
        assert!(
            seen[100..150].windows(2).all(|w| w[1].0 == w[0].0 + 1),
            "fresh readings"
        );
        assert!(seen[150..180].iter().all(|&(_, a)| a != frozen), "moves on");
        assert!(seen[180..185].iter().all(|&(_, a)| a == half_range));
        assert!(seen[185].1 < half_range);
    }
}
