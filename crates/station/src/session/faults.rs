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
    /// An arm IMU is unplugged: the arm sensing reports the sensor lost and freezes the pose
    /// (until an `imu-replug`, or for good).
    ImuUnplug,
    /// The arm IMUs send NaN rates for the fault's duration (default 200 ms).
    ImuNan,
    /// The unplugged wheel is plugged back in: it answers again (ends the `wheel-unplug`
    /// before it).
    WheelReplug,
    /// The wheel's encoder freezes: its angle holds while its readings stay fresh (default
    /// 1 s).
    WheelFrozen,
    /// The wheel's encoder saturates: its angle reads the end of its range (default 200 ms).
    WheelSaturated,
    /// The unplugged arm IMU is plugged back in (ends the `imu-unplug` before it).
    ImuReplug,
    /// The arm IMUs' rates freeze at their last value while their samples stay fresh
    /// (default 1 s).
    ImuFrozen,
    /// The arm IMUs' rates read their full scale, ±[`IMU_FULL_SCALE_RAD_S`] (default 200 ms).
    ImuSaturated,
    /// The therapist's hub goes away: the link's connection is cut and every new one refused
    /// (until a `hub-up`, or for good).
    HubDown,
    /// The hub comes back (ends the `hub-down` before it).
    HubUp,
}

/// Full scale of a consumer controller's gyro, rad/s (±2000 °/s: DualShock 4, DualSense,
/// Joy-Con): a rate at or beyond it is clipped by the sensor.
pub const IMU_FULL_SCALE_RAD_S: f64 = 2000.0 * std::f64::consts::PI / 180.0;

impl FaultKind {
    /// Every kind, by its name.
    pub const ALL: [FaultKind; 15] = [
        FaultKind::WheelUnplug,
        FaultKind::WheelReplug,
        FaultKind::WheelNan,
        FaultKind::WheelStall,
        FaultKind::WheelFrozen,
        FaultKind::WheelSaturated,
        FaultKind::HapticStall,
        FaultKind::DiskFull,
        FaultKind::ImuUnplug,
        FaultKind::ImuReplug,
        FaultKind::ImuNan,
        FaultKind::ImuFrozen,
        FaultKind::ImuSaturated,
        FaultKind::HubDown,
        FaultKind::HubUp,
    ];

    /// The kind's name, as written after `--fault`.
    pub fn name(self) -> &'static str {
        match self {
            FaultKind::WheelUnplug => "wheel-unplug",
            FaultKind::WheelReplug => "wheel-replug",
            FaultKind::WheelNan => "wheel-nan",
            FaultKind::WheelStall => "wheel-stall",
            FaultKind::WheelFrozen => "wheel-frozen",
            FaultKind::WheelSaturated => "wheel-saturated",
            FaultKind::HapticStall => "haptic-stall",
            FaultKind::DiskFull => "disk-full",
            FaultKind::ImuUnplug => "imu-unplug",
            FaultKind::ImuReplug => "imu-replug",
            FaultKind::ImuNan => "imu-nan",
            FaultKind::ImuFrozen => "imu-frozen",
            FaultKind::ImuSaturated => "imu-saturated",
            FaultKind::HubDown => "hub-down",
            FaultKind::HubUp => "hub-up",
        }
    }

    /// How long the fault lasts when its spec does not say, s (`None`: for good, or until the
    /// kind that ends it).
    fn default_duration_s(self) -> Option<f64> {
        match self {
            FaultKind::WheelUnplug
            | FaultKind::DiskFull
            | FaultKind::ImuUnplug
            | FaultKind::HubDown => None,
            FaultKind::WheelNan | FaultKind::ImuNan => Some(0.2),
            FaultKind::WheelStall => Some(0.2),
            FaultKind::HapticStall => Some(0.1),
            FaultKind::WheelFrozen | FaultKind::ImuFrozen => Some(1.0),
            FaultKind::WheelSaturated | FaultKind::ImuSaturated => Some(0.2),
            // An event, not a window: it ends the fault before it.
            FaultKind::WheelReplug | FaultKind::ImuReplug | FaultKind::HubUp => Some(0.0),
        }
    }

    /// A fault of the wheel's readings (what [`FaultyWheel`] plays on each read).
    fn acts_on_readings(self) -> bool {
        matches!(
            self,
            FaultKind::WheelUnplug
                | FaultKind::WheelNan
                | FaultKind::WheelStall
                | FaultKind::WheelFrozen
                | FaultKind::WheelSaturated
        )
    }

    /// The kind that ends this one (`wheel-unplug` → `wheel-replug`, …), if any.
    pub fn ended_by(self) -> Option<FaultKind> {
        match self {
            FaultKind::WheelUnplug => Some(FaultKind::WheelReplug),
            FaultKind::ImuUnplug => Some(FaultKind::ImuReplug),
            FaultKind::HubDown => Some(FaultKind::HubUp),
            _ => None,
        }
    }

    /// The kind this one ends, if it is an end (`wheel-replug` → `wheel-unplug`, …).
    fn ends(self) -> Option<FaultKind> {
        FaultKind::ALL
            .into_iter()
            .find(|k| k.ended_by() == Some(self))
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

/// Check a session's faults together: each replug or hub-up must follow the unplug or
/// hub-down it ends; the error names it.
pub fn validate_all(faults: &[FaultSpec]) -> Result<(), String> {
    for f in faults {
        f.validate()?;
        if let Some(ended) = f.kind.ends()
            && !faults
                .iter()
                .any(|g| g.kind == ended && g.duration_s.is_none() && g.at_s <= f.at_s)
        {
            return Err(format!(
                "fault {}@{}: no {ended} (without a duration) before it to end",
                f.kind, f.at_s
            ));
        }
    }
    Ok(())
}

/// Every fault's session-time window, ns `[start, end)`: an unplug or a hub-down without a
/// duration lasts until the first replug or hub-up at or after its start, else for good; the
/// events that end them have no window of their own.
pub fn windows(faults: &[FaultSpec]) -> Vec<(FaultKind, u64, u64)> {
    faults
        .iter()
        .filter(|f| f.kind.ends().is_none())
        .map(|f| {
            let (start, mut end) = f.window_ns();
            if f.duration_s.is_none()
                && let Some(back) = f.kind.ended_by()
            {
                end = faults
                    .iter()
                    .filter(|g| g.kind == back)
                    .map(|g| g.window_ns().0)
                    .filter(|&t| t >= start)
                    .min()
                    .unwrap_or(u64::MAX);
            }
            (f.kind, start, end)
        })
        .collect()
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
    /// `inner`, failing as the wheel faults among `faults` say (other kinds are ignored: an
    /// arm, hub or disk fault at the same time must not hide a wheel fault).
    pub fn new(inner: W, faults: &[FaultSpec]) -> Self {
        let wheel_faults = windows(faults)
            .into_iter()
            .filter(|(k, _, _)| k.acts_on_readings() || *k == FaultKind::HapticStall)
            .collect();
        Self {
            inner,
            faults: wheel_faults,
            frozen: None,
            // Room for every stall up front: the haptic thread never allocates.
            stalled: Vec::with_capacity(faults.len()),
        }
    }

    /// The fault of the wheel's readings acting at `t_ns`, if any.
    fn acting(&self, t_ns: u64) -> Option<FaultKind> {
        self.faults
            .iter()
            .find(|(k, start, end)| k.acts_on_readings() && (*start..*end).contains(&t_ns))
            .map(|(k, _, _)| *k)
    }
}

/// The arm-sensor faults among `faults`, with their session-time windows (ns).
pub fn imu_faults(faults: &[FaultSpec]) -> Vec<(FaultKind, u64, u64)> {
    windows(faults)
        .into_iter()
        .filter(|(k, _, _)| {
            matches!(
                k,
                FaultKind::ImuUnplug
                    | FaultKind::ImuNan
                    | FaultKind::ImuFrozen
                    | FaultKind::ImuSaturated
            )
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
    /// The end of the wheel's range, rad (what a saturated encoder reads).
    fn half_range_rad(&self) -> f64;
}

impl Stallable for haptic_wheel::SimWheel {
    fn half_range_rad(&self) -> f64 {
        self.capabilities().half_range_rad
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
        let now = self.inner.read().map(|r| r.t_ns).unwrap_or(0);
        if self.acting(now) == Some(FaultKind::WheelUnplug) {
            let _ = self.inner.command_torque(0.0);
            return Err(WheelError::Fault(WheelFault::Unplugged));
        }
        self.inner.command_torque(torque_nm)
    }
    fn set_torque_ceiling_nm(&mut self, ceiling_nm: f64) -> Result<(), WheelError> {
        self.inner.set_torque_ceiling_nm(ceiling_nm)
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

/// The therapist link's seam for `hub-down`: a relay on loopback between the station's link
/// and its hub, on the link's runtime. In a hub-down window (session time, told by
/// [`HubSwitch::at`] with each summary) it cuts the connections it carries and refuses new
/// ones (accepted and closed at once, as a hub that went away answers); otherwise it passes
/// bytes through untouched (TLS included: it sees only ciphertext).
pub struct HubSwitch {
    windows: Vec<(u64, u64)>,
    down: tokio::sync::watch::Sender<bool>,
    local: std::net::SocketAddr,
}

impl HubSwitch {
    /// A relay to `hub` (`host:port`, resolved on each connection) on `runtime`, when `faults`
    /// take the hub down; `None` otherwise.
    pub fn start(
        runtime: &tokio::runtime::Handle,
        hub: &str,
        faults: &[FaultSpec],
    ) -> std::io::Result<Option<Self>> {
        let windows: Vec<(u64, u64)> = windows(faults)
            .into_iter()
            .filter(|(k, _, _)| *k == FaultKind::HubDown)
            .map(|(_, start, end)| (start, end))
            .collect();
        if windows.is_empty() {
            return Ok(None);
        }
        let std_listener = std::net::TcpListener::bind((std::net::Ipv4Addr::LOCALHOST, 0))?;
        std_listener.set_nonblocking(true)?;
        let local = std_listener.local_addr()?;
        let listener = {
            let _in_runtime = runtime.enter();
            tokio::net::TcpListener::from_std(std_listener)?
        };
        let (down, watch) = tokio::sync::watch::channel(false);
        runtime.spawn(relay(listener, hub.to_owned(), watch));
        Ok(Some(Self {
            windows,
            down,
            local,
        }))
    }

    /// Where the station's link connects instead of the hub.
    pub fn address(&self) -> std::net::SocketAddr {
        self.local
    }

    /// Session time is `t_ns`: the hub is down in a hub-down window, up otherwise (said in the
    /// log when it changes).
    pub fn at(&self, t_ns: u64) {
        let down = self
            .windows
            .iter()
            .any(|(start, end)| (*start..*end).contains(&t_ns));
        let changed = self
            .down
            .send_if_modified(|d| std::mem::replace(d, down) != down);
        if changed && down {
            tracing::warn!(
                t_s = t_ns as f64 * 1e-9,
                "the therapist's hub went away (injected fault): summaries wait in the queue"
            );
        } else if changed {
            tracing::info!(
                t_s = t_ns as f64 * 1e-9,
                "the therapist's hub is back (injected fault ended)"
            );
        }
    }
}

/// Accept the link's connections and relay each to `hub` while the hub is up.
async fn relay(
    listener: tokio::net::TcpListener,
    hub: String,
    down: tokio::sync::watch::Receiver<bool>,
) {
    loop {
        let Ok((station, _)) = listener.accept().await else {
            // Out of descriptors, say: try again shortly rather than spin.
            tokio::time::sleep(std::time::Duration::from_millis(10)).await;
            continue;
        };
        if *down.borrow() {
            // Refused: closed before a byte is read.
            drop(station);
            continue;
        }
        let hub = hub.clone();
        let mut down = down.clone();
        tokio::spawn(async move {
            let Ok(upstream) = tokio::net::TcpStream::connect(hub.as_str()).await else {
                return;
            };
            let (mut station, mut upstream) = (station, upstream);
            tokio::select! {
                _ = tokio::io::copy_bidirectional(&mut station, &mut upstream) => {}
                // Cut: both sockets close mid-stream, as a hub that went away does.
                _ = down.wait_for(|d| *d) => {}
            }
        });
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
    fn an_unplug_lasts_until_its_replug_and_a_replug_without_an_unplug_is_refused() {
        let faults = [
            FaultSpec::parse("wheel-unplug@1").unwrap(),
            FaultSpec::parse("wheel-replug@2.5").unwrap(),
            FaultSpec::parse("hub-down@3").unwrap(),
            FaultSpec::parse("hub-up@4").unwrap(),
            FaultSpec::parse("imu-unplug@5").unwrap(),
        ];
        validate_all(&faults).unwrap();
        assert_eq!(
            windows(&faults),
            [
                (FaultKind::WheelUnplug, 1_000_000_000, 2_500_000_000),
                (FaultKind::HubDown, 3_000_000_000, 4_000_000_000),
                (FaultKind::ImuUnplug, 5_000_000_000, u64::MAX),
            ]
        );
        let err = validate_all(&[FaultSpec::parse("imu-replug@2").unwrap()]).unwrap_err();
        assert!(err.contains("no imu-unplug"), "{err}");
        // A replug before its unplug ends nothing.
        let err = validate_all(&[
            FaultSpec::parse("hub-up@1").unwrap(),
            FaultSpec::parse("hub-down@2").unwrap(),
        ])
        .unwrap_err();
        assert!(err.contains("hub-up@1"), "{err}");
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

    fn plant_with(faults: &[&str], grace_s: f64) -> crate::session::plant::Plant {
        let mut cfg = crate::config::StationConfig::default();
        cfg.session.exercise = "sine-road".into();
        cfg.session.duration_s = 20.0;
        cfg.session.seed = 7;
        cfg.haptic.replug_grace_s = grace_s;
        cfg.faults = faults
            .iter()
            .map(|f| FaultSpec::parse(f).unwrap())
            .collect();
        cfg.validate().unwrap();
        let course = crate::session::course::build(&cfg, None).unwrap();
        crate::session::plant::Plant::simulated(&cfg, course).unwrap()
    }

    #[test]
    fn a_wheel_plugged_back_within_the_grace_resumes_the_paused_exercise_with_a_soft_start() {
        // The sine road's first bend (and its torque) comes after 3 s.
        let mut plant = plant_with(&["wheel-unplug@4", "wheel-replug@5"], 30.0);
        let ticks: Vec<_> = (0..8000).map(|_| plant.tick()).collect();
        let torque = |i: usize| ticks[i].wheel.commanded_nm;
        assert!(
            (3500..4000).all(|i| torque(i).abs() > 0.0),
            "torque before the unplug"
        );
        // Away: no torque, the exercise paused (its clock stands still).
        for t in &ticks[4200..5000] {
            assert_eq!(t.wheel.commanded_nm, 0.0, "tick {}", t.tick);
            assert!(t.score.paused, "tick {}", t.tick);
        }
        assert_eq!(ticks[4200].score.active_s, ticks[4999].score.active_s);
        // Back: still paused until the supervisor's fault clears, then a soft start: the
        // torque grows from zero (by no more than the slew limit) and the exercise resumes.
        let resumed = (5000..8000)
            .find(|&i| !ticks[i].score.paused)
            .expect("resumed");
        assert!(resumed > 5000, "not at once: {resumed}");
        assert_eq!(torque(resumed - 1), 0.0);
        assert_eq!(ticks[resumed].wheel.watchdog.to_string(), "soft-start");
        assert!((6000..8000).any(|i| torque(i).abs() > 0.0), "torque again");
        assert_eq!(plant.wheel_fault(), None);
        assert_eq!(plant.wheel_replugs(), 1);
    }

    #[test]
    fn a_wheel_not_back_within_the_grace_ends_the_session_as_unplugged() {
        let mut plant = plant_with(&["wheel-unplug@1"], 0.5);
        for _ in 0..1400 {
            plant.tick();
        }
        assert_eq!(plant.wheel_fault(), None, "within the grace");
        assert!(plant.wheel_away());
        for _ in 0..200 {
            plant.tick();
        }
        assert_eq!(plant.wheel_fault(), Some(WheelFault::Unplugged));
        // With no grace, at once (as before there was one).
        let mut plant = plant_with(&["wheel-unplug@1"], 0.0);
        for _ in 0..1000 {
            plant.tick();
        }
        assert_eq!(plant.wheel_fault(), None);
        for _ in 0..20 {
            plant.tick();
        }
        assert_eq!(plant.wheel_fault(), Some(WheelFault::Unplugged));
    }

    #[test]
    fn the_hub_relay_cuts_and_refuses_while_down_and_relays_again_when_up() {
        use std::io::{Read, Write};
        // The "hub": echoes what it reads.
        let hub = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
        let hub_addr = hub.local_addr().unwrap().to_string();
        std::thread::spawn(move || {
            for conn in hub.incoming() {
                let Ok(mut c) = conn else { continue };
                std::thread::spawn(move || {
                    let mut buf = [0u8; 64];
                    while let Ok(n @ 1..) = c.read(&mut buf) {
                        let _ = c.write_all(&buf[..n]);
                    }
                });
            }
        });
        let runtime = tokio::runtime::Builder::new_multi_thread()
            .worker_threads(1)
            .enable_all()
            .build()
            .unwrap();
        let faults = [
            FaultSpec::parse("hub-down@1").unwrap(),
            FaultSpec::parse("hub-up@2").unwrap(),
        ];
        let switch = HubSwitch::start(runtime.handle(), &hub_addr, &faults)
            .unwrap()
            .expect("a relay for a hub-down");
        let connect = || {
            let c = std::net::TcpStream::connect(switch.address()).unwrap();
            c.set_read_timeout(Some(std::time::Duration::from_secs(10)))
                .unwrap();
            c
        };
        let echo = |c: &mut std::net::TcpStream| {
            c.write_all(b"seq 1").ok()?;
            let mut buf = [0u8; 5];
            c.read_exact(&mut buf).ok()?;
            Some(buf)
        };
        switch.at(500_000_000);
        let mut before = connect();
        assert_eq!(echo(&mut before), Some(*b"seq 1"), "up: relayed");
        // Down: the open connection is cut, a new one closed before it carries a byte.
        switch.at(1_000_000_000);
        let mut buf = [0u8; 1];
        assert!(matches!(before.read(&mut buf), Ok(0) | Err(_)), "cut");
        let mut refused = connect();
        assert_eq!(echo(&mut refused), None, "refused while down");
        // Up again: relayed.
        switch.at(2_000_000_000);
        let mut after = connect();
        assert_eq!(echo(&mut after), Some(*b"seq 1"), "up again");
        // Without a hub-down there is no relay.
        assert!(
            HubSwitch::start(runtime.handle(), &hub_addr, &[])
                .unwrap()
                .is_none()
        );
    }

    #[test]
    fn a_saturated_encoder_is_no_reading_the_torque_fades_and_the_car_keeps_the_last_angle() {
        let mut plant = plant_with(&["wheel-saturated@2+0.3"], 30.0);
        let ticks: Vec<_> = (0..4000).map(|_| plant.tick()).collect();
        let half_range = SimWheel::new(SimWheelParams::default()).half_range_rad();
        assert!(
            ticks
                .iter()
                .all(|t| t.wheel.angle_rad.abs() < half_range / 2.0),
            "the end of the range never steered the car"
        );
        assert!(
            ticks[2010..2300]
                .iter()
                .all(|t| t.wheel.watchdog.to_string() == "fault-stale-reading"),
            "no reading while saturated"
        );
        assert!(
            ticks[2150..2300]
                .iter()
                .all(|t| t.wheel.commanded_nm == 0.0)
        );
        assert!(
            ticks[3000..]
                .iter()
                .any(|t| t.wheel.commanded_nm.abs() > 0.0),
            "torque again"
        );
    }
}
