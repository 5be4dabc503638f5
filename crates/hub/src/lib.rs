//! The clinic hub: the system of record for patients, stations, sessions and regimens
//! ([`db`], SQLite or PostgreSQL through one code path) and the HTTPS JSON API of the
//! therapist console ([`web`]); the station link's store and pairing authority ([`ingest`]);
//! a clinic's data directory, `hub init` and `hub serve` ([`clinic`]); what `hub patient …`
//! does to the database ([`patients`]); where recordings are kept, the data directory or an
//! S3-compatible store ([`recordings`]); what one hub tells the others of its clinic through
//! PostgreSQL ([`fanout`]); partial uploads expired ([`uploads`]); the load
//! generator of `hub bench` ([`bench`](mod@bench)); what an operator watches — `/metrics`,
//! `/healthz`, `/readyz` ([`telemetry`], `web::ops`); the
//! crate's errors ([`HubError`], [`PairRefusal`], module `error`).
//!
//! Layering (DESIGN.md): this crate uses `netlink`'s frame types and never the station's
//! device crates.

pub mod attention;
pub mod backup;
pub mod bench;
pub mod care;
pub mod cli;
pub mod clinic;
pub mod db;
mod error;
pub mod fanout;
pub mod fhir;
pub mod ingest;
pub mod limits;
pub mod news;
pub mod pain_mail;
pub mod patient_data;
pub mod patients;
pub mod recordings;
pub mod refusal;
mod sheet_words;
pub mod telemetry;
pub mod thresholds;
pub mod uploads;
pub mod web;

pub use db::{Backend, Db, Patient, Role, Station, Therapist};
pub use error::{HubError, PairRefusal};
