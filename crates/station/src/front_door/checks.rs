//! The device check before a session, in words a patient understands: the wheel (or what to
//! plug in), its strongest push, the arm sensors, and a permission problem with its fix. The
//! technical details stay in `telerehab doctor`, which the lines point to.

use crate::commands::doctor::{self, Status};
use crate::render::StatusLine;
use haptic_wheel::DeviceReport;

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
    let mut devices = haptic_wheel::enumerate_devices();
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
    let permissions = doctor::permissions_check(devices);
    let wheel_ready = match devices.wheels.first() {
        None => {
            lines.push(line(
                Some(false),
                "No steering wheel found: plug it in and switch it on (most wheels need their \
                 own power supply). This page updates by itself."
                    .into(),
            ));
            false
        }
        Some(w) => {
            let push = w.ceiling.as_ref().map_or(String::new(), |c| {
                format!(", pushes at most {:.1} N·m", c.ceiling_nm)
            });
            let unknown = if w.ceiling.as_ref().is_some_and(|c| c.assumed) {
                " (a model telerehab does not know: its force is kept low until the clinic sets it)"
            } else {
                ""
            };
            lines.push(line(
                Some(true),
                format!("Wheel: {}{push}{unknown}", w.traits.name),
            ));
            true
        }
    };
    if permissions.status == Status::Fail {
        lines.push(line(
            Some(false),
            "This computer does not yet let telerehab use the wheel or the arm sensors. Install \
             the telerehab package (it sets this up), then unplug and plug them in again. \
             `telerehab doctor` says more."
                .into(),
        ));
    }
    match imus {
        Ok(list) if !list.is_empty() => {
            let names: Vec<&str> = list.iter().map(|d| d.name.as_str()).collect();
            lines.push(line(
                Some(true),
                format!("Arm sensors: {}", names.join(", ")),
            ));
        }
        _ => lines.push(line(
            None,
            "No arm sensors: the session runs without measuring your arm.".into(),
        )),
    }
    DeviceCheck {
        lines,
        wheel_ready: wheel_ready && permissions.status != Status::Fail,
        wheel_path: devices.wheels.first().map(|w| w.path.clone()),
    }
}
