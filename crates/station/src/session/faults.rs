//! Faults injected into a simulated session, compiled into the product so that tests and
//! demos exercise the real safety paths (`telerehab run --sim --fault KIND@SECONDS`, or a
//! `[[faults]]` table in the configuration).
//!
//! The wheel's faults act at the device seam, where a real wheel's do: [`FaultyWheel`] wraps
//! the simulated wheel and, from the fault's session time on, answers as an unplugged,
//! misbehaving or stalled device would. Everything above it — the haptic chain, its safety
//! supervisor, the session's end — is the code a real wheel runs.

use haptic_wheel::{Wheel, WheelError, WheelFault, WheelReading};
use serde::{Deserialize, Serialize};
use std::fmt;

/// What goes wrong.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FaultKind {
    /// The wheel is unplugged: every read and command fails as the kernel's ENODEV does.
    WheelUnplug,
    /// The wheel reports NaN angles for the fault's duration.
    WheelNan,
    /// The wheel's USB stalls: its readings freeze (same timestamp) for the fault's duration
    /// (50–500 ms makes sense; default 200 ms).
    WheelStall,
    /// The haptic loop stalls past the watchdog: no tick for the fault's duration (default
    /// 100 ms) while the wheel's motor keeps its last command and the wheel moves on.
    HapticStall,
    /// The disk fills up: from then on every write of the recording fails with ENOSPC.
    DiskFull,
    /// An arm IMU is unplugged: the arm sensing reports the sensor lost and freezes the pose.
    ImuUnplug,
    /// The arm IMUs send NaN rates for the fault's duration (default 200 ms).
    ImuNan,
}

impl FaultKind {
    /// Every kind, by its name.
    pub const ALL: [FaultKind; 7] = [
        FaultKind::WheelUnplug,
        FaultKind::WheelNan,
        FaultKind::WheelStall,
        FaultKind::HapticStall,
        FaultKind::DiskFull,
        FaultKind::ImuUnplug,
        FaultKind::ImuNan,
    ];

    /// The kind's name, as written after `--fault`.
    pub fn name(self) -> &'static str {
        match self {
            FaultKind::WheelUnplug => "wheel-unplug",
            FaultKind::WheelNan => "wheel-nan",
            FaultKind::WheelStall => "wheel-stall",
            FaultKind::HapticStall => "haptic-stall",
            FaultKind::DiskFull => "disk-full",
            FaultKind::ImuUnplug => "imu-unplug",
            FaultKind::ImuNan => "imu-nan",
        }
    }

    /// How long the fault lasts when its spec does not say, s (`None`: for good).
    fn default_duration_s(self) -> Option<f64> {
        match self {
            FaultKind::WheelUnplug | FaultKind::DiskFull | FaultKind::ImuUnplug => None,
            FaultKind::WheelNan | FaultKind::ImuNan => Some(0.2),
            FaultKind::WheelStall => Some(0.2),
            FaultKind::HapticStall => Some(0.1),
        }
    }
}

impl fmt::Display for FaultKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// One injected fault: what, when (session time, s) and for how long (s; absent: the kind's
/// default).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FaultSpec {
    /// What goes wrong.
    pub kind: FaultKind,
    /// When it starts, s of session time.
    pub at_s: f64,
    /// How long it lasts, s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub duration_s: Option<f64>,
}

impl FaultSpec {
    /// Parse `KIND@SECONDS` or `KIND@SECONDS+DURATION` (e.g. `wheel-stall@5+0.3`); the error
    /// names what is wrong and the kinds known.
    pub fn parse(text: &str) -> Result<Self, String> {
        let known = || {
            FaultKind::ALL
                .iter()
                .map(|k| k.name())
                .collect::<Vec<_>>()
                .join(", ")
        };
        let (kind, when) = text
            .split_once('@')
            .ok_or_else(|| format!("fault {text:?}: write KIND@SECONDS (kinds: {})", known()))?;
        let kind = FaultKind::ALL
            .into_iter()
            .find(|k| k.name() == kind)
            .ok_or_else(|| format!("unknown fault kind {kind:?} (kinds: {})", known()))?;
        let (at, duration) = match when.split_once('+') {
            Some((at, d)) => (at, Some(d)),
            None => (when, None),
        };
        let number = |what: &str, s: &str| {
            s.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite() && *v >= 0.0 && *v <= 4.0 * 3600.0)
                .ok_or_else(|| format!("fault {text:?}: {what} {s:?} is not 0 to 14400 s"))
        };
        let spec = FaultSpec {
            kind,
            at_s: number("time", at)?,
            duration_s: duration.map(|d| number("duration", d)).transpose()?,
        };
        spec.validate()?;
        Ok(spec)
    }

    /// Check the times; the error names the fault.
    pub fn validate(&self) -> Result<(), String> {
        let ok = |v: f64| v.is_finite() && (0.0..=4.0 * 3600.0).contains(&v);
        if !ok(self.at_s) || !self.duration_s.is_none_or(ok) {
            return Err(format!(
                "fault {}: at_s and duration_s must be 0 to 14400 s",
                self.kind
            ));
        }
        Ok(())
    }

    /// The session-time window it acts in, ns: `[start, end)`.
    fn window_ns(&self) -> (u64, u64) {
        let start = (self.at_s * 1e9).round() as u64;
        let end = self
            .duration_s
            .or(self.kind.default_duration_s())
            .map_or(u64::MAX, |d| start + (d * 1e9).round() as u64);
        (start, end)
    }
}

/// A wheel that fails as `faults` say, on the session time of its own readings.
pub struct FaultyWheel<W> {
    inner: W,
    faults: Vec<(FaultKind, u64, u64)>,
    /// The reading a stall repeats.
    frozen: Option<WheelReading>,
    /// Haptic stalls already played (by start time, ns).
    stalled: Vec<u64>,
}

impl<W: Wheel> FaultyWheel<W> {
    /// `inner`, failing as the wheel faults among `faults` say (other kinds are ignored).
    pub fn new(inner: W, faults: &[FaultSpec]) -> Self {
        Self {
            inner,
            faults: faults
                .iter()
                .map(|f| {
                    let (start, end) = f.window_ns();
                    (f.kind, start, end)
                })
                .collect(),
            frozen: None,
            // Room for every stall up front: the haptic thread never allocates.
            stalled: Vec::with_capacity(faults.len()),
        }
    }

    /// The fault acting at `t_ns`, if any.
    fn acting(&self, t_ns: u64) -> Option<FaultKind> {
        self.faults
            .iter()
            .find(|(_, start, end)| (*start..*end).contains(&t_ns))
            .map(|(k, _, _)| *k)
    }
}

/// The arm-sensor faults among `faults`, with their session-time windows (ns).
pub fn imu_faults(faults: &[FaultSpec]) -> Vec<(FaultKind, u64, u64)> {
    faults
        .iter()
        .filter(|f| matches!(f.kind, FaultKind::ImuUnplug | FaultKind::ImuNan))
        .map(|f| {
            let (start, end) = f.window_ns();
            (f.kind, start, end)
        })
        .collect()
}

/// When the disk fills up in a session with `faults`, ns of session time.
pub fn disk_full_at_ns(faults: &[FaultSpec]) -> Option<u64> {
    faults
        .iter()
        .filter(|f| f.kind == FaultKind::DiskFull)
        .map(|f| f.window_ns().0)
        .min()
}

/// A recording's file that fails every write with ENOSPC once its disk is [`Disk::fill`]ed,
/// as a full disk does (the station's recorder fills it at the injected fault's session time).
pub struct FillingFile {
    file: std::fs::File,
    full: Disk,
}

/// The disk under a [`FillingFile`]: filling it makes the file's writes fail; it also keeps
/// the last I/O error the file met (real or injected), which the MCAP library's own error
/// does not carry.
#[derive(Clone, Debug, Default)]
pub struct Disk {
    full: std::sync::Arc<std::sync::atomic::AtomicBool>,
    last_error: std::sync::Arc<std::sync::Mutex<Option<(std::io::ErrorKind, String)>>>,
}

impl Disk {
    /// From now on, writes fail.
    pub fn fill(&self) {
        self.full.store(true, std::sync::atomic::Ordering::Relaxed);
    }

    fn is_full(&self) -> bool {
        self.full.load(std::sync::atomic::Ordering::Relaxed)
    }

    /// The last I/O error of the file, if any.
    pub fn last_error(&self) -> Option<std::io::Error> {
        let last = self.last_error.lock().ok()?.clone();
        last.map(|(kind, message)| std::io::Error::new(kind, message))
    }

    /// Keep `result`'s error, if it is one.
    fn note<T>(&self, result: std::io::Result<T>) -> std::io::Result<T> {
        if let (Err(e), Ok(mut slot)) = (&result, self.last_error.lock()) {
            *slot = Some((e.kind(), e.to_string()));
        }
        result
    }
}

impl FillingFile {
    /// `file` on `disk`.
    pub fn new(file: std::fs::File, disk: Disk) -> Self {
        Self { file, full: disk }
    }

    /// The file.
    pub fn file(&self) -> &std::fs::File {
        &self.file
    }
}

impl std::io::Write for FillingFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let result = if self.full.is_full() {
            Err(std::io::Error::from(std::io::ErrorKind::StorageFull))
        } else {
            self.file.write(buf)
        };
        self.full.note(result)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        let result = if self.full.is_full() {
            Err(std::io::Error::from(std::io::ErrorKind::StorageFull))
        } else {
            self.file.flush()
        };
        self.full.note(result)
    }
}

impl std::io::Seek for FillingFile {
    fn seek(&mut self, pos: std::io::SeekFrom) -> std::io::Result<u64> {
        let result = self.file.seek(pos);
        self.full.note(result)
    }
}

/// A wheel that can run on its own for a while, as a simulated wheel does while the loop
/// that drives it is stalled.
pub trait Stallable {
    /// Let `dt_s` pass with nobody commanding or holding the wheel.
    fn run_unattended(&mut self, dt_s: f64);
}

impl Stallable for haptic_wheel::SimWheel {
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
        match self.acting(reading.t_ns) {
            Some(FaultKind::WheelUnplug) => Err(WheelError::Fault(WheelFault::Unplugged)),
            Some(FaultKind::WheelNan) => Ok(WheelReading {
                angle_rad: f64::NAN,
                ..reading
            }),
            Some(FaultKind::WheelStall) => Ok(*self.frozen.get_or_insert(reading)),
            Some(
                FaultKind::HapticStall
                | FaultKind::DiskFull
                | FaultKind::ImuUnplug
                | FaultKind::ImuNan,
            )
            | None => {
                self.frozen = None;
                Ok(reading)
            }
        }
    }

    fn command_torque(&mut self, torque_nm: f64) -> Result<(), WheelError> {
        // An unplugged wheel takes no command: the motor is unpowered (the simulated one
        // is told zero, as a wheel that lost USB power drops its force).
        let now = self.inner.read().map(|r| r.t_ns).unwrap_or(0);
        if self.acting(now) == Some(FaultKind::WheelUnplug) {
            let _ = self.inner.command_torque(0.0);
            return Err(WheelError::Fault(WheelFault::Unplugged));
        }
        self.inner.command_torque(torque_nm)
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
    fn a_fault_is_parsed_with_its_time_and_duration_or_refused_by_name() {
        assert_eq!(
            FaultSpec::parse("wheel-stall@5+0.3").unwrap(),
            FaultSpec {
                kind: FaultKind::WheelStall,
                at_s: 5.0,
                duration_s: Some(0.3)
            }
        );
        assert_eq!(FaultSpec::parse("wheel-unplug@2").unwrap().duration_s, None);
        let err = FaultSpec::parse("wheel-melt@2").unwrap_err();
        assert!(
            err.contains("unknown fault kind \"wheel-melt\"") && err.contains("wheel-nan"),
            "{err}"
        );
        assert!(
            FaultSpec::parse("wheel-nan")
                .unwrap_err()
                .contains("KIND@SECONDS")
        );
        assert!(
            FaultSpec::parse("wheel-nan@-1")
                .unwrap_err()
                .contains("not 0 to 14400 s")
        );
        assert!(
            FaultSpec::parse("wheel-nan@1+inf")
                .unwrap_err()
                .contains("duration")
        );
    }

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
}
