//! `telerehab devices`' scan: every input node through the wheel backend (Linux, `evdev`;
//! Windows, DirectInput's force-feedback game controllers, `dinput`), and gamepads through
//! gilrs where evdev is absent, into a [`DeviceReport`] that explains itself. The device
//! kinds and the report are [`crate::devices`]'; the backends classify with them, and this
//! module calls the backends.

use crate::devices::DeviceReport;
#[cfg(all(target_os = "linux", feature = "evdev"))]
use crate::devices::event_nodes;

/// Scan for wheels, pedals and gamepads. Never panics and never fails: anything that goes
/// wrong becomes a note in the report.
pub fn enumerate_devices() -> DeviceReport {
    let mut report = DeviceReport::default();
    scan_platform(&mut report);
    report.explain();
    report
}

#[cfg(all(target_os = "linux", feature = "evdev"))]
fn scan_platform(report: &mut DeviceReport) {
    let paths = match event_nodes() {
        Ok(p) => p,
        Err(e) => {
            report.notes.push(format!(
                "This system has no readable /dev/input ({e}): no input devices are visible to \
                 this process (a container or VM without USB passthrough, or no devices at all)."
            ));
            return;
        }
    };
    if paths.is_empty() {
        report
            .notes
            .push("/dev/input has no event devices: nothing is connected.".into());
    }
    for path in paths {
        match crate::evdev_wheel::inspect(&path) {
            Ok(Some(info)) => report.add(info),
            Ok(None) => {}
            Err(e) => report.unreadable.push((path, e.to_string())),
        }
    }
}

#[cfg(not(all(target_os = "linux", feature = "evdev")))]
fn scan_platform(report: &mut DeviceReport) {
    #[cfg(all(windows, feature = "dinput"))]
    match crate::dinput_wheel::com::ComFinder.devices() {
        Ok(found) => {
            for d in &found {
                report.add(crate::dinput_wheel::com::describe(d));
            }
        }
        Err(e) => report.notes.push(format!(
            "DirectInput could not list the game controllers: {e}"
        )),
    }
    #[cfg(not(all(windows, feature = "dinput")))]
    report.notes.push(
        "Force-feedback wheels are supported through the Linux kernel FF API (feature `evdev`) \
         and DirectInput on Windows (feature `dinput`); this build has no wheel backend."
            .into(),
    );
    #[cfg(feature = "gilrs")]
    match crate::peripherals::list_gamepads() {
        Ok(list) => {
            for d in list {
                report.add(d);
            }
        }
        Err(e) => report.notes.push(format!("gamepad scan failed: {e}")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn enumerate_devices_explains_itself_when_nothing_is_found() {
        // On this machine (no /dev/input) and on CI: no wheel, and a plain note why.
        let r = enumerate_devices();
        let text = r.to_string();
        println!("{text}");
        if !r.has_wheel() {
            assert!(text.contains("No force-feedback wheel found"), "{text}");
        }
        assert!(!r.notes.is_empty() || r.has_wheel());
    }
}
