//! `telerehab devices`: which wheels, pedals and gamepads are connected, what they can do,
//! and — when nothing usable is found — a plain explanation of what to check.
//!
//! On Linux with the `evdev` feature every `/dev/input/event*` node is inspected. Nodes that
//! exist but cannot be opened are counted (usually missing permissions: the udev rule in
//! `packaging/udev/` fixes that). Elsewhere gamepads are listed through gilrs when that
//! feature is on.

use std::fmt;
use std::path::PathBuf;

use haptic_wheel::profile::DeviceProfile;

/// What kind of input device this is, for the haptic station.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DeviceClass {
    /// Force feedback with constant force and a steering axis: the haptic loop can drive it.
    Wheel,
    /// Absolute axes without force feedback or gamepad buttons, e.g. pedals.
    Pedals,
    /// A gamepad (face buttons); may have rumble, which the station never uses on a wheel.
    Gamepad,
}

/// The facts used to classify a device, independent of the OS API.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DeviceTraits {
    /// Device name as reported by the driver.
    pub name: String,
    /// Force-feedback effect names supported (e.g. "constant", "spring", "gain").
    pub ff_effects: Vec<&'static str>,
    /// Absolute axis names present (e.g. "x", "wheel", "gas").
    pub abs_axes: Vec<&'static str>,
    /// Has gamepad face buttons (BTN_SOUTH / BTN_GAMEPAD).
    pub gamepad_buttons: bool,
}

/// Classify a device from its traits; `None` for anything the station does not use
/// (keyboards, mice, power buttons…).
pub fn classify(t: &DeviceTraits) -> Option<DeviceClass> {
    let steering = t.abs_axes.iter().any(|a| *a == "x" || *a == "wheel");
    if t.ff_effects.contains(&"constant") && steering {
        return Some(DeviceClass::Wheel);
    }
    if t.gamepad_buttons {
        return Some(DeviceClass::Gamepad);
    }
    let pedal_axes = ["gas", "brake", "throttle", "rudder", "z", "rz", "y"];
    let lower = t.name.to_lowercase();
    if t.ff_effects.is_empty()
        && (lower.contains("pedal")
            || t.abs_axes
                .iter()
                .any(|a| ["gas", "brake", "throttle"].contains(a))
            || (!t.abs_axes.is_empty() && t.abs_axes.iter().all(|a| pedal_axes.contains(a))))
    {
        return Some(DeviceClass::Pedals);
    }
    None
}

/// One input device found.
#[derive(Clone, Debug, PartialEq)]
pub struct DeviceInfo {
    /// Device node (`/dev/input/eventN`) or backend id.
    pub path: String,
    /// What it is.
    pub class: DeviceClass,
    /// Name, axes, buttons, force-feedback effects.
    pub traits: DeviceTraits,
    /// USB vendor and product id, when known.
    pub usb_id: Option<(u16, u16)>,
    /// For wheels: the device profile the backend would use (scales, rate policy).
    pub profile: Option<DeviceProfile>,
    /// For wheels: the torque ceiling that would hold with the station's configuration
    /// ([`DeviceReport::apply_config`]).
    pub ceiling: Option<haptic_wheel::wheel_config::CeilingReport>,
    /// For wheels: the torque updates a second the backend would send it, Hz (the driver's
    /// rate policy, lowered by a configured `update_rate_hz`; [`DeviceReport::apply_config`]).
    pub expected_update_rate_hz: Option<f64>,
    /// For wheels: how many effects the device can hold at once.
    pub max_ff_effects: usize,
}

/// Everything `telerehab devices` prints.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DeviceReport {
    /// Force-feedback wheels.
    pub wheels: Vec<DeviceInfo>,
    /// Pedal sets and other axis-only devices.
    pub pedals: Vec<DeviceInfo>,
    /// Gamepads.
    pub gamepads: Vec<DeviceInfo>,
    /// Input nodes that exist but could not be opened, with the reason.
    pub unreadable: Vec<(PathBuf, String)>,
    /// Plain-language notes: what was checked, what to do.
    pub notes: Vec<String>,
}

/// Where the shipped udev rule lives and how to install it.
pub const UDEV_HINT: &str = "install the telerehab package (it ships the udev rule as \
/usr/lib/udev/rules.d/70-telerehab.rules and reloads udev), or from the sources \
`sudo cp packaging/udev/70-telerehab.rules /etc/udev/rules.d/ && sudo udevadm control --reload \
&& sudo udevadm trigger` (packaging/udev/README.md), then unplug and replug the device";

impl DeviceReport {
    /// Resolve each wheel's profile with the station's `[wheel]` configuration and state the
    /// torque ceiling that would hold for a patient ceiling `patient_ceiling_nm` (`None`: the
    /// device maximum), and the update rate the backend would drive the wheel at.
    pub fn apply_config(
        &mut self,
        config: &haptic_wheel::wheel_config::WheelConfig,
        patient_ceiling_nm: Option<f64>,
    ) {
        for w in &mut self.wheels {
            let (vendor, product) = w.usb_id.unwrap_or((0, 0));
            let profile = config.resolve_profile(vendor, product);
            w.expected_update_rate_hz =
                Some(config.update_rate_for(profile.driver, profile.max_update_rate_hz));
            w.ceiling = Some(haptic_wheel::wheel_config::CeilingReport::new(
                &profile,
                config.gain,
                patient_ceiling_nm,
            ));
            w.profile = Some(profile);
        }
    }

    /// Whether a wheel the haptic loop can drive was found.
    pub fn has_wheel(&self) -> bool {
        !self.wheels.is_empty()
    }

    /// File a device under its class.
    pub fn add(&mut self, d: DeviceInfo) {
        match d.class {
            DeviceClass::Wheel => self.wheels.push(d),
            DeviceClass::Pedals => self.pedals.push(d),
            DeviceClass::Gamepad => self.gamepads.push(d),
        }
    }

    /// Add the plain explanation for what is missing (called once the scan is done).
    pub(crate) fn explain(&mut self) {
        if !self.unreadable.is_empty() {
            self.notes.push(format!(
                "{} input device(s) could not be opened (permission denied?): {}",
                self.unreadable.len(),
                UDEV_HINT
            ));
        }
        if self.wheels.is_empty() {
            // Where the wheel's driver lives: the kernel on Linux, the maker's package on Windows.
            let driver = if cfg!(windows) {
                "that its maker's Windows driver is installed (docs/WINDOWS.md)"
            } else {
                "that its kernel driver is loaded (`lsmod | grep -E 'hid_lg|pidff|tmff|fanatec'`)"
            };
            self.notes.push(format!(
                "No force-feedback wheel found. Check that it is plugged in and powered (most \
                 wheels need their own power supply for force feedback), that it is in PC mode, \
                 and {driver}. `telerehab run --sim` works without one."
            ));
        }
    }
}

fn list(f: &mut fmt::Formatter<'_>, title: &str, ds: &[DeviceInfo]) -> fmt::Result {
    writeln!(f, "{title}: {}", ds.len())?;
    for d in ds {
        write!(f, "  {}  {}", d.path, d.traits.name)?;
        if let Some((v, p)) = d.usb_id {
            write!(f, "  [{v:04x}:{p:04x}]")?;
        }
        writeln!(f)?;
        if !d.traits.abs_axes.is_empty() {
            writeln!(f, "      axes: {}", d.traits.abs_axes.join(", "))?;
        }
        if !d.traits.ff_effects.is_empty() {
            writeln!(
                f,
                "      force feedback: {} (up to {} effects)",
                d.traits.ff_effects.join(", "),
                d.max_ff_effects
            )?;
        }
        if let Some(p) = &d.profile {
            writeln!(
                f,
                "      profile: {}; torque updates up to {} Hz; motor {:.1} N·m ({}{}); range ±{:.0}°",
                p.name,
                p.max_update_rate_hz,
                p.max_torque_nm,
                p.torque_source.describe(),
                if p.reference.is_empty() {
                    String::new()
                } else {
                    format!(": {}", p.reference)
                },
                p.half_range_rad.to_degrees()
            )?;
        }
        if let Some(hz) = d.expected_update_rate_hz {
            writeln!(
                f,
                "      expected torque updates at the motor: {hz:.0} /s, one every {:.1} ms (the rate \
                 policy's; a session's summary reports the rate reached)",
                1e3 / hz
            )?;
        }
        if let Some(c) = &d.ceiling {
            writeln!(f, "      {c}")?;
        }
    }
    Ok(())
}

impl fmt::Display for DeviceReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        list(f, "Wheels", &self.wheels)?;
        list(f, "Pedals", &self.pedals)?;
        list(f, "Gamepads", &self.gamepads)?;
        for (p, why) in &self.unreadable {
            writeln!(f, "Could not open {}: {why}", p.display())?;
        }
        for n in &self.notes {
            writeln!(f, "{n}")?;
        }
        Ok(())
    }
}

/// Every `/dev/input/event*` node, sorted: the one place that walks `/dev/input` (the
/// device listing and the wheel search both use it).
pub fn event_nodes() -> std::io::Result<Vec<PathBuf>> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir("/dev/input")?
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.starts_with("event"))
        })
        .collect();
    paths.sort();
    Ok(paths)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn traits(name: &str, ff: &[&'static str], axes: &[&'static str], pad: bool) -> DeviceTraits {
        DeviceTraits {
            name: name.into(),
            ff_effects: ff.to_vec(),
            abs_axes: axes.to_vec(),
            gamepad_buttons: pad,
        }
    }

    #[test]
    fn classifies_wheels_pedals_gamepads_and_ignores_the_rest() {
        let g29 = traits(
            "Logitech G29 Driving Force Racing Wheel",
            &["constant", "autocenter", "gain"],
            &["x", "y", "z", "rz", "hat0x", "hat0y"],
            false,
        );
        assert_eq!(classify(&g29), Some(DeviceClass::Wheel));
        let pedals = traits("Fanatec ClubSport Pedals", &[], &["x", "y", "z"], false);
        assert_eq!(classify(&pedals), Some(DeviceClass::Pedals));
        let ds4 = traits(
            "Wireless Controller",
            &["rumble", "periodic", "gain"],
            &["x", "y", "rx", "ry", "z", "rz"],
            true,
        );
        assert_eq!(classify(&ds4), Some(DeviceClass::Gamepad));
        let kbd = traits("AT Translated Set 2 keyboard", &[], &[], false);
        assert_eq!(classify(&kbd), None);
        // Rumble alone does not make a wheel.
        let rumble_stick = traits("stick", &["rumble"], &["x", "y"], false);
        assert_ne!(classify(&rumble_stick), Some(DeviceClass::Wheel));
    }

    /// A wheel as the evdev listing finds it, before the configuration is applied.
    fn wheel(path: &str, name: &str, usb_id: (u16, u16)) -> DeviceInfo {
        DeviceInfo {
            path: path.into(),
            class: DeviceClass::Wheel,
            traits: traits(name, &["constant", "gain"], &["x"], false),
            usb_id: Some(usb_id),
            profile: None,
            ceiling: None,
            expected_update_rate_hz: None,
            max_ff_effects: 16,
        }
    }

    #[test]
    fn report_lists_wheels_with_their_profile() {
        let mut r = DeviceReport::default();
        r.add(wheel("/dev/input/event7", "G29", (0x046d, 0xc24f)));
        r.add(wheel("/dev/input/event9", "Mystery DD", (0x1234, 0x0001)));
        r.apply_config(&haptic_wheel::WheelConfig::default(), None);
        r.unreadable
            .push(("/dev/input/event3".into(), "Permission denied".into()));
        r.explain();
        let text = r.to_string();
        assert!(text.contains("Wheels: 2"), "{text}");
        assert!(text.contains("046d:c24f"), "{text}");
        assert!(text.contains("500 Hz"), "{text}");
        assert!(
            text.contains("expected torque updates at the motor: 500 /s, one every 2.0 ms"),
            "{text}"
        );
        // The ceiling in N·m and as a share of the motor, and the unknown wheel said so.
        assert!(
            text.contains("torque ceiling 1.00 N·m = 3.1 % of the motor's 32.00 N·m"),
            "{text}"
        );
        assert!(text.contains("UNKNOWN"), "{text}");
        assert!(text.contains("packaging/udev"), "{text}");
        assert!(!text.contains("No force-feedback wheel found"), "{text}");
    }

    #[test]
    fn devices_state_the_update_rate_a_configured_limit_leaves_at_the_motor() {
        let mut r = DeviceReport::default();
        r.add(wheel("/dev/input/event7", "T300", (0x044f, 0xb66e)));
        r.add(wheel("/dev/input/event8", "G29", (0x046d, 0xc24f)));
        let config = haptic_wheel::WheelConfig {
            update_rate_hz: Some(250.0),
            ..Default::default()
        };
        r.apply_config(&config, None);
        let text = r.to_string();
        // hid-tmff2's own 125 Hz is below the limit; the G29's 500 Hz is held to 250 — each
        // said in its own wheel's lines, the driver's own rate kept in its profile line.
        let (t300, g29) = text
            .split_once("/dev/input/event8")
            .expect("both wheels listed");
        assert!(
            t300.contains("expected torque updates at the motor: 125 /s, one every 8.0 ms"),
            "{text}"
        );
        assert!(
            g29.contains("expected torque updates at the motor: 250 /s, one every 4.0 ms"),
            "{text}"
        );
        assert!(g29.contains("torque updates up to 500 Hz"), "{text}");
    }
}
