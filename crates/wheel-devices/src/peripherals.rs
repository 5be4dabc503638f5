//! Pedals, buttons and gamepads through gilrs.
//!
//! gilrs's force feedback is rumble only, runs on its own 50 ms loop, and opens force
//! feedback on *any* device that advertises periodic effects and gain — wheels included —
//! then keeps sending rumble to it (FIELD-NOTES). Two rules keep it away from the wheel the
//! haptic loop drives, and both are enforced here:
//!
//! 1. gilrs is always built with force feedback disabled
//!    (`GilrsBuilder::with_force_feedback(false)`): its FF server thread never starts, so it
//!    never opens a device for writing effects. This module never exposes gilrs's `ff` API.
//! 2. Input from the driven wheel's USB id (and from any device that looks like a wheel) is
//!    ignored, so the wheel's own pedals/buttons, which the evdev backend reads, are not
//!    counted twice.

use gilrs::{Axis, Button, EventType, Gilrs, GilrsBuilder};

use crate::devices::{DeviceClass, DeviceInfo, DeviceTraits};
use haptic_wheel::wheel::WheelError;

/// Controls the station reads from pedals and gamepads, latest values.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ControlState {
    /// Accelerator, 0..=1 (right trigger or gas pedal).
    pub throttle: f32,
    /// Brake, 0..=1 (left trigger or brake pedal).
    pub brake: f32,
    /// Confirm / start exercise (south face button).
    pub confirm: bool,
    /// Back / cancel (east face button).
    pub cancel: bool,
    /// Pause (start button).
    pub pause: bool,
}

/// Gamepads and pedals through gilrs, with force feedback off and the driven wheel excluded.
pub struct Peripherals {
    gilrs: Gilrs,
    excluded_usb_ids: Vec<(u16, u16)>,
    state: ControlState,
}

impl std::fmt::Debug for Peripherals {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Peripherals")
            .field("excluded_usb_ids", &self.excluded_usb_ids)
            .field("state", &self.state)
            .finish_non_exhaustive()
    }
}

fn build_gilrs() -> Result<Gilrs, String> {
    match GilrsBuilder::new().with_force_feedback(false).build() {
        Ok(g) => Ok(g),
        // Unsupported platform: gilrs hands back a working dummy context with no devices.
        Err(gilrs::Error::NotImplemented(g)) => Ok(g),
        Err(e) => Err(e.to_string()),
    }
}

fn looks_like_wheel(name: &str) -> bool {
    let n = name.to_lowercase();
    n.contains("wheel") || n.contains("racing")
}

impl Peripherals {
    /// Open gilrs with force feedback disabled, ignoring devices with any of
    /// `driven_wheel_usb_ids` (vendor, product) and anything named like a wheel.
    pub fn new(driven_wheel_usb_ids: &[(u16, u16)]) -> Result<Self, WheelError> {
        let gilrs = build_gilrs().map_err(|e| WheelError::Io {
            device: "gilrs".into(),
            source: std::io::Error::other(e),
        })?;
        Ok(Self {
            gilrs,
            excluded_usb_ids: driven_wheel_usb_ids.to_vec(),
            state: ControlState::default(),
        })
    }

    fn excluded(&self, id: gilrs::GamepadId) -> bool {
        let g = self.gilrs.gamepad(id);
        let usb = g.vendor_id().zip(g.product_id());
        usb.is_some_and(|u| self.excluded_usb_ids.contains(&u)) || looks_like_wheel(g.name())
    }

    /// Drain pending events and return the latest control state. Call from the main or
    /// input thread, not the haptic loop (gilrs may allocate and lock).
    pub fn poll(&mut self) -> ControlState {
        while let Some(ev) = self.gilrs.next_event() {
            if self.excluded(ev.id) {
                continue;
            }
            match ev.event {
                EventType::ButtonChanged(Button::RightTrigger2, v, _) => self.state.throttle = v,
                EventType::ButtonChanged(Button::LeftTrigger2, v, _) => self.state.brake = v,
                EventType::AxisChanged(Axis::RightZ, v, _) => {
                    self.state.throttle = v.clamp(0.0, 1.0);
                }
                EventType::AxisChanged(Axis::LeftZ, v, _) => {
                    self.state.brake = v.clamp(0.0, 1.0);
                }
                EventType::ButtonPressed(Button::South, _) => self.state.confirm = true,
                EventType::ButtonReleased(Button::South, _) => self.state.confirm = false,
                EventType::ButtonPressed(Button::East, _) => self.state.cancel = true,
                EventType::ButtonReleased(Button::East, _) => self.state.cancel = false,
                EventType::ButtonPressed(Button::Start, _) => self.state.pause = true,
                EventType::ButtonReleased(Button::Start, _) => self.state.pause = false,
                _ => {}
            }
        }
        self.state
    }
}

/// Gamepads gilrs can see (force feedback disabled), for `telerehab devices` where evdev is
/// not available.
pub fn list_gamepads() -> Result<Vec<DeviceInfo>, String> {
    let gilrs = build_gilrs()?;
    Ok(gilrs
        .gamepads()
        .filter(|(_, g)| !looks_like_wheel(g.name()))
        .map(|(id, g)| DeviceInfo {
            path: format!("gilrs:{id}"),
            class: DeviceClass::Gamepad,
            traits: DeviceTraits {
                name: g.name().to_string(),
                ff_effects: if g.is_ff_supported() {
                    vec!["rumble"]
                } else {
                    Vec::new()
                },
                abs_axes: Vec::new(),
                gamepad_buttons: true,
            },
            usb_id: g.vendor_id().zip(g.product_id()),
            profile: None,
            ceiling: None,
            expected_update_rate_hz: None,
            max_ff_effects: 0,
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wheels_are_recognised_by_name_for_exclusion() {
        assert!(looks_like_wheel("Logitech G29 Driving Force Racing Wheel"));
        assert!(looks_like_wheel("Thrustmaster T300RS Racing wheel"));
        assert!(!looks_like_wheel("Xbox Wireless Controller"));
    }

    #[test]
    fn opening_gilrs_without_devices_works_and_reports_no_input() {
        // This machine has no input devices; gilrs must still open (FF off) without panic.
        match Peripherals::new(&[(0x046d, 0xc24f)]) {
            Ok(mut p) => assert_eq!(p.poll(), ControlState::default()),
            Err(e) => println!("gilrs unavailable here: {e}"),
        }
    }
}
