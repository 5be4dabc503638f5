//! The end screen after the last exercise: the session's results in plain words (against the
//! patient's last sessions when the home keeps them), then three optional questions — pain
//! now (0–10), tiredness (0–10), and "too easy / about right / too hard" — answered with the
//! wheel (a turn chooses, a button confirms: `session::buttons`), a gamepad (A confirms, B
//! skips), or the arrow keys or digits and Enter (Esc skips one). Each page waits at most a set time, then
//! goes on as if skipped. The answers ([`netlink::CheckIn`]) go to the hub in the session's
//! `Bye`.
//!
//! [`CheckInFlow`] is the pages' state machine; the window process drives it with the
//! patient's keys and draws its [`CheckInFlow::page`].

use crate::render::window::UserRequest;
use crate::render::{StatusLine, Welcome};
use crate::session::SessionReport;
use netlink::CheckIn;
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::time::{Duration, Instant};

/// How long each page of the end screen waits for the patient by default, s.
pub const DEFAULT_QUESTION_TIMEOUT_S: u64 = 60;

/// Sessions whose results the home keeps to compare the next one with.
pub const KEPT_RESULTS: usize = 5;

/// The answers of the difficulty question, in the order shown, with their words.
const DIFFICULTY: [(&str, &str); 3] = [
    ("too_easy", "Too easy"),
    ("about_right", "About right"),
    ("too_hard", "Too hard"),
];

/// One session's results, as the end screen compares them (and the home keeps them).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct EndResults {
    /// Time the exercises ran (pauses not counted), s.
    pub active_s: f64,
    /// Time within the lane on the road exercises, %, if the session had any.
    pub pct_in_lane: Option<f64>,
    /// The dial's RMS tracking error, degrees, if the session had the dial.
    pub dial_error_deg: Option<f64>,
}

impl EndResults {
    /// The results of a finished session.
    pub fn of(report: &SessionReport) -> Self {
        let rec = &report.recorder;
        let score = &rec.last.score;
        Self {
            active_s: score.active_s,
            pct_in_lane: (rec.road_ticks > 0).then_some(score.pct_in_lane),
            dial_error_deg: (rec.dial_ticks > 0).then_some(score.dial_rms_error_deg),
        }
    }
}

/// "4 minutes 30 seconds", "45 seconds".
fn duration_words(s: f64) -> String {
    let s = s.max(0.0).round() as u64;
    let (m, s) = (s / 60, s % 60);
    let unit = |n: u64, one: &str| format!("{n} {one}{}", if n == 1 { "" } else { "s" });
    match (m, s) {
        (0, s) => unit(s, "second"),
        (m, 0) => unit(m, "minute"),
        (m, s) => format!("{} {}", unit(m, "minute"), unit(s, "second")),
    }
}

/// The mean of `f` over `before`, where it is known.
fn mean_of(before: &[EndResults], f: impl Fn(&EndResults) -> Option<f64>) -> Option<f64> {
    let v: Vec<f64> = before
        .iter()
        .filter_map(f)
        .filter(|x| x.is_finite())
        .collect();
    (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
}

/// The end screen's lines: this session's results in plain words, and what improved against
/// the mean of the sessions `before` (newest first; none: this session's only).
pub fn result_lines(now: &EndResults, before: &[EndResults]) -> Vec<String> {
    let mut lines = vec![format!(
        "You exercised for {}.",
        duration_words(now.active_s)
    )];
    let mut better = Vec::new();
    if let Some(lane) = now.pct_in_lane.filter(|x| x.is_finite()) {
        lines.push(format!("You stayed in your lane {lane:.0} % of the time."));
        if let Some(was) = mean_of(before, |r| r.pct_in_lane)
            && lane >= was + 1.0
        {
            better.push(format!(
                "More time in your lane: {lane:.0} % (recently {was:.0} %)"
            ));
        }
    }
    if let Some(err) = now.dial_error_deg.filter(|x| x.is_finite()) {
        lines.push(format!(
            "Your pointer followed the dial within {err:.0}° on average."
        ));
        if let Some(was) = mean_of(before, |r| r.dial_error_deg)
            && err <= was - 0.5
        {
            better.push(format!(
                "Closer on the dial: {err:.0}° (recently {was:.0}°)"
            ));
        }
    }
    if let Some(was) = mean_of(before, |r| Some(r.active_s))
        && now.active_s >= was + 30.0
    {
        better.push(format!(
            "Longer exercise: {} (recently {})",
            duration_words(now.active_s),
            duration_words(was)
        ));
    }
    if before.is_empty() {
        lines.push("Next time you will see how you compare.".to_owned());
    } else if better.is_empty() {
        lines.push("About the same as your last sessions. Well kept up!".to_owned());
    } else {
        lines.push("Better than your last sessions:".to_owned());
        lines.extend(better);
    }
    lines
}

/// The results of the patient's last sessions kept in `path` (newest first; none if the file
/// is missing or unreadable).
pub fn load_results(path: &Path) -> Vec<EndResults> {
    std::fs::read(path)
        .ok()
        .and_then(|b| serde_json::from_slice(&b).ok())
        .unwrap_or_default()
}

/// Keeps `now` first in `path` with up to [`KEPT_RESULTS`] − 1 of `before`.
pub fn save_results(path: &Path, now: &EndResults, before: &[EndResults]) -> anyhow::Result<()> {
    let kept: Vec<EndResults> = std::iter::once(*now)
        .chain(before.iter().copied())
        .take(KEPT_RESULTS)
        .collect();
    crate::home::write_private(path, &serde_json::to_vec(&kept)?)
}

/// The page the end screen shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Page {
    Results,
    Pain,
    Tiredness,
    Difficulty,
    Thanks,
    Done,
}

/// The end screen's pages, driven by the patient's keys and the clock.
#[derive(Debug, Clone)]
pub struct CheckInFlow {
    results: Vec<String>,
    page: Page,
    /// The value being chosen on a question page (0–10, or 0–2 for the difficulty).
    choice: u8,
    /// The last key was the digit 1 (so a 0 now makes 10).
    after_one: bool,
    answers: CheckIn,
    timeout: Duration,
    page_since: Instant,
}

impl CheckInFlow {
    /// The end screen showing `results` first, each page waiting at most `timeout`.
    pub fn new(results: Vec<String>, timeout: Duration, now: Instant) -> Self {
        Self {
            results,
            page: Page::Results,
            choice: 0,
            after_one: false,
            answers: CheckIn::default(),
            timeout,
            page_since: now,
        }
    }

    /// The end screen has closed: the answers are final.
    pub fn is_done(&self) -> bool {
        self.page == Page::Done
    }

    /// The answers so far (`None`: skipped or not reached).
    pub fn answers(&self) -> &CheckIn {
        &self.answers
    }

    fn go(&mut self, page: Page, now: Instant) {
        self.page = page;
        self.page_since = now;
        self.after_one = false;
        self.choice = match page {
            Page::Difficulty => 1,
            _ => 0,
        };
    }

    fn next(&mut self, now: Instant) {
        let next = match self.page {
            Page::Results => Page::Pain,
            Page::Pain => Page::Tiredness,
            Page::Tiredness => Page::Difficulty,
            Page::Difficulty => Page::Thanks,
            Page::Thanks | Page::Done => Page::Done,
        };
        self.go(next, now);
    }

    fn max_choice(&self) -> u8 {
        match self.page {
            Page::Difficulty => DIFFICULTY.len() as u8 - 1,
            _ => netlink::frame::MAX_CHECKIN_SCORE,
        }
    }

    fn confirm(&mut self, now: Instant) {
        match self.page {
            Page::Pain => self.answers.pain_0_10 = Some(self.choice),
            Page::Tiredness => self.answers.tiredness_0_10 = Some(self.choice),
            Page::Difficulty => {
                self.answers.difficulty = Some(DIFFICULTY[self.choice as usize].0.to_owned());
            }
            _ => {}
        }
        self.next(now);
    }

    /// A key the patient pressed: ←/→ (and ↓/↑) choose, a digit chooses (1 then 0 makes
    /// 10; 1–3 on the last question), Enter or Space confirms, Esc skips the page.
    pub fn apply(&mut self, request: UserRequest, now: Instant) {
        let asking = matches!(self.page, Page::Pain | Page::Tiredness | Page::Difficulty);
        let max = self.max_choice();
        let was_one = std::mem::take(&mut self.after_one);
        match request {
            UserRequest::Confirm | UserRequest::TogglePause => self.confirm(now),
            UserRequest::Quit => self.next(now),
            UserRequest::SeekBack | UserRequest::Slower if asking => {
                self.choice = self.choice.saturating_sub(1);
            }
            UserRequest::SeekForward | UserRequest::Faster if asking => {
                self.choice = (self.choice + 1).min(max);
            }
            UserRequest::Typed(c) if asking => {
                let Some(d) = c.to_digit(10) else { return };
                let d = d as u8;
                if self.page == Page::Difficulty {
                    if (1..=3).contains(&d) {
                        self.choice = d - 1;
                    }
                } else if was_one && d == 0 {
                    self.choice = 10;
                } else {
                    self.choice = d;
                    self.after_one = d == 1;
                }
            }
            _ => {}
        }
    }

    /// Moves on from a page the patient left unanswered for the timeout (as if skipped).
    pub fn tick(&mut self, now: Instant) {
        let limit = match self.page {
            // The thanks page is read in a moment.
            Page::Thanks => self.timeout.min(Duration::from_secs(4)),
            _ => self.timeout,
        };
        if self.page != Page::Done && now.duration_since(self.page_since) >= limit {
            self.next(now);
        }
    }

    /// What the window shows now.
    pub fn page(&self) -> Welcome {
        let plain = |text: String| StatusLine { ok: None, text };
        let scale = |lo: &str, hi: &str| {
            let marks: String = (0..=10)
                .map(|n| {
                    if n == self.choice {
                        format!("[{n}]")
                    } else {
                        format!(" {n} ")
                    }
                })
                .collect();
            vec![plain(format!("0 = {lo}      10 = {hi}")), plain(marks)]
        };
        let question_keys = vec![
            "Turn the wheel (or Left / Right): choose".to_owned(),
            "A wheel button (or Enter): confirm".to_owned(),
            "Esc: skip".to_owned(),
        ];
        let (title, lines, keys) = match self.page {
            Page::Results | Page::Done => (
                "Well done — session complete",
                self.results.iter().cloned().map(plain).collect(),
                vec![
                    "A wheel button (or Enter): answer three short questions".to_owned(),
                    "Esc: skip".to_owned(),
                ],
            ),
            Page::Pain => (
                "How much pain do you feel now?",
                scale("no pain", "worst pain"),
                question_keys,
            ),
            Page::Tiredness => (
                "How tired do you feel now?",
                scale("not tired", "exhausted"),
                question_keys,
            ),
            Page::Difficulty => (
                "How was today's session?",
                DIFFICULTY
                    .iter()
                    .enumerate()
                    .map(|(i, (_, words))| StatusLine {
                        ok: (i == self.choice as usize).then_some(true),
                        text: format!("{}: {words}", i + 1),
                    })
                    .collect(),
                question_keys,
            ),
            Page::Thanks => (
                "Thank you",
                vec![plain(
                    "Your answers will reach your therapist. See you next time!".to_owned(),
                )],
                vec!["A wheel button (or Enter): close".to_owned()],
            ),
        };
        let field = matches!(self.page, Page::Pain | Page::Tiredness).then(|| {
            (
                "Your answer".to_owned(),
                format!("{} out of 10", self.choice),
            )
        });
        Welcome {
            title: title.to_owned(),
            lines,
            field,
            error: None,
            keys,
            ..Welcome::default()
        }
    }
}

/// The answers in a few words, for the session's report (`None`: nothing answered).
pub fn answers_words(c: &CheckIn) -> Option<String> {
    if c.is_empty() {
        return None;
    }
    let score = |v: Option<u8>| v.map_or("skipped".to_owned(), |v| format!("{v}/10"));
    let difficulty = c
        .difficulty
        .as_deref()
        .and_then(|d| DIFFICULTY.iter().find(|(k, _)| *k == d))
        .map_or("skipped", |(_, words)| words);
    Some(format!(
        "pain {}, tiredness {}, {}",
        score(c.pain_0_10),
        score(c.tiredness_0_10),
        difficulty.to_lowercase()
    ))
}

#[cfg(test)]
mod tests;
