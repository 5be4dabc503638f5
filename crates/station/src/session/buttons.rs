//! The wheel's and a gamepad's buttons during a session with the patient's window: any
//! button of the wheel, a gamepad's south (A/✕) or start button does what Space does (start,
//! pause, resume, or go on from a rest now); a gamepad's east button (B/○) asks for a rest.
//! The wheel's input node is read without grabbing it (the session's own reading of the wheel
//! is not disturbed); gamepads through gilrs with force feedback off. Nothing here runs on the
//! haptic thread.

use super::controls::{BreakKind, Controls};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

/// How long one look at the wheel's buttons lasts (and the gamepad's polling period).
const LOOK: Duration = Duration::from_millis(100);

/// Space's job: go on from a break, else pause or resume (and start).
pub fn space(controls: &Controls) {
    if controls.break_now().kind == BreakKind::None {
        controls.pause.fetch_xor(true, Ordering::Relaxed);
    } else {
        controls.end_break.store(true, Ordering::Relaxed);
    }
}

/// Watch the buttons until `done`: the wheel's at `wheel_node` (its evdev node, if known) and
/// any gamepad's.
pub fn watch(controls: &Controls, wheel_node: Option<&std::path::Path>, done: &AtomicBool) {
    let mut pads = haptic_wheel::peripherals::Peripherals::new(&[])
        .map_err(|e| tracing::debug!("no gamepad buttons this session: {e}"))
        .ok();
    let mut wheel_node = wheel_node;
    let mut last = haptic_wheel::peripherals::ControlState::default();
    while !done.load(Ordering::Acquire) && !controls.stop.load(Ordering::Relaxed) {
        match wheel_node.map(button_only) {
            Some(Ok(true)) => space(controls),
            Some(Ok(false)) => {}
            Some(Err(e)) => {
                tracing::debug!("the wheel's buttons cannot be read: {e}");
                wheel_node = None;
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
            last = now;
        }
    }
}

#[cfg(target_os = "linux")]
fn button_only(node: &std::path::Path) -> std::io::Result<bool> {
    haptic_wheel::evdev_wheel::button_pressed_within(node, LOOK)
}

#[cfg(not(target_os = "linux"))]
fn button_only(_node: &std::path::Path) -> std::io::Result<bool> {
    Err(std::io::Error::other(
        "wheel buttons are read on Linux only",
    ))
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
