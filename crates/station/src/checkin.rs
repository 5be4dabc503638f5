//! The end screen after the last exercise: the session's results in plain words (against the
//! patient's last sessions when the home keeps them, [`results`]), then three optional
//! questions on pictured scales — pain now (0–10, six faces green to red), effort (0–10,
//! Borg's CR10 words) and "too easy / just right / too hard" (a thumb down, flat, up) — and
//! the thanks; or, after a pain at or over the clinic's threshold ([`care`]), a page that says
//! to stop, rest and call the clinic instead of the remaining questions and the thanks.
//!
//! Nothing is preset: a question's answer is recorded only once the patient has chosen a
//! value and confirmed it. With the wheel alone: turn to choose, a short press confirms, a
//! long press skips (a gamepad's A confirms and B skips; the arrow keys or digits and Enter
//! confirm, Esc skips). Each page waits at most a set time, then goes on as if skipped. The
//! answers ([`netlink::CheckIn`]) go to the hub in the session's `Bye`; effort travels in its
//! `tiredness_0_10` field.
//!
//! [`CheckInFlow`] is the pages' state machine; the window process drives it with the
//! patient's keys and draws its [`CheckInFlow::page`]. Every sentence comes from the
//! `checkin` catalogue ([`i18n`]); [`CheckInFlow::spoken`] names the page's main sentence for
//! speech.

pub mod care;
pub mod results;

pub use results::{
    EndResults, KEPT_RESULTS, end_lines, load_results, result_lines, save_results, wheel_stopped,
};

use netlink::CheckIn;
use render::window::UserRequest;
use render::{CheckInPage, CheckInScale, ScaleKind};
use std::time::{Duration, Instant};

/// How long each page of the end screen waits for the patient by default, s.
pub const DEFAULT_QUESTION_TIMEOUT_S: u64 = 60;

/// The thanks page is read in a moment: it closes after this at most.
const THANKS_FOR: Duration = Duration::from_secs(4);

/// The answers of the difficulty question, in the order shown: the wire value and the
/// catalogue's message.
const DIFFICULTY: [(&str, &str); 3] = [
    ("too_easy", "checkin-difficulty-too-easy"),
    ("about_right", "checkin-difficulty-just-right"),
    ("too_hard", "checkin-difficulty-too-hard"),
];

/// The effort values Borg's CR10 names (the others take the word below them).
const EFFORT_WORDS_AT: [u8; 8] = [0, 1, 2, 3, 4, 5, 7, 10];

/// The page the end screen shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Page {
    Results,
    Pain,
    Effort,
    Difficulty,
    /// The pain answered was at or over the clinic's threshold.
    PainStop,
    Thanks,
    Done,
}

impl Page {
    fn id(self) -> &'static str {
        match self {
            Self::Results => "results",
            Self::Pain => "pain",
            Self::Effort => "effort",
            Self::Difficulty => "difficulty",
            Self::PainStop => "pain-stop",
            Self::Thanks => "thanks",
            Self::Done => "done",
        }
    }

    fn is_question(self) -> bool {
        matches!(self, Self::Pain | Self::Effort | Self::Difficulty)
    }

    /// The page's main sentence, the one spoken.
    fn message_id(self) -> Option<&'static str> {
        Some(match self {
            Self::Results => "checkin-results-title",
            Self::Pain => "checkin-pain-question",
            Self::Effort => "checkin-effort-question",
            Self::Difficulty => "checkin-difficulty-question",
            Self::PainStop => "checkin-stop-title",
            Self::Thanks => "checkin-thanks-title",
            Self::Done => return None,
        })
    }
}

/// The end screen's pages, driven by the patient's keys and the clock.
#[derive(Debug, Clone)]
pub struct CheckInFlow {
    results: Vec<String>,
    page: Page,
    /// The value chosen on a question page (0–10, or 0–2 for the difficulty); `None` until
    /// the patient chooses.
    choice: Option<u8>,
    /// The last key was the digit 1 (so a 0 now makes 10).
    after_one: bool,
    /// The patient confirmed before choosing: the page says how to choose.
    nudged: bool,
    answers: CheckIn,
    timeout: Duration,
    page_since: Instant,
    /// A pain at or over this ends on the page that says to stop.
    pain_threshold_0_10: u8,
    /// The clinic's phone number for that page.
    clinic_phone: Option<String>,
    /// The session stopped before its end (the wheel stopped working): the results page's
    /// title says so instead of "Well done! You finished."
    stopped_early: bool,
}

impl CheckInFlow {
    /// The end screen showing `results` first, each page waiting at most `timeout`, with the
    /// default pain threshold and no phone number ([`Self::with_care`] sets the clinic's).
    pub fn new(results: Vec<String>, timeout: Duration, now: Instant) -> Self {
        Self {
            results,
            page: Page::Results,
            choice: None,
            after_one: false,
            nudged: false,
            answers: CheckIn::default(),
            timeout,
            page_since: now,
            pain_threshold_0_10: care::DEFAULT_PAIN_THRESHOLD_0_10,
            clinic_phone: None,
            stopped_early: false,
        }
    }

    /// The session stopped before its end ([`wheel_stopped`]): the results page's title says
    /// so, not that the patient finished.
    pub fn stopped_early(mut self, stopped: bool) -> Self {
        self.stopped_early = stopped;
        self
    }

    /// The page's main sentence, the one spoken: [`Page::message_id`], but a session stopped
    /// early is not "finished".
    fn message_id(&self) -> Option<&'static str> {
        match self.page {
            Page::Results if self.stopped_early => Some("checkin-results-stopped-title"),
            page => page.message_id(),
        }
    }

    /// The clinic's pain threshold (0–10) and phone number, as the hub sent them.
    pub fn with_care(mut self, pain_threshold_0_10: u8, clinic_phone: Option<String>) -> Self {
        self.pain_threshold_0_10 = pain_threshold_0_10;
        self.clinic_phone = clinic_phone.filter(|p| !p.trim().is_empty());
        self
    }

    /// The end screen has closed: the answers are final.
    pub fn is_done(&self) -> bool {
        self.page == Page::Done
    }

    /// The answers so far (`None`: skipped or not reached).
    pub fn answers(&self) -> &CheckIn {
        &self.answers
    }

    /// The page's stable id: `results`, `pain`, `effort`, `difficulty`, `pain-stop`,
    /// `thanks` or `done`.
    pub fn page_id(&self) -> &'static str {
        self.page.id()
    }

    /// The page's main sentence for speech: its catalogue id and its words in the language in
    /// force (`None` once closed).
    pub fn spoken(&self) -> Option<(&'static str, String)> {
        let id = self.message_id()?;
        Some((id, i18n::tr!(id)))
    }

    /// The value chosen on this page so far (`None`: nothing chosen yet).
    pub fn choice(&self) -> Option<u8> {
        self.choice
    }

    fn go(&mut self, page: Page, now: Instant) {
        tracing::info!(page = page.id(), "end screen page");
        self.page = page;
        self.page_since = now;
        self.after_one = false;
        self.nudged = false;
        self.choice = None;
    }

    fn next(&mut self, now: Instant) {
        let next = match self.page {
            Page::Results => Page::Pain,
            Page::Pain => Page::Effort,
            Page::Effort => Page::Difficulty,
            Page::Difficulty => Page::Thanks,
            Page::PainStop | Page::Thanks | Page::Done => Page::Done,
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
        if !self.page.is_question() {
            self.next(now);
            return;
        }
        let Some(choice) = self.choice else {
            // Nothing chosen: nothing is recorded, and the page says how to choose.
            self.nudged = true;
            return;
        };
        match self.page {
            Page::Pain => {
                self.answers.pain_0_10 = Some(choice);
                if choice >= self.pain_threshold_0_10 {
                    self.go(Page::PainStop, now);
                    return;
                }
            }
            Page::Effort => self.answers.tiredness_0_10 = Some(choice),
            Page::Difficulty => {
                self.answers.difficulty = Some(DIFFICULTY[usize::from(choice)].0.to_owned());
            }
            _ => {}
        }
        self.next(now);
    }

    /// One step along the scale: the first step enters from the side turned from (right: 0,
    /// left: the top), the next ones move by one and stop at the ends.
    fn step(&mut self, up: bool) {
        let max = self.max_choice();
        self.choice = Some(match (self.choice, up) {
            (None, true) => 0,
            (None, false) => max,
            (Some(c), true) => (c + 1).min(max),
            (Some(c), false) => c.saturating_sub(1),
        });
        self.nudged = false;
    }

    /// A key the patient pressed (the wheel's and a gamepad's arrive as keys too): → and ↑
    /// (a turn right) choose higher, ← and ↓ lower, a digit chooses (1 then 0 makes 10;
    /// 1–3 on the last question), Enter or Space (a short press) confirms, Esc (a long
    /// press) skips the page.
    pub fn apply(&mut self, request: UserRequest, now: Instant) {
        let asking = self.page.is_question();
        let was_one = std::mem::take(&mut self.after_one);
        match request {
            UserRequest::Confirm | UserRequest::TogglePause => self.confirm(now),
            UserRequest::Quit => self.next(now),
            UserRequest::SeekBack | UserRequest::Slower if asking => self.step(false),
            UserRequest::SeekForward | UserRequest::Faster if asking => self.step(true),
            UserRequest::Typed(c) if asking => {
                let Some(d) = c.to_digit(10) else { return };
                let d = d as u8;
                if self.page == Page::Difficulty {
                    if (1..=3).contains(&d) {
                        self.choice = Some(d - 1);
                    }
                } else if was_one && d == 0 {
                    self.choice = Some(10);
                } else {
                    self.choice = Some(d);
                    self.after_one = d == 1;
                }
                self.nudged = false;
            }
            _ => {}
        }
    }

    /// Moves on from a page the patient left unanswered for the timeout (as if skipped).
    pub fn tick(&mut self, now: Instant) {
        let limit = match self.page {
            Page::Thanks => self.timeout.min(THANKS_FOR),
            _ => self.timeout,
        };
        if self.page != Page::Done && now.duration_since(self.page_since) >= limit {
            self.next(now);
        }
    }

    /// What the window shows now.
    pub fn page(&self) -> CheckInPage {
        let question_keys = || {
            vec![
                i18n::tr!("checkin-key-turn"),
                i18n::tr!("checkin-key-press"),
                i18n::tr!("checkin-key-hold"),
                i18n::tr!("checkin-key-keyboard"),
            ]
        };
        let title = self
            .message_id()
            .map(|id| i18n::tr!(id))
            .unwrap_or_default();
        let mut page = CheckInPage {
            id: self.page.id(),
            title,
            scale: None,
            lines: Vec::new(),
            stop: false,
            keys: Vec::new(),
        };
        match self.page {
            Page::Results | Page::Done => {
                page.lines = self.results.clone();
                page.keys = vec![
                    i18n::tr!("checkin-key-start"),
                    i18n::tr!("checkin-key-hold"),
                ];
            }
            Page::Pain | Page::Effort | Page::Difficulty => {
                page.scale = Some(self.scale());
                page.keys = question_keys();
            }
            Page::PainStop => {
                page.stop = true;
                page.lines = vec![
                    i18n::tr!("checkin-stop-rest"),
                    i18n::tr!("checkin-stop-no-more"),
                    match &self.clinic_phone {
                        Some(phone) => i18n::tr!("checkin-stop-call", phone = phone.clone()),
                        None => i18n::tr!("checkin-stop-call-clinic"),
                    },
                    i18n::tr!("checkin-stop-told"),
                ];
                page.keys = vec![i18n::tr!("checkin-key-close")];
            }
            Page::Thanks => {
                page.lines = vec![
                    i18n::tr!("checkin-thanks-text"),
                    i18n::tr!("checkin-thanks-bye"),
                ];
                page.keys = vec![i18n::tr!("checkin-key-close")];
            }
        }
        page
    }

    /// The question page's scale: its picture, the choice and every value's words.
    fn scale(&self) -> CheckInScale {
        let (kind, words): (ScaleKind, Vec<String>) = match self.page {
            Page::Pain => (ScaleKind::Faces, (0..=10).map(pain_words).collect()),
            Page::Effort => (ScaleKind::Effort, (0..=10).map(effort_words).collect()),
            _ => (
                ScaleKind::Thumbs,
                DIFFICULTY.iter().map(|(_, id)| i18n::tr!(*id)).collect(),
            ),
        };
        let chosen = match self.choice {
            None => i18n::tr!("checkin-choose-first"),
            Some(c) if kind == ScaleKind::Thumbs => words[usize::from(c)].clone(),
            Some(c) => i18n::tr!(
                "checkin-chosen-score",
                value = c,
                words = words[usize::from(c)].clone()
            ),
        };
        CheckInScale {
            kind,
            choice: self.choice,
            words,
            chosen,
        }
    }
}

/// The words of pain `value` (0–10): the words of its face.
pub fn pain_words(value: u8) -> String {
    let face = usize::from(value.min(10)).div_ceil(2);
    i18n::tr!(&format!("checkin-pain-{face}"))
}

/// The words of effort `value` (0–10) on Borg's CR10 scale (a value it leaves unnamed takes
/// the words below it).
pub fn effort_words(value: u8) -> String {
    let at = EFFORT_WORDS_AT
        .iter()
        .rev()
        .find(|&&w| w <= value)
        .copied()
        .unwrap_or(0);
    i18n::tr!(&format!("checkin-effort-{at}"))
}

/// The answers in a few words, for the session's report in the terminal (`None`: nothing
/// answered). For the clinic's technician: English, as the rest of the report.
pub fn answers_words(c: &CheckIn) -> Option<String> {
    if c.is_empty() {
        return None;
    }
    let score = |v: Option<u8>| v.map_or("skipped".to_owned(), |v| format!("{v}/10"));
    let difficulty = match c.difficulty.as_deref() {
        Some("too_easy") => "too easy",
        Some("about_right") => "just right",
        Some("too_hard") => "too hard",
        _ => "skipped",
    };
    Some(format!(
        "pain {}, effort {}, {}",
        score(c.pain_0_10),
        score(c.tiredness_0_10),
        difficulty
    ))
}

#[cfg(test)]
mod tests;
