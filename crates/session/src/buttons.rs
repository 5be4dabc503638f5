//! The wheel's and a gamepad's buttons and pedals during a session with the patient's window.
//! The wheel alone runs the session ([`wheel_gesture`]): a short press of any of its buttons
//! does what Space does (start, pause, resume, go on from a break or "Ready?"); paused, a turn
//! chooses between going on, a rest and ending ([`PauseChoice`]) and a press does it; a long
//! press ([`super::wheel_gestures::HOLD`]) asks "End now?", where a press ends and another long
//! press goes on; on the end screen turns choose,
//! a press confirms and a long press skips. A gamepad's south (A/✕) or start button is a
//! press, its east button (B/○) asks for a rest. The pedals (the wheel's pedal port, separate
//! USB pedals, or a gamepad's triggers) drive the car in an exercise the regimen gives them.
//! The wheel's input node is read without grabbing it (the session's own reading of the wheel
//! is not disturbed); gamepads through gilrs with force feedback off. Nothing here runs on the
//! haptic thread.

use super::controls::{BreakKind, Controls, PauseChoice};
use super::wheel_gestures::{Gesture, WheelGestures};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

/// How long one look at the wheel's buttons lasts (and the gamepad's and pedals' polling
/// period).
const LOOK: Duration = Duration::from_millis(20);

/// Space's job: go on from a break, else pause or resume (and start). A pause begins with
/// "Go on" chosen.
pub fn space(controls: &Controls) {
    if controls.break_now().kind == BreakKind::None {
        controls
            .pause_choice
            .store(PauseChoice::GoOn.as_u8(), Ordering::Relaxed);
        let paused = !controls.pause.fetch_xor(true, Ordering::Relaxed);
        tracing::info!(paused, "the patient paused or went on");
    } else {
        controls.end_break.store(true, Ordering::Relaxed);
    }
}

/// Watch the buttons and pedals until `done`: the wheel's at `wheel_node` (its evdev node,
/// if known, or a simulated wheel's script, [`super::wheel_gestures`]) and any gamepad's (its
/// triggers, or separate USB pedals, as throttle and brake). The pedals reach the haptic
/// thread through [`Controls::set_pedals`]: the further pressed of the wheel's and a
/// gamepad's. The wheel's gestures go to [`wheel_gesture`]; a gamepad's A does what a short
/// press does, its B asks for a rest (on the end screen: skips).
pub fn watch(controls: &Controls, wheel_node: Option<&std::path::Path>, done: &AtomicBool) {
    let mut pads = wheel_devices::peripherals::Peripherals::new(&[])
        .map_err(|e| tracing::debug!("no gamepad buttons this session: {e}"))
        .ok();
    let mut wheel = WheelGestures::open(wheel_node);
    tracing::info!(wheel = wheel.is_some(), "the wheel's buttons are watched");
    let mut last = wheel_devices::peripherals::ControlState::default();
    let mut said = (BreakKind::None, false);
    while !done.load(Ordering::Acquire) && !controls.stop.load(Ordering::Relaxed) {
        let end = controls.end_screen_up.load(Ordering::Acquire);
        // The breaks and cards the wheel answers, one log line each (tests and support).
        let brk = controls.break_now();
        let now = (brk.kind, brk.end_asked);
        if now != said {
            let waits = brk.kind == BreakKind::Ready && brk.left_s == 0.0;
            tracing::info!(brk = ?brk.kind, end_asked = brk.end_asked, waits, "break or card");
            said = now;
        }
        let mut pedals = exercises::Pedals::default();
        match wheel.as_mut().map(|w| w.look(LOOK, choosing(controls))) {
            Some(Ok(look)) => {
                for g in look.gestures {
                    wheel_gesture(controls, g);
                }
                pedals = look.pedals;
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
                wheel_gesture(controls, Gesture::Press);
            }
            if now.cancel && !last.cancel {
                if end {
                    controls.end_answers.skip();
                } else {
                    controls.rest.store(true, Ordering::Relaxed);
                }
            }
            pedals.throttle = pedals.throttle.max(f64::from(now.throttle));
            pedals.brake = pedals.brake.max(f64::from(now.brake));
            last = now;
        }
        controls.set_pedals(pedals);
    }
    controls.set_pedals(exercises::Pedals::default());
}

/// Whether the wheel's turns choose now (a card with choices is up) rather than drive.
fn choosing(controls: &Controls) -> bool {
    controls.end_screen_up.load(Ordering::Acquire)
        || controls.end_asked.load(Ordering::Relaxed)
        || (controls.pause.load(Ordering::Relaxed) && controls.break_now().kind == BreakKind::None)
}

/// What a gesture of the wheel does in a session:
/// - on the end screen: a turn chooses, a press confirms, a long press skips the question;
/// - while "End now?" is asked: a press ends, a long press goes on;
/// - paused: a turn chooses between going on, a rest and ending, a press does what is chosen
///   (ending asks "End now?" first);
/// - otherwise a press does what Space does (start, pause, go on from a break) and a long
///   press asks "End now?" (the exercise waits meanwhile).
pub fn wheel_gesture(controls: &Controls, g: Gesture) {
    if controls.end_screen_up.load(Ordering::Acquire) {
        match g {
            Gesture::Turn(by) => controls.end_answers.step(by),
            Gesture::Press => controls.end_answers.confirm(),
            Gesture::Hold => controls.end_answers.skip(),
        }
        return;
    }
    if controls.end_asked.load(Ordering::Relaxed) {
        match g {
            Gesture::Press => {
                tracing::info!("the patient ended the session from the wheel");
                controls.stop.store(true, Ordering::Relaxed);
            }
            Gesture::Hold => controls.end_asked.store(false, Ordering::Relaxed),
            Gesture::Turn(_) => {}
        }
        return;
    }
    let paused =
        controls.pause.load(Ordering::Relaxed) && controls.break_now().kind == BreakKind::None;
    match g {
        Gesture::Turn(by) if paused => {
            let now = PauseChoice::from_u8(controls.pause_choice.load(Ordering::Relaxed));
            let chosen = now.step(by);
            controls
                .pause_choice
                .store(chosen.as_u8(), Ordering::Relaxed);
            tracing::info!(?chosen, "the pause page's choice");
        }
        Gesture::Turn(_) => {}
        Gesture::Press if paused => {
            let chosen = controls
                .pause_choice
                .swap(PauseChoice::GoOn.as_u8(), Ordering::Relaxed);
            match PauseChoice::from_u8(chosen) {
                PauseChoice::GoOn => space(controls),
                PauseChoice::Rest => controls.rest.store(true, Ordering::Relaxed),
                PauseChoice::End => {
                    tracing::info!("the patient chose to end from the pause page");
                    controls.end_asked.store(true, Ordering::Relaxed);
                }
            }
        }
        Gesture::Press => space(controls),
        Gesture::Hold => {
            tracing::info!("the patient asked to end from the wheel");
            controls.end_asked.store(true, Ordering::Relaxed);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::controls::BreakKind;

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

    #[test]
    fn a_long_press_asks_to_end_then_a_press_ends_and_another_long_press_goes_on() {
        let c = Controls::default();
        wheel_gesture(&c, Gesture::Press);
        assert!(c.pause.load(Ordering::Relaxed), "a press paused");
        wheel_gesture(&c, Gesture::Hold);
        assert!(c.end_asked.load(Ordering::Relaxed), "a long press asks");
        assert!(!c.stop.load(Ordering::Relaxed), "but does not end yet");
        wheel_gesture(&c, Gesture::Turn(1));
        wheel_gesture(&c, Gesture::Hold);
        assert!(
            !c.end_asked.load(Ordering::Relaxed),
            "another long press goes on"
        );
        wheel_gesture(&c, Gesture::Hold);
        wheel_gesture(&c, Gesture::Press);
        assert!(c.stop.load(Ordering::Relaxed), "asked, then a press: ended");
    }

    #[test]
    fn paused_turns_choose_go_on_rest_or_end_and_a_press_does_the_chosen_one() {
        let c = Controls::default();
        // A press pauses, with "Go on" chosen.
        wheel_gesture(&c, Gesture::Press);
        assert!(c.pause.load(Ordering::Relaxed));
        assert_eq!(c.break_now().pause_choice, PauseChoice::GoOn);
        // Right: rest; right again: end; further right stays at the end; left: rest.
        wheel_gesture(&c, Gesture::Turn(1));
        assert_eq!(c.break_now().pause_choice, PauseChoice::Rest);
        wheel_gesture(&c, Gesture::Turn(1));
        wheel_gesture(&c, Gesture::Turn(3));
        assert_eq!(c.break_now().pause_choice, PauseChoice::End);
        wheel_gesture(&c, Gesture::Turn(-1));
        wheel_gesture(&c, Gesture::Press);
        assert!(c.rest.load(Ordering::Relaxed), "the rest was asked for");
        assert!(!c.end_asked.load(Ordering::Relaxed));
        // Paused again: "Go on" chosen afresh; a press goes on.
        c.rest.store(false, Ordering::Relaxed);
        wheel_gesture(&c, Gesture::Turn(-1));
        wheel_gesture(&c, Gesture::Press);
        assert!(!c.rest.load(Ordering::Relaxed) && !c.pause.load(Ordering::Relaxed));
        // End, chosen and pressed, asks "End now?" (the exercise waits); a press there ends.
        wheel_gesture(&c, Gesture::Press);
        wheel_gesture(&c, Gesture::Turn(2));
        wheel_gesture(&c, Gesture::Press);
        assert!(c.end_asked.load(Ordering::Relaxed), "ending asks first");
        assert!(!c.stop.load(Ordering::Relaxed));
        assert!(c.pause.load(Ordering::Relaxed), "the exercise waits");
        wheel_gesture(&c, Gesture::Press);
        assert!(c.stop.load(Ordering::Relaxed), "ended");
    }

    #[test]
    fn a_pause_begun_by_space_starts_on_go_on_whatever_was_chosen_before() {
        let c = Controls::default();
        space(&c);
        wheel_gesture(&c, Gesture::Turn(2));
        space(&c);
        space(&c);
        assert!(c.pause.load(Ordering::Relaxed));
        assert_eq!(c.break_now().pause_choice, PauseChoice::GoOn);
    }

    #[test]
    fn on_the_end_screen_turns_choose_a_press_confirms_and_a_long_press_skips() {
        let c = Controls::default();
        c.end_screen_up.store(true, Ordering::Relaxed);
        for g in [
            Gesture::Turn(1),
            Gesture::Turn(1),
            Gesture::Press,
            Gesture::Hold,
        ] {
            wheel_gesture(&c, g);
        }
        let taken = c.end_answers.take();
        assert_eq!((taken.steps, taken.confirms, taken.skips), (2, 1, 1));
        assert!(!c.stop.load(Ordering::Relaxed) && !c.end_asked.load(Ordering::Relaxed));
    }
}
