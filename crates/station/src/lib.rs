//! The telerehab station: the patient's session, its threads and recorder, the first-run
//! pages, the link to the clinic and the station's commands. The one `telerehab` binary is
//! the `telerehab` crate (its command line names these commands); the window's drawing is the
//! `render` crate, the clinic's hub the `hub` crate, benches and drills the `tools` crate. The
//! design of the whole product is `docs/DESIGN.md`.
//!
//! # Module map
//!
//! - [`commands`]: one file per subcommand of the station, each owning its arguments and
//!   `run()`: [`commands::run`] (a patient session), [`commands::window_process`] (the patient
//!   window's own process), [`commands::replay`], [`commands::report`],
//!   [`commands::recover`], [`commands::render`], [`commands::devices`],
//!   [`commands::wheel`], [`commands::vehicle`], [`commands::pair`] and [`commands::sync`] (a
//!   station and its clinic), [`commands::therapist`] (a file-store hub for development),
//!   [`commands::start`] (`telerehab` with no arguments: the first-run pages, then a session).
//!   [`logging`] sets up the one `tracing` subscriber.
//! - [`front_door`]: the first-run pages' state (pairing, today's session, the device check
//!   in plain words); [`settings`]: the patient's settings file; [`readiness`]: a check's
//!   line and the device-permission check, shared by `doctor` and the front door;
//!   [`version`]: what `--version` says.
//! - [`session`]: the threads of a running session. [`session::run`] wires them;
//!   [`session::haptic`] is the 1 kHz loop driving a [`session::plant::Plant`] (wheel, patient,
//!   car, haptic chain, assist) through the exercises of [`session::course`];
//!   [`session::recorder`] writes the records and thins summaries, syncing the file and
//!   watching the room left on its disk ([`session::disk_space`]), and hands back a
//!   [`session::outcome::RecorderOutcome`]; [`session::arm`] and
//!   [`session::arm_calibration`] turn the IMUs into joint angles and arm lengths;
//!   [`session::window`] runs the patient's window in a process of its own (restarted,
//!   the exercise paused, if it dies or hangs); [`session::signals`]
//!   turns SIGINT/SIGTERM into a stop request and [`session::Controls`] carries stop and
//!   pause to the loop; [`session::measures`] computes the movement measures;
//!   [`session::recorded`] is a body made of a recording's raw inputs (replay);
//!   [`session::faults`] injects faults into simulated sessions; [`session::words`] names
//!   exercises and instructions for the patient (the screen and the end reasons speak them).
//! - [`config`]: the station's TOML, validated input (the therapist's prescription is the
//!   `regimen` crate; the recording format, the `record` crate).
//! - [`link`]: the therapist link (tokio runtime, store-and-forward through `netlink`), its
//!   on-disk queue and the recording uploads; [`home`]: the station's home directory
//!   (pairing, queue, recordings).
//! - [`screen`] (a tick → a [`render::Scene`], drawn by the `render` crate: wgpu, window and
//!   offscreen); the tests of the session's pages as drawn (sizes, screenshots) are the
//!   screen's, since `render` knows no session.
//! - [`report`] (the end-of-session text) and [`timing`] (loop-timing percentiles).
//! - [`html_report`]: recorded sessions → one self-contained HTML report (reads `record`,
//!   and the measures' rate from `session::measures`).
//! - [`resident`]: bounded buffers made resident up front, and the process's memory figures.
//!
//! Dependencies point down the list: `commands` → `session`, `link`, `screen`, `report` →
//! `config`, `timing` (and the `render`, `record` and `regimen` crates); nothing below
//! `commands` knows a command, and `session` draws through a scene closure, not the screen (the `[[faults]]` a
//! configuration names are `config::faults`; `session::faults` injects them). Time comes from one
//! injectable [`clock::Clock`] in [`session::SessionOptions`] (mock clocks in tests); the pure
//! crates get `dt` or timestamps.
//!
//! Threads (DESIGN.md): `haptic` (1 kHz, absolute deadlines, real-time priority where
//! granted) → wait-free ring → `recorder` (MCAP, summaries) → the therapist link's tokio
//! runtime and the window's triple buffer; the main thread answers the window process's pulls
//! from that buffer and watches it, the session runs on a `session` thread beside it.

pub mod adapt;
pub mod assessment;
pub mod checkin;
pub mod commands;
pub mod config;
pub mod front_door;
pub mod home;
pub mod html_report;
pub mod language;
pub mod link;
pub mod logging;
pub mod messages;
pub mod platform;
pub mod readiness;
pub mod report;
pub mod resident;
pub mod screen;
pub mod session;
pub mod settings;
pub mod speech;
pub mod timing;
pub mod version;
