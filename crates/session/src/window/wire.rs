//! The messages between the station and its patient-window process, and their framing.
//!
//! One Unix stream socket carries both directions. Every message is a little-endian `u32`
//! length and that many bytes of CBOR (self-describing, so an optional field left out reads
//! back as absent, and a NaN a sensor sent reaches the screen as sent). The window asks for a
//! frame each time it wants one ([`FromWindow::Pull`], about 120 times a second), and the
//! station answers with the newest tick: the station never writes more than the window reads,
//! and the pulls are the window's heartbeat.

use record::TickRecord;
use render::AdapterSummary;
use render::window::UserRequest;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use std::io::{self, Read, Write};

/// The largest message either side accepts, bytes (a frame is about 2 KB; the first message
/// carries the configuration and the regimen).
pub const MAX_MESSAGE_BYTES: usize = 1 << 20;

/// What the window draws and how: the first message the station sends.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Hello {
    /// Window title.
    pub title: String,
    /// Initial inner size, logical pixels.
    pub size: (u32, u32),
    /// Start in borderless full screen.
    pub fullscreen: bool,
    /// Most frames drawn per second (`None`: the display rate, or the software cap).
    pub max_fps: Option<f64>,
    /// The station switches drawing on and off with each frame's `draw` (a benchmark).
    pub gated: bool,
    /// Run the window below the session's threads (nice 10, `haptic::WINDOW_NICE`).
    pub background_priority: bool,
    /// The session's configuration, TOML (the window builds its view of the course from it).
    pub config_toml: String,
    /// The session's regimen, TOML, if it has one.
    pub regimen_toml: Option<String>,
    /// This window replaces one that died or hung: the pause card says why the exercise
    /// paused.
    #[serde(default)]
    pub replaces_a_lost_window: bool,
    /// The therapist's message for the start card, if any.
    #[serde(default)]
    pub message: Option<String>,
    /// The session is the practice: every screen says so (nothing is recorded or sent).
    #[serde(default)]
    pub practice: bool,
}

/// From the station to the window.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum ToWindow {
    /// The first message.
    Hello(Box<Hello>),
    /// The newest tick, answering a [`FromWindow::Pull`]; `draw` is the draw gate.
    Frame {
        /// The tick to show.
        record: Box<TickRecord>,
        /// Draw it (false: the window stays open without drawing).
        draw: bool,
        /// The break in progress (a rest, or the card between exercises).
        #[serde(default)]
        brk: crate::BreakNow,
        /// The patient's own arm lengths (upper arm, elbow to grip, m) once the session has
        /// measured them; absent before (the arm inset draws the configured ones).
        #[serde(default)]
        arm_measured_m: Option<[f64; 2]>,
    },
    /// The session is over (the haptic loop has stopped, torque zero): show the end screen
    /// and ask the check-in questions (the station's `checkin`), then answer
    /// [`FromWindow::CheckIn`] and close.
    EndScreen(Box<EndScreen>),
    /// Answers to the end screen given with the wheel or a gamepad (turns, buttons), in
    /// order, as the keys that mean the same: sent instead of a frame once the end screen
    /// is up.
    EndInput(Vec<UserRequest>),
}

/// What the end screen shows and how long each of its pages waits.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EndScreen {
    /// The session's results in plain words, one line each.
    pub lines: Vec<String>,
    /// Longest wait on one page before it goes on as if skipped, s.
    pub question_timeout_s: u64,
    /// A pain at or over this (0–10) ends on the page that says to stop and call the clinic.
    pub pain_threshold_0_10: u8,
    /// The clinic's phone number for that page, if the hub sent one.
    pub clinic_phone: Option<String>,
    /// The session stopped before its end (the wheel stopped working): the results page's
    /// title says so.
    #[serde(default)]
    pub stopped_early: bool,
}

/// From the window to the station.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum FromWindow {
    /// The window is open and can draw.
    Opened,
    /// Send the newest tick (and: the window's loop is alive).
    Pull,
    /// The patient pressed a key that means something to the session.
    Request(UserRequest),
    /// The window closed normally (the session ended, or the patient closed it).
    Closed {
        /// Frames drawn and presented.
        frames_drawn: u64,
        /// The adapter that drew them.
        adapter: Option<AdapterSummary>,
    },
    /// The window could not open, or drawing failed.
    Failed(String),
    /// The patient's answers on the end screen (each optional), just before it closes.
    CheckIn(netlink::CheckIn),
    /// The start card with the therapist's message was drawn and presented (said once).
    MessageShown,
}

/// Write one message.
pub fn send<T: Serialize>(out: &mut impl Write, message: &T) -> io::Result<()> {
    let mut buf = Vec::with_capacity(2048);
    buf.extend_from_slice(&[0; 4]);
    ciborium::into_writer(message, &mut buf)
        .map_err(|e| io::Error::new(io::ErrorKind::InvalidData, e.to_string()))?;
    let len = buf.len() - 4;
    if len > MAX_MESSAGE_BYTES {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("a window message of {len} bytes is over the {MAX_MESSAGE_BYTES}-byte limit"),
        ));
    }
    buf[..4].copy_from_slice(&(len as u32).to_le_bytes());
    out.write_all(&buf)
}

/// Read one message; `Ok(None)` when the other side closed the socket between messages.
pub fn recv<T: DeserializeOwned>(input: &mut impl Read) -> io::Result<Option<T>> {
    let mut len = [0u8; 4];
    match input.read_exact(&mut len) {
        Ok(()) => {}
        Err(e) if e.kind() == io::ErrorKind::UnexpectedEof => return Ok(None),
        Err(e) => return Err(e),
    }
    let len = u32::from_le_bytes(len) as usize;
    if len > MAX_MESSAGE_BYTES {
        return Err(io::Error::new(
            io::ErrorKind::InvalidData,
            format!("a window message of {len} bytes is over the {MAX_MESSAGE_BYTES}-byte limit"),
        ));
    }
    let mut body = vec![0; len];
    input.read_exact(&mut body)?;
    ciborium::from_reader(body.as_slice())
        .map(Some)
        .map_err(|e| io::Error::new(io::ErrorKind::InvalidData, format!("a window message: {e}")))
}

#[cfg(test)]
mod tests {
    use super::*;
    use record::{ArmSample, VehicleSample};

    #[test]
    fn a_frame_reads_back_exactly_with_nan_infinity_and_absent_parts() {
        let mut record = TickRecord {
            tick: 1234,
            t_ns: 1_234_000_000,
            vehicle: Some(VehicleSample {
                x_m: 12.5,
                ..Default::default()
            }),
            arm: None,
            ..Default::default()
        };
        record.wheel.angle_rad = f64::NAN;
        record.wheel.velocity_rad_s = f64::INFINITY;
        record.wheel.true_angle_rad = None;
        record.wheel.hand_nm = Some(-0.25);
        let mut wire = Vec::new();
        let sent = ToWindow::Frame {
            record: Box::new(record),
            draw: true,
            brk: crate::BreakNow::default(),
            arm_measured_m: Some([0.31, 0.32]),
        };
        send(&mut wire, &sent).unwrap();
        let back: ToWindow = recv(&mut wire.as_slice()).unwrap().unwrap();
        let ToWindow::Frame {
            record: got, draw, ..
        } = back
        else {
            panic!("not a frame: {back:?}");
        };
        assert!(draw);
        assert!(got.wheel.angle_rad.is_nan());
        assert_eq!(got.wheel.velocity_rad_s, f64::INFINITY);
        let (mut a, mut b) = (*got, record);
        (a.wheel.angle_rad, b.wheel.angle_rad) = (0.0, 0.0);
        assert_eq!(a, b);
        // An arm present reads back too.
        let with_arm = TickRecord {
            arm: Some(ArmSample::default()),
            ..record
        };
        let mut wire = Vec::new();
        send(&mut wire, &FromWindow::Pull).unwrap();
        send(
            &mut wire,
            &ToWindow::Frame {
                record: Box::new(with_arm),
                draw: false,
                brk: crate::BreakNow::default(),
                arm_measured_m: None,
            },
        )
        .unwrap();
        let mut r = wire.as_slice();
        assert_eq!(recv::<FromWindow>(&mut r).unwrap(), Some(FromWindow::Pull));
        assert!(matches!(
            recv::<ToWindow>(&mut r).unwrap(),
            Some(ToWindow::Frame { record, draw: false, .. }) if record.arm.is_some()
        ));
        assert_eq!(recv::<ToWindow>(&mut r).unwrap(), None, "clean end");
    }

    #[test]
    fn an_oversized_or_truncated_message_is_an_error_naming_it() {
        let mut huge = (MAX_MESSAGE_BYTES as u32 + 1).to_le_bytes().to_vec();
        huge.extend_from_slice(&[0; 16]);
        let e = recv::<FromWindow>(&mut huge.as_slice()).unwrap_err();
        assert!(e.to_string().contains("over the"), "{e}");
        let mut wire = Vec::new();
        send(&mut wire, &FromWindow::Failed("no display".into())).unwrap();
        wire.truncate(wire.len() - 2);
        let e = recv::<FromWindow>(&mut wire.as_slice()).unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::UnexpectedEof);
        let garbage = [3u8, 0, 0, 0, 0xff, 0xff, 0xff];
        let e = recv::<FromWindow>(&mut garbage.as_slice()).unwrap_err();
        assert!(e.to_string().contains("a window message"), "{e}");
    }
}
