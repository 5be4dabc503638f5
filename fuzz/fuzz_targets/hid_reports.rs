//! Every HID report parser of the controller IMUs (DualShock 4, DualSense, Switch) and their
//! calibration readers, over arbitrary bytes: no panic; a parsed sample is finite; an error
//! names the device and what was wrong.
//!
//! The first byte picks the parser, the rest is the report as the device would send it.

#![no_main]

use gyro_imu::ImuError;
use gyro_imu::device::TickUnwrapper;
use gyro_imu::device::sony::{self, SonyCalibration};
use gyro_imu::device::switch::{self, SwitchCalibration};
use libfuzzer_sys::fuzz_target;

fn check_error(e: &ImuError) {
    let msg = e.to_string();
    assert!(
        matches!(e, ImuError::MalformedReport { reason, .. } if !reason.is_empty()),
        "not a malformed-report error: {msg}"
    );
    assert!(msg.len() > 10, "{msg}");
}

fn check_sony(r: Result<sony::SonySample, ImuError>, ticks: &mut TickUnwrapper, modulus: u64) {
    match r {
        Ok(s) => {
            assert!(s.rate_rad_s.iter().all(|v| v.is_finite()), "{s:?}");
            assert!(s.acc_m_s2.iter().all(|v| v.is_finite()), "{s:?}");
            assert!(s.ticks < modulus);
            ticks.unwrap(s.ticks, modulus);
        }
        Err(e) => check_error(&e),
    }
}

fuzz_target!(|data: &[u8]| {
    let Some((&which, report)) = data.split_first() else {
        return;
    };
    let mut ticks = TickUnwrapper::default();
    match which % 4 {
        0 => {
            // Sony: the calibration feature report (USB and Bluetooth layouts), then input
            // reports with the nominal and, when it parsed, the report's own calibration.
            let cal = match SonyCalibration::from_feature_report(report, which & 0x10 != 0) {
                Ok(c) => {
                    for v in c
                        .gyro_bias
                        .iter()
                        .chain(&c.gyro_scale)
                        .chain(&c.acc_bias)
                        .chain(&c.acc_scale)
                    {
                        assert!(v.is_finite(), "{c:?}");
                    }
                    c
                }
                Err(e) => {
                    check_error(&e);
                    SonyCalibration::nominal()
                }
            };
            check_sony(
                sony::parse_ds4(report, &cal),
                &mut ticks,
                sony::DS4_TICK_MODULUS,
            );
            check_sony(
                sony::parse_dualsense(report, &cal),
                &mut ticks,
                sony::DUALSENSE_TICK_MODULUS,
            );
        }
        1 => {
            check_sony(
                sony::parse_ds4(report, &SonyCalibration::nominal()),
                &mut ticks,
                sony::DS4_TICK_MODULUS,
            );
            check_sony(
                sony::parse_dualsense(report, &SonyCalibration::nominal()),
                &mut ticks,
                sony::DUALSENSE_TICK_MODULUS,
            );
        }
        2 => {
            // Switch: an SPI read reply carrying the calibration block, then the block itself.
            let addr = switch::FACTORY_IMU_CAL_ADDR;
            if let Some(block) = switch::spi_reply(report, addr) {
                assert!(block.len() <= report.len().saturating_sub(20));
                match SwitchCalibration::from_spi(block) {
                    Ok(c) => assert!(
                        c.acc_scale
                            .iter()
                            .chain(&c.gyro_scale)
                            .all(|v| v.is_finite())
                    ),
                    Err(e) => check_error(&e),
                }
            }
            if let Err(e) = SwitchCalibration::from_spi(report) {
                check_error(&e);
            }
        }
        _ => {
            let cal = SwitchCalibration::nominal();
            match switch::parse_full_report(report, &cal) {
                Ok(r) => {
                    for f in 0..3 {
                        assert!(r.rate_rad_s[f].iter().all(|v| v.is_finite()));
                        assert!(r.acc_m_s2[f].iter().all(|v| v.is_finite()));
                    }
                    ticks.unwrap(u64::from(r.timer), 256);
                }
                Err(e) => check_error(&e),
            }
        }
    }
});
