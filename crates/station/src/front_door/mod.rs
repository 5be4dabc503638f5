//! What `telerehab` with no arguments shows before a session: the first-run pages, every step
//! of which can be done with the wheel alone (turn to choose, a short press of any wheel
//! button to confirm, a long press to go back); the keyboard stays as an alternative.
//!
//! - **Language** (first run, until one is chosen): the catalogues' languages, each in its
//!   own name, chosen with the wheel; the caller stores the choice and puts it in force.
//! - **Unpaired**: no address is typed. The clinic either pairs the station before lending it
//!   (`telerehab pair`), or prepares a pairing card ([`pairing_file`]) that this page finds
//!   and uses with one press. When the card (or the clinic's installation) gives only the
//!   address, the code is chosen sign by sign with the wheel. A refused code stays on the
//!   page, so the patient can check it against the letter. Without any address the page says
//!   to call the clinic (a keyboard can still type it).
//! - **Paired**: today's session (its exercises and minutes, rests included), the device
//!   check in plain words, and three choices: start, practice (the try-out), close.
//!
//! [`FrontDoor`] is the pages' state, driven by the patient's keys ([`UserRequest`]), the
//! wheel ([`Gesture`]) and what the background work reports (pairing, device checks, the
//! plan); it draws nothing itself: its [`FrontDoor::page`] is the [`Welcome`] the window
//! draws. `commands::start` runs it.

pub mod checks;
pub mod pairing_file;
pub mod today;

use i18n::tr;
use render::window::UserRequest;
use render::{Picture, StatusLine, Welcome};
use session::wheel_gestures::Gesture;
pub use today::TodayPlan;

/// The station port a clinic address gets when none is typed (the hub's default).
pub const DEFAULT_HUB_PORT: u16 = 7878;

/// Longest address or code accepted from the keyboard, characters.
const MAX_TYPED: usize = 80;

/// Signs in a pairing code (two halves of four, `7KQ2-M9XD`).
pub const CODE_SIGNS: usize = 8;

/// How the pages ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    /// Start today's session on the real devices.
    Start,
    /// A short simulated try-out (practice).
    TryOut,
    /// The patient closed the window.
    Quit,
}

/// What the caller must do after a key or a gesture.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Action {
    /// Nothing more.
    None,
    /// The patient chose this language (a tag of [`i18n::LANGUAGES`]): store it in the
    /// settings and put it in force.
    Language(String),
    /// Pair with the hub at `address` using `code`, then report with [`FrontDoor::paired`].
    Pair {
        /// `host:port`.
        address: String,
        /// The code as typed or chosen.
        code: String,
    },
    /// Close the pages: the outcome is decided.
    Done(Outcome),
}

/// One thing the patient did: a key, or a gesture of the wheel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Input {
    /// A key (the keyboard, the alternative).
    Key(UserRequest),
    /// The wheel.
    Wheel(Gesture),
}

/// The choices of today's page, in order.
const TODAY_CHOICES: [Outcome; 3] = [Outcome::Start, Outcome::TryOut, Outcome::Quit];

/// How the pairing page asks for the clinic and the code.
#[derive(Debug, Clone, PartialEq)]
struct Pairing {
    /// The clinic's address (from the card or the installation; typed only on a keyboard).
    address: String,
    /// The card's code, when the clinic wrote it on the card: one press pairs.
    card_code: Option<String>,
    /// The card could not be read.
    card_unreadable: bool,
    /// The code chosen or typed so far.
    code: String,
    /// The sign the wheel points at now (an index into the code's alphabet).
    sign: usize,
    /// The keyboard types the address (Tab), not the code.
    typing_address: bool,
    /// What went wrong last, in plain words (the code stays).
    error: Option<String>,
}

#[derive(Debug, Clone, PartialEq)]
enum Page {
    Language { chosen: usize, then: Box<Page> },
    Pairing(Pairing),
    Connecting { address: String, pairing: Pairing },
    Today { plan: TodayPlan, chosen: usize },
}

/// The first-run pages' state.
#[derive(Debug, Clone)]
pub struct FrontDoor {
    page: Page,
    /// The device check, in plain words (empty until the first check ends).
    devices: Vec<StatusLine>,
    /// A wheel is there and usable: the session may start.
    wheel_ready: bool,
    /// Set once the device check has run.
    checked: bool,
    /// Something about the clinic the patient must know (e.g. an update is required).
    notice: Option<StatusLine>,
    /// The therapist's newest message, shown on today's page.
    message: Option<String>,
    /// A pain at or over the clinic's threshold today: this page instead of today's
    /// session, and nothing starts one ([`crate::checkin::care`]).
    rest_today: Option<Welcome>,
}

/// The pairing code's signs (the hub's alphabet).
fn alphabet() -> &'static [u8] {
    netlink::pairing::CODE_ALPHABET
}

impl FrontDoor {
    /// Unpaired: the pairing page. `card` is the clinic's pairing card if one was found
    /// ([`pairing_file::find`]); `clinic_address` the address the clinic's installation wrote
    /// in the settings.
    pub fn unpaired(card: &pairing_file::Found, clinic_address: Option<&str>) -> Self {
        let (address, card_code, card_unreadable) = match card {
            pairing_file::Found::Card(_, c) => (
                c.clinic_address.trim().to_owned(),
                c.code.clone().filter(|c| !c.trim().is_empty()),
                false,
            ),
            pairing_file::Found::Unreadable(..) => {
                (clinic_address.unwrap_or_default().to_owned(), None, true)
            }
            pairing_file::Found::Nothing => {
                (clinic_address.unwrap_or_default().to_owned(), None, false)
            }
        };
        Self::with_page(Page::Pairing(Pairing {
            typing_address: address.is_empty(),
            address,
            card_code,
            card_unreadable,
            code: String::new(),
            sign: 0,
            error: None,
        }))
    }

    /// Paired: today's session.
    pub fn paired_with(plan: TodayPlan) -> Self {
        Self::with_page(Page::Today { plan, chosen: 0 })
    }

    /// Ask for the language first (the first run, before one was chosen), `current` chosen
    /// at first (a tag; the first language when it is none of them).
    pub fn asking_language(mut self, current: &str) -> Self {
        let chosen = i18n::LANGUAGES
            .iter()
            .position(|l| current.starts_with(l))
            .unwrap_or(0);
        let then = Box::new(self.page.clone());
        self.page = Page::Language { chosen, then };
        self
    }

    fn with_page(page: Page) -> Self {
        Self {
            page,
            devices: Vec::new(),
            wheel_ready: false,
            checked: false,
            notice: None,
            message: None,
            rest_today: None,
        }
    }

    /// Today's session is replaced by `page` (rest today, call the clinic) while a pain stop
    /// holds; `None` offers the session again.
    pub fn set_rest_today(&mut self, page: Option<Welcome>) {
        self.rest_today = page;
    }

    /// The page says to rest today instead of offering the session.
    pub fn is_resting_today(&self) -> bool {
        self.rest_today.is_some() && matches!(self.page, Page::Today { .. })
    }

    /// The device check's latest lines and whether a wheel is ready.
    pub fn set_devices(&mut self, lines: Vec<StatusLine>, wheel_ready: bool) {
        self.devices = lines;
        self.wheel_ready = wheel_ready;
        self.checked = true;
    }

    /// Something the patient must know about the clinic's hub (`None` clears it).
    pub fn set_notice(&mut self, notice: Option<StatusLine>) {
        self.notice = notice;
    }

    /// Today's plan as it stands now (fetched again while the page is open).
    pub fn set_plan(&mut self, fresh: TodayPlan) {
        if let Page::Today { plan, .. } = &mut self.page {
            *plan = fresh;
        }
    }

    /// The therapist's newest message (`None`: none).
    pub fn set_message(&mut self, message: Option<String>) {
        self.message = message;
    }

    /// Whether today's page is showing (the caller then keeps its plan up to date).
    pub fn is_today(&self) -> bool {
        matches!(self.page, Page::Today { .. })
    }

    /// Whether the pairing pages are showing (the caller then has nothing to check at the
    /// hub).
    pub fn is_pairing(&self) -> bool {
        match &self.page {
            Page::Language { then, .. } => !matches!(**then, Page::Today { .. }),
            Page::Today { .. } => false,
            _ => true,
        }
    }

    /// What pairing came to: today's plan, or what went wrong in plain words. A refused code
    /// stays on the page so the patient can check it.
    pub fn paired(&mut self, result: Result<TodayPlan, String>) {
        let Page::Connecting { pairing, .. } = &self.page else {
            return;
        };
        let mut pairing = pairing.clone();
        self.page = match result {
            Ok(plan) => {
                self.notice = Some(StatusLine {
                    ok: Some(true),
                    text: tr!("front-connected"),
                });
                Page::Today { plan, chosen: 0 }
            }
            Err(error) => {
                pairing.error = Some(error);
                Page::Pairing(pairing)
            }
        };
    }

    /// Act on a key.
    pub fn apply(&mut self, request: UserRequest) -> Action {
        self.act(Input::Key(request))
    }

    /// Act on a gesture of the wheel.
    pub fn wheel(&mut self, gesture: Gesture) -> Action {
        self.act(Input::Wheel(gesture))
    }

    /// Act on what the patient did.
    pub fn act(&mut self, input: Input) -> Action {
        use Input::{Key, Wheel};
        if input == Key(UserRequest::Quit) {
            return Action::Done(Outcome::Quit);
        }
        // A pain stop today: nothing starts a session (crate::checkin::care); a press of the
        // wheel closes the page, as Esc does.
        let resting = self.rest_today.is_some();
        let wheel_ready = self.wheel_ready && !resting;
        match &mut self.page {
            Page::Today { .. } if resting => match input {
                Wheel(Gesture::Press) => Action::Done(Outcome::Quit),
                _ => Action::None,
            },
            Page::Language { chosen, then } => match input {
                Wheel(Gesture::Turn(by)) => {
                    *chosen = step(*chosen, by, i18n::LANGUAGES.len());
                    Action::None
                }
                Key(UserRequest::SeekBack) => {
                    *chosen = step(*chosen, -1, i18n::LANGUAGES.len());
                    Action::None
                }
                Key(UserRequest::SeekForward) => {
                    *chosen = step(*chosen, 1, i18n::LANGUAGES.len());
                    Action::None
                }
                Wheel(Gesture::Press) | Key(UserRequest::Confirm | UserRequest::TogglePause) => {
                    let tag = i18n::LANGUAGES[*chosen].to_owned();
                    self.page = (**then).clone();
                    Action::Language(tag)
                }
                _ => Action::None,
            },
            Page::Pairing(p) => match input {
                Key(UserRequest::TryOut) => Action::Done(Outcome::TryOut),
                Wheel(g) => pairing_wheel(p, g).map_or(Action::None, |_| self.connect()),
                Key(k) => pairing_key(p, k).map_or(Action::None, |_| self.connect()),
            },
            Page::Connecting { .. } => Action::None,
            Page::Today { chosen, .. } => {
                let choose = |c: Outcome| match c {
                    Outcome::Start if !wheel_ready => Action::None,
                    c => Action::Done(c),
                };
                match input {
                    Wheel(Gesture::Turn(by)) => {
                        *chosen = step(*chosen, by, TODAY_CHOICES.len());
                        Action::None
                    }
                    Wheel(Gesture::Press) => choose(TODAY_CHOICES[*chosen]),
                    Key(UserRequest::TogglePause | UserRequest::Confirm) => choose(Outcome::Start),
                    Key(UserRequest::TryOut) => Action::Done(Outcome::TryOut),
                    _ => Action::None,
                }
            }
        }
    }

    /// Pair with what the pairing page holds, or say what is missing.
    fn connect(&mut self) -> Action {
        let Page::Pairing(p) = &mut self.page else {
            return Action::None;
        };
        if p.address.trim().is_empty() {
            p.typing_address = true;
            p.error = Some(tr!("front-error-no-address"));
            return Action::None;
        }
        let code = p.card_code.clone().unwrap_or_else(|| p.code.clone());
        let address = with_default_port(p.address.trim());
        let pairing = Pairing {
            error: None,
            ..p.clone()
        };
        self.page = Page::Connecting {
            address: address.clone(),
            pairing,
        };
        Action::Pair {
            address,
            code: code.trim().to_owned(),
        }
    }

    /// The page's stable name (logs and tests).
    pub fn page_id(&self) -> &'static str {
        self.page().id
    }

    /// The page to draw now.
    pub fn page(&self) -> Welcome {
        match &self.page {
            Page::Language { chosen, .. } => Welcome {
                id: "language",
                title: tr!("front-language-title"),
                lines: vec![plain(&tr!("front-language-how"))],
                choices: i18n::LANGUAGES
                    .iter()
                    .map(|l| own_name(l).to_owned())
                    .collect(),
                chosen: *chosen,
                picture: Some(Picture::Wheel {
                    hold: false,
                    turn: true,
                }),
                ..Welcome::default()
            },
            Page::Pairing(p) => pairing_page(p),
            Page::Connecting { .. } => Welcome {
                id: "connecting",
                title: tr!("front-connecting-title"),
                lines: vec![plain(&tr!("front-connecting-wait"))],
                ..Welcome::default()
            },
            Page::Today { .. } if self.rest_today.is_some() => {
                self.rest_today.clone().unwrap_or_default()
            }
            Page::Today { plan, chosen } => self.today_page(plan, *chosen),
        }
    }

    fn today_page(&self, plan: &TodayPlan, chosen: usize) -> Welcome {
        let mut lines = plan.lines();
        if let Some(m) = &self.message {
            lines.push(plain(&format!("{} {m}", tr!("front-today-message"))));
        }
        lines.extend(self.notice.clone());
        if self.checked {
            lines.extend(self.devices.iter().cloned());
        } else {
            lines.push(plain(&tr!("front-today-checking")));
        }
        if !self.wheel_ready {
            lines.push(plain(&tr!("front-today-wait-wheel")));
        }
        Welcome {
            id: "today",
            title: tr!("front-today-title"),
            lines,
            choices: vec![
                tr!("front-today-start"),
                tr!("front-today-practice"),
                tr!("front-today-close"),
            ],
            chosen,
            picture: Some(Picture::Wheel {
                hold: false,
                turn: true,
            }),
            keys: vec![tr!("front-today-how"), tr!("front-today-keys")],
            ..Welcome::default()
        }
    }
}

/// `at` moved `by` steps within `0..n`, wrapping round.
fn step(at: usize, by: i32, n: usize) -> usize {
    let n = n.max(1) as i64;
    ((at as i64 + i64::from(by)).rem_euclid(n)) as usize
}

/// A language's name in that language.
pub fn own_name(tag: &str) -> &'static str {
    match tag {
        "de" => "Deutsch",
        "es" => "Español",
        "zh" => "中文",
        _ => "English",
    }
}

/// A wheel gesture on the pairing page; `Some(())` when it is time to connect.
fn pairing_wheel(p: &mut Pairing, g: Gesture) -> Option<()> {
    if p.card_code.is_some() {
        // The card has everything: a press connects.
        return (g == Gesture::Press).then_some(());
    }
    if p.address.is_empty() {
        return None; // nothing the wheel can do: the page says to call the clinic
    }
    match g {
        Gesture::Turn(by) => p.sign = step(p.sign, by, alphabet().len()),
        Gesture::Press
            if p.code.chars().filter(char::is_ascii_alphanumeric).count() >= CODE_SIGNS =>
        {
            return Some(());
        }
        Gesture::Press => {
            p.code.push(char::from(alphabet()[p.sign]));
            p.error = None;
            if p.code.chars().filter(char::is_ascii_alphanumeric).count() == CODE_SIGNS {
                return Some(());
            }
        }
        Gesture::Hold => {
            p.code.pop();
            p.error = None;
        }
    }
    None
}

/// A key on the pairing page; `Some(())` when it is time to connect.
fn pairing_key(p: &mut Pairing, k: UserRequest) -> Option<()> {
    let field = if p.typing_address {
        &mut p.address
    } else {
        &mut p.code
    };
    match k {
        UserRequest::Typed(c) if field.chars().count() < MAX_TYPED => {
            field.push(c);
            p.error = None;
        }
        UserRequest::Erase => {
            field.pop();
        }
        UserRequest::NextField => p.typing_address = !p.typing_address,
        UserRequest::Confirm if p.card_code.is_some() => return Some(()),
        UserRequest::Confirm if p.typing_address && !p.address.trim().is_empty() => {
            p.typing_address = false;
        }
        UserRequest::Confirm if !p.code.trim().is_empty() => return Some(()),
        _ => {}
    }
    None
}

fn plain(text: &str) -> StatusLine {
    StatusLine {
        ok: None,
        text: text.into(),
    }
}

fn pairing_page(p: &Pairing) -> Welcome {
    let press = Picture::Wheel {
        hold: false,
        turn: false,
    };
    let title = tr!("front-pairing-title");
    let mut page = if p.card_code.is_some() {
        Welcome {
            id: "pairing-card",
            title,
            lines: vec![
                plain(&tr!("front-pairing-card")),
                plain(&tr!("front-pairing-card-press")),
            ],
            picture: Some(press),
            ..Welcome::default()
        }
    } else if p.address.is_empty() || p.typing_address {
        let mut lines = Vec::new();
        if p.card_unreadable {
            lines.push(StatusLine {
                ok: Some(false),
                text: tr!("front-pairing-card-bad"),
            });
        } else {
            lines.push(plain(&tr!("front-pairing-ask-clinic")));
            lines.push(plain(&tr!("front-pairing-call-clinic")));
        }
        Welcome {
            id: "pairing-ask-clinic",
            title,
            lines,
            field: p
                .typing_address
                .then(|| (tr!("front-pairing-address-label"), p.address.clone())),
            keys: vec![tr!("front-pairing-keys")],
            ..Welcome::default()
        }
    } else {
        let next = char::from(alphabet()[p.sign]);
        Welcome {
            id: "pairing-code",
            title,
            lines: vec![
                plain(&tr!("front-pairing-code-intro")),
                plain(&tr!("front-pairing-code-how")),
                plain(&tr!("front-pairing-code-back")),
            ],
            field: Some((
                tr!("front-pairing-code-label"),
                format!("{}  [{next}]", spaced_code(&p.code)),
            )),
            picture: Some(Picture::Wheel {
                hold: false,
                turn: true,
            }),
            keys: vec![tr!("front-pairing-keys")],
            ..Welcome::default()
        }
    };
    page.error.clone_from(&p.error);
    page
}

/// A code as the clinic's letter prints it: a dash after the fourth sign.
fn spaced_code(code: &str) -> String {
    let mut out = String::new();
    for (i, c) in code.chars().enumerate() {
        if i == CODE_SIGNS / 2 && c != '-' {
            out.push('-');
        }
        out.push(c);
    }
    out
}

/// `host` or `host:port`; a bare host gets the hub's default port.
pub fn with_default_port(address: &str) -> String {
    let has_port = address
        .rsplit_once(':')
        .is_some_and(|(host, port)| !host.is_empty() && port.parse::<u16>().is_ok());
    if has_port {
        address.to_owned()
    } else {
        format!("{address}:{DEFAULT_HUB_PORT}")
    }
}

/// `s` capitalised and ending with a full stop.
pub(crate) fn sentence(s: &str) -> String {
    let mut out = crate::screen::capitalised(s.trim_end());
    if !out.ends_with(['.', '!', '?']) {
        out.push('.');
    }
    out
}

/// What went wrong while pairing, in words for the patient (the technical reason goes to the
/// log, for the clinic's support).
pub fn pairing_error_words(e: &netlink::pairing::PairError) -> String {
    use netlink::pairing::PairError;
    tracing::warn!("pairing failed: {e}");
    match e {
        PairError::BadCode(why) if why.contains("letters and digits (like") => {
            tr!("front-error-code-length")
        }
        PairError::BadCode(_) => tr!("front-error-code"),
        PairError::Unreachable { .. } => tr!("front-error-unreachable"),
        PairError::Refused(_) => tr!("front-error-refused"),
        PairError::NotAuthentic(_) => tr!("front-error-not-authentic"),
        _ => tr!("front-error-other"),
    }
}

#[cfg(test)]
mod tests;
