//! The clinic hub's top: the HTTPS JSON API of the therapist console ([`web`]); a clinic's
//! data directory, `hub init` and `hub serve`, which runs the station link and the console
//! together ([`clinic`]); the hub's own command line, `telerehab hub …` ([`cli`]); backup and
//! restore ([`backup`](mod@backup)); a patient's export and erasure ([`patient_data`]); the
//! load generator of `hub bench` ([`bench`](mod@bench)).
//!
//! The hub is three crates, arrows pointing down: `hub` (this one) → `hub_care` (the clinical
//! logic and the station link: ingest, recordings, alerts, pain care and mail, FHIR, patients,
//! telemetry, fan-out between hubs) → `hub_store` (the database, its migrations, the errors,
//! refusal codes and thresholds). Product code in this crate names their real paths.
//!
//! Re-exports: the modules of the two crates below and the store's main types are re-exported
//! here under their former `hub::` paths (`hub::db`, `hub::ingest`, `hub::Db`, `hub::HubError`,
//! …) for the hub's integration tests, the workspace tests, `tools` and the examples, which
//! depend on `hub` alone; `web` likewise names `hub_care::live`'s `LiveEvent`, `unix_ms` and
//! `system_now_ms`, which the API's state and streams carry.
//!
//! Layering (DESIGN.md): this crate uses `netlink`'s frame types and never the station's
//! device crates.

pub mod backup;
pub mod bench;
pub mod cli;
pub mod clinic;
pub mod patient_data;
pub mod web;

pub use hub_care::{
    attention, care, fanout, fhir, ingest, limits, news, pain_mail, patients, recordings,
    telemetry, uploads,
};
pub use hub_store::{
    Backend, Db, HubError, PairRefusal, Patient, Role, Station, Therapist, db, refusal, thresholds,
};
