//! What to read of a recording ([`Selection`]: which channels, over which span of session
//! time) and its checked form, shared by the readers that honour it: the front-to-back column
//! reader ([`super::columns`]) and the indexed one ([`super::select`]).

use super::error::ReadError;
use std::collections::BTreeSet;

/// What to read of a recording: which channels, over which span of session time.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Selection {
    /// The topics to read (`/wheel`, `/score`, …); `None`: every channel.
    pub topics: Option<Vec<String>>,
    /// The session time the samples start at, s, inclusive (`None`: from the start).
    pub start_s: Option<f64>,
    /// The session time the samples end before, s, exclusive (`None`: to the end).
    pub end_s: Option<f64>,
}

impl Selection {
    /// The checked selection, or why it cannot be read: a start or end that is not a number,
    /// a start after the end, an empty list of topics.
    pub(crate) fn checked(&self) -> Result<Picked, ReadError> {
        let bad = |why: String| Err(ReadError::BadSelection(why));
        for (name, t) in [("start_s", self.start_s), ("end_s", self.end_s)] {
            if t.is_some_and(f64::is_nan) {
                return bad(format!("{name} is NaN, not a session time"));
            }
        }
        let start_s = self.start_s.unwrap_or(f64::NEG_INFINITY);
        let end_s = self.end_s.unwrap_or(f64::INFINITY);
        if start_s > end_s {
            return bad(format!(
                "start_s {start_s} s is after end_s {end_s} s (the window is [start_s, end_s))"
            ));
        }
        let topics: Option<BTreeSet<String>> =
            self.topics.as_ref().map(|t| t.iter().cloned().collect());
        if topics.as_ref().is_some_and(BTreeSet::is_empty) {
            return bad("no channel named: name at least one, or none to read them all".into());
        }
        Ok(Picked {
            topics,
            window: Window { start_s, end_s },
        })
    }
}

/// A span of session time, `[start_s, end_s)`, s (infinite ends: unbounded).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Window {
    pub(crate) start_s: f64,
    pub(crate) end_s: f64,
}

impl Window {
    /// Whether the window is all of time.
    pub(crate) fn is_all(&self) -> bool {
        self.start_s == f64::NEG_INFINITY && self.end_s == f64::INFINITY
    }

    /// Whether a sample at `t_s` (its stamp as the columns hold it) is in the window.
    pub(crate) fn holds(&self, t_s: f64) -> bool {
        self.start_s <= t_s && t_s < self.end_s
    }

    /// The window in whole nanoseconds of session time, `[start, end)`: exactly the stamps
    /// `t_ns` whose `t_s` ([`Window::holds`]) is in the window.
    pub(crate) fn ns(&self) -> (u64, u64) {
        (first_ns_from(self.start_s), first_ns_from(self.end_s))
    }
}

/// The least whole nanosecond whose session time as the columns give it (`t_ns · 1e-9`, in
/// floating point) is at or after `s` (`u64::MAX` for none).
fn first_ns_from(s: f64) -> u64 {
    let from = |ns: u64| ns as f64 * 1e-9 >= s;
    if s <= 0.0 {
        return 0;
    }
    if !from(u64::MAX) {
        return u64::MAX;
    }
    // Within a few nanoseconds of the product (its rounding is far below one); then exact.
    let mut ns = (s * 1e9) as u64;
    while ns > 0 && from(ns - 1) {
        ns -= 1;
    }
    while !from(ns) {
        ns += 1;
    }
    ns
}

/// A selection checked: the topics (`None`: all) and the window.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Picked {
    pub(crate) topics: Option<BTreeSet<String>>,
    pub(crate) window: Window,
}

impl Picked {
    /// Whether channel `topic` is read.
    pub(crate) fn wants(&self, topic: &str) -> bool {
        self.topics.as_ref().is_none_or(|t| t.contains(topic))
    }

    /// The first topic asked for that is not among `readable`, as the error naming it.
    pub(crate) fn missing(&self, readable: &BTreeSet<String>) -> Result<(), ReadError> {
        let Some(topics) = &self.topics else {
            return Ok(());
        };
        match topics.iter().find(|t| !readable.contains(*t)) {
            None => Ok(()),
            Some(topic) => Err(ReadError::NoSuchChannel {
                topic: topic.clone(),
                present: readable.iter().cloned().collect(),
            }),
        }
    }
}
