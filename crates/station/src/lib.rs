//! The telerehab station: command line, configuration, threads, recorder and therapist hub.
//!
//! Thread layout (DESIGN.md): the `haptic` thread runs the 1 kHz loop ([`session::haptic`]),
//! the `recorder` thread ([`session::recorder`]) writes MCAP in the [`record`] format and thins
//! summaries, a tokio runtime owns the therapist link ([`link`], [`commands::therapist`]).

pub mod cli;
pub mod commands;
pub mod config;
pub mod link;
pub mod logging;
pub mod record;
pub mod regimen;
pub mod render;
pub mod report;
pub mod screen;
pub mod session;
pub mod timing;
