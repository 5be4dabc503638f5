//! The clinic hub: the system of record for patients, stations, sessions and regimens
//! ([`db`], SQLite or PostgreSQL through one code path) and the HTTPS JSON API of the
//! therapist console ([`web`]).
//!
//! Layering (DESIGN.md): this crate uses `netlink`'s frame types and never the station's
//! device crates.

pub mod db;
mod error;
pub mod web;

pub use db::{Backend, Db, Patient, Role, Station, Therapist};
pub use error::{HubError, PairRefusal};
