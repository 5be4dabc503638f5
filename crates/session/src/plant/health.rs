//! The wheel's health as the plant sees it: which readings are readings, whether the wheel
//! went away (unplugged) and came back within the replug grace, and the fault the session
//! ends on. Allocation-free.

use haptic_wheel::{WatchdogState, WheelError, WheelFault, WheelReading};

/// Whether the wheel answers, and what it said last.
pub(super) struct WheelHealth {
    /// The first fault the wheel reported (unplugged past the replug grace, silent, out of
    /// range): the session ends on it, and says why.
    pub(super) fault: Option<WheelFault>,
    /// When the wheel went away (unplugged), ns of loop time: it has the replug grace to come
    /// back, the exercise paused and the torque at zero meanwhile.
    gone_since_ns: Option<u64>,
    /// The wheel came back: the exercise stays paused until the supervisor's fault has
    /// cleared, then resumes with a soft start (never a torque step).
    settling: bool,
    /// Times the wheel went away and came back within the grace.
    pub(super) replugs: u32,
    /// `[haptic] replug_grace_s`, ns.
    pub(super) replug_grace_ns: u64,
    /// Tells a saturated encoder from a wheel turned to its end.
    plausibility: AnglePlausibility,
    /// The last finite wheel angle read, rad (what the car steers by without a reading).
    last_angle_rad: f64,
    /// Force commands the wheel refused so far (while it answered reads).
    pub(super) write_failures: u64,
    /// When the present run of refused commands began, ns of loop time.
    refusing_since_ns: Option<u64>,
}

/// Longest a run of refused force commands may last, ns: the motor keeps its last force
/// meanwhile, not the one the safety chain chose. As old as a reading may be before the
/// supervisor fades the torque (`SupervisorConfig::max_reading_age_s`, 20 ms): a command that
/// old is as stale. Past it the session ends on [`WheelFault::CommandsRefused`] (the wheel
/// closed, which stops a force feedback device's effects).
pub const MAX_REFUSED_WRITES_NS: u64 = 20_000_000;

impl WheelHealth {
    /// A wheel that answered nothing yet, whose encoder ends at ±`half_range_rad`, waited
    /// for `replug_grace_ns` when unplugged.
    pub(super) fn new(half_range_rad: f64, replug_grace_ns: u64) -> Self {
        Self {
            fault: None,
            gone_since_ns: None,
            settling: false,
            replugs: 0,
            replug_grace_ns,
            plausibility: AnglePlausibility::new(half_range_rad),
            last_angle_rad: 0.0,
            write_failures: 0,
            refusing_since_ns: None,
        }
    }

    /// The tick's force commands at loop time `t_ns` were `taken` by the wheel, or not: a
    /// refused one is counted, and a run longer than [`MAX_REFUSED_WRITES_NS`] is a fault. An
    /// unplugged wheel's refusals are its unplugging (the replug grace's), not counted.
    pub(super) fn wrote(&mut self, taken: bool, t_ns: u64) {
        if taken {
            self.refusing_since_ns = None;
            return;
        }
        if self.gone_since_ns.is_some() {
            return;
        }
        self.write_failures += 1;
        let since = *self.refusing_since_ns.get_or_insert(t_ns);
        if t_ns.saturating_sub(since) >= MAX_REFUSED_WRITES_NS {
            self.fault = self.fault.or(Some(WheelFault::CommandsRefused));
        }
    }

    /// The wheel is away (unplugged, within the replug grace) or settling after it came back.
    pub(super) fn away(&self) -> bool {
        self.gone_since_ns.is_some() || self.settling
    }

    /// What the chain may use of a read of the wheel at loop time `t_ns`. A wheel that answers
    /// is back; a NaN or infinite angle is no reading, nor is a clipped (saturated) one: the
    /// supervisor fades the torque out as for a stale one, and the car keeps the last good
    /// angle. A failed read is a fault (see [`WheelHealth::failed`]).
    pub(super) fn reading(
        &mut self,
        read: Result<WheelReading, WheelError>,
        t_ns: u64,
    ) -> Option<WheelReading> {
        if read.is_ok() {
            self.back();
        }
        match read {
            Ok(r) if r.angle_rad.is_finite() && self.plausibility.accept(&r) => Some(r),
            Ok(_) => None,
            Err(e) => {
                self.failed(&e, t_ns);
                None
            }
        }
    }

    /// The angle the car steers by: `reading`'s, or the last good one without a reading, rad.
    pub(super) fn angle_rad(&mut self, reading: Option<WheelReading>) -> f64 {
        self.last_angle_rad = reading.map_or(self.last_angle_rad, |r| r.angle_rad);
        self.last_angle_rad
    }

    /// The supervisor is in `watchdog` after this tick: the fault after a replug has cleared
    /// once it left `Paused`, and the exercise resumes (from paused, so with a soft start).
    pub(super) fn supervisor_is(&mut self, watchdog: WatchdogState) {
        self.settling &= watchdog != WatchdogState::Paused;
    }

    /// A read of the wheel failed with `e` at loop time `t_ns`. An unplugged wheel has the
    /// replug grace to come back (the exercise paused meanwhile); any other fault, or the
    /// grace over, ends the session. No allocation: a running wheel's faults are `Copy`.
    fn failed(&mut self, e: &WheelError, t_ns: u64) {
        match e.fault() {
            Some(WheelFault::Unplugged) if self.fault.is_none() => {
                let since = *self.gone_since_ns.get_or_insert(t_ns);
                if t_ns - since >= self.replug_grace_ns {
                    self.fault = Some(WheelFault::Unplugged);
                }
            }
            fault => self.fault = self.fault.or(fault),
        }
    }

    /// The wheel answered a read: if it was away it is back, and the exercise resumes once
    /// the supervisor's fault has cleared.
    fn back(&mut self) {
        if self.gone_since_ns.take().is_some() {
            self.settling = true;
            self.replugs += 1;
        }
    }
}

/// Fastest a hand (or a released wheel) turns a wheel, rad/s (~5700 °/s): a reading further
/// from the last good one than this allows is a glitch, not a movement.
const MAX_PLAUSIBLE_RATE_RAD_S: f64 = 100.0;

/// Tells a saturated (clipped) encoder from a wheel turned to its end: a reading at the end of
/// the range reached by a jump no hand could make is no reading, and neither are the readings
/// that hold there after it; one reached by turning is a reading. Any other jump is a glitch
/// and dropped. Allocation-free.
#[derive(Clone, Copy, Debug)]
struct AnglePlausibility {
    half_range_rad: f64,
    /// The last accepted reading: (t_ns, angle_rad).
    last_good: Option<(u64, f64)>,
    /// The encoder is clipped at its end since a jump there.
    clipped: bool,
}

impl AnglePlausibility {
    fn new(half_range_rad: f64) -> Self {
        Self {
            half_range_rad,
            last_good: None,
            clipped: false,
        }
    }

    /// Whether `r` (a finite angle) is a reading of the wheel's position.
    fn accept(&mut self, r: &WheelReading) -> bool {
        let at_end = r.angle_rad.abs() >= self.half_range_rad * (1.0 - 1e-6);
        let jump = self.last_good.is_some_and(|(t, a)| {
            let dt_s = r.t_ns.saturating_sub(t) as f64 * 1e-9;
            (r.angle_rad - a).abs() > MAX_PLAUSIBLE_RATE_RAD_S * dt_s.max(1e-3)
        });
        self.clipped = at_end && (jump || self.clipped);
        if jump || self.clipped {
            return false;
        }
        self.last_good = Some((r.t_ns, r.angle_rad));
        true
    }
}
