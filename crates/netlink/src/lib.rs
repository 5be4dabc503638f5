//! The station–therapist link: a versioned, length-prefixed frame codec and its tokio
//! transport (TCP, optionally TLS) with store-and-forward of session summaries.
