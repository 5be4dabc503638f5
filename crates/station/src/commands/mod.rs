//! Subcommands of `telerehab`.

pub mod bench;
pub mod vehicle;
