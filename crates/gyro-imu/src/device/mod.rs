//! IMU devices: the [`Imu`] trait, its sample type, and the report parsers of common game
//! controllers' IMUs (pure, always built). The hidapi backend is behind the `hid` feature.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::error::ImuError;

pub mod sony;
pub mod switch;

#[cfg(feature = "hid")]
pub mod hid;

/// One timestamped IMU sample in SI units, sensor frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImuSample {
    /// Sample time (ns) on the caller's monotonic clock.
    pub t_ns: u64,
    /// Body angular rate (rad/s).
    pub rate_rad_s: Vector3<f64>,
    /// Specific force (m/s²), if the device has an accelerometer.
    pub acc_m_s2: Option<Vector3<f64>>,
}

impl ImuSample {
    /// Whether every value is finite.
    pub fn is_finite(&self) -> bool {
        self.rate_rad_s.iter().all(|x| x.is_finite())
            && self
                .acc_m_s2
                .is_none_or(|a| a.iter().all(|x| x.is_finite()))
    }
}

/// Which kind of IMU a device is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[non_exhaustive]
pub enum ImuKind {
    /// A simulated sensor.
    Simulated,
    /// Sony DualShock 4.
    DualShock4,
    /// Sony DualSense.
    DualSense,
    /// Nintendo Joy-Con (left).
    JoyConLeft,
    /// Nintendo Joy-Con (right).
    JoyConRight,
    /// Nintendo Switch Pro Controller.
    ProController,
}

/// A device that can be opened as an IMU.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ImuDeviceInfo {
    /// Device family.
    pub kind: ImuKind,
    /// Human-readable name.
    pub name: String,
    /// Backend-specific path to open (hidraw path for HID devices).
    pub path: String,
    /// USB vendor id.
    pub vendor_id: u16,
    /// USB product id.
    pub product_id: u16,
    /// Whether connected over Bluetooth (otherwise USB).
    pub bluetooth: bool,
    /// The unit's serial number (over Bluetooth usually its address), if it reports one: what
    /// tells two controllers of the same model apart.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub serial: Option<String>,
}

/// The rates a gyro can read before it clips, per axis (rad/s): each device's own, from its
/// report parser's scale and bias (a DualShock 4 at nominal scale reads at most
/// 32767 · 2000/32768 = 1999.94 °/s one way and 2000 °/s the other).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GyroRange {
    /// The most negative rate each axis reads (its smallest count), rad/s.
    pub min_rad_s: [f64; 3],
    /// The most positive rate each axis reads (its largest count), rad/s.
    pub max_rad_s: [f64; 3],
    /// Half a count of each axis, rad/s: a reading this close to a limit is at it.
    pub half_count_rad_s: [f64; 3],
}

impl GyroRange {
    /// A gyro reading signed 16-bit counts as `(count − bias) · scale` (rad/s per count).
    pub fn from_i16_counts(bias: [f64; 3], scale_rad_s: [f64; 3]) -> Self {
        Self {
            min_rad_s: std::array::from_fn(|i| (f64::from(i16::MIN) - bias[i]) * scale_rad_s[i]),
            max_rad_s: std::array::from_fn(|i| (f64::from(i16::MAX) - bias[i]) * scale_rad_s[i]),
            half_count_rad_s: scale_rad_s.map(|s| 0.5 * s.abs()),
        }
    }

    /// A gyro clamped to ±`full_scale_rad_s` on every axis, read without quantisation (a
    /// simulated sensor).
    pub fn symmetric(full_scale_rad_s: f64) -> Self {
        Self {
            min_rad_s: [-full_scale_rad_s; 3],
            max_rad_s: [full_scale_rad_s; 3],
            half_count_rad_s: [0.0; 3],
        }
    }

    /// Whether any axis of `rate_rad_s` reads at (within half a count of) or beyond its
    /// limit: the sensor clipped, and the reading is not the motion.
    pub fn clips(&self, rate_rad_s: &Vector3<f64>) -> bool {
        (0..3).any(|i| {
            let (r, h) = (rate_rad_s[i], self.half_count_rad_s[i]);
            r >= self.max_rad_s[i] - h || r <= self.min_rad_s[i] + h
        })
    }
}

/// A source of IMU samples. Reading never blocks and never allocates.
pub trait Imu {
    /// What this device is.
    fn info(&self) -> &ImuDeviceInfo;

    /// The rates this device's gyro reads before it clips (its own scale and bias).
    fn gyro_range(&self) -> GyroRange;

    /// Move the samples received since the last call into `out` (oldest first); returns how
    /// many were written. Samples that do not fit are kept for the next call.
    fn poll(&mut self, out: &mut [ImuSample]) -> Result<usize, ImuError>;
}

/// USB vendor/product ids of the supported controllers.
pub const KNOWN_DEVICES: [(u16, u16, ImuKind, &str); 7] = [
    (0x054c, 0x05c4, ImuKind::DualShock4, "DualShock 4 (v1)"),
    (0x054c, 0x09cc, ImuKind::DualShock4, "DualShock 4 (v2)"),
    (0x054c, 0x0ce6, ImuKind::DualSense, "DualSense"),
    (0x054c, 0x0df2, ImuKind::DualSense, "DualSense Edge"),
    (0x057e, 0x2006, ImuKind::JoyConLeft, "Joy-Con (L)"),
    (0x057e, 0x2007, ImuKind::JoyConRight, "Joy-Con (R)"),
    (0x057e, 0x2009, ImuKind::ProController, "Pro Controller"),
];

/// The supported family of a vendor/product id pair.
pub fn classify(vendor_id: u16, product_id: u16) -> Option<(ImuKind, &'static str)> {
    KNOWN_DEVICES
        .iter()
        .find(|(v, p, _, _)| *v == vendor_id && *p == product_id)
        .map(|(_, _, k, n)| (*k, *n))
}

/// List the IMU devices present. Without the `hid` feature, or without any device, the list
/// is empty; an error only if the HID subsystem itself cannot be opened.
pub fn enumerate() -> Result<Vec<ImuDeviceInfo>, ImuError> {
    #[cfg(feature = "hid")]
    {
        hid::enumerate()
    }
    #[cfg(not(feature = "hid"))]
    {
        Ok(Vec::new())
    }
}

/// Unwraps a device's wrapping tick counter into a monotonic tick count.
#[derive(Debug, Clone, Copy, Default)]
pub struct TickUnwrapper {
    last: Option<u64>,
    total: u64,
}

impl TickUnwrapper {
    /// Feed a raw counter value that wraps at `modulus`; returns ticks since the first value.
    pub fn unwrap(&mut self, raw: u64, modulus: u64) -> u64 {
        if let Some(last) = self.last {
            self.total += (raw + modulus - last) % modulus;
        }
        self.last = Some(raw);
        self.total
    }
}

pub(crate) fn le_i16(buf: &[u8], at: usize) -> i16 {
    i16::from_le_bytes([buf[at], buf[at + 1]])
}

pub(crate) fn le_u16(buf: &[u8], at: usize) -> u16 {
    u16::from_le_bytes([buf[at], buf[at + 1]])
}

pub(crate) fn le_u32(buf: &[u8], at: usize) -> u32 {
    u32::from_le_bytes([buf[at], buf[at + 1], buf[at + 2], buf[at + 3]])
}

/// Standard gravity used to convert g to m/s².
pub const G_M_S2: f64 = 9.80665;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tick_unwrapper_counts_across_wraps() {
        let mut u = TickUnwrapper::default();
        assert_eq!(u.unwrap(65530, 65536), 0);
        assert_eq!(u.unwrap(4, 65536), 10);
        assert_eq!(u.unwrap(10, 65536), 16);
    }

    #[test]
    fn known_ids_classify_and_unknown_do_not() {
        assert_eq!(classify(0x054c, 0x0ce6).unwrap().0, ImuKind::DualSense);
        assert!(classify(0x046d, 0xc24f).is_none());
    }

    #[test]
    fn enumerate_returns_a_list_or_a_clear_error_without_devices() {
        match enumerate() {
            Ok(list) => assert!(
                list.iter()
                    .all(|d| classify(d.vendor_id, d.product_id).is_some())
            ),
            Err(e) => assert!(!e.to_string().is_empty()),
        }
    }
}
