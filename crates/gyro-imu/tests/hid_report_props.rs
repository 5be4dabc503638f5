//! The HID report parsers of the controller IMUs (DualShock 4, DualSense, Switch) and their
//! calibration readers over arbitrary bytes and over valid reports mutated and truncated: no
//! panic, every parsed value finite, and every refusal names the device and the problem (the
//! length it needed, the report id it cannot use, the calibration axis out of range).
//! The same parsers run under cargo-fuzz: `fuzz/README.md`.

use gyro_imu::ImuError;
use gyro_imu::device::TickUnwrapper;
use gyro_imu::device::sony::{self, SonyCalibration};
use gyro_imu::device::switch::{self, SwitchCalibration};
use proptest::prelude::*;

fn put(buf: &mut [u8], at: usize, v: i16) {
    buf[at..at + 2].copy_from_slice(&v.to_le_bytes());
}

/// A DualShock 4 calibration feature report (USB layout, interleaved plus/minus).
fn ds4_calibration() -> Vec<u8> {
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

/// One valid report of each kind the parsers read.
fn valid_reports() -> Vec<Vec<u8>> {
    let mut ds4 = vec![0u8; 64];
    ds4[0] = 0x01;
    put(&mut ds4, 13, 8893);
    let mut ds4_bt = vec![0u8; 78];
    ds4_bt[0] = 0x11;
    put(&mut ds4_bt, 15, 16384);
    let mut dualsense = vec![0u8; 78];
    dualsense[0] = 0x31;
    put(&mut dualsense, 19, -16384);
    let mut full = vec![0u8; 49];
    full[0] = 0x30;
    put(&mut full, 17, 4096);
    let mut spi = vec![0u8; 64];
    spi[0] = 0x21;
    spi[13] = 0x90;
    spi[14] = 0x10;
    spi[15..19].copy_from_slice(&switch::FACTORY_IMU_CAL_ADDR.to_le_bytes());
    spi[19] = 24;
    for i in 0..3 {
        put(&mut spi, 26 + 2 * i, 16384);
        put(&mut spi, 38 + 2 * i, 13371);
    }
    vec![ds4_calibration(), ds4, ds4_bt, dualsense, full, spi]
}

/// The error is a malformed report naming `device` and saying what was wrong.
fn names_the_problem(e: &ImuError, device: &str) -> Result<(), TestCaseError> {
    let msg = e.to_string();
    prop_assert!(msg.contains(device), "{msg} does not name {device}");
    let reason_named = ["need", "report id", "empty report", "axis", "range", "span"]
        .iter()
        .any(|w| msg.contains(w));
    prop_assert!(reason_named, "{msg} does not say what was wrong");
    Ok(())
}

fn check_sony(
    r: Result<sony::SonySample, ImuError>,
    device: &str,
    buf: &[u8],
    need: [usize; 2],
    ids: [u8; 2],
    modulus: u64,
) -> Result<(), TestCaseError> {
    match r {
        Ok(s) => {
            prop_assert!(
                s.rate_rad_s
                    .iter()
                    .chain(s.acc_m_s2.iter())
                    .all(|v| v.is_finite())
            );
            prop_assert!(s.ticks < modulus);
            TickUnwrapper::default().unwrap(s.ticks, modulus);
        }
        Err(e) => {
            names_the_problem(&e, device)?;
            let msg = e.to_string();
            match buf.first() {
                None => prop_assert!(msg.contains("empty report"), "{msg}"),
                Some(id) if !ids.contains(id) => prop_assert!(msg.contains("report id"), "{msg}"),
                Some(id) => {
                    let need = if *id == ids[0] { need[0] } else { need[1] };
                    prop_assert!(buf.len() < need, "{msg} for {} bytes", buf.len());
                    prop_assert!(msg.contains(&format!("need {need}")), "{msg}");
                }
            }
        }
    }
    Ok(())
}

/// Run every parser on `buf`.
fn parse_everything(buf: &[u8]) -> Result<(), TestCaseError> {
    let nominal = SonyCalibration::nominal();
    for interleaved in [false, true] {
        match SonyCalibration::from_feature_report(buf, interleaved) {
            Ok(c) => {
                let all = c.gyro_bias.iter().chain(&c.gyro_scale);
                prop_assert!(
                    all.chain(&c.acc_bias)
                        .chain(&c.acc_scale)
                        .all(|v| v.is_finite())
                );
                // A sample through the report's own calibration is finite too.
                if let Ok(s) = sony::parse_ds4(buf, &c) {
                    prop_assert!(s.rate_rad_s.iter().all(|v| v.is_finite()));
                }
            }
            Err(e) => names_the_problem(&e, "Sony calibration")?,
        }
    }
    check_sony(
        sony::parse_ds4(buf, &nominal),
        "DualShock 4",
        buf,
        [25, 27],
        [0x01, 0x11],
        sony::DS4_TICK_MODULUS,
    )?;
    check_sony(
        sony::parse_dualsense(buf, &nominal),
        "DualSense",
        buf,
        [32, 33],
        [0x01, 0x31],
        sony::DUALSENSE_TICK_MODULUS,
    )?;
    match switch::parse_full_report(buf, &SwitchCalibration::nominal()) {
        Ok(r) => {
            for f in 0..3 {
                prop_assert!(r.rate_rad_s[f].iter().all(|v| v.is_finite()));
                prop_assert!(r.acc_m_s2[f].iter().all(|v| v.is_finite()));
            }
        }
        Err(e) => names_the_problem(&e, "Switch")?,
    }
    for addr in [switch::FACTORY_IMU_CAL_ADDR, switch::USER_IMU_CAL_ADDR + 2] {
        if let Some(block) = switch::spi_reply(buf, addr) {
            prop_assert!(block.len() <= usize::from(buf[19]));
            match SwitchCalibration::from_spi(block) {
                Ok(c) => prop_assert!(
                    c.acc_scale
                        .iter()
                        .chain(&c.gyro_scale)
                        .all(|v| v.is_finite())
                ),
                Err(e) => names_the_problem(&e, "Switch calibration")?,
            }
        }
    }
    if let Err(e) = SwitchCalibration::from_spi(buf) {
        names_the_problem(&e, "Switch calibration")?;
    }
    Ok(())
}

/// A valid report with some bytes replaced and its length changed.
fn mutated_report() -> impl Strategy<Value = Vec<u8>> {
    let n = valid_reports().len();
    (
        0..n,
        proptest::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 0..8),
        prop_oneof![Just(None), (0usize..100).prop_map(Some)],
    )
        .prop_map(|(which, flips, len)| {
            let mut r = valid_reports()[which].clone();
            for (at, byte) in flips {
                let i = at.index(r.len());
                r[i] = byte;
            }
            if let Some(len) = len {
                r.resize(len, 0);
            }
            r
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

    #[test]
    fn arbitrary_bytes_never_panic_and_refusals_name_the_problem(
        buf in proptest::collection::vec(any::<u8>(), 0..100),
    ) {
        parse_everything(&buf)?;
    }

    #[test]
    fn mutated_and_truncated_reports_never_panic_and_refusals_name_the_problem(
        buf in mutated_report(),
    ) {
        parse_everything(&buf)?;
    }
}

#[test]
fn the_valid_reports_parse() {
    let r = valid_reports();
    let cal = SonyCalibration::from_feature_report(&r[0], true).unwrap();
    assert!(sony::parse_ds4(&r[1], &cal).is_ok());
    assert!(sony::parse_ds4(&r[2], &cal).is_ok());
    assert!(sony::parse_dualsense(&r[3], &cal).is_ok());
    assert!(switch::parse_full_report(&r[4], &SwitchCalibration::nominal()).is_ok());
    let block = switch::spi_reply(&r[5], switch::FACTORY_IMU_CAL_ADDR).unwrap();
    assert!(SwitchCalibration::from_spi(block).is_ok());
}
