//! The one `telerehab` binary: its command line ([`cli`]) and the man pages written from it
//! ([`docs`]); every subcommand's work is in a library — the station (`station`), the clinic
//! hub (`hub`), the window (`render`), the measurements and drills (`tools`). The crates and
//! what may depend on what: docs/DESIGN.md, "Five minutes for a new developer".

pub mod cli;
pub mod docs;
