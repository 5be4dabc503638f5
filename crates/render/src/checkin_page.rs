//! What the end screen's pages show ([`CheckInPage`]): plain data the check-in
//! (the station's `checkin::CheckInFlow`) builds and the HUD draws (`hud::checkin`).

/// The picture a question is answered on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ScaleKind {
    /// Pain 0–10 under six faces, green (no pain) to red (the worst pain).
    Faces,
    /// Effort 0–10 as bars growing left to right, with Borg's CR10 words.
    Effort,
    /// Too easy, just right, too hard: a thumb down, flat and up.
    Thumbs,
}

/// A question's scale: its picture, the patient's choice so far and the words of each value.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CheckInScale {
    /// The picture.
    pub kind: ScaleKind,
    /// The value chosen (0–10, or 0–2 for the thumbs); `None` until the patient chooses.
    pub choice: Option<u8>,
    /// The words of each value, one per value (11, or 3 for the thumbs).
    pub words: Vec<String>,
    /// The choice in words, large ("8 of 10: Very bad pain"), or the hint to choose.
    pub chosen: String,
}

/// One page of the end screen.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CheckInPage {
    /// The page's stable id (`results`, `pain`, `effort`, `difficulty`, `pain-stop`,
    /// `thanks`), for tests and for speech.
    pub id: &'static str,
    /// The page's one sentence: the question, or the title.
    pub title: String,
    /// The question's scale, on a question page.
    pub scale: Option<CheckInScale>,
    /// Further lines in plain words.
    pub lines: Vec<String>,
    /// The page says to stop and call the clinic (drawn in red with a telephone).
    pub stop: bool,
    /// How to answer: the wheel's moves first, then the keyboard's.
    pub keys: Vec<String>,
}
