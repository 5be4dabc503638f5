//! The tick's raw inputs as `/raw/wheel` and `/raw/imu` record them: what a replay needs to
//! run the same session again, bit for bit.

use arm::ArmSeam;
use haptic_wheel::WheelReading;
use record::raw::{RawImuSample, RawRead, RawTick, RawWheelSample, same_sample};

/// The patient's own inputs (pause, stop) and the IMU samples `/raw/imu` already holds.
pub(super) struct RawInputs {
    /// The patient paused the exercise.
    pub(super) paused: bool,
    /// A stop has been asked for.
    pub(super) stop_requested: bool,
    /// Where the pedals were (the patient's, or the simulated foot's).
    pub(super) pedals: exercises::Pedals,
    /// The wheel refused this tick's force command.
    pub(super) write_failed: bool,
    /// The IMU samples last recorded on `/raw/imu`, per sensor (a held one is not repeated).
    last_imu: [Option<gyro_imu::device::ImuSample>; 2],
}

impl RawInputs {
    /// Nothing asked for, nothing recorded yet.
    pub(super) fn new() -> Self {
        Self {
            paused: false,
            stop_requested: false,
            pedals: exercises::Pedals::default(),
            write_failed: false,
            last_imu: [None; 2],
        }
    }

    /// This tick's raw inputs: how the wheel's read came out and its reading (`read`), the
    /// body clock the chain ran at (`now_ns`), the patient's pause and stop, and what the arm
    /// tracker was handed (`seam`).
    pub(super) fn tick(
        &mut self,
        read: (RawRead, Option<WheelReading>),
        now_ns: u64,
        seam: Option<ArmSeam>,
    ) -> RawTick {
        let (read, reading) = read;
        RawTick {
            wheel: RawWheelSample {
                read,
                angle_rad: reading.map_or(0.0, |r| r.angle_rad),
                reading_t_ns: reading.map_or(0, |r| r.t_ns),
                now_ns,
                paused: self.paused,
                stop: self.stop_requested,
                throttle: self.pedals.throttle,
                brake: self.pedals.brake,
                write_failed: self.write_failed,
                arm_stepped: seam.is_some_and(|s| s.stepped.is_some()),
                arm_lost: seam.is_some_and(|s| s.lost),
                arm_regained: seam.is_some_and(|s| s.regained),
                solver_answered: seam.is_some_and(|s| s.solver_answered),
                solver_timed_out: seam.is_some_and(|s| s.solver_timed_out),
            },
            imu: self.new_imu_samples(seam),
        }
    }

    /// The IMU samples the tracker was stepped with this tick that `/raw/imu` does not hold
    /// yet (a sample held over ticks is recorded once).
    fn new_imu_samples(&mut self, seam: Option<ArmSeam>) -> [Option<RawImuSample>; 2] {
        let mut out = [None; 2];
        if let Some((a, b)) = seam.and_then(|s| s.stepped) {
            for (i, s) in [a, b].into_iter().enumerate() {
                if !self.last_imu[i].is_some_and(|last| same_sample(&last, &s)) {
                    self.last_imu[i] = Some(s);
                    out[i] = Some(RawImuSample::of(i as u32, &s));
                }
            }
        }
        out
    }
}
