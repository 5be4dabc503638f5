//! The clinic's records: the hub's system of record for patients, stations, sessions,
//! regimens, therapists and their logins ([`db`], SQLite or PostgreSQL through one sqlx code
//! path, the migrations of `crates/hub-store/migrations/`), the crate's errors ([`HubError`],
//! [`PairRefusal`]), why the hub refused in any language ([`refusal`]) and the clinic's
//! thresholds for the caseload's alerts ([`thresholds`]).
//!
//! Layering (DESIGN.md): the bottom of the hub's three crates (`hub-store` ← `hub-care` ←
//! `hub`): it knows no web framework, no station link's transport and no device crate; it
//! uses `netlink`'s frame types, `regimen`'s prescription and `metrics`' measure words.

pub mod db;
mod error;
pub mod refusal;
pub mod thresholds;

pub use db::{Backend, Db, Patient, Role, Station, Therapist};
pub use error::{HubError, PairRefusal};
