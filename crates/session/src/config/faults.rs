//! Faults as the command line and the configuration give them (`KIND@SECONDS[+DURATION]`),
//! checked together, and the session-time window each acts in.

use arm::sim::ImuFault;
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
    /// The arm IMUs' rates read their full scale, ±[`arm::sim::IMU_FULL_SCALE_RAD_S`] (default
    /// 200 ms).
    ImuSaturated,
    /// The therapist's hub goes away: the link's connection is cut and every new one refused
    /// (until a `hub-up`, or for good).
    HubDown,
    /// The hub comes back (ends the `hub-down` before it).
    HubUp,
    /// The wheel refuses the station's force commands (every write of the ceiling and the
    /// torque fails, EIO) while its readings stay fresh; its motor keeps the last force
    /// (default 200 ms).
    WheelWriteFail,
}

impl FaultKind {
    /// Every kind, by its name.
    pub const ALL: [FaultKind; 16] = [
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
        FaultKind::WheelWriteFail,
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
            FaultKind::WheelWriteFail => "wheel-write-fail",
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
            FaultKind::WheelWriteFail => Some(0.2),
            // An event, not a window: it ends the fault before it.
            FaultKind::WheelReplug | FaultKind::ImuReplug | FaultKind::HubUp => Some(0.0),
        }
    }

    /// A fault of the wheel's readings (what [`FaultyWheel`] plays on each read).
    pub(crate) fn acts_on_readings(self) -> bool {
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

/// The arm-sensor faults among `faults`, as the simulated IMUs take them, with their
/// session-time windows (ns).
pub fn imu_faults(faults: &[FaultSpec]) -> Vec<(ImuFault, u64, u64)> {
    windows(faults)
        .into_iter()
        .filter_map(|(k, start, end)| {
            let fault = match k {
                FaultKind::ImuUnplug => ImuFault::Unplug,
                FaultKind::ImuNan => ImuFault::Nan,
                FaultKind::ImuFrozen => ImuFault::Frozen,
                FaultKind::ImuSaturated => ImuFault::Saturated,
                _ => return None,
            };
            Some((fault, start, end))
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

#[cfg(test)]
mod tests {
    use super::*;

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
}
