//! What a session and a course of sessions leave for people to read: the end-of-session text
//! on the terminal ([`terminal`], for the therapist and the technician; its lines are
//! snapshot-tested because scripts read them) and the clinician's self-contained HTML report of
//! recorded sessions ([`html`], `telerehab report`: measures, charts, progress).
//!
//! Reads recordings through the `record` crate and a session's outcome and measures through
//! the `session` crate; writes files, starts no thread.

pub mod html;
pub mod terminal;
