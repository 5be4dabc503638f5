//! The clinic hub's clinical logic and its station link, between the records (`hub_store`)
//! and the console's API (`hub::web`): the station side of the hub, netlink's store and
//! pairing authority over the database ([`ingest`]); what a station is told of its patient
//! ([`news`]); where recordings are kept, the data directory or an S3-compatible store
//! ([`recordings`]); partial uploads expired ([`uploads`]); the caseload's alerts
//! ([`attention`]); the clinic's pain settings and who is mailed a pain ([`care`],
//! [`pain_mail`]); a patient's record as FHIR ([`fhir`]) and the words written for a clinician
//! outside the console ([`sheet_words`]); what `hub patient …` does to the database
//! ([`patients`]); what one hub tells the others of its clinic through PostgreSQL ([`fanout`])
//! and what reaches a live view ([`live`]); what an operator watches, the Prometheus registry
//! ([`telemetry`]); the file-descriptor budget of `hub serve` ([`limits`]).
//!
//! Layering (DESIGN.md): above `hub-store`, below `hub`; it knows no web framework (the
//! console's API uses it, never the reverse) and never the station's device crates.

pub mod attention;
pub mod care;
pub mod fanout;
pub mod fhir;
pub mod ingest;
pub mod limits;
pub mod live;
pub mod news;
pub mod pain_mail;
pub mod patients;
pub mod recordings;
pub mod sheet_words;
pub mod telemetry;
pub mod uploads;
