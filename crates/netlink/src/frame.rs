//! Frame bodies exchanged between a station and a therapist hub, and their validation.
//!
//! Every body is serialised as JSON inside a frame (see [`crate::codec`]). Unknown JSON fields
//! are ignored on decode so that a newer station can talk to an older hub; fields added after
//! protocol version 1 carry `#[serde(default)]`.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

/// The newest protocol version this crate speaks (a station's [`Hello::protocol_version`]).
/// Version 2 adds the therapist's messages ([`Message`], [`MessageSeen`]); version 3 the
/// clinic's pain settings ([`Care`]); version 4 answers a station's check with the patient's
/// care, unseen messages and current regimen ([`CHECK_NEWS_VERSION`]); the framing (the
/// header's `version`, [`crate::codec::HEADER_VERSION`]) is version 1's.
pub const PROTOCOL_VERSION: u16 = 4;

/// The first protocol version with [`Message`] and [`MessageSeen`] frames: a hub sends a
/// `Message` only on a connection negotiated at this version or above.
pub const MESSAGES_VERSION: u16 = 2;

/// Most characters (not bytes) of a therapist's message text ([`Message::text`]).
pub const MAX_MESSAGE_TEXT_CHARS: usize = 500;

/// The first protocol version with the [`Care`] frame: a hub sends it only on a connection
/// negotiated at this version or above.
pub const CARE_VERSION: u16 = 3;

/// The first protocol version whose station check ([`CHECK_EXERCISE`]) the hub answers with
/// the patient's news before its [`Bye`]: [`Care`], each unseen [`Message`] (oldest first) and
/// the current [`Regimen`]. Below it a check gets the `Bye` alone.
pub const CHECK_NEWS_VERSION: u16 = 4;

/// The pain (0–10) at or over which a station stops the day's training when the clinic has
/// set no other ([`Care::pain_threshold_0_10`]).
pub const DEFAULT_PAIN_THRESHOLD_0_10: u8 = 7;

/// Longest clinic phone number in a [`Care`] frame, bytes.
pub const MAX_PHONE_LEN: usize = 40;

/// The oldest protocol version this crate speaks.
pub const MIN_PROTOCOL_VERSION: u16 = 1;

/// [`ErrorFrame::code`] of a hub that cannot serve any version the station speaks: the
/// station stops retrying and tells the patient the software needs an update.
pub const UPDATE_REQUIRED: &str = "update_required";

/// [`Hello::exercise`] of a station's check (`telerehab doctor --hub`, the first-run page):
/// the hub answers it as any `Hello` (versions, the station's certificate), then at once with a
/// [`Bye`] carrying its clock (at [`CHECK_NEWS_VERSION`] and above, after the patient's news),
/// and stores nothing — no session, so a check never counts as a
/// session done.
pub const CHECK_EXERCISE: &str = "doctor-check";

/// This machine's clock now, ms since the Unix epoch (0 before 1970): what a hub's Bye
/// carries as [`Bye::hub_unix_ms`].
pub fn unix_ms_now() -> u64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_millis() as u64)
}

/// Longest identifier (station, patient, session, regimen id) in bytes.
pub const MAX_ID_LEN: usize = 64;

/// Longest free-text field (exercise, software version, reason) in bytes.
pub const MAX_TEXT_LEN: usize = 256;

/// Longest error message in bytes.
pub const MAX_MESSAGE_LEN: usize = 4096;

/// Largest forward step of a summary's sequence number: a summary's `seq` must be at most
/// `expected + MAX_SEQ_STEP`, where `expected` is the sequence number after the last one
/// stored (0 for an empty session). 2^24 summaries are 19 days at 10 Hz — more than any gap a
/// station can leave by dropping summaries — while a peer jumping as far as it may on every
/// frame needs 2^40 summaries to reach `u64::MAX` and silence the session.
pub const MAX_SEQ_STEP: u64 = 1 << 24;

/// Most entries allowed in [`Summary::extra`].
pub const MAX_EXTRA_ENTRIES: usize = 64;

/// The kind byte of a frame header.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum FrameKind {
    /// Station → hub, first frame of every connection.
    Hello = 1,
    /// Station → hub, one periodic session summary.
    Summary = 2,
    /// Hub → station, cumulative acknowledgement.
    Ack = 3,
    /// Hub → station, a new exercise regimen (validated by the station).
    Regimen = 4,
    /// Either way: orderly end of a session.
    Bye = 5,
    /// Either way: the sender saw a protocol error and closes the connection.
    Error = 6,
    /// Station → hub, first frame of a pairing connection (instead of `Hello`).
    PairStart = 7,
    /// Hub → station, the hub's half of the password-authenticated key exchange.
    PairChallenge = 8,
    /// Station → hub, the station's certificate request, proven with the exchanged key.
    PairFinish = 9,
    /// Hub → station, the station's credential, proven with the exchanged key.
    Paired = 10,
    /// Station → hub, after `Hello`: a session's recording is about to be uploaded.
    UploadStart = 11,
    /// Hub → station: where the upload resumes (bytes held), or that it is complete.
    UploadAt = 12,
    /// Station → hub: bytes of the recording at an offset.
    UploadChunk = 13,
    /// Hub → station (protocol ≥ 2): a message from the therapist to show the patient.
    Message = 14,
    /// Station → hub (protocol ≥ 2): a message was shown on the patient's screen.
    MessageSeen = 15,
    /// Hub → station (protocol ≥ 3): the clinic's pain threshold, phone number and clearance.
    Care = 16,
}

impl FrameKind {
    /// The kind for a header byte, or `None` if the byte names no known kind.
    pub fn from_byte(byte: u8) -> Option<Self> {
        Some(match byte {
            1 => Self::Hello,
            2 => Self::Summary,
            3 => Self::Ack,
            4 => Self::Regimen,
            5 => Self::Bye,
            6 => Self::Error,
            7 => Self::PairStart,
            8 => Self::PairChallenge,
            9 => Self::PairFinish,
            10 => Self::Paired,
            11 => Self::UploadStart,
            12 => Self::UploadAt,
            13 => Self::UploadChunk,
            14 => Self::Message,
            15 => Self::MessageSeen,
            16 => Self::Care,
            _ => return None,
        })
    }

    /// The header byte of this kind.
    pub fn byte(self) -> u8 {
        self as u8
    }
}

impl std::fmt::Display for FrameKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let name = match self {
            Self::Hello => "Hello",
            Self::Summary => "Summary",
            Self::Ack => "Ack",
            Self::Regimen => "Regimen",
            Self::Bye => "Bye",
            Self::Error => "Error",
            Self::PairStart => "PairStart",
            Self::PairChallenge => "PairChallenge",
            Self::PairFinish => "PairFinish",
            Self::Paired => "Paired",
            Self::UploadStart => "UploadStart",
            Self::UploadAt => "UploadAt",
            Self::UploadChunk => "UploadChunk",
            Self::Message => "Message",
            Self::MessageSeen => "MessageSeen",
            Self::Care => "Care",
        };
        f.write_str(name)
    }
}

/// First frame a station sends on every (re)connection.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Hello {
    /// The newest protocol version the station speaks (= [`PROTOCOL_VERSION`] for this crate).
    pub protocol_version: u16,
    /// Identifier of the station (device); becomes a directory name in the hub's store.
    pub station_id: String,
    /// Pseudonymous patient identifier (never a name).
    pub patient_id: String,
    /// Identifier of this session; becomes a file name in the hub's store.
    pub session_id: String,
    /// Exercise name, e.g. `sine-road`.
    pub exercise: String,
    /// Session start, milliseconds since the Unix epoch (station clock).
    pub started_unix_ms: u64,
    /// Station software version, e.g. `telerehab 0.1.0`.
    pub software_version: String,
    /// The oldest protocol version the station speaks; `None` (absent on the wire, as from a
    /// station older than this field) means `protocol_version` only. The station link fills it
    /// in with [`MIN_PROTOCOL_VERSION`] when left `None`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_protocol_version: Option<u16>,
    /// The patient's wheel as the station drives it; `None` (absent on the wire, as from a
    /// station older than this field) when the station did not say.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wheel: Option<WheelInfo>,
}

/// Most torque a [`WheelInfo`] may state, N·m (well above any consumer wheel's motor).
pub const MAX_WHEEL_TORQUE_NM: f64 = 100.0;

/// The patient's force-feedback wheel, as the station tells the hub in its [`Hello`]: what the
/// clinic's prescribe form bounds every torque by.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WheelInfo {
    /// The wheel's model in words, e.g. `Logitech G29` (`unknown wheel …` for a model the
    /// station has no profile for).
    pub model: String,
    /// The motor's rated (peak) torque, N·m: the maker's figure, a measured or entered one, or
    /// the assumed figure of an unknown wheel.
    pub rated_torque_nm: f64,
    /// The most torque the station's safety chain lets this wheel give the patient, in this
    /// configuration (the wheel's usable maximum at its gain, capped by the station's patient
    /// ceiling), N·m.
    pub ceiling_nm: f64,
    /// The model is unknown to the station: its rating is assumed and its ceiling the
    /// conservative one for unknown wheels.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub unknown: bool,
}

impl WheelInfo {
    /// Checks the model's text and that both torques are finite, ceiling within
    /// [0, `rated_torque_nm`] and rating within (0, [`MAX_WHEEL_TORQUE_NM`]].
    pub fn validate(&self) -> Result<(), FieldError> {
        check_text("wheel.model", &self.model, MAX_TEXT_LEN)?;
        if !(self.rated_torque_nm.is_finite()
            && self.rated_torque_nm > 0.0
            && self.rated_torque_nm <= MAX_WHEEL_TORQUE_NM)
        {
            return Err(FieldError(format!(
                "wheel.rated_torque_nm = {}, allowed (0, {MAX_WHEEL_TORQUE_NM}] N·m",
                self.rated_torque_nm
            )));
        }
        if !(self.ceiling_nm.is_finite()
            && self.ceiling_nm >= 0.0
            && self.ceiling_nm <= self.rated_torque_nm)
        {
            return Err(FieldError(format!(
                "wheel.ceiling_nm = {}, allowed [0, rated_torque_nm = {}] N·m",
                self.ceiling_nm, self.rated_torque_nm
            )));
        }
        Ok(())
    }
}

/// One periodic summary of a running session (about every 100 ms).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    /// Session this summary belongs to (equals the connection's [`Hello::session_id`]).
    pub session_id: String,
    /// Sequence number, strictly increasing within a session; the receiver dedups on it.
    pub seq: u64,
    /// Session time of this summary, s (≥ 0).
    pub t_s: f64,
    /// Exercise name.
    pub exercise: String,
    /// Vehicle forward speed, m/s.
    pub speed_m_s: f64,
    /// Current lateral deviation from the road centre, m (signed).
    pub lateral_m: f64,
    /// RMS lateral deviation so far, m (≥ 0).
    pub rms_lateral_m: f64,
    /// Largest |lateral deviation| so far, m (≥ 0).
    pub max_lateral_m: f64,
    /// Percentage of session time within the lane so far, in [0, 100].
    pub pct_in_lane: f64,
    /// Largest |commanded wheel torque| so far, N·m (≥ 0).
    pub max_abs_torque_nm: f64,
    /// 99th percentile of the haptic loop period error so far, µs (≥ 0).
    pub loop_p99_us: f64,
    /// Haptic ticks run so far.
    pub ticks: u64,
    /// Records the station's recorder had to drop so far.
    #[serde(default)]
    pub dropped_records: u64,
    /// Optional further metrics (assist level, joint angles, …), each finite; name → value.
    #[serde(default)]
    pub extra: BTreeMap<String, f64>,
}

/// Cumulative acknowledgement: every summary of `session_id` with sequence ≤ `seq` is stored.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Ack {
    /// Session acknowledged.
    pub session_id: String,
    /// Highest sequence number stored (all lower ones are stored too, or were never sent).
    pub seq: u64,
}

/// A new exercise regimen from the therapist. The text is opaque here: the station parses and
/// validates it against its safety bounds before anything reaches the haptic thread.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Regimen {
    /// Identifier of this regimen (for audit and acknowledgement in logs).
    pub id: String,
    /// Regimen as TOML text.
    pub toml: String,
    /// Who prescribed it, as the clinic names its therapists (their e-mail), for the
    /// station's recordings and report; at most [`MAX_TEXT_LEN`] bytes. Absent from hubs
    /// older than this field.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub prescribed_by: Option<String>,
}

/// Orderly end of a session.
///
/// Station → hub: the session ended; `final_seq` is the last sequence number the station
/// produced (`None` if it produced none). Hub → station (reply): the session file is synced to
/// disk; `final_seq` is the last sequence number stored.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Bye {
    /// Session ending.
    pub session_id: String,
    /// Why it ends, for humans.
    pub reason: String,
    /// Last sequence number produced (station) or stored (hub).
    pub final_seq: Option<u64>,
    /// Station → hub: the session's movement measures, name (unit in the name) → finite
    /// value, computed at its end; at most [`MAX_EXTRA_ENTRIES`]. Empty in the hub's reply and
    /// for a session without measures (absent from the JSON then).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub measures: BTreeMap<String, f64>,
    /// Hub → station: the hub's clock when it answered, ms since the Unix epoch, for the
    /// station to tell its clock difference (`telerehab doctor --hub`). Absent from a
    /// station's Bye and from hubs older than this field.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hub_unix_ms: Option<u64>,
    /// Station → hub: the patient's answers on the end screen (every one optional), if the
    /// session asked. Absent from the hub's reply and from stations older than this field.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub checkin: Option<CheckIn>,
    /// Station → hub: the difficulty the session ran at and why it changed, when its regimen
    /// adapts the difficulty (`[difficulty]`). Absent otherwise, from the hub's reply and
    /// from stations older than this field.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub difficulty: Option<DifficultyChange>,
    /// Station → hub: each exercise's own results, in course order; at most
    /// [`MAX_EXERCISE_RESULTS`]. Empty in the hub's reply and from stations older than this
    /// field (absent from the JSON then).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub exercises: Vec<ExerciseResult>,
}

/// The difficulty a session ran at (its regimen's `[difficulty]` adapting it), in a Bye.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DifficultyChange {
    /// The difficulty the session ran at, in [0, 1].
    pub difficulty: f64,
    /// The change from the session before, in [−1, 1] (0 for the first session).
    pub change: f64,
    /// Why, in words, e.g. `success 82 % above the 70 % target: +0.05`; at most
    /// [`MAX_TEXT_LEN`] bytes.
    pub reason: String,
    /// The session's success rate, in [0, 1], when it ran long enough to tell.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub success_rate: Option<f64>,
    /// The same why as [`DifficultyChange::reason`], for words in any language; absent from
    /// stations older than this field.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub why: Option<DifficultyWhy>,
}

/// Why a session's difficulty was chosen, for a clinician's words in any language (the
/// console's `progress-difficulty-why-<code>`, `progress-difficulty-held-<held_at>`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DifficultyWhy {
    /// One of [`DifficultyWhy::CODES`].
    pub code: String,
    /// The last session's success, %, for the `success-*` codes.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub success_pct: Option<f64>,
    /// The therapist's target success, %, for the `success-*` codes.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub target_pct: Option<f64>,
    /// `highest` or `lowest` when the therapist's bound held the step (the difficulty is that
    /// bound).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub held_at: Option<String>,
}

impl DifficultyWhy {
    /// Every code: adaptation off, the first session (at the therapist's start, or midway
    /// between the bounds), the last session's success above, below or at the target, no
    /// success rate (held), and the patient's "too hard" / "too easy".
    pub const CODES: &'static [&'static str] = &[
        "adapt-off",
        "first-start",
        "first-midway",
        "success-above",
        "success-below",
        "success-at",
        "no-rate",
        "felt-too-hard",
        "felt-too-easy",
    ];

    /// Checks the code, the percentages and the bound named.
    pub fn validate(&self) -> Result<(), FieldError> {
        if !Self::CODES.contains(&self.code.as_str()) {
            return Err(FieldError(format!(
                "difficulty.why.code {:?} is not one of {}",
                self.code.chars().take(40).collect::<String>(),
                Self::CODES.join(", ")
            )));
        }
        for (name, v) in [
            ("success_pct", self.success_pct),
            ("target_pct", self.target_pct),
        ] {
            if let Some(v) = v
                && !(v.is_finite() && (0.0..=100.0).contains(&v))
            {
                return Err(FieldError(format!(
                    "difficulty.why.{name} is {v}, allowed 0 to 100"
                )));
            }
        }
        match self.held_at.as_deref() {
            None | Some("highest" | "lowest") => Ok(()),
            Some(other) => Err(FieldError(format!(
                "difficulty.why.held_at {:?} is not highest or lowest",
                other.chars().take(40).collect::<String>()
            ))),
        }
    }
}

impl DifficultyChange {
    /// Checks every field's range; the message names the field.
    pub fn validate(&self) -> Result<(), FieldError> {
        let check = |name: &str, v: f64, lo: f64, hi: f64| {
            if v.is_finite() && (lo..=hi).contains(&v) {
                Ok(())
            } else {
                Err(FieldError(format!("{name} is {v}, allowed {lo} to {hi}")))
            }
        };
        check("difficulty.difficulty", self.difficulty, 0.0, 1.0)?;
        check("difficulty.change", self.change, -1.0, 1.0)?;
        if let Some(r) = self.success_rate {
            check("difficulty.success_rate", r, 0.0, 1.0)?;
        }
        check_text("difficulty.reason", &self.reason, MAX_TEXT_LEN)?;
        self.why.as_ref().map_or(Ok(()), DifficultyWhy::validate)
    }
}

/// Most exercises a [`Bye`] reports results of (a regimen holds at most 60).
pub const MAX_EXERCISE_RESULTS: usize = 60;

/// Longest an exercise's prescription or active time may be in a [`Bye`], s (a day).
pub const MAX_EXERCISE_S: f64 = 86_400.0;

/// One exercise's own results in a session ([`Bye::exercises`]).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct ExerciseResult {
    /// Its place in the session's course, from 0.
    pub index: u32,
    /// Its kind, the regimen's short name (`sine-road`, `dial-sine`).
    pub kind: String,
    /// Its name as the patient sees it (`Sine road`).
    pub name: String,
    /// The prescribed duration, s.
    pub prescribed_s: f64,
    /// The time it ran, s (the patient's pauses left out).
    pub active_s: f64,
    /// Its scores and movement measures, name (unit in the name) → finite value; at most
    /// [`MAX_EXTRA_ENTRIES`].
    #[serde(default)]
    pub scores: BTreeMap<String, f64>,
    /// The standard assessment this exercise is a part of (its `kind` then starts
    /// `assessment-`); absent for an exercise, and from stations older than this field.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub assessment: Option<AssessmentTag>,
}

/// Which standard assessment an exercise result belongs to (the station's
/// `exercises::assessment`): its protocol version and the seed its steps were drawn from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct AssessmentTag {
    /// The protocol's version, from 1.
    pub protocol: u32,
    /// The seed the steps' times and sides were drawn from.
    pub seed: u32,
}

impl ExerciseResult {
    /// Checks the fields; the message names the exercise and the field.
    pub fn validate(&self) -> Result<(), FieldError> {
        let at = format!("exercises[{}]", self.index);
        check_id(&format!("{at}.kind"), &self.kind)?;
        check_text(&format!("{at}.name"), &self.name, MAX_ID_LEN)?;
        if let Some(tag) = &self.assessment {
            if tag.protocol == 0 {
                return Err(FieldError(format!(
                    "{at}.assessment.protocol is 0, allowed 1 or more"
                )));
            }
            if !self.kind.starts_with("assessment-") {
                return Err(FieldError(format!(
                    "{at}.assessment is set on kind {:?}, allowed only on an assessment-* kind",
                    self.kind
                )));
            }
        }
        for (name, v) in [
            ("prescribed_s", self.prescribed_s),
            ("active_s", self.active_s),
        ] {
            if !(0.0..=MAX_EXERCISE_S).contains(&v) {
                return Err(FieldError(format!(
                    "{at}.{name} is {v}, allowed 0 to {MAX_EXERCISE_S}"
                )));
            }
        }
        check_named_values(&format!("{at}.scores"), &self.scores)
    }
}

/// Checks a [`Bye`]'s exercise results: at most [`MAX_EXERCISE_RESULTS`], each valid, their
/// indices distinct; a session runs one standard assessment, so its tagged parts share one
/// tag and each part appears once (the hub files and exports them as one assessment).
pub fn check_exercise_results(exercises: &[ExerciseResult]) -> Result<(), FieldError> {
    if exercises.len() > MAX_EXERCISE_RESULTS {
        return Err(FieldError(format!(
            "exercises has {} entries, at most {MAX_EXERCISE_RESULTS} allowed",
            exercises.len()
        )));
    }
    let mut seen = std::collections::BTreeSet::new();
    let mut parts = std::collections::BTreeSet::new();
    let mut tag = None;
    for e in exercises {
        e.validate()?;
        if !seen.insert(e.index) {
            return Err(FieldError(format!("exercises[{}] appears twice", e.index)));
        }
        let Some(this) = e.assessment else { continue };
        if *tag.get_or_insert(this) != this {
            return Err(FieldError(format!(
                "exercises[{}].assessment differs from the session's first assessment part's: \
                 one session runs one assessment",
                e.index
            )));
        }
        if !parts.insert(e.kind.as_str()) {
            return Err(FieldError(format!(
                "exercises[{}] is a second {:?} part of the session's assessment",
                e.index, e.kind
            )));
        }
    }
    Ok(())
}

/// Highest answer of a 0–10 check-in question ([`CheckIn::pain_0_10`], [`CheckIn::tiredness_0_10`]).
pub const MAX_CHECKIN_SCORE: u8 = 10;

/// The answers [`CheckIn::difficulty`] may take.
pub const CHECKIN_DIFFICULTIES: [&str; 3] = ["too_easy", "about_right", "too_hard"];

/// The patient's answers to the end screen's three optional questions (`None`: skipped).
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct CheckIn {
    /// Pain now, 0 (none) to 10 (worst imaginable).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pain_0_10: Option<u8>,
    /// Tiredness now, 0 (not tired) to 10 (exhausted).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tiredness_0_10: Option<u8>,
    /// How the session felt: one of [`CHECKIN_DIFFICULTIES`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub difficulty: Option<String>,
}

impl CheckIn {
    /// True when every question was skipped.
    pub fn is_empty(&self) -> bool {
        self.pain_0_10.is_none() && self.tiredness_0_10.is_none() && self.difficulty.is_none()
    }

    /// Checks every answer is in its range; the message names the field.
    pub fn validate(&self) -> Result<(), FieldError> {
        for (name, v) in [
            ("checkin.pain_0_10", self.pain_0_10),
            ("checkin.tiredness_0_10", self.tiredness_0_10),
        ] {
            if let Some(v) = v
                && v > MAX_CHECKIN_SCORE
            {
                return Err(FieldError(format!(
                    "{name} is {v}, allowed 0 to {MAX_CHECKIN_SCORE}"
                )));
            }
        }
        if let Some(d) = &self.difficulty
            && !CHECKIN_DIFFICULTIES.contains(&d.as_str())
        {
            return Err(FieldError(format!(
                "checkin.difficulty is {:?}, allowed one of {}",
                printable(d, 32),
                CHECKIN_DIFFICULTIES.join(", ")
            )));
        }
        Ok(())
    }
}

/// The sender found a protocol error and is closing the connection.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct ErrorFrame {
    /// What went wrong, for humans.
    pub message: String,
    /// A machine-readable reason, absent for an ordinary protocol error. [`UPDATE_REQUIRED`]
    /// is not retriable: the station stops reconnecting.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub code: Option<String>,
}

/// Bytes of one SPAKE2 (Ed25519) message: a side byte and a 32-byte group element.
pub const PAKE_MESSAGE_LEN: usize = 33;
/// Bytes of an HMAC-SHA-256 tag.
pub const MAC_LEN: usize = 32;
/// Most bytes of a PEM text in a pairing frame.
pub const MAX_PEM_LEN: usize = 16 * 1024;

/// Station → hub, the first frame of a pairing connection. The pairing code `XXXX-XXXX` has a
/// public half, `code_id` (which code), and a secret half that never crosses the wire: it is
/// the password of a SPAKE2 exchange whose first message is `pake` (see `PROTOCOL.md`).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct PairStart {
    /// The public half of the pairing code, e.g. `7KQ2`.
    pub code_id: String,
    /// The station's SPAKE2 message, lowercase hex.
    pub pake: String,
}

/// Hub → station: the hub's SPAKE2 message, lowercase hex.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct PairChallenge {
    /// The hub's SPAKE2 message, lowercase hex.
    pub pake: String,
}

/// Station → hub: a certificate signing request for the station's own key (which never leaves
/// the station), with `mac` = HMAC-SHA-256 under the exchanged key over the request and the
/// hub's TLS certificate as the station saw it (so a relay in the middle is found out).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct PairFinish {
    /// PKCS#10 certificate signing request, PEM.
    pub csr_pem: String,
    /// HMAC-SHA-256 tag, lowercase hex.
    pub mac: String,
}

/// Hub → station: the station's credential, proven with the exchanged key.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Paired {
    /// The identity the hub gave this station (its certificate names it).
    pub station_id: String,
    /// The pseudonymous patient the station speaks for.
    pub patient_id: String,
    /// The clinic's CA certificate, PEM: the only root the station trusts from now on.
    pub ca_pem: String,
    /// The station's certificate, PEM, signed by the CA.
    pub cert_pem: String,
    /// The name the hub's certificate carries, to check on every connection.
    pub server_name: String,
    /// HMAC-SHA-256 tag over all of the above under the exchanged key, lowercase hex.
    pub mac: String,
    /// The patient's pseudonym as the clinic knows it (`P-0042`), for the station to name
    /// its sessions by. Not under `mac` (older stations check the MAC without it): the
    /// connection's TLS, whose certificate the MAC proves, keeps it intact. Absent from hubs
    /// older than this field.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub patient_pseudonym: Option<String>,
}

/// Largest recording a station may upload, bytes (an hour of session is about 2 GB today).
pub const MAX_RECORDING_BYTES: u64 = 16 << 30;
/// Most raw bytes in one [`UploadChunk`].
pub const MAX_CHUNK_BYTES: usize = 32 * 1024;
/// Most base64 characters in one [`UploadChunk`] (`MAX_CHUNK_BYTES` encoded).
pub const MAX_CHUNK_BASE64_LEN: usize = MAX_CHUNK_BYTES.div_ceil(3) * 4;

/// Station → hub, after `Hello` on a connection of that session: the session's recording
/// (`size_bytes`, SHA-256 `sha256`) follows. The hub answers [`UploadAt`] with the offset to
/// resume from (bytes it already holds of this very file).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct UploadStart {
    /// The session recorded (the connection's).
    pub session_id: String,
    /// The file's size, bytes.
    pub size_bytes: u64,
    /// Lowercase hex SHA-256 of the whole file.
    pub sha256: String,
}

/// Hub → station: the hub holds `offset` bytes; `complete` once the whole file arrived and its
/// SHA-256 matched (then the recording is stored for the console's replay).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct UploadAt {
    /// The session.
    pub session_id: String,
    /// Bytes the hub holds, from the start of the file.
    pub offset: u64,
    /// The upload is complete and verified.
    pub complete: bool,
}

/// Station → hub: bytes of the recording starting at `offset` (which must be what the hub
/// said it holds), base64 (standard alphabet, padded).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct UploadChunk {
    /// The session.
    pub session_id: String,
    /// Where these bytes start in the file.
    pub offset: u64,
    /// The bytes, base64, at most [`MAX_CHUNK_BYTES`] decoded.
    pub data: String,
}

/// Hub → station, after `Hello` on a connection negotiated at [`MESSAGES_VERSION`] or above:
/// a message from the therapist, shown to the patient on the start card of the next session.
/// The hub sends every message the station has not yet reported seen, oldest first, on each
/// such connection; the station keeps each once (by `id`).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Message {
    /// The message's identifier at the hub.
    pub id: String,
    /// Plain text: 1 to [`MAX_MESSAGE_TEXT_CHARS`] characters, no control characters, not
    /// only spaces.
    pub text: String,
    /// When the therapist wrote it (hub clock), ms since the Unix epoch.
    pub sent_unix_ms: u64,
}

/// Station → hub: message `id` was shown on the patient's screen at `seen_unix_ms` (station
/// clock). Sent only for a message a hub sent, so only to a hub that speaks version 2; sent
/// again on later connections until a `Bye` of the hub confirms the connection it went on.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct MessageSeen {
    /// The message shown ([`Message::id`]).
    pub id: String,
    /// When it was shown, ms since the Unix epoch (station clock).
    pub seen_unix_ms: u64,
}

/// Hub → station, after `Hello` on a connection negotiated at [`CARE_VERSION`] or above, and
/// again whenever it changes: what the clinic says about pain. A pain answered at or over
/// `pain_threshold_0_10` ends the session on a page that says to rest and call
/// `clinic_phone`, and the station offers no session for the rest of that day unless the
/// therapist clears the patient (`cleared_unix_ms` later than the pain).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Care {
    /// Pain at or over this, 0–10 (1 to [`MAX_CHECKIN_SCORE`]), stops the day's training.
    pub pain_threshold_0_10: u8,
    /// The clinic's phone number for patients, as the clinic writes it (digits, spaces, `+`,
    /// `-`, `/`, `(`, `)`, `.`; at most [`MAX_PHONE_LEN`] bytes); absent: none set.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub clinic_phone: Option<String>,
    /// When the therapist last cleared the patient to train again after a pain stop, ms
    /// since the Unix epoch (hub clock); absent: never.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cleared_unix_ms: Option<u64>,
}

/// Checks a clinic phone number: not empty, at most [`MAX_PHONE_LEN`] bytes, only digits,
/// spaces and `+ - / ( ) .`, with at least three digits. The message names the problem.
pub fn check_phone(phone: &str) -> Result<(), FieldError> {
    if phone.len() > MAX_PHONE_LEN {
        return Err(FieldError(format!(
            "the phone number is too long: {} bytes, at most {MAX_PHONE_LEN}",
            phone.len()
        )));
    }
    if let Some(c) = phone
        .chars()
        .find(|c| !(c.is_ascii_digit() || " +-/().".contains(*c)))
    {
        return Err(FieldError(format!(
            "the phone number contains {c:?}; use digits, spaces and + - / ( ) . only"
        )));
    }
    if phone.chars().filter(char::is_ascii_digit).count() < 3 {
        return Err(FieldError(format!(
            "the phone number {phone:?} has fewer than three digits"
        )));
    }
    Ok(())
}

impl Care {
    /// Checks the threshold (1 to [`MAX_CHECKIN_SCORE`]) and the phone number
    /// ([`check_phone`]).
    pub fn validate(&self) -> Result<(), FieldError> {
        if !(1..=MAX_CHECKIN_SCORE).contains(&self.pain_threshold_0_10) {
            return Err(FieldError(format!(
                "pain_threshold_0_10 = {}, allowed [1, {MAX_CHECKIN_SCORE}]",
                self.pain_threshold_0_10
            )));
        }
        match &self.clinic_phone {
            Some(p) => check_phone(p),
            None => Ok(()),
        }
    }
}

/// Checks a therapist's message text: 1 to [`MAX_MESSAGE_TEXT_CHARS`] characters (counted
/// as characters, not bytes), not only spaces, no control characters (a line break is one:
/// the text is one paragraph). The message names the problem.
pub fn check_message_text(text: &str) -> Result<(), FieldError> {
    if text.trim().is_empty() {
        return Err(FieldError("the message is empty".into()));
    }
    let chars = text.chars().count();
    if chars > MAX_MESSAGE_TEXT_CHARS {
        return Err(FieldError(format!(
            "the message is too long: {chars} characters, at most {MAX_MESSAGE_TEXT_CHARS}"
        )));
    }
    if let Some(c) = text.chars().find(|c| c.is_control()) {
        return Err(FieldError(format!(
            "the message contains a control character ({:?}); write plain text on one line",
            c
        )));
    }
    Ok(())
}

/// Any frame of the protocol.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum Frame {
    /// See [`Hello`].
    Hello(Hello),
    /// See [`Summary`].
    Summary(Summary),
    /// See [`Ack`].
    Ack(Ack),
    /// See [`Regimen`].
    Regimen(Regimen),
    /// See [`Bye`].
    Bye(Bye),
    /// See [`ErrorFrame`].
    Error(ErrorFrame),
    /// See [`PairStart`].
    PairStart(PairStart),
    /// See [`PairChallenge`].
    PairChallenge(PairChallenge),
    /// See [`PairFinish`].
    PairFinish(PairFinish),
    /// See [`Paired`].
    Paired(Paired),
    /// See [`UploadStart`].
    UploadStart(UploadStart),
    /// See [`UploadAt`].
    UploadAt(UploadAt),
    /// See [`UploadChunk`].
    UploadChunk(UploadChunk),
    /// See [`Message`].
    Message(Message),
    /// See [`MessageSeen`].
    MessageSeen(MessageSeen),
    /// See [`Care`].
    Care(Care),
}

impl Frame {
    /// The header kind of this frame.
    pub fn kind(&self) -> FrameKind {
        match self {
            Self::Hello(_) => FrameKind::Hello,
            Self::Summary(_) => FrameKind::Summary,
            Self::Ack(_) => FrameKind::Ack,
            Self::Regimen(_) => FrameKind::Regimen,
            Self::Bye(_) => FrameKind::Bye,
            Self::Error(_) => FrameKind::Error,
            Self::PairStart(_) => FrameKind::PairStart,
            Self::PairChallenge(_) => FrameKind::PairChallenge,
            Self::PairFinish(_) => FrameKind::PairFinish,
            Self::Paired(_) => FrameKind::Paired,
            Self::UploadStart(_) => FrameKind::UploadStart,
            Self::UploadAt(_) => FrameKind::UploadAt,
            Self::UploadChunk(_) => FrameKind::UploadChunk,
            Self::Message(_) => FrameKind::Message,
            Self::MessageSeen(_) => FrameKind::MessageSeen,
            Self::Care(_) => FrameKind::Care,
        }
    }

    /// Checks the body's fields; the message names the offending field and its allowed range.
    pub fn validate(&self) -> Result<(), FieldError> {
        match self {
            Self::Hello(h) => h.validate(),
            Self::Summary(s) => s.validate(),
            Self::Ack(a) => check_id("session_id", &a.session_id),
            Self::Regimen(r) => {
                check_id("id", &r.id)?;
                match &r.prescribed_by {
                    Some(by) => check_text("prescribed_by", by, MAX_TEXT_LEN),
                    None => Ok(()),
                }
            }
            Self::Bye(b) => {
                check_id("session_id", &b.session_id)?;
                check_text("reason", &b.reason, MAX_TEXT_LEN)?;
                if let Some(c) = &b.checkin {
                    c.validate()?;
                }
                if let Some(d) = &b.difficulty {
                    d.validate()?;
                }
                check_exercise_results(&b.exercises)?;
                check_named_values("measures", &b.measures)
            }
            Self::Error(e) => {
                if let Some(code) = &e.code {
                    check_id("code", code)?;
                }
                check_text("message", &e.message, MAX_MESSAGE_LEN)
            }
            Self::PairStart(p) => {
                check_id("code_id", &p.code_id)?;
                check_hex("pake", &p.pake, PAKE_MESSAGE_LEN)
            }
            Self::PairChallenge(p) => check_hex("pake", &p.pake, PAKE_MESSAGE_LEN),
            Self::PairFinish(p) => {
                check_text("csr_pem", &p.csr_pem.replace(['\n', '\r'], ""), MAX_PEM_LEN)?;
                check_hex("mac", &p.mac, MAC_LEN)
            }
            Self::Paired(p) => {
                check_id("station_id", &p.station_id)?;
                check_id("patient_id", &p.patient_id)?;
                check_text("server_name", &p.server_name, MAX_TEXT_LEN)?;
                if let Some(pseudonym) = &p.patient_pseudonym {
                    check_text("patient_pseudonym", pseudonym, MAX_ID_LEN)?;
                }
                for (name, pem) in [("ca_pem", &p.ca_pem), ("cert_pem", &p.cert_pem)] {
                    check_text(name, &pem.replace(['\n', '\r'], ""), MAX_PEM_LEN)?;
                }
                check_hex("mac", &p.mac, MAC_LEN)
            }
            Self::UploadStart(u) => {
                check_id("session_id", &u.session_id)?;
                check_hex("sha256", &u.sha256, 32)?;
                if u.size_bytes == 0 || u.size_bytes > MAX_RECORDING_BYTES {
                    return Err(FieldError(format!(
                        "size_bytes is {}, allowed 1 to {MAX_RECORDING_BYTES}",
                        u.size_bytes
                    )));
                }
                Ok(())
            }
            Self::UploadAt(u) => check_id("session_id", &u.session_id),
            Self::UploadChunk(c) => {
                check_id("session_id", &c.session_id)?;
                if c.data.is_empty() || c.data.len() > MAX_CHUNK_BASE64_LEN {
                    return Err(FieldError(format!(
                        "data has {} base64 bytes, allowed 1 to {MAX_CHUNK_BASE64_LEN}",
                        c.data.len()
                    )));
                }
                Ok(())
            }
            Self::Message(m) => {
                check_id("id", &m.id)?;
                check_message_text(&m.text).map_err(|e| FieldError(format!("text: {e}")))
            }
            Self::MessageSeen(m) => check_id("id", &m.id),
            Self::Care(c) => c.validate(),
        }
    }
}

/// A frame field outside what the protocol allows, or a version range nobody can serve; the
/// message names the field and its allowed range (it is what the peer is told).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct FieldError(pub String);

impl From<FieldError> for String {
    /// The message, for an answer or a log line.
    fn from(e: FieldError) -> Self {
        e.0
    }
}

impl Hello {
    /// The range of protocol versions the station speaks, oldest and newest.
    pub fn versions(&self) -> (u16, u16) {
        (
            self.min_protocol_version.unwrap_or(self.protocol_version),
            self.protocol_version,
        )
    }

    /// The newest version both the station and this crate speak, or why there is none.
    pub fn negotiate(&self) -> Result<u16, FieldError> {
        self.negotiate_with(MIN_PROTOCOL_VERSION)
    }

    /// The newest version both the station and a hub serving `hub_min`..=[`PROTOCOL_VERSION`]
    /// speak (`hub_min` above [`MIN_PROTOCOL_VERSION`] only in tests playing a newer hub), or
    /// why there is none, in words the patient is shown as they are.
    pub fn negotiate_with(&self, hub_min: u16) -> Result<u16, FieldError> {
        let (min, max) = self.versions();
        let hub_min = hub_min.max(MIN_PROTOCOL_VERSION);
        let best = max.min(PROTOCOL_VERSION);
        if best >= min.max(hub_min) {
            return Ok(best);
        }
        Err(FieldError(if max < hub_min {
            format!(
                "update required: this station speaks link protocol {max}, the hub needs \
                 ≥ {hub_min} — install the newest telerehab package"
            )
        } else {
            format!(
                "update required: this station needs link protocol ≥ {min}, the hub speaks \
                 at most {PROTOCOL_VERSION} — the clinic must install the newest telerehab \
                 package on its hub"
            )
        }))
    }

    /// Checks every field (identifiers are safe file names; see [`check_id`]). The version
    /// range need only be well formed here; whether it can be served is [`Self::negotiate`].
    pub fn validate(&self) -> Result<(), FieldError> {
        let (min, max) = self.versions();
        if min == 0 || min > max {
            return Err(FieldError(format!(
                "protocol versions {min}..={max}: min_protocol_version must be in [1, \
                 protocol_version]"
            )));
        }
        check_id("station_id", &self.station_id)?;
        check_id("patient_id", &self.patient_id)?;
        check_id("session_id", &self.session_id)?;
        check_text("exercise", &self.exercise, MAX_TEXT_LEN)?;
        check_text("software_version", &self.software_version, MAX_TEXT_LEN)?;
        self.wheel.as_ref().map_or(Ok(()), WheelInfo::validate)
    }
}

impl Summary {
    /// A plausible summary of a sine-road session at `seq` (t = seq × 0.1 s): for examples,
    /// tests and load generators.
    pub fn example(session_id: &str, seq: u64) -> Self {
        Self {
            session_id: session_id.to_owned(),
            seq,
            t_s: seq as f64 * 0.1,
            exercise: "sine-road".to_owned(),
            speed_m_s: 12.5,
            lateral_m: -0.25,
            rms_lateral_m: 0.31,
            max_lateral_m: 0.9,
            pct_in_lane: 97.5,
            max_abs_torque_nm: 1.2,
            loop_p99_us: 45.0,
            ticks: seq.saturating_mul(100),
            dropped_records: 0,
            extra: BTreeMap::new(),
        }
    }

    /// Checks every field: identifiers, finiteness and the documented ranges.
    pub fn validate(&self) -> Result<(), FieldError> {
        check_id("session_id", &self.session_id)?;
        check_text("exercise", &self.exercise, MAX_TEXT_LEN)?;
        let fields = [
            ("t_s", self.t_s, 0.0, f64::MAX),
            ("speed_m_s", self.speed_m_s, f64::MIN, f64::MAX),
            ("lateral_m", self.lateral_m, f64::MIN, f64::MAX),
            ("rms_lateral_m", self.rms_lateral_m, 0.0, f64::MAX),
            ("max_lateral_m", self.max_lateral_m, 0.0, f64::MAX),
            ("pct_in_lane", self.pct_in_lane, 0.0, 100.0),
            ("max_abs_torque_nm", self.max_abs_torque_nm, 0.0, f64::MAX),
            ("loop_p99_us", self.loop_p99_us, 0.0, f64::MAX),
        ];
        for (name, value, lo, hi) in fields {
            if !value.is_finite() {
                return Err(FieldError(format!("{name} is {value}, must be finite")));
            }
            if value < lo || value > hi {
                return Err(FieldError(format!(
                    "{name} is {value}, allowed range [{lo}, {hi}]"
                )));
            }
        }
        check_named_values("extra", &self.extra)
    }
}

/// A map of named values (a summary's `extra`, a Bye's `measures`): at most
/// [`MAX_EXTRA_ENTRIES`], printable names of at most [`MAX_ID_LEN`] bytes, finite values.
pub(crate) fn check_named_values(
    field: &str,
    values: &BTreeMap<String, f64>,
) -> Result<(), FieldError> {
    if values.len() > MAX_EXTRA_ENTRIES {
        return Err(FieldError(format!(
            "{field} has {} entries, at most {MAX_EXTRA_ENTRIES} allowed",
            values.len()
        )));
    }
    for (key, value) in values {
        check_text(&format!("{field} key"), key, MAX_ID_LEN)?;
        if !value.is_finite() {
            return Err(FieldError(format!(
                "{field}[{key:?}] is {value}, must be finite"
            )));
        }
    }
    Ok(())
}

/// The highest sequence number a summary may carry when `last` is the last one stored (or
/// produced) in its session, `None` for none: `last + 1 + MAX_SEQ_STEP`, or `MAX_SEQ_STEP`.
pub fn max_next_seq(last: Option<u64>) -> u64 {
    last.map_or(0, |l| l.saturating_add(1))
        .saturating_add(MAX_SEQ_STEP)
}

/// Checks an identifier: 1 to [`MAX_ID_LEN`] bytes of ASCII letters, digits, `_`, `-`, `.`,
/// not starting with `.`. Identifiers become file and directory names in the hub's store, so
/// this is what keeps a hostile peer from writing outside it.
pub fn check_id(name: &str, value: &str) -> Result<(), FieldError> {
    if value.is_empty() || value.len() > MAX_ID_LEN {
        return Err(FieldError(format!(
            "{name} has {} bytes, allowed 1 to {MAX_ID_LEN}",
            value.len()
        )));
    }
    if value.starts_with('.') {
        return Err(FieldError(format!(
            "{name} {value:?} must not start with '.'"
        )));
    }
    if let Some(bad) = value
        .chars()
        .find(|c| !(c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.')))
    {
        return Err(FieldError(format!(
            "{name} {value:?} contains {bad:?}; allowed are ASCII letters, digits, '_', '-', '.'"
        )));
    }
    Ok(())
}

/// `text` with control characters replaced by spaces, cut to at most `max` bytes on a
/// character boundary: fit for a free-text frame field.
pub(crate) fn printable(text: &str, max: usize) -> String {
    let mut out = String::with_capacity(text.len().min(max));
    for c in text.chars().map(|c| if c.is_control() { ' ' } else { c }) {
        if out.len() + c.len_utf8() > max {
            break;
        }
        out.push(c);
    }
    out
}

fn check_hex(name: &str, value: &str, bytes: usize) -> Result<(), FieldError> {
    if value.len() != 2 * bytes || !value.bytes().all(|b| b.is_ascii_hexdigit()) {
        return Err(FieldError(format!(
            "{name} must be {bytes} bytes as {} hex digits",
            2 * bytes
        )));
    }
    Ok(())
}

fn check_text(name: &str, value: &str, max: usize) -> Result<(), FieldError> {
    if value.len() > max {
        return Err(FieldError(format!(
            "{name} has {} bytes, at most {max} allowed",
            value.len()
        )));
    }
    if value.chars().any(char::is_control) {
        return Err(FieldError(format!("{name} contains control characters")));
    }
    Ok(())
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A valid summary for tests.
    pub(crate) fn summary(session_id: &str, seq: u64) -> Summary {
        Summary::example(session_id, seq)
    }

    #[test]
    fn ids_with_path_separators_or_leading_dot_are_rejected() {
        for bad in [
            "",
            "..",
            ".hidden",
            "a/b",
            "a\\b",
            "é",
            "a b",
            &"x".repeat(65),
        ] {
            assert!(check_id("station_id", bad).is_err(), "{bad:?} accepted");
        }
        for good in ["st-01", "session_2026.11.21", "A_b-9", &"x".repeat(64)] {
            assert!(check_id("station_id", good).is_ok(), "{good:?} rejected");
        }
    }

    #[test]
    fn summary_with_nan_or_out_of_range_field_names_the_field() {
        let mut s = summary("s1", 1);
        s.rms_lateral_m = f64::NAN;
        assert!(s.validate().unwrap_err().0.contains("rms_lateral_m"));
        let mut s = summary("s1", 1);
        s.pct_in_lane = 100.5;
        assert!(s.validate().unwrap_err().0.contains("pct_in_lane"));
        let mut s = summary("s1", 1);
        s.extra.insert("assist_level".into(), f64::INFINITY);
        assert!(s.validate().unwrap_err().0.contains("assist_level"));
        assert!(summary("s1", 1).validate().is_ok());
    }

    #[test]
    fn printable_cuts_on_char_boundary_and_removes_control_characters() {
        assert_eq!(printable("a\nbé", 5), "a bé");
        assert_eq!(printable("a\nbé", 4), "a b");
    }

    #[test]
    fn hello_with_other_protocol_version_cannot_be_negotiated() {
        let h = Hello {
            protocol_version: PROTOCOL_VERSION + 1,
            station_id: "st".into(),
            patient_id: "p".into(),
            session_id: "s".into(),
            exercise: "sine-road".into(),
            started_unix_ms: 0,
            software_version: "x".into(),
            min_protocol_version: None,
            wheel: None,
        };
        assert!(h.validate().is_ok());
        assert!(h.negotiate().unwrap_err().0.contains("update required"));
        let h = Hello {
            min_protocol_version: Some(1),
            ..h
        };
        assert_eq!(h.negotiate(), Ok(PROTOCOL_VERSION));
        // A version-1 station (before messages) is served at 1: it is sent no Message.
        let v1 = Hello {
            protocol_version: 1,
            min_protocol_version: None,
            ..h.clone()
        };
        assert_eq!(v1.negotiate(), Ok(1));
        assert!(v1.negotiate().unwrap() < MESSAGES_VERSION);
        let h = Hello {
            min_protocol_version: Some(PROTOCOL_VERSION + 2),
            ..h
        };
        assert!(h.validate().unwrap_err().0.contains("min_protocol_version"));
    }

    #[test]
    fn summary_from_an_older_station_without_optional_fields_decodes() {
        let json = r#"{"session_id":"s","seq":3,"t_s":0.3,"exercise":"e","speed_m_s":1.0,
            "lateral_m":0.0,"rms_lateral_m":0.0,"max_lateral_m":0.0,"pct_in_lane":100.0,
            "max_abs_torque_nm":0.0,"loop_p99_us":1.0,"ticks":300,"future_field":[1,2]}"#;
        let s: Summary = serde_json::from_str(json).unwrap();
        assert_eq!(s.dropped_records, 0);
        assert!(s.extra.is_empty());
        assert_eq!(s.seq, 3);
    }
}
