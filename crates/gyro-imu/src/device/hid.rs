//! Real controller IMUs over hidapi (feature `hid`): enumerate, open (enable the IMU and read
//! its calibration), and poll timestamped SI samples without blocking.

use std::ffi::CString;

use hidapi::{BusType, HidApi, HidDevice};

use super::sony::{self, SonyCalibration};
use super::switch::{self, SwitchCalibration};
use super::{Imu, ImuDeviceInfo, ImuKind, ImuSample, TickUnwrapper, classify};
use crate::error::ImuError;

fn dev_err(what: &str, e: impl std::fmt::Display) -> ImuError {
    ImuError::Device(format!("{what}: {e}"))
}

/// List the supported controllers present on the HID bus.
pub fn enumerate() -> Result<Vec<ImuDeviceInfo>, ImuError> {
    let api = HidApi::new().map_err(|e| dev_err("cannot open the HID subsystem", e))?;
    let mut out: Vec<ImuDeviceInfo> = Vec::new();
    for d in api.device_list() {
        let Some((kind, name)) = classify(d.vendor_id(), d.product_id()) else {
            continue;
        };
        let path = d.path().to_string_lossy().into_owned();
        if out.iter().any(|o| o.path == path) {
            continue;
        }
        out.push(ImuDeviceInfo {
            kind,
            name: d
                .product_string()
                .filter(|s| !s.is_empty())
                .unwrap_or(name)
                .to_string(),
            path,
            vendor_id: d.vendor_id(),
            product_id: d.product_id(),
            bluetooth: matches!(d.bus_type(), BusType::Bluetooth),
            serial: d
                .serial_number()
                .filter(|s| !s.is_empty())
                .map(str::to_owned),
        });
    }
    Ok(out)
}

enum Protocol {
    Sony {
        cal: SonyCalibration,
        dualsense: bool,
        ticks: TickUnwrapper,
        anchor_ns: Option<u64>,
    },
    Switch {
        cal: SwitchCalibration,
    },
}

/// An open controller IMU.
pub struct HidImu {
    info: ImuDeviceInfo,
    dev: HidDevice,
    proto: Protocol,
    clock_ns: fn() -> u64,
    buf: [u8; 128],
}

impl std::fmt::Debug for HidImu {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("HidImu")
            .field("info", &self.info)
            .finish_non_exhaustive()
    }
}

impl HidImu {
    /// Open `info`'s device, enable its IMU reports and read its calibration (falling back to
    /// nominal scales, with the reason, if the calibration cannot be read). `clock_ns` is the
    /// caller's monotonic clock (ns) used to anchor device timestamps.
    pub fn open(
        info: &ImuDeviceInfo,
        clock_ns: fn() -> u64,
    ) -> Result<(Self, Option<ImuError>), ImuError> {
        let api = HidApi::new().map_err(|e| dev_err("cannot open the HID subsystem", e))?;
        let path = CString::new(info.path.clone()).map_err(|e| dev_err("bad device path", e))?;
        let dev = api
            .open_path(&path)
            .map_err(|e| dev_err(&format!("cannot open {}", info.path), e))?;
        let mut cal_warning = None;
        let proto = match info.kind {
            ImuKind::DualShock4 | ImuKind::DualSense => {
                let dualsense = info.kind == ImuKind::DualSense;
                // Reading the calibration feature report also switches Bluetooth controllers
                // to the full input report that carries the IMU.
                let (id, interleaved) = match (dualsense, info.bluetooth) {
                    (true, _) => (0x05, true),
                    (false, false) => (0x02, true),
                    (false, true) => (0x05, false),
                };
                let mut fb = [0u8; 64];
                fb[0] = id;
                let cal = match dev.get_feature_report(&mut fb) {
                    Ok(n) => SonyCalibration::from_feature_report(&fb[..n], interleaved),
                    Err(e) => Err(dev_err("calibration feature report", e)),
                }
                .unwrap_or_else(|e| {
                    cal_warning = Some(e);
                    SonyCalibration::nominal()
                });
                Protocol::Sony {
                    cal,
                    dualsense,
                    ticks: TickUnwrapper::default(),
                    anchor_ns: None,
                }
            }
            ImuKind::JoyConLeft | ImuKind::JoyConRight | ImuKind::ProController => {
                if !info.bluetooth && info.kind == ImuKind::ProController {
                    // USB handshake, then stop the USB timeout so reports keep flowing.
                    for cmd in [[0x80u8, 0x02], [0x80, 0x04]] {
                        dev.write(&cmd)
                            .map_err(|e| dev_err("Pro Controller USB handshake", e))?;
                    }
                }
                let cal = read_switch_calibration(&dev).unwrap_or_else(|e| {
                    cal_warning = Some(e);
                    SwitchCalibration::nominal()
                });
                dev.write(&switch::enable_imu(2))
                    .map_err(|e| dev_err("enable IMU", e))?;
                dev.write(&switch::set_full_report_mode(3))
                    .map_err(|e| dev_err("set report mode", e))?;
                Protocol::Switch { cal }
            }
            ImuKind::Simulated => {
                return Err(ImuError::Device(
                    "a simulated IMU is not a HID device".into(),
                ));
            }
        };
        dev.set_blocking_mode(false)
            .map_err(|e| dev_err("non-blocking mode", e))?;
        Ok((
            Self {
                info: info.clone(),
                dev,
                proto,
                clock_ns,
                buf: [0; 128],
            },
            cal_warning,
        ))
    }
}

/// Read the user IMU calibration if present, else the factory one (blocking, at open time).
fn read_switch_calibration(dev: &HidDevice) -> Result<SwitchCalibration, ImuError> {
    let read = |counter: u8, addr: u32, len: u8| -> Result<Vec<u8>, ImuError> {
        dev.write(&switch::spi_read(counter, addr, len))
            .map_err(|e| dev_err("SPI read request", e))?;
        let mut buf = [0u8; 64];
        for _ in 0..50 {
            let n = dev
                .read_timeout(&mut buf, 20)
                .map_err(|e| dev_err("SPI read reply", e))?;
            if let Some(data) = switch::spi_reply(&buf[..n], addr) {
                return Ok(data.to_vec());
            }
        }
        Err(ImuError::Device(format!(
            "no reply to SPI read at {addr:#06x}"
        )))
    };
    let magic = read(0, switch::USER_IMU_CAL_ADDR, 2)?;
    if magic == [0xb2, 0xa1] {
        SwitchCalibration::from_spi(&read(1, switch::USER_IMU_CAL_ADDR + 2, 24)?)
    } else {
        SwitchCalibration::from_spi(&read(1, switch::FACTORY_IMU_CAL_ADDR, 24)?)
    }
}

impl Imu for HidImu {
    fn info(&self) -> &ImuDeviceInfo {
        &self.info
    }

    fn gyro_range(&self) -> super::GyroRange {
        match &self.proto {
            Protocol::Sony { cal, .. } => cal.gyro_range(),
            Protocol::Switch { cal } => cal.gyro_range(),
        }
    }

    fn poll(&mut self, out: &mut [ImuSample]) -> Result<usize, ImuError> {
        let mut written = 0;
        while out.len() - written >= 3 {
            let n = self
                .dev
                .read(&mut self.buf)
                .map_err(|e| dev_err("read", e))?;
            if n == 0 {
                break;
            }
            let now = (self.clock_ns)();
            let report = &self.buf[..n];
            match &mut self.proto {
                Protocol::Sony {
                    cal,
                    dualsense,
                    ticks,
                    anchor_ns,
                } => {
                    let parsed = if *dualsense {
                        sony::parse_dualsense(report, cal)
                    } else {
                        sony::parse_ds4(report, cal)
                    };
                    let Ok(s) = parsed else { continue }; // other report ids (e.g. reduced BT reports)
                    let (tick_ns, modulus) = if *dualsense {
                        (sony::DUALSENSE_TICK_NS, sony::DUALSENSE_TICK_MODULUS)
                    } else {
                        (sony::DS4_TICK_NS, sony::DS4_TICK_MODULUS)
                    };
                    let elapsed = (ticks.unwrap(s.ticks, modulus) as f64 * tick_ns) as u64;
                    let anchor = *anchor_ns.get_or_insert(now);
                    out[written] = ImuSample {
                        t_ns: anchor + elapsed,
                        rate_rad_s: s.rate_rad_s,
                        acc_m_s2: Some(s.acc_m_s2),
                    };
                    written += 1;
                }
                Protocol::Switch { cal } => {
                    let Ok(r) = switch::parse_full_report(report, cal) else {
                        continue;
                    };
                    for f in 0..3 {
                        let back = (2 - f as u64) * switch::FRAME_PERIOD_NS;
                        out[written] = ImuSample {
                            t_ns: now.saturating_sub(back),
                            rate_rad_s: r.rate_rad_s[f],
                            acc_m_s2: Some(r.acc_m_s2[f]),
                        };
                        written += 1;
                    }
                }
            }
        }
        Ok(written)
    }
}
