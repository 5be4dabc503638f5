//! A readiness check and how it came out ([`Check`]: what was found, what to do), the line
//! `telerehab doctor` prints per check and the front door's device check words for the
//! patient; and the check both run before a session: can the device nodes be opened
//! ([`permissions_check`]).

use serde::Serialize;
use std::path::PathBuf;

/// How a check came out.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Status {
    /// Ready.
    Pass,
    /// A session cannot run (or cannot run safely) until this is fixed.
    Fail,
    /// A session runs, with less (no arm sensing, more jitter, software drawing…).
    Warn,
    /// Not checked, with the reason in the detail.
    Skip,
}

impl Status {
    /// The word `doctor`'s text prints for it (`PASS`, `FAIL`, `WARN`, `SKIP`).
    pub fn tag(self) -> &'static str {
        match self {
            Status::Pass => "PASS",
            Status::Fail => "FAIL",
            Status::Warn => "WARN",
            Status::Skip => "SKIP",
        }
    }
}

/// One check: what was found and what to do about it.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Check {
    /// What was checked, e.g. "wheel".
    pub name: String,
    /// How it came out.
    pub status: Status,
    /// What was found.
    pub detail: String,
    /// What to do (empty when there is nothing to do).
    pub fix: String,
}

/// A check named `name` that came out `status`.
pub fn check(
    name: &str,
    status: Status,
    detail: impl Into<String>,
    fix: impl Into<String>,
) -> Check {
    Check {
        name: name.into(),
        status,
        detail: detail.into(),
        fix: fix.into(),
    }
}

/// `/dev/hidraw*` nodes that exist but cannot be opened, with the reason.
fn unopenable_hidraw() -> Vec<(PathBuf, String)> {
    let Ok(entries) = std::fs::read_dir("/dev") else {
        return Vec::new();
    };
    let mut nodes: Vec<PathBuf> = entries
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.starts_with("hidraw"))
        })
        .collect();
    nodes.sort();
    nodes
        .into_iter()
        .filter_map(|p| {
            let opened = std::fs::OpenOptions::new().read(true).write(true).open(&p);
            opened.err().map(|e| (p, e.to_string()))
        })
        .collect()
}

/// Event and hidraw nodes that exist but cannot be opened: named, with the udev fix.
pub fn permissions_check(report: &wheel_devices::DeviceReport) -> Check {
    let mut blocked = report.unreadable.clone();
    blocked.extend(unopenable_hidraw());
    if blocked.is_empty() {
        return check(
            "device permissions",
            Status::Pass,
            "every input and HID device node present can be opened",
            "",
        );
    }
    let named: Vec<String> = blocked
        .iter()
        .map(|(p, why)| format!("{} ({why})", p.display()))
        .collect();
    check(
        "device permissions",
        Status::Fail,
        format!("cannot open {}", named.join(", ")),
        format!(
            "give the logged-in user access with a udev rule (`TAG+=\"uaccess\"`, sorted before \
             73-seat-late.rules): {}",
            wheel_devices::devices::UDEV_HINT
        ),
    )
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A device report holding one force-feedback wheel named `name` (the doctor's and the
    /// front door's tests use it).
    pub(crate) fn found_wheel(name: &str, usb_id: (u16, u16)) -> wheel_devices::DeviceReport {
        use wheel_devices::devices::{DeviceClass, DeviceInfo, DeviceTraits};
        let mut report = wheel_devices::DeviceReport::default();
        report.add(DeviceInfo {
            path: "/dev/input/event7".into(),
            class: DeviceClass::Wheel,
            traits: DeviceTraits {
                name: name.into(),
                ff_effects: vec!["constant", "gain"],
                abs_axes: vec!["x"],
                gamepad_buttons: false,
            },
            usb_id: Some(usb_id),
            profile: None,
            ceiling: None,
            expected_update_rate_hz: None,
            max_ff_effects: 16,
        });
        report.apply_config(&haptic_wheel::wheel_config::WheelConfig::default(), None);
        report
    }

    #[test]
    fn doctor_names_a_node_it_cannot_open_and_the_uaccess_rule_that_fixes_it() {
        let mut report = wheel_devices::DeviceReport::default();
        report.unreadable.push((
            PathBuf::from("/dev/input/event9"),
            "Permission denied (os error 13)".into(),
        ));
        let c = permissions_check(&report);
        assert_eq!(c.status, Status::Fail);
        assert!(
            c.detail.contains("/dev/input/event9 (Permission denied"),
            "{}",
            c.detail
        );
        assert!(c.fix.contains("TAG+=\"uaccess\""), "{}", c.fix);
    }
}
