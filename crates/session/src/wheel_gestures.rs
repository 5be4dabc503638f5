//! The wheel as the patient's only control: a turn chooses, a short press of any of its
//! buttons confirms, a long press ([`HOLD`]) goes back or asks to end. Read from the wheel's
//! input node (Linux evdev, never grabbed) — or, for a simulated station, from a script
//! file named by [`SCRIPT_ENV`] that tests append gestures to (one a line: `press`, `hold`,
//! `turn 1`, `turn -1`), so a whole first run can be driven without a keyboard.

pub use super::controls::HOLD;
use std::io::{BufRead, Seek};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, OnceLock};
use std::time::{Duration, Instant};

/// The environment variable naming a simulated wheel's gesture script (tests, demos).
pub const SCRIPT_ENV: &str = "TELEREHAB_WHEEL_SCRIPT";

/// How far the script was read already, bytes (set when the program starts itself again,
/// e.g. the first-run pages after the practice, so no gesture is read twice).
pub const SCRIPT_FROM_ENV: &str = "TELEREHAB_WHEEL_SCRIPT_FROM";

/// What the patient did with the wheel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Gesture {
    /// Turned one step: +1 right, −1 left.
    Turn(i32),
    /// A button pressed and let go within [`HOLD`].
    Press,
    /// A button held for [`HOLD`] (said once, when the time is reached).
    Hold,
}

/// What one look at the wheel saw.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct GestureLook {
    /// The gestures, in order.
    pub gestures: Vec<Gesture>,
    /// The pedals' travel.
    pub pedals: exercises::Pedals,
}

/// Tells a short press from a long one from whether a button is down, look after look.
#[derive(Debug, Default)]
pub struct PressTimer {
    down_since: Option<Instant>,
    held_said: bool,
}

impl PressTimer {
    /// A button `went_down` during the look and is `held` at its end, at `now`.
    pub fn update(&mut self, went_down: bool, held: bool, now: Instant) -> Option<Gesture> {
        match (self.down_since, held || went_down) {
            (None, true) => {
                self.down_since = Some(now);
                self.held_said = false;
                if !held {
                    // Down and up again within one look.
                    self.down_since = None;
                    return Some(Gesture::Press);
                }
                None
            }
            (Some(since), true) => {
                if !self.held_said && now.duration_since(since) >= HOLD {
                    self.held_said = true;
                    return Some(Gesture::Hold);
                }
                None
            }
            (Some(_), false) => {
                self.down_since = None;
                (!std::mem::take(&mut self.held_said)).then_some(Gesture::Press)
            }
            (None, false) => None,
        }
    }
}

/// Past this share of the wheel's range either way, a turn is one step.
pub const STEP_AT: f64 = 0.05;
/// Back within this share of the middle, the next turn steps at once.
pub const REARM_AT: f64 = 0.025;
/// Held past [`STEP_AT`], a turn steps again this often.
pub const REPEAT: Duration = Duration::from_millis(600);

/// The wheel's turns as steps: turned past [`STEP_AT`] of its range is one step that way
/// (+1 right, −1 left), again every [`REPEAT`] while held there; back near the middle
/// ([`REARM_AT`]) re-arms.
#[derive(Debug, Default)]
pub struct TurnSteps {
    /// The side held and when it last stepped.
    held: Option<(i32, Instant)>,
}

impl TurnSteps {
    /// The steps of the wheel turned to `fraction` (−1 full left to 1 full right) at `now`.
    pub fn turn(&mut self, fraction: f64, now: Instant) -> i32 {
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

/// A gesture script being read: the file and how far it has been read (process-wide, so the
/// first-run pages and the session after them read each gesture once).
struct Script {
    path: PathBuf,
    offset: u64,
}

fn script() -> Option<&'static Mutex<Script>> {
    static SCRIPT: OnceLock<Option<Mutex<Script>>> = OnceLock::new();
    SCRIPT
        .get_or_init(|| {
            std::env::var_os(SCRIPT_ENV)
                .filter(|p| !p.is_empty())
                .map(|p| {
                    Mutex::new(Script {
                        path: PathBuf::from(p),
                        offset: std::env::var(SCRIPT_FROM_ENV)
                            .ok()
                            .and_then(|o| o.parse().ok())
                            .unwrap_or(0),
                    })
                })
        })
        .as_ref()
}

/// Whether this station's wheel is a scripted simulated one ([`SCRIPT_ENV`] is set).
pub fn scripted() -> bool {
    script().is_some()
}

/// How far the script has been read, bytes (`None`: no script).
pub fn script_offset() -> Option<u64> {
    script().map(|s| {
        s.lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .offset
    })
}

/// One line of a script as a gesture (`None`: blank, a comment or not understood).
pub fn parse_line(line: &str) -> Option<Gesture> {
    let mut words = line.split_whitespace();
    match (words.next()?, words.next()) {
        ("press", None) => Some(Gesture::Press),
        ("hold", None) => Some(Gesture::Hold),
        ("turn", Some(n)) => n.parse().ok().map(Gesture::Turn),
        _ => None,
    }
}

/// The whole lines added to the script since the last read, as gestures.
fn read_script(s: &mut Script) -> std::io::Result<Vec<Gesture>> {
    let mut file = match std::fs::File::open(&s.path) {
        Ok(f) => f,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(e),
    };
    file.seek(std::io::SeekFrom::Start(s.offset))?;
    let mut reader = std::io::BufReader::new(file);
    let mut out = Vec::new();
    let mut line = String::new();
    while reader.read_line(&mut line)? > 0 {
        if !line.ends_with('\n') {
            break; // a line still being written: read it whole next time
        }
        s.offset += line.len() as u64;
        match parse_line(&line) {
            Some(g) => {
                tracing::info!(gesture = ?g, "scripted wheel");
                out.push(g);
            }
            None if line.trim().is_empty() || line.trim_start().starts_with('#') => {}
            None => tracing::warn!(line = line.trim(), "scripted wheel: not a gesture"),
        }
        line.clear();
    }
    Ok(out)
}

/// The wheel's gestures: its evdev node's buttons and turns, or the script.
pub struct WheelGestures {
    source: Source,
}

enum Source {
    Script,
    /// The wheel's evdev node, and the timers that turn its readings into gestures.
    #[cfg(target_os = "linux")]
    Evdev {
        controls: Box<wheel_devices::evdev_wheel::WheelControls>,
        press: PressTimer,
        turns: TurnSteps,
    },
}

impl WheelGestures {
    /// The script when there is one, else the wheel at `node`; `None` when neither can be
    /// read (the reason is logged).
    pub fn open(node: Option<&Path>) -> Option<Self> {
        let source = if scripted() {
            Source::Script
        } else {
            open_node(node?)
                .map_err(|e| tracing::debug!("the wheel's buttons cannot be read: {e}"))
                .ok()?
        };
        Some(Self { source })
    }

    /// Look for `window`: the gestures seen (turns only when `choosing`: while the patient
    /// drives, turning the wheel is the exercise) and the pedals.
    pub fn look(&mut self, window: Duration, choosing: bool) -> std::io::Result<GestureLook> {
        match &mut self.source {
            Source::Script => {
                std::thread::sleep(window);
                let mut s = script()
                    .expect("a script source has a script")
                    .lock()
                    .unwrap_or_else(std::sync::PoisonError::into_inner);
                let gestures = read_script(&mut s)?
                    .into_iter()
                    .filter(|g| choosing || !matches!(g, Gesture::Turn(_)))
                    .collect();
                Ok(GestureLook {
                    gestures,
                    pedals: exercises::Pedals::default(),
                })
            }
            #[cfg(target_os = "linux")]
            Source::Evdev {
                controls,
                press,
                turns,
            } => {
                let l = controls.look(window)?;
                let now = Instant::now();
                let mut gestures = Vec::new();
                if let Some(g) = press.update(l.pressed, l.held, now) {
                    gestures.push(g);
                }
                if let Some(fraction) = l.steering.filter(|_| choosing) {
                    let by = turns.turn(fraction, now);
                    if by != 0 {
                        gestures.push(Gesture::Turn(by));
                    }
                }
                let (throttle, brake) = l.pedals.unwrap_or((0.0, 0.0));
                Ok(GestureLook {
                    gestures,
                    pedals: exercises::Pedals { throttle, brake },
                })
            }
        }
    }
}

#[cfg(target_os = "linux")]
fn open_node(node: &Path) -> std::io::Result<Source> {
    let c = wheel_devices::evdev_wheel::WheelControls::open(node)?;
    if let Some(axes) = c.pedal_axes() {
        tracing::info!(
            ?axes,
            "the wheel's pedals drive the car where the regimen asks"
        );
    }
    Ok(Source::Evdev {
        controls: Box::new(c),
        press: PressTimer::default(),
        turns: TurnSteps::default(),
    })
}

#[cfg(not(target_os = "linux"))]
fn open_node(_node: &Path) -> std::io::Result<Source> {
    Err(std::io::Error::other(
        "wheel buttons are read on Linux only",
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_press_let_go_within_the_hold_time_is_short_and_one_held_is_long_said_once() {
        let mut t = PressTimer::default();
        let t0 = Instant::now();
        let at = |ms: u64| t0 + Duration::from_millis(ms);
        assert_eq!(t.update(true, true, at(0)), None, "down: not yet known");
        assert_eq!(t.update(false, true, at(500)), None);
        assert_eq!(t.update(false, false, at(600)), Some(Gesture::Press));
        assert_eq!(
            t.update(true, false, at(700)),
            Some(Gesture::Press),
            "a tap"
        );
        assert_eq!(t.update(true, true, at(1000)), None);
        assert_eq!(t.update(false, true, at(2499)), None);
        assert_eq!(t.update(false, true, at(2500)), Some(Gesture::Hold));
        assert_eq!(t.update(false, true, at(4000)), None, "said once");
        assert_eq!(
            t.update(false, false, at(4100)),
            None,
            "its release is no press"
        );
    }

    #[test]
    fn a_turn_is_one_step_repeated_while_held_and_rearmed_at_the_middle() {
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

    #[test]
    fn script_lines_are_gestures_and_anything_else_is_none() {
        assert_eq!(parse_line("press\n"), Some(Gesture::Press));
        assert_eq!(parse_line("hold"), Some(Gesture::Hold));
        assert_eq!(parse_line("turn -1"), Some(Gesture::Turn(-1)));
        assert_eq!(parse_line("turn 2"), Some(Gesture::Turn(2)));
        assert_eq!(parse_line("# a comment"), None);
        assert_eq!(parse_line("jump"), None);
    }
}
