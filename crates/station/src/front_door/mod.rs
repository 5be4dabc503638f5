//! What `telerehab` with no arguments shows before a session: the first-run pages.
//!
//! - **Unpaired**: the clinic's address and the pairing code, typed in large type; errors in
//!   plain words; F2 offers a short simulated try-out that is neither recorded nor sent.
//! - **Paired**: today's session (its exercises and minutes) and the device check in plain
//!   words; Space (or a wheel button) starts it once a wheel is ready.
//!
//! [`FrontDoor`] is the pages' state, driven by the patient's keys ([`UserRequest`]) and by
//! what the background work reports (pairing, device checks); it draws nothing itself: its
//! [`FrontDoor::page`] is the [`Welcome`] the window draws. `commands::start` runs it.

pub mod checks;
pub mod today;

use crate::render::window::UserRequest;
use crate::render::{StatusLine, Welcome};
pub use today::TodayPlan;

/// The station port a clinic address gets when none is typed (the hub's default).
pub const DEFAULT_HUB_PORT: u16 = 7878;

/// Longest address or code accepted from the keyboard, characters.
const MAX_TYPED: usize = 80;

/// How the pages ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    /// Start today's session on the real devices.
    Start,
    /// A short simulated try-out.
    TryOut,
    /// The patient closed the window.
    Quit,
}

/// What the caller must do after a key.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Action {
    /// Nothing more.
    None,
    /// Pair with the hub at `address` using `code`, then report with [`FrontDoor::paired`].
    Pair {
        /// `host:port`.
        address: String,
        /// The code as typed.
        code: String,
    },
    /// Close the pages: the outcome is decided.
    Done(Outcome),
}

/// Which field the keys type into on the pairing page.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Focus {
    Address,
    Code,
}

#[derive(Debug, Clone, PartialEq)]
enum Page {
    Pairing {
        address: String,
        code: String,
        focus: Focus,
        error: Option<String>,
    },
    Connecting {
        address: String,
    },
    Today(TodayPlan),
}

/// The first-run pages' state.
#[derive(Debug, Clone)]
pub struct FrontDoor {
    page: Page,
    /// The device check, in plain words (empty until the first check ends).
    devices: Vec<StatusLine>,
    /// A wheel is there and usable: Space may start.
    wheel_ready: bool,
    /// Set once the device check has run.
    checked: bool,
    /// Something about the clinic the patient must know (e.g. an update is required).
    notice: Option<StatusLine>,
    /// A pain at or over the clinic's threshold today: this page instead of today's
    /// session, and nothing starts one ([`crate::checkin::care`]).
    rest_today: Option<Welcome>,
}

impl FrontDoor {
    /// Unpaired: the pairing page, the address filled in when the clinic's installation
    /// named it.
    pub fn unpaired(clinic_address: Option<&str>) -> Self {
        let address = clinic_address.unwrap_or_default().to_owned();
        let focus = if address.is_empty() {
            Focus::Address
        } else {
            Focus::Code
        };
        Self::with_page(Page::Pairing {
            address,
            code: String::new(),
            focus,
            error: None,
        })
    }

    /// Paired: today's session.
    pub fn paired_with(plan: TodayPlan) -> Self {
        Self::with_page(Page::Today(plan))
    }

    fn with_page(page: Page) -> Self {
        Self {
            page,
            devices: Vec::new(),
            wheel_ready: false,
            checked: false,
            notice: None,
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
        self.rest_today.is_some() && matches!(self.page, Page::Today(_))
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

    /// Whether the pairing page is showing (the caller then has nothing to check at the hub).
    pub fn is_pairing(&self) -> bool {
        !matches!(self.page, Page::Today(_))
    }

    /// What pairing came to: today's plan, or what went wrong in plain words.
    pub fn paired(&mut self, result: Result<TodayPlan, String>) {
        let address = match &self.page {
            Page::Connecting { address } => address.clone(),
            _ => String::new(),
        };
        self.page = match result {
            Ok(plan) => {
                self.notice = Some(StatusLine {
                    ok: Some(true),
                    text: format!("This computer is now connected to your clinic ({address})."),
                });
                Page::Today(plan)
            }
            Err(error) => Page::Pairing {
                address,
                code: String::new(),
                focus: Focus::Code,
                error: Some(error),
            },
        };
    }

    /// Act on a key.
    pub fn apply(&mut self, request: UserRequest) -> Action {
        if request == UserRequest::Quit {
            return Action::Done(Outcome::Quit);
        }
        match &mut self.page {
            Page::Pairing {
                address,
                code,
                focus,
                error,
            } => {
                let field = match focus {
                    Focus::Address => address,
                    Focus::Code => code,
                };
                match request {
                    UserRequest::TryOut => return Action::Done(Outcome::TryOut),
                    UserRequest::Typed(c) if field.chars().count() < MAX_TYPED => {
                        field.push(c);
                        *error = None;
                    }
                    UserRequest::Erase => {
                        field.pop();
                    }
                    UserRequest::NextField => {
                        *focus = match focus {
                            Focus::Address => Focus::Code,
                            Focus::Code => Focus::Address,
                        };
                    }
                    UserRequest::Confirm => return self.confirm(),
                    _ => {}
                }
                Action::None
            }
            Page::Connecting { .. } => Action::None,
            Page::Today(_) if self.rest_today.is_some() => Action::None,
            Page::Today(_) => match request {
                UserRequest::TogglePause | UserRequest::Confirm if self.wheel_ready => {
                    Action::Done(Outcome::Start)
                }
                UserRequest::TryOut => Action::Done(Outcome::TryOut),
                _ => Action::None,
            },
        }
    }

    /// Enter on the pairing page: the next field, or connect when both are filled in.
    fn confirm(&mut self) -> Action {
        let Page::Pairing {
            address,
            code,
            focus,
            error,
        } = &mut self.page
        else {
            return Action::None;
        };
        if *focus == Focus::Address || code.trim().is_empty() {
            *focus = if address.trim().is_empty() {
                Focus::Address
            } else {
                Focus::Code
            };
            return Action::None;
        }
        if address.trim().is_empty() {
            *focus = Focus::Address;
            *error = Some("Type the clinic's address first (it is on the clinic's letter).".into());
            return Action::None;
        }
        let address = with_default_port(address.trim());
        let code = code.trim().to_owned();
        self.page = Page::Connecting {
            address: address.clone(),
        };
        Action::Pair { address, code }
    }

    /// The page to draw now.
    pub fn page(&self) -> Welcome {
        match &self.page {
            Page::Pairing {
                address,
                code,
                focus,
                error,
            } => pairing_page(address, code, *focus, error.clone()),
            Page::Connecting { address } => Welcome {
                title: "Connecting to your clinic…".into(),
                lines: vec![plain(&format!("Asking {address} to accept this computer."))],
                keys: vec!["Esc: close".into()],
                ..Welcome::default()
            },
            Page::Today(_) if self.rest_today.is_some() => {
                self.rest_today.clone().unwrap_or_default()
            }
            Page::Today(plan) => self.today_page(plan),
        }
    }

    fn today_page(&self, plan: &TodayPlan) -> Welcome {
        let mut lines = plan.lines();
        lines.extend(self.notice.clone());
        if self.checked {
            lines.extend(self.devices.iter().cloned());
        } else {
            lines.push(plain("Checking the wheel and the arm sensors…"));
        }
        let start = if self.wheel_ready {
            "Space or a wheel button: start"
        } else {
            "Start: once the wheel is ready"
        };
        Welcome {
            title: "Today's session".into(),
            lines,
            keys: vec![start.into(), "F2: try it out".into(), "Esc: close".into()],
            ..Welcome::default()
        }
    }
}

fn plain(text: &str) -> StatusLine {
    StatusLine {
        ok: None,
        text: text.into(),
    }
}

fn pairing_page(address: &str, code: &str, focus: Focus, error: Option<String>) -> Welcome {
    let mut lines = vec![plain(
        "To connect this computer to your clinic, type the address and the pairing code from \
         the clinic's letter.",
    )];
    let field = match focus {
        Focus::Address => ("Clinic address".to_owned(), address.to_owned()),
        Focus::Code => {
            if !address.is_empty() {
                lines.push(plain(&format!("Clinic: {address}   (Tab to change)")));
            }
            ("Pairing code, e.g. 7KQ2-M9XD".to_owned(), code.to_owned())
        }
    };
    Welcome {
        title: "Welcome to telerehab".into(),
        lines,
        field: Some(field),
        error,
        keys: vec![
            "Enter: next / connect".into(),
            "F2: a 1-minute try-out".into(),
            "Esc: close".into(),
        ],
    }
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

/// What went wrong while pairing, in words for the patient (the technical reason follows in
/// brackets for the clinic's support).
pub fn pairing_error_words(e: &netlink::pairing::PairError) -> String {
    use netlink::pairing::PairError;
    match e {
        PairError::BadCode(why) => {
            format!("That is not a pairing code ({why}). Check it against the clinic's letter.")
        }
        PairError::Unreachable { addr, reason } => format!(
            "Cannot reach the clinic at {addr}. Check the internet connection and the address, \
             then press Enter to try again. ({reason})"
        ),
        // The hub's refusal is already written for the patient.
        PairError::Refused(why) => sentence(why),
        PairError::NotAuthentic(why) => format!(
            "The answer did not come from your clinic, so nothing was saved. Check the address \
             and the code. ({why})"
        ),
        other => format!("Pairing did not work ({other}). Ask the clinic's support."),
    }
}

#[cfg(test)]
mod tests;
