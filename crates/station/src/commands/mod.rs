//! Subcommands of `telerehab`.

pub mod vehicle;
