//! The wheel's own buttons and pedals, read beside the session (never on the haptic thread):
//! the node is opened read-only and never grabbed, so the session's reading of the wheel is
//! not disturbed. A wheel's pedal port reports each pedal as an absolute axis; which axes, and
//! which way round, depends on the wheel ([`PedalAxes`]).

use std::io;
use std::path::Path;
use std::time::{Duration, Instant};

use evdev::{AbsInfo, AbsoluteAxisCode, EventType};

/// Logitech's USB vendor id (G25, G27, G29, G920, G923, PRO: pedals on the wheel's port).
const LOGITECH: u16 = 0x046d;

/// Which absolute axes of a wheel's node carry its pedals.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PedalAxes {
    /// The accelerator's axis.
    pub throttle: AbsoluteAxisCode,
    /// The brake's axis.
    pub brake: AbsoluteAxisCode,
    /// The axis reads its maximum when the pedal is released (Logitech's pedal port: 255
    /// released, 0 pressed).
    pub released_at_max: bool,
}

impl PedalAxes {
    /// The pedal axes of a wheel from `vendor` whose node has the axes `has` reports: the
    /// kernel's own gas and brake axes when the driver declares them; on a Logitech wheel
    /// its pedal port (accelerator on Z, brake on RZ, clutch on Y, each released at its
    /// maximum); none otherwise (separate USB pedals are read as a game controller).
    pub fn of(vendor: u16, has: impl Fn(AbsoluteAxisCode) -> bool) -> Option<Self> {
        if has(AbsoluteAxisCode::ABS_GAS) && has(AbsoluteAxisCode::ABS_BRAKE) {
            return Some(Self {
                throttle: AbsoluteAxisCode::ABS_GAS,
                brake: AbsoluteAxisCode::ABS_BRAKE,
                released_at_max: false,
            });
        }
        (vendor == LOGITECH && has(AbsoluteAxisCode::ABS_Z) && has(AbsoluteAxisCode::ABS_RZ))
            .then_some(Self {
                throttle: AbsoluteAxisCode::ABS_Z,
                brake: AbsoluteAxisCode::ABS_RZ,
                released_at_max: true,
            })
    }

    /// A pedal's travel in [0, 1] from its raw `value` within the driver's declared
    /// `minimum..=maximum` (0 for a degenerate range).
    pub fn travel(&self, value: i32, minimum: i32, maximum: i32) -> f64 {
        let span = f64::from(maximum) - f64::from(minimum);
        if span <= 0.0 {
            return 0.0;
        }
        let x = ((f64::from(value) - f64::from(minimum)) / span).clamp(0.0, 1.0);
        if self.released_at_max { 1.0 - x } else { x }
    }
}

/// Whether a button of the input device at `path` is pressed within `window` (any key or
/// button going down, `BTN_*` or `KEY_*`): the wheel's buttons start a session from the
/// first-run page.
pub fn button_pressed_within(path: &Path, window: Duration) -> io::Result<bool> {
    Ok(WheelControls::open(path)?.look(window)?.pressed)
}

/// Where a steering axis at raw `value` within `minimum..=maximum` is turned: −1 (full left)
/// to 1 (full right), 0 in the middle (and for a degenerate range).
pub fn steering_fraction(value: i32, minimum: i32, maximum: i32) -> f64 {
    let half = (f64::from(maximum) - f64::from(minimum)) / 2.0;
    if half <= 0.0 {
        return 0.0;
    }
    let mid = f64::from(minimum) + half;
    ((f64::from(value) - mid) / half).clamp(-1.0, 1.0)
}

/// What one look at the wheel's controls saw.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ControlsLook {
    /// A button went down.
    pub pressed: bool,
    /// A button is down at the end of the look (how long it is held tells a long press).
    pub held: bool,
    /// The pedals' travel (throttle, brake), each in [0, 1], if the wheel has pedals.
    pub pedals: Option<(f64, f64)>,
    /// Where the wheel is turned, −1 (full left) to 1 (full right) of its declared range.
    pub steering: Option<f64>,
}

/// The wheel's input node, open for its buttons and pedals.
pub struct WheelControls {
    dev: evdev::Device,
    pedals: Option<PedalAxes>,
    steering: Option<AbsoluteAxisCode>,
}

impl std::fmt::Debug for WheelControls {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("WheelControls")
            .field("pedals", &self.pedals)
            .finish_non_exhaustive()
    }
}

impl WheelControls {
    /// Open the node at `path` read-only, without grabbing it.
    pub fn open(path: &Path) -> io::Result<Self> {
        let dev = evdev::Device::open(path)?;
        dev.set_nonblocking(true)?;
        let has = |a| {
            dev.supported_absolute_axes()
                .is_some_and(|axes| axes.contains(a))
        };
        let pedals = PedalAxes::of(dev.input_id().vendor(), has);
        let steering = [AbsoluteAxisCode::ABS_WHEEL, AbsoluteAxisCode::ABS_X]
            .into_iter()
            .find(|&a| has(a));
        Ok(Self {
            dev,
            pedals,
            steering,
        })
    }

    /// The pedal axes found, if any.
    pub fn pedal_axes(&self) -> Option<PedalAxes> {
        self.pedals
    }

    /// Look for `window`: whether a button went down (returning as soon as one does), and
    /// where the pedals are at the end.
    pub fn look(&mut self, window: Duration) -> io::Result<ControlsLook> {
        let deadline = Instant::now() + window;
        let mut pressed = false;
        loop {
            match self.dev.fetch_events() {
                Ok(events) => {
                    pressed |= events
                        .into_iter()
                        .any(|e| e.event_type() == EventType::KEY && e.value() == 1);
                }
                Err(e) if e.kind() == io::ErrorKind::WouldBlock => {}
                Err(e) => return Err(e),
            }
            if pressed || Instant::now() >= deadline {
                break;
            }
            std::thread::sleep(Duration::from_millis(10));
        }
        let held = self.dev.get_key_state()?.iter().next().is_some();
        let abs = self.dev.get_abs_state()?;
        let info = |axis: AbsoluteAxisCode| AbsInfo::from(abs[axis.0 as usize]);
        let pedals = self.pedals.map(|axes| {
            let travel = |a| {
                let i = info(a);
                axes.travel(i.value(), i.minimum(), i.maximum())
            };
            (travel(axes.throttle), travel(axes.brake))
        });
        let steering = self.steering.map(|a| {
            let i = info(a);
            steering_fraction(i.value(), i.minimum(), i.maximum())
        });
        Ok(ControlsLook {
            pressed,
            held,
            pedals,
            steering,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_logitech_pedal_port_reads_released_at_its_maximum() {
        let all = |_| true;
        let g29 = PedalAxes::of(LOGITECH, |a| a != AbsoluteAxisCode::ABS_GAS).unwrap();
        assert_eq!(g29.throttle, AbsoluteAxisCode::ABS_Z);
        assert_eq!(g29.brake, AbsoluteAxisCode::ABS_RZ);
        assert_eq!(g29.travel(255, 0, 255), 0.0, "released");
        assert_eq!(g29.travel(0, 0, 255), 1.0, "floored");
        assert!((g29.travel(128, 0, 255) - 0.498).abs() < 0.01);
        // Declared gas and brake axes win, read as they come.
        let gas = PedalAxes::of(0x1234, all).unwrap();
        assert_eq!(gas.throttle, AbsoluteAxisCode::ABS_GAS);
        assert_eq!(gas.travel(0, 0, 1023), 0.0);
        // An unknown wheel without them has no pedals here; out of range and a degenerate
        // range read within [0, 1].
        assert_eq!(
            PedalAxes::of(0x1234, |a| a != AbsoluteAxisCode::ABS_GAS),
            None
        );
        assert_eq!(gas.travel(5000, 0, 1023), 1.0);
        assert_eq!(gas.travel(7, 7, 7), 0.0);
    }

    #[test]
    fn the_steering_axis_reads_from_full_left_to_full_right() {
        assert_eq!(steering_fraction(0, 0, 65535), -1.0);
        assert_eq!(steering_fraction(65535, 0, 65535), 1.0);
        assert!(steering_fraction(32768, 0, 65535).abs() < 1e-4);
        assert_eq!(steering_fraction(-20, -10, 10), -1.0, "clamped");
        assert_eq!(steering_fraction(3, 3, 3), 0.0);
    }
}
