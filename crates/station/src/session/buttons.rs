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
use std::time::{Duration, Instant};

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
/// the wheel's and a gamepad's. Once the end screen is up, the wheel's turns choose and its
/// buttons confirm, a gamepad's A confirms and B skips ([`Controls::end_answers`]).
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
    let mut turns = TurnSteps::default();
    while !done.load(Ordering::Acquire) && !controls.stop.load(Ordering::Relaxed) {
        let end = controls.end_screen_up.load(Ordering::Acquire);
        let press = || {
            if end {
                controls.end_answers.confirm();
            } else {
                space(controls);
            }
        };
        let mut pedals = vehicle::Pedals::default();
        match wheel.as_mut().map(|w| w.look(LOOK)) {
            Some(Ok(look)) => {
                if look.pressed {
                    press();
                }
                pedals = look.pedals;
                if let Some(turned) = look.steering.filter(|_| end) {
                    let by = turns.turn(turned, Instant::now());
                    if by != 0 {
                        controls.end_answers.step(by);
                    }
                }
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
                press();
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
    controls.set_pedals(vehicle::Pedals::default());
}

/// Past this share of the wheel's range either way, a turn is one step on the end screen.
const STEP_AT: f64 = 0.05;
/// Back within this share of the middle, the next turn steps at once.
const REARM_AT: f64 = 0.025;
/// Held past [`STEP_AT`], a turn steps again this often.
const REPEAT: Duration = Duration::from_millis(600);

/// The wheel's turns as steps on the end screen's questions: turned past [`STEP_AT`] of its
/// range is one step that way (+1 right, −1 left), again every [`REPEAT`] while held there;
/// back near the middle ([`REARM_AT`]) re-arms.
#[derive(Debug, Default)]
struct TurnSteps {
    /// The side held and when it last stepped.
    held: Option<(i32, Instant)>,
}

impl TurnSteps {
    /// The steps of the wheel turned to `fraction` (−1 full left to 1 full right) at `now`.
    fn turn(&mut self, fraction: f64, now: Instant) -> i32 {
        let side = if fraction >= STEP_AT {
            1
        } else if fraction <= -STEP_AT {
            -1
        } else {
            if fraction.abs() <= REARM_AT {
                self.held = None;
            }
            return 0;
        };
        match self.held {
            Some((held, since)) if held == side && now.duration_since(since) < REPEAT => 0,
            _ => {
                self.held = Some((side, now));
                side
            }
        }
    }
}

/// What one look at the wheel saw.
struct WheelLook {
    pressed: bool,
    pedals: vehicle::Pedals,
    steering: Option<f64>,
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

    /// Whether a button went down within `window`, the pedals and the steering.
    fn look(&mut self, window: Duration) -> std::io::Result<WheelLook> {
        let l = self.0.look(window)?;
        let (throttle, brake) = l.pedals.unwrap_or((0.0, 0.0));
        Ok(WheelLook {
            pressed: l.pressed,
            pedals: vehicle::Pedals { throttle, brake },
            steering: l.steering,
        })
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

    fn look(&mut self, _window: Duration) -> std::io::Result<WheelLook> {
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

    #[test]
    fn on_the_end_screen_a_turn_is_one_step_repeated_while_held_and_rearmed_at_the_middle() {
        let mut t = TurnSteps::default();
        let t0 = Instant::now();
        let at = |ms: u64| t0 + Duration::from_millis(ms);
        assert_eq!(t.turn(0.01, at(0)), 0, "a hand resting on the wheel");
        assert_eq!(t.turn(0.08, at(20)), 1, "turned right: one step");
        assert_eq!(t.turn(0.09, at(40)), 0, "held: not again at once");
        assert_eq!(t.turn(0.09, at(700)), 1, "held: again after the repeat");
        assert_eq!(
            t.turn(0.04, at(720)),
            0,
            "between: neither steps nor re-arms"
        );
        assert_eq!(t.turn(0.08, at(740)), 0, "not re-armed");
        assert_eq!(t.turn(0.0, at(760)), 0, "back in the middle re-arms");
        assert_eq!(t.turn(0.08, at(780)), 1, "so the next turn steps at once");
        assert_eq!(t.turn(-0.2, at(800)), -1, "left: one step back");
    }
}
