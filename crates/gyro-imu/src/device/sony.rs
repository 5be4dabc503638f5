//! Sony DualShock 4 and DualSense IMU reports (layouts from the Linux `hid-playstation`
//! driver's public structure definitions).
//!
//! DualShock 4: USB input report `0x01` (64 bytes), Bluetooth `0x11` (78 bytes, 2 more header
//! bytes); after the header: sticks (4), buttons (3), triggers (2), timestamp `u16` in 16/3 µs
//! ticks, temperature (1), gyro `i16 ×3`, accel `i16 ×3` (little-endian, order x, y, z =
//! pitch, yaw, roll). DualSense: USB `0x01` (64 bytes), Bluetooth `0x31` (78 bytes, 1 more
//! header byte); sticks (4), triggers (2), sequence (1), buttons (4), reserved (4), gyro
//! `i16 ×3`, accel `i16 ×3`, timestamp `u32` in 1/3 µs ticks.
//!
//! Calibration feature report (DS4 USB `0x02`, DS4 BT `0x05`, DualSense `0x05`): gyro bias
//! `i16 ×3`; then the ±reference readings (`plus`, `minus` per axis interleaved on DS4 USB
//! and DualSense; all `plus` then all `minus` on DS4 BT); gyro reference speed `plus`,
//! `minus` (deg/s); accel `plus`, `minus` per axis (readings at ±1 g).

use nalgebra::Vector3;

use super::{G_M_S2, le_i16, le_u16, le_u32};
use crate::error::ImuError;

/// Per-axis linear calibration of a Sony controller's IMU.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SonyCalibration {
    /// Gyro zero-rate reading (counts).
    pub gyro_bias: [f64; 3],
    /// Gyro scale (rad/s per count).
    pub gyro_scale: [f64; 3],
    /// Accelerometer zero-g reading (counts).
    pub acc_bias: [f64; 3],
    /// Accelerometer scale (m/s² per count).
    pub acc_scale: [f64; 3],
}

impl SonyCalibration {
    /// Nominal values when the feature report is unavailable: ±2000 deg/s and ±4 g over 16 bit.
    pub fn nominal() -> Self {
        Self {
            gyro_bias: [0.0; 3],
            gyro_scale: [(2000.0f64 / 32768.0).to_radians(); 3],
            acc_bias: [0.0; 3],
            acc_scale: [G_M_S2 / 8192.0; 3],
        }
    }

    /// Decode a calibration feature report (`buf[0]` is the report id). `interleaved` is true
    /// for DS4 over USB and for the DualSense, false for DS4 over Bluetooth.
    pub fn from_feature_report(buf: &[u8], interleaved: bool) -> Result<Self, ImuError> {
        let bad = |reason: String| ImuError::MalformedReport {
            device: "Sony calibration",
            reason,
        };
        if buf.len() < 35 {
            return Err(bad(format!("{} bytes, need 35", buf.len())));
        }
        let r = |i: usize| f64::from(le_i16(buf, i));
        let bias = [r(1), r(3), r(5)];
        let (plus, minus) = if interleaved {
            ([r(7), r(11), r(15)], [r(9), r(13), r(17)])
        } else {
            ([r(7), r(9), r(11)], [r(13), r(15), r(17)])
        };
        let speed_2x = r(19) + r(21);
        let mut cal = Self {
            gyro_bias: bias,
            ..Self::nominal()
        };
        for i in 0..3 {
            let denom = (plus[i] - bias[i]).abs() + (minus[i] - bias[i]).abs();
            if denom < 1.0 || speed_2x <= 0.0 {
                return Err(bad(format!(
                    "gyro axis {i} reference range is {denom} counts at {speed_2x} deg/s"
                )));
            }
            cal.gyro_scale[i] = (speed_2x / denom).to_radians();
            let (ap, am) = (r(23 + 4 * i), r(25 + 4 * i));
            let range_2g = ap - am;
            if range_2g < 1.0 {
                return Err(bad(format!(
                    "accel axis {i} ±1 g range is {range_2g} counts"
                )));
            }
            cal.acc_bias[i] = ap - range_2g / 2.0;
            cal.acc_scale[i] = 2.0 * G_M_S2 / range_2g;
        }
        Ok(cal)
    }

    /// The rates this calibration reads at the 16-bit counts' extremes: the gyro's own full
    /// scale (±2000 °/s nominal reads at most 1999.94 °/s up, 2000 °/s down).
    pub fn gyro_range(&self) -> super::GyroRange {
        super::GyroRange::from_i16_counts(self.gyro_bias, self.gyro_scale)
    }

    fn convert(&self, gyro: [i16; 3], acc: [i16; 3]) -> (Vector3<f64>, Vector3<f64>) {
        let g =
            Vector3::from_fn(|i, _| (f64::from(gyro[i]) - self.gyro_bias[i]) * self.gyro_scale[i]);
        let a = Vector3::from_fn(|i, _| (f64::from(acc[i]) - self.acc_bias[i]) * self.acc_scale[i]);
        (g, a)
    }
}

/// A parsed report: device tick counter and SI values.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SonySample {
    /// Raw device timestamp counter.
    pub ticks: u64,
    /// Body rate (rad/s).
    pub rate_rad_s: Vector3<f64>,
    /// Specific force (m/s²).
    pub acc_m_s2: Vector3<f64>,
}

/// DualShock 4 timestamp: 16/3 µs per tick, wraps at 2¹⁶.
pub const DS4_TICK_NS: f64 = 16_000.0 / 3.0;
/// DualShock 4 timestamp modulus.
pub const DS4_TICK_MODULUS: u64 = 1 << 16;
/// DualSense timestamp: 1/3 µs per tick, wraps at 2³².
pub const DUALSENSE_TICK_NS: f64 = 1000.0 / 3.0;
/// DualSense timestamp modulus.
pub const DUALSENSE_TICK_MODULUS: u64 = 1 << 32;

fn raw3(buf: &[u8], at: usize) -> [i16; 3] {
    [le_i16(buf, at), le_i16(buf, at + 2), le_i16(buf, at + 4)]
}

/// Parse a DualShock 4 input report (`0x01` USB or `0x11` Bluetooth, `buf[0]` = report id).
pub fn parse_ds4(buf: &[u8], cal: &SonyCalibration) -> Result<SonySample, ImuError> {
    let base = match buf.first() {
        Some(0x01) => 1,
        Some(0x11) => 3,
        Some(id) => {
            return Err(ImuError::MalformedReport {
                device: "DualShock 4",
                reason: format!("report id {id:#04x} carries no IMU data"),
            });
        }
        None => {
            return Err(ImuError::MalformedReport {
                device: "DualShock 4",
                reason: "empty report".into(),
            });
        }
    };
    if buf.len() < base + 24 {
        return Err(ImuError::MalformedReport {
            device: "DualShock 4",
            reason: format!("{} bytes, need {}", buf.len(), base + 24),
        });
    }
    let (rate, acc) = cal.convert(raw3(buf, base + 12), raw3(buf, base + 18));
    Ok(SonySample {
        ticks: u64::from(le_u16(buf, base + 9)),
        rate_rad_s: rate,
        acc_m_s2: acc,
    })
}

/// Parse a DualSense input report (`0x01` USB or `0x31` Bluetooth, `buf[0]` = report id).
pub fn parse_dualsense(buf: &[u8], cal: &SonyCalibration) -> Result<SonySample, ImuError> {
    let base = match buf.first() {
        Some(0x01) => 1,
        Some(0x31) => 2,
        Some(id) => {
            return Err(ImuError::MalformedReport {
                device: "DualSense",
                reason: format!("report id {id:#04x} carries no IMU data"),
            });
        }
        None => {
            return Err(ImuError::MalformedReport {
                device: "DualSense",
                reason: "empty report".into(),
            });
        }
    };
    if buf.len() < base + 31 {
        return Err(ImuError::MalformedReport {
            device: "DualSense",
            reason: format!("{} bytes, need {}", buf.len(), base + 31),
        });
    }
    let (rate, acc) = cal.convert(raw3(buf, base + 15), raw3(buf, base + 21));
    Ok(SonySample {
        ticks: u64::from(le_u32(buf, base + 27)),
        rate_rad_s: rate,
        acc_m_s2: acc,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn put(buf: &mut [u8], at: usize, v: i16) {
        buf[at..at + 2].copy_from_slice(&v.to_le_bytes());
    }

    /// A DS4 USB calibration report: bias (−7, 9, −7), ±reference readings ±8900 around the
    /// bias at ±540 deg/s, accel ±8192 around (+100, −50, 0).
    fn ds4_usb_calibration() -> Vec<u8> {
        let mut b = vec![0u8; 37];
        b[0] = 0x02;
        for (i, v) in [-7i16, 9, -7].into_iter().enumerate() {
            put(&mut b, 1 + 2 * i, v);
            put(&mut b, 7 + 4 * i, v + 8900);
            put(&mut b, 9 + 4 * i, v - 8900);
        }
        put(&mut b, 19, 540);
        put(&mut b, 21, 540);
        for (i, c) in [100i16, -50, 0].into_iter().enumerate() {
            put(&mut b, 23 + 4 * i, c + 8192);
            put(&mut b, 25 + 4 * i, c - 8192);
        }
        b
    }

    #[test]
    fn ds4_calibration_decodes_scale_and_bias() {
        let cal = SonyCalibration::from_feature_report(&ds4_usb_calibration(), true).unwrap();
        assert_eq!(cal.gyro_bias, [-7.0, 9.0, -7.0]);
        assert!((cal.gyro_scale[0] - (1080.0f64 / 17800.0).to_radians()).abs() < 1e-15);
        assert_eq!(cal.acc_bias, [100.0, -50.0, 0.0]);
        assert!((cal.acc_scale[2] - G_M_S2 / 8192.0).abs() < 1e-15);
    }

    #[test]
    fn ds4_usb_report_is_parsed_to_si_units() {
        let cal = SonyCalibration::from_feature_report(&ds4_usb_calibration(), true).unwrap();
        // Report 0x01: sticks centred, timestamp 0x1234, gyro x = bias + 8900 (= +540 deg/s),
        // accel z = +8192 counts (= +1 g).
        let mut r = vec![0u8; 64];
        r[0] = 0x01;
        r[1..5].copy_from_slice(&[0x80; 4]);
        r[10] = 0x34;
        r[11] = 0x12;
        put(&mut r, 13, -7 + 8900);
        put(&mut r, 15, 9);
        put(&mut r, 17, -7 - 890);
        put(&mut r, 19, 100);
        put(&mut r, 21, -50);
        put(&mut r, 23, 8192);
        let s = parse_ds4(&r, &cal).unwrap();
        assert_eq!(s.ticks, 0x1234);
        assert!((s.rate_rad_s.x.to_degrees() - 540.0).abs() < 1e-9);
        assert!(s.rate_rad_s.y.abs() < 1e-12);
        assert!((s.rate_rad_s.z.to_degrees() + 54.0).abs() < 1e-9);
        assert!(s.acc_m_s2.x.abs() < 1e-12 && s.acc_m_s2.y.abs() < 1e-12);
        assert!((s.acc_m_s2.z - G_M_S2).abs() < 1e-9);
    }

    #[test]
    fn ds4_bluetooth_report_has_two_more_header_bytes() {
        let cal = SonyCalibration::nominal();
        let mut r = vec![0u8; 78];
        r[0] = 0x11;
        r[1] = 0xc0;
        r[12] = 0x01; // timestamp low byte at 3 + 9
        put(&mut r, 15, 16384); // gyro x at 3 + 12
        let s = parse_ds4(&r, &cal).unwrap();
        assert_eq!(s.ticks, 1);
        assert!((s.rate_rad_s.x.to_degrees() - 1000.0).abs() < 1e-9);
    }

    #[test]
    fn dualsense_usb_and_bluetooth_reports_are_parsed() {
        let cal = SonyCalibration::nominal();
        let mut usb = vec![0u8; 64];
        usb[0] = 0x01;
        put(&mut usb, 16, 0); // gyro x
        put(&mut usb, 18, -16384); // gyro y = −1000 deg/s
        put(&mut usb, 26, 8192); // accel z = 1 g
        usb[28..32].copy_from_slice(&0xdead_beef_u32.to_le_bytes());
        let s = parse_dualsense(&usb, &cal).unwrap();
        assert_eq!(s.ticks, 0xdead_beef);
        assert!((s.rate_rad_s.y.to_degrees() + 1000.0).abs() < 1e-9);
        assert!((s.acc_m_s2.z - G_M_S2).abs() < 1e-9);
        let mut bt = vec![0u8; 78];
        bt[0] = 0x31;
        bt[2..65].copy_from_slice(&usb[1..64]);
        let b = parse_dualsense(&bt, &cal).unwrap();
        assert_eq!(b, s);
    }

    #[test]
    fn a_dualshock_4_clips_at_its_own_full_scale_of_1999_94_deg_s_not_2000() {
        let cal = SonyCalibration::nominal();
        let range = cal.gyro_range();
        assert!((range.max_rad_s[0].to_degrees() - 1999.939).abs() < 1e-3);
        assert!((range.min_rad_s[0].to_degrees() + 2000.0).abs() < 1e-9);
        let mut r = vec![0u8; 64];
        r[0] = 0x01;
        let rate = |r: &mut Vec<u8>, x: i16| {
            put(r, 13, x);
            parse_ds4(r, &cal).unwrap().rate_rad_s
        };
        // The largest count reads 1999.94 °/s: clipped, though below 2000.
        let top = rate(&mut r, i16::MAX);
        assert!(top.x.to_degrees() < 2000.0 && range.clips(&top));
        // One count below it is a rate the sensor measured.
        assert!(!range.clips(&rate(&mut r, i16::MAX - 1)));
        assert!(range.clips(&rate(&mut r, i16::MIN)));
        assert!(!range.clips(&rate(&mut r, i16::MIN + 1)));
    }

    #[test]
    fn a_dualsense_clips_at_its_calibrated_full_scale_per_axis() {
        // Factory calibration of 540 °/s over 8900 counts each way, bias −7: the y axis reads
        // at most (32767 + 7) · 1080/17800 = 1988.5 °/s.
        let mut c = ds4_usb_calibration();
        c[0] = 0x05;
        let cal = SonyCalibration::from_feature_report(&c, true).unwrap();
        let range = cal.gyro_range();
        let expected_deg_s = (32767.0 - 9.0) * 1080.0 / 17800.0;
        assert!((range.max_rad_s[1].to_degrees() - expected_deg_s).abs() < 1e-9);
        let mut usb = vec![0u8; 64];
        usb[0] = 0x01;
        put(&mut usb, 18, i16::MAX);
        let top = parse_dualsense(&usb, &cal).unwrap().rate_rad_s;
        assert!(top.y.to_degrees() < 1990.0 && range.clips(&top));
        put(&mut usb, 18, i16::MAX - 1);
        assert!(!range.clips(&parse_dualsense(&usb, &cal).unwrap().rate_rad_s));
    }

    #[test]
    fn short_or_foreign_reports_are_errors() {
        let cal = SonyCalibration::nominal();
        assert!(parse_ds4(&[0x01, 0, 0], &cal).is_err());
        assert!(parse_ds4(&[0x05; 64], &cal).is_err());
        assert!(parse_dualsense(&[], &cal).is_err());
        assert!(SonyCalibration::from_feature_report(&[0x02; 37], true).is_err());
    }
}
