//! Subcommands of `telerehab`.

pub mod bench;
pub mod devices;
pub mod vehicle;
pub mod wheel;
