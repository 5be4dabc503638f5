//! The telerehab station: command line, configuration, threads, recorder and therapist hub.

pub mod cli;
pub mod render;
