//! The telerehab station around a session: the station's commands, the first-run pages, the
//! link to the clinic, the screen, the check-in and the reports. A session itself (its threads,
//! recorder, configuration) is the `session` crate; the window's drawing the `render` crate;
//! the reports (the end-of-session text, the HTML report) the `report` crate; the one
//! `telerehab` binary the `telerehab` crate (its command line names these commands);
//! the clinic's hub the `hub` crate; benches and drills the `tools` crate. The design of the
//! whole product is `docs/DESIGN.md`.
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
//!   in plain words); [`readiness`]: a check's line and the device-permission check, shared by
//!   `doctor` and the front door; [`version`]: what `--version` says.
//! - [`checkin`]: the questions before and after a session (pain, effort, difficulty);
//!   [`adapt`]: the next session's difficulty; [`speech`]: each page's main sentence spoken.
//! - [`link`]: the therapist link (tokio runtime, store-and-forward through `netlink`), its
//!   on-disk queue and the recording uploads; [`home`]: the station's home directory
//!   (pairing, queue, recordings); [`messages`]: the therapist's messages kept.
//! - [`screen`] (a tick → a [`render::Scene`], drawn by the `render` crate: wgpu, window and
//!   offscreen); the tests of the session's pages as drawn (sizes, screenshots) are the
//!   screen's, since `render` knows no session.
//!
//! Dependencies point down the list: `commands` → `front_door`, `link`, `screen` → the
//! `report`, `session`, `render`, `record` and `regimen` crates; nothing below `commands` knows a
//! command, and a session draws through a scene closure, not the screen. Time comes from one
//! injectable [`clock::Clock`] in `session::SessionOptions` (mock clocks in tests).

pub mod adapt;
pub mod checkin;
pub mod commands;
pub mod front_door;
pub mod home;
pub mod link;
pub mod logging;
pub mod messages;
pub mod readiness;
pub mod screen;
pub mod speech;
pub mod version;
