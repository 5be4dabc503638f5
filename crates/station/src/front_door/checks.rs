//! The device check before a session, in words a patient understands: the wheel (or what to
//! plug in), its strongest push, the arm sensors, and a permission problem with its fix. The
//! technical details stay in `telerehab doctor`, which the lines point to.

use crate::readiness::{Status, permissions_check};
use render::StatusLine;
use wheel_devices::DeviceReport;

/// The lines of the device check and whether a wheel is ready to start a session.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DeviceCheck {
    /// One line per device, in plain words.
    pub lines: Vec<StatusLine>,
    /// A force-feedback wheel is there and can be used.
    pub wheel_ready: bool,
    /// The wheel's input node (its buttons start the session).
    pub wheel_path: Option<String>,
}

fn line(ok: Option<bool>, text: String) -> StatusLine {
    StatusLine { ok, text }
}

/// Checks the devices now (a few milliseconds; the arm sensors are listed, not opened).
/// `patient_ceiling_nm` is the station's torque ceiling for the patient, if configured.
pub fn check_devices(
    wheel_config: &haptic_wheel::wheel_config::WheelConfig,
    patient_ceiling_nm: Option<f64>,
) -> DeviceCheck {
    let mut devices = wheel_devices::enumerate_devices();
    devices.apply_config(wheel_config, patient_ceiling_nm);
    let imus = gyro_imu::device::enumerate().map_err(|e| e.to_string());
    describe(&devices, &imus)
}

/// The lines for what was found (separate from the scan so it is tested without devices).
pub fn describe(
    devices: &DeviceReport,
    imus: &Result<Vec<gyro_imu::device::ImuDeviceInfo>, String>,
) -> DeviceCheck {
    let mut lines = Vec::new();
    let permissions = permissions_check(devices);
    let wheel_ready = match devices.wheels.first() {
        None => {
            lines.push(line(Some(false), i18n::tr!("front-device-no-wheel")));
            false
        }
        Some(w) => {
            lines.push(line(
                Some(true),
                i18n::tr!("front-device-wheel", name = w.traits.name.clone()),
            ));
            if w.ceiling.as_ref().is_some_and(|c| c.assumed) {
                // A model telerehab does not know: its force is kept low.
                lines.push(line(None, i18n::tr!("front-device-wheel-unknown")));
            }
            true
        }
    };
    if permissions.status == Status::Fail {
        lines.push(line(Some(false), i18n::tr!("front-device-permission")));
    }
    match imus {
        Ok(list) if !list.is_empty() => {
            let names: Vec<&str> = list.iter().map(|d| d.name.as_str()).collect();
            lines.push(line(
                Some(true),
                i18n::tr!("front-device-arm-sensors", names = names.join(", ")),
            ));
        }
        _ => lines.push(line(None, i18n::tr!("front-device-no-arm-sensors"))),
    }
    DeviceCheck {
        lines,
        wheel_ready: wheel_ready && permissions.status != Status::Fail,
        wheel_path: devices.wheels.first().map(|w| w.path.clone()),
    }
}

/// The device check of a station whose wheel is simulated and scripted
/// ([`session::wheel_gestures::SCRIPT_ENV`]: tests and demonstrations): a wheel ready.
pub fn simulated() -> DeviceCheck {
    DeviceCheck {
        lines: vec![line(Some(true), i18n::tr!("front-device-simulated"))],
        wheel_ready: true,
        wheel_path: None,
    }
}
