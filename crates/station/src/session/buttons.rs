//! The wheel's and a gamepad's buttons and pedals during a session with the patient's window:
//! any button of the wheel, a gamepad's south (A/✕) or start button does what Space does
//! (start, pause, resume, or go on from a rest now); a gamepad's east button (B/○) asks for a
//! rest; the pedals (the wheel's pedal port, separate USB pedals, or a gamepad's triggers)
//! drive the car in an exercise the regimen gives the pedals.
//! The wheel's input node is read without grabbing it (the session's own reading of the wheel
//! is not disturbed); gamepads through gilrs with force feedback off. Nothing here runs on the
//! haptic thread.

use super::controls::{BreakKind, Controls};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

/// How long one look at the wheel's buttons lasts (and the gamepad's and pedals' polling
/// period).
const LOOK: Duration = Duration::from_millis(20);

/// Space's job: go on from a break, else pause or resume (and start).
pub fn space(controls: &Controls) {
    if controls.break_now().kind == BreakKind::None {
        controls.pause.fetch_xor(true, Ordering::Relaxed);
    } else {
        controls.end_break.store(true, Ordering::Relaxed);
    }
}

/// Watch the buttons and pedals until `done`: the wheel's at `wheel_node` (its evdev node,
/// if known) and any gamepad's (its triggers, or separate USB pedals, as throttle and brake).
/// The pedals reach the haptic thread through [`Controls::set_pedals`]: the further pressed of
/// the wheel's and a gamepad's.
pub fn watch(controls: &Controls, wheel_node: Option<&std::path::Path>, done: &AtomicBool) {
    let mut pads = haptic_wheel::peripherals::Peripherals::new(&[])
        .map_err(|e| tracing::debug!("no gamepad buttons this session: {e}"))
        .ok();
    let mut wheel = wheel_node.and_then(|node| {
        WheelInputs::open(node)
            .map_err(|e| tracing::debug!("the wheel's buttons cannot be read: {e}"))
            .ok()
    });
    let mut last = haptic_wheel::peripherals::ControlState::default();
    while !done.load(Ordering::Acquire) && !controls.stop.load(Ordering::Relaxed) {
        let mut pedals = vehicle::Pedals::default();
        match wheel.as_mut().map(|w| w.look(LOOK)) {
            Some(Ok((pressed, wheel_pedals))) => {
                if pressed {
                    space(controls);
                }
                pedals = wheel_pedals;
            }
            Some(Err(e)) => {
                tracing::debug!("the wheel's buttons cannot be read: {e}");
                wheel = None;
            }
            None => std::thread::sleep(LOOK),
        }
        if let Some(p) = &mut pads {
            let now = p.poll();
            if (now.confirm && !last.confirm) || (now.pause && !last.pause) {
                space(controls);
            }
            if now.cancel && !last.cancel {
                controls.rest.store(true, Ordering::Relaxed);
            }
            pedals.throttle = pedals.throttle.max(f64::from(now.throttle));
            pedals.brake = pedals.brake.max(f64::from(now.brake));
            last = now;
        }
        controls.set_pedals(pedals);
    }
    controls.set_pedals(vehicle::Pedals::default());
}

/// The wheel's own buttons and pedals (Linux: its evdev node).
#[cfg(target_os = "linux")]
struct WheelInputs(haptic_wheel::evdev_wheel::WheelControls);

#[cfg(target_os = "linux")]
impl WheelInputs {
    fn open(node: &std::path::Path) -> std::io::Result<Self> {
        let c = haptic_wheel::evdev_wheel::WheelControls::open(node)?;
        if let Some(axes) = c.pedal_axes() {
            tracing::info!(
                ?axes,
                "the wheel's pedals drive the car where the regimen asks"
            );
        }
        Ok(Self(c))
    }

    /// Whether a button went down within `window`, and the pedals.
    fn look(&mut self, window: Duration) -> std::io::Result<(bool, vehicle::Pedals)> {
        let l = self.0.look(window)?;
        let (throttle, brake) = l.pedals.unwrap_or((0.0, 0.0));
        Ok((l.pressed, vehicle::Pedals { throttle, brake }))
    }
}

#[cfg(not(target_os = "linux"))]
struct WheelInputs;

#[cfg(not(target_os = "linux"))]
impl WheelInputs {
    fn open(_node: &std::path::Path) -> std::io::Result<Self> {
        Err(std::io::Error::other(
            "wheel buttons are read on Linux only",
        ))
    }

    fn look(&mut self, _window: Duration) -> std::io::Result<(bool, vehicle::Pedals)> {
        Err(std::io::Error::other(
            "wheel buttons are read on Linux only",
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::session::controls::BreakKind;

    #[test]
    fn a_button_starts_pauses_and_resumes_and_during_a_break_goes_on() {
        let c = Controls::default();
        c.pause.store(true, Ordering::Relaxed);
        space(&c);
        assert!(!c.pause.load(Ordering::Relaxed), "started");
        space(&c);
        assert!(c.pause.load(Ordering::Relaxed), "paused");
        space(&c);
        c.break_kind
            .store(BreakKind::Prescribed.as_u8(), Ordering::Relaxed);
        space(&c);
        assert!(c.end_break.load(Ordering::Relaxed), "went on from the rest");
        assert!(!c.pause.load(Ordering::Relaxed), "not paused by it");
    }
}
