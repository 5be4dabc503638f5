//! Nintendo Joy-Con and Pro Controller IMU reports (public reverse-engineering notes, dekuNukem
//! "Nintendo_Switch_Reverse_Engineering", and the Linux `hid-nintendo` driver).
//!
//! Standard full input report `0x30`: id, timer (u8), battery/connection, buttons (3), left
//! stick (3), right stick (3), vibrator byte, then three IMU frames 5 ms apart, each accel
//! `i16 ×3` then gyro `i16 ×3` (little-endian), oldest first. The IMU is off until subcommand
//! `0x40 01`; full reports need subcommand `0x03 30`. Subcommands go in output report `0x01`:
//! id, packet counter (0–15), 8 bytes of neutral rumble, subcommand id, arguments. Factory IMU
//! calibration lives in SPI flash at `0x6020` (24 bytes: accel origin ×3, accel sensitivity
//! ×3, gyro origin ×3, gyro sensitivity ×3); user calibration at `0x8028` when `0x8026` holds
//! the magic `B2 A1`. Conversion: accel `g = raw·4 / (sens − origin)`, gyro
//! `deg/s = (raw − origin)·936 / (sens − origin)`.

use nalgebra::Vector3;

use super::{G_M_S2, le_i16};
use crate::error::ImuError;

/// Time between the three IMU frames of one report (ns).
pub const FRAME_PERIOD_NS: u64 = 5_000_000;
/// SPI address of the factory IMU calibration.
pub const FACTORY_IMU_CAL_ADDR: u32 = 0x6020;
/// SPI address of the user IMU calibration magic (`B2 A1`), data follows at +2.
pub const USER_IMU_CAL_ADDR: u32 = 0x8026;

/// Neutral rumble bytes sent with every subcommand.
const NEUTRAL_RUMBLE: [u8; 8] = [0x00, 0x01, 0x40, 0x40, 0x00, 0x01, 0x40, 0x40];

/// Build an output report `0x01` carrying subcommand `id` with `args` (max 38 bytes).
pub fn subcommand(counter: u8, id: u8, args: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(49);
    out.push(0x01);
    out.push(counter & 0x0f);
    out.extend_from_slice(&NEUTRAL_RUMBLE);
    out.push(id);
    out.extend_from_slice(&args[..args.len().min(38)]);
    out.resize(49, 0);
    out
}

/// Subcommand enabling the IMU (`0x40 01`).
pub fn enable_imu(counter: u8) -> Vec<u8> {
    subcommand(counter, 0x40, &[0x01])
}

/// Subcommand selecting the standard full report mode `0x30` (`0x03 30`).
pub fn set_full_report_mode(counter: u8) -> Vec<u8> {
    subcommand(counter, 0x03, &[0x30])
}

/// Subcommand reading `len` bytes of SPI flash at `addr` (`0x10`, address LE, length).
pub fn spi_read(counter: u8, addr: u32, len: u8) -> Vec<u8> {
    let a = addr.to_le_bytes();
    subcommand(counter, 0x10, &[a[0], a[1], a[2], a[3], len])
}

/// Extract the data of an SPI-read reply (input report `0x21`, ack byte 13, subcommand id
/// `0x10` at 14, address at 15–18, length at 19, data from 20). `None` if `buf` is not the
/// reply to a read of `addr`.
pub fn spi_reply(buf: &[u8], addr: u32) -> Option<&[u8]> {
    if buf.len() < 20 || buf[0] != 0x21 || buf[14] != 0x10 || buf[13] & 0x80 == 0 {
        return None;
    }
    if u32::from_le_bytes([buf[15], buf[16], buf[17], buf[18]]) != addr {
        return None;
    }
    let len = buf[19] as usize;
    buf.get(20..20 + len)
}

/// Linear IMU calibration of a Switch controller.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SwitchCalibration {
    /// Accelerometer scale (m/s² per count).
    pub acc_scale: [f64; 3],
    /// Gyro zero-rate reading (counts).
    pub gyro_origin: [f64; 3],
    /// Gyro scale (rad/s per count).
    pub gyro_scale: [f64; 3],
}

impl SwitchCalibration {
    /// Nominal values (accel sensitivity 16384, gyro sensitivity 13371, origins 0).
    pub fn nominal() -> Self {
        Self {
            acc_scale: [4.0 * G_M_S2 / 16384.0; 3],
            gyro_origin: [0.0; 3],
            gyro_scale: [(936.0f64 / 13371.0).to_radians(); 3],
        }
    }

    /// The rates this calibration reads at the 16-bit counts' extremes: the gyro's own full
    /// scale (nominal: 32767 · 936/13371 = 2293.8 °/s up, 2293.9 °/s down).
    pub fn gyro_range(&self) -> super::GyroRange {
        super::GyroRange::from_i16_counts(self.gyro_origin, self.gyro_scale)
    }

    /// Decode the 24-byte SPI calibration block.
    pub fn from_spi(block: &[u8]) -> Result<Self, ImuError> {
        if block.len() < 24 {
            return Err(ImuError::MalformedReport {
                device: "Switch calibration",
                reason: format!("{} bytes, need 24", block.len()),
            });
        }
        let r = |i: usize| f64::from(le_i16(block, 2 * i));
        let mut c = Self::nominal();
        for i in 0..3 {
            let (ao, asens, go, gsens) = (r(i), r(3 + i), r(6 + i), r(9 + i));
            if asens - ao < 1.0 || gsens - go < 1.0 {
                return Err(ImuError::MalformedReport {
                    device: "Switch calibration",
                    reason: format!(
                        "axis {i}: accel span {} / gyro span {} counts",
                        asens - ao,
                        gsens - go
                    ),
                });
            }
            c.acc_scale[i] = 4.0 * G_M_S2 / (asens - ao);
            c.gyro_origin[i] = go;
            c.gyro_scale[i] = (936.0 / (gsens - go)).to_radians();
        }
        Ok(c)
    }
}

/// One parsed `0x30` report: the report timer and three IMU frames, oldest first.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SwitchReport {
    /// The report's 8-bit timer.
    pub timer: u8,
    /// Body rates (rad/s), oldest first, 5 ms apart.
    pub rate_rad_s: [Vector3<f64>; 3],
    /// Specific forces (m/s²), oldest first.
    pub acc_m_s2: [Vector3<f64>; 3],
}

/// Parse a standard full input report `0x30` (`buf[0]` = report id).
pub fn parse_full_report(buf: &[u8], cal: &SwitchCalibration) -> Result<SwitchReport, ImuError> {
    let bad = |reason: String| ImuError::MalformedReport {
        device: "Switch",
        reason,
    };
    match buf.first() {
        Some(0x30) => {}
        Some(id) => return Err(bad(format!("report id {id:#04x} carries no IMU data"))),
        None => return Err(bad("empty report".into())),
    }
    if buf.len() < 49 {
        return Err(bad(format!("{} bytes, need 49", buf.len())));
    }
    let mut rep = SwitchReport {
        timer: buf[1],
        rate_rad_s: [Vector3::zeros(); 3],
        acc_m_s2: [Vector3::zeros(); 3],
    };
    for f in 0..3 {
        let at = 13 + 12 * f;
        rep.acc_m_s2[f] =
            Vector3::from_fn(|i, _| f64::from(le_i16(buf, at + 2 * i)) * cal.acc_scale[i]);
        rep.rate_rad_s[f] = Vector3::from_fn(|i, _| {
            (f64::from(le_i16(buf, at + 6 + 2 * i)) - cal.gyro_origin[i]) * cal.gyro_scale[i]
        });
    }
    Ok(rep)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn subcommands_are_byte_exact() {
        assert_eq!(
            enable_imu(3)[..12],
            [
                0x01, 0x03, 0x00, 0x01, 0x40, 0x40, 0x00, 0x01, 0x40, 0x40, 0x40, 0x01
            ]
        );
        assert_eq!(set_full_report_mode(17)[1..2], [0x01]);
        assert_eq!(set_full_report_mode(0)[10..12], [0x03, 0x30]);
        let r = spi_read(5, 0x6020, 24);
        assert_eq!(r.len(), 49);
        assert_eq!(r[10..16], [0x10, 0x20, 0x60, 0x00, 0x00, 24]);
    }

    #[test]
    fn spi_reply_data_is_extracted_only_for_the_matching_read() {
        let mut buf = vec![0u8; 64];
        buf[0] = 0x21;
        buf[13] = 0x90;
        buf[14] = 0x10;
        buf[15..19].copy_from_slice(&0x6020u32.to_le_bytes());
        buf[19] = 24;
        buf[20] = 0xaa;
        assert_eq!(spi_reply(&buf, 0x6020).unwrap()[0], 0xaa);
        assert!(spi_reply(&buf, 0x8026).is_none());
    }

    #[test]
    fn calibration_block_and_full_report_convert_to_si() {
        // Accel origin (10, −20, 30), sensitivity origin + 16384; gyro origin (5, −5, 2),
        // sensitivity origin + 13371.
        let mut block = Vec::new();
        for v in [
            10i16,
            -20,
            30,
            10 + 16384,
            -20 + 16384,
            30 + 16384,
            5,
            -5,
            2,
            5 + 13371,
            -5 + 13371,
            2 + 13371,
        ] {
            block.extend_from_slice(&v.to_le_bytes());
        }
        let cal = SwitchCalibration::from_spi(&block).unwrap();
        let mut r = vec![0u8; 49];
        r[0] = 0x30;
        r[1] = 0x42;
        // Frame 2 (the newest): accel z = 4096 counts = 1 g; gyro x = origin + 1337.1·… use
        // exactly 13371 counts above origin = 936 deg/s.
        let at = 13 + 24;
        r[at + 4..at + 6].copy_from_slice(&4096i16.to_le_bytes());
        r[at + 6..at + 8].copy_from_slice(&(5i16 + 13371).to_le_bytes());
        // Frame 0: gyro y at origin → 0.
        r[13 + 8..13 + 10].copy_from_slice(&(-5i16).to_le_bytes());
        let rep = parse_full_report(&r, &cal).unwrap();
        assert_eq!(rep.timer, 0x42);
        assert!((rep.acc_m_s2[2].z - G_M_S2).abs() < 1e-9);
        assert!((rep.rate_rad_s[2].x.to_degrees() - 936.0).abs() < 1e-9);
        assert!(rep.rate_rad_s[0].y.abs() < 1e-12);
        assert!(parse_full_report(&r[..40], &cal).is_err());
        assert!(parse_full_report(&[0x3f; 49], &cal).is_err());
    }

    #[test]
    fn a_joy_con_clips_at_its_own_full_scale_of_about_2294_deg_s() {
        let cal = SwitchCalibration::nominal();
        let range = cal.gyro_range();
        let expected_deg_s = 32767.0 * 936.0 / 13371.0;
        assert!((range.max_rad_s[2].to_degrees() - expected_deg_s).abs() < 1e-9);
        let mut r = vec![0u8; 49];
        r[0] = 0x30;
        // Frame 0's gyro z at the largest count, frame 1's one count below it.
        r[13 + 10..13 + 12].copy_from_slice(&i16::MAX.to_le_bytes());
        r[25 + 10..25 + 12].copy_from_slice(&(i16::MAX - 1).to_le_bytes());
        let rep = parse_full_report(&r, &cal).unwrap();
        // 2293.8 °/s: far above a Sony controller's 2000, and a clipped reading here.
        assert!(rep.rate_rad_s[0].z.to_degrees() > 2290.0 && range.clips(&rep.rate_rad_s[0]));
        assert!(!range.clips(&rep.rate_rad_s[1]));
        // A DualShock 4's full scale is a rate a Joy-Con measures.
        let ds4_top = super::super::sony::SonyCalibration::nominal()
            .gyro_range()
            .max_rad_s;
        assert!(!range.clips(&Vector3::from(ds4_top)));
    }
}
