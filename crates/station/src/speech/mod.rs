//! The patient's voice: each page's main sentence spoken in the patient's language, offline.
//!
//! Debian's `espeak-ng` (a formant synthesiser for 100+ languages, no network, no model
//! files) writes the sentence as a WAV to its standard output; [`rodio`] plays it on the
//! default sound card. The command, not a binding: the Rust bindings to libespeak-ng are
//! unmaintained, and a child process keeps a synthesiser fault out of the station.
//!
//! [`Speaker`] runs on its own thread behind a one-place queue: [`Speaker::say`] never
//! blocks (not the window, not the haptic loop), and a new page's sentence replaces one not
//! yet spoken and cuts short the one being spoken. With no `espeak-ng` or no sound card the
//! speaker logs it once and stays silent; it never fails the session.
//!
//! Which messages are spoken is [`spoken`]: a test synthesises each in every language and
//! checks with `sox` that none is silent.

mod wav;

pub use wav::Wav;

use regimen::{NeglectedSide, PatientSettings};
use render::ScreenState;
use render::{Movement, Picture};
use std::sync::{Arc, Condvar, Mutex, OnceLock};
use std::time::Duration;

/// The ids of every spoken message: the captions of the pages' main pictures (each exercise,
/// rest, pause, the end) and the anchoring cue's "look here".
pub fn spoken() -> Vec<&'static str> {
    let mut ids: Vec<&'static str> = Movement::ALL
        .iter()
        .map(|m| Picture::Exercise(*m).caption_id())
        .collect();
    ids.extend(
        [
            Picture::Rest,
            Picture::Pause,
            Picture::Done,
            Picture::Wheel {
                hold: false,
                turn: false,
            },
        ]
        .map(Picture::caption_id),
    );
    ids.push(LOOK_HERE);
    // The devices' own pages: their titles are what is said.
    ids.extend(["controls-unplugged-title", "controls-arm-unplugged-title"]);
    // The gentle cue to sit up, said over the running exercise.
    ids.push(SIT_UP);
    ids
}

/// The gentle cue's message id (`arm::trunk_cue`).
pub const SIT_UP: &str = "hud-sit-up";

/// The anchoring cue's message id.
pub const LOOK_HERE: &str = "neglect-look-here";

/// The espeak-ng voice for a catalogue language (`en`, `de`, `es`, `zh`; a region or the
/// pseudo-locale falls back to its base language).
pub fn voice(language: &str) -> &'static str {
    match language.split(['-', '_']).next().unwrap_or("en") {
        "de" => "de",
        "es" => "es",
        "zh" => "cmn",
        _ => "en",
    }
}

/// What can stop a sentence being spoken.
#[derive(Debug, thiserror::Error)]
pub enum SpeechError {
    /// `espeak-ng` is not installed or could not run.
    #[error(
        "the speech program espeak-ng could not run ({0}); install the Debian package espeak-ng"
    )]
    NoSynthesiser(std::io::Error),
    /// `espeak-ng` ran and failed.
    #[error("espeak-ng failed: {0}")]
    Synthesis(String),
    /// Its output was not a WAV this module reads.
    #[error("espeak-ng's sound could not be read: {0}")]
    BadWav(String),
}

/// `text` spoken by the espeak-ng `voice`, as WAV bytes.
pub fn synthesise(voice: &str, text: &str) -> Result<Vec<u8>, SpeechError> {
    let out = std::process::Command::new("espeak-ng")
        .args(["-v", voice, "--stdout", "--", text])
        .stdin(std::process::Stdio::null())
        .output()
        .map_err(SpeechError::NoSynthesiser)?;
    if !out.status.success() || out.stdout.len() < 44 {
        return Err(SpeechError::Synthesis(
            String::from_utf8_lossy(&out.stderr).trim().to_owned(),
        ));
    }
    Ok(out.stdout)
}

/// One sentence to speak.
#[derive(Debug, Clone, PartialEq)]
struct Utterance {
    text: String,
    voice: &'static str,
    /// Played from this side only (the anchoring cue), else from both.
    from: NeglectedSide,
}

/// The one-place queue between the pages and the speaking thread.
#[derive(Default)]
struct Slot {
    next: Option<Utterance>,
    on: bool,
    volume: f32,
    /// Bumped by every `say`: the thread cuts short a sentence once it changes.
    generation: u64,
}

/// The speaking thread's handle; cheap to share (`Arc` inside).
#[derive(Clone)]
pub struct Speaker {
    shared: Arc<(Mutex<Slot>, Condvar)>,
}

impl Speaker {
    /// Starts the speaking thread, speech on at 80 % until [`Self::configure`].
    pub fn start() -> Speaker {
        let shared = Arc::new((
            Mutex::new(Slot {
                on: true,
                volume: 0.8,
                ..Slot::default()
            }),
            Condvar::new(),
        ));
        let s = Speaker { shared };
        let worker = s.clone();
        if let Err(e) = std::thread::Builder::new()
            .name("speech".into())
            .spawn(move || worker.run())
        {
            tracing::warn!("speech: no thread for the voice ({e}); the station stays silent");
        }
        s
    }

    /// Speech on or off and its volume, from the patient's prescribed settings.
    pub fn configure(&self, settings: &PatientSettings) {
        let mut slot = self.lock();
        slot.on = settings.speech_on();
        slot.volume = settings.speech_volume() as f32;
        if !slot.on {
            slot.next = None;
            slot.generation += 1;
        }
    }

    /// Speaks `text` in the language in force; replaces a sentence not yet spoken. Never
    /// blocks.
    pub fn say(&self, text: &str) {
        self.put(text, NeglectedSide::None);
    }

    /// Speaks `text` from the `side` speaker only (the anchoring cue's "look here").
    pub fn say_from(&self, text: &str, side: NeglectedSide) {
        self.put(text, side);
    }

    fn put(&self, text: &str, from: NeglectedSide) {
        let voice = voice(i18n::current().tag());
        let mut slot = self.lock();
        slot.generation += 1;
        if slot.on && !text.trim().is_empty() {
            slot.next = Some(Utterance {
                text: text.to_owned(),
                voice,
                from,
            });
        }
        self.shared.1.notify_one();
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, Slot> {
        self.shared.0.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// The next sentence, waiting for one.
    fn take(&self) -> (Utterance, f32, u64) {
        let mut slot = self.lock();
        loop {
            if let Some(u) = slot.next.take() {
                return (u, slot.volume, slot.generation);
            }
            slot = self.shared.1.wait(slot).unwrap_or_else(|e| e.into_inner());
        }
    }

    fn run(self) {
        let mut device: Option<rodio::MixerDeviceSink> = None;
        let mut told_no_device = false;
        let mut told_no_voice = false;
        loop {
            let (u, volume, generation) = self.take();
            let wav = match synthesise(u.voice, &u.text).and_then(|b| Wav::parse(&b)) {
                Ok(w) => w,
                Err(e) => {
                    if !told_no_voice {
                        tracing::warn!("speech: {e}; the station goes on without a voice");
                        told_no_voice = true;
                    }
                    continue;
                }
            };
            if device.is_none() && !told_no_device {
                match rodio::DeviceSinkBuilder::open_default_sink() {
                    Ok(mut d) => {
                        d.log_on_drop(false);
                        device = Some(d);
                    }
                    Err(e) => {
                        tracing::warn!("speech: no sound card ({e}); the station goes on silently");
                        told_no_device = true;
                    }
                }
            }
            let Some(d) = &device else { continue };
            let player = rodio::Player::connect_new(d.mixer());
            player.set_volume(volume);
            let (channels, samples) = wav.stereo_from(u.from);
            let (Some(ch), Some(rate)) = (
                std::num::NonZero::new(channels),
                std::num::NonZero::new(wav.sample_rate),
            ) else {
                continue;
            };
            player.append(rodio::buffer::SamplesBuffer::new(ch, rate, samples));
            // Until it ends, or a newer page's sentence arrives.
            while !player.empty() {
                let slot = self.lock();
                let (slot, _) = self
                    .shared
                    .1
                    .wait_timeout(slot, Duration::from_millis(50))
                    .unwrap_or_else(|e| e.into_inner());
                if slot.generation != generation {
                    player.stop();
                    break;
                }
            }
        }
    }
}

/// The station's one speaker (started on first use).
pub fn speaker() -> &'static Speaker {
    static S: OnceLock<Speaker> = OnceLock::new();
    S.get_or_init(Speaker::start)
}

/// The main sentence of `screen`, the one spoken: the caption of its picture (the next
/// exercise's movement, the rest, the pause, the end), else its title. `None` while an
/// exercise runs.
pub fn main_sentence(screen: &ScreenState) -> Option<String> {
    Some(match screen {
        ScreenState::Next(c) if c.countdown_s.is_some() => Picture::Rest.caption(),
        ScreenState::Next(c) => Picture::Exercise(c.movement).caption(),
        ScreenState::Pictured { picture, .. } => picture.caption(),
        ScreenState::Paused => Picture::Pause.caption(),
        ScreenState::Summary(_) => Picture::Done.caption(),
        ScreenState::Instruction { title, .. } => title.clone(),
        // The pause page says its picture's sentence ("Paused. Take your time.").
        ScreenState::Welcome(page) if page.picture == Some(Picture::Pause) => {
            Picture::Pause.caption()
        }
        ScreenState::Welcome(page) => page.title.clone(),
        // The check-in's question (or the pain page's "stop"): its one sentence.
        ScreenState::CheckIn(page) => page.title.clone(),
        ScreenState::Start | ScreenState::Running => return None,
    })
}

/// What to say for `screen` shown to a patient who neglects `neglected`, and from which
/// side: before an exercise the anchoring cue ("Look over here.") comes first, from the
/// neglected side; everything else from both.
pub fn utterance(
    screen: &ScreenState,
    neglected: NeglectedSide,
) -> Option<(String, NeglectedSide)> {
    let sentence = main_sentence(screen)?;
    match screen {
        ScreenState::Next(c) if c.countdown_s.is_none() && neglected != NeglectedSide::None => {
            Some((format!("{} {sentence}", i18n::tr!(LOOK_HERE)), neglected))
        }
        _ => Some((sentence, NeglectedSide::None)),
    }
}

/// Speaks the main sentence of `screen` on the station's speaker when it changes: call it
/// with every frame's screen. Never blocks.
pub fn speak_page(screen: &ScreenState) {
    static LAST: Mutex<Option<String>> = Mutex::new(None);
    let said = utterance(screen, render::layout::neglected_side());
    say_when_changed(&LAST, said.as_ref().map(|(t, side)| (t.as_str(), *side)));
}

/// Says `said` (from its side) when it differs from what `last` holds, and keeps it there:
/// once per appearance, whatever the frame rate.
fn say_when_changed(last: &Mutex<Option<String>>, said: Option<(&str, NeglectedSide)>) {
    let mut last = last.lock().unwrap_or_else(|e| e.into_inner());
    let text = said.map(|(t, _)| t);
    if last.as_deref() != text {
        *last = text.map(str::to_owned);
        if let Some((t, side)) = said {
            speaker().say_from(t, side);
        }
    }
}

/// Speaks the running exercise's notice (the gentle cue to sit up) when it appears: call it
/// with every frame's notice. Once per appearance; never blocks.
pub fn speak_notice(notice: Option<&str>) {
    static LAST: Mutex<Option<String>> = Mutex::new(None);
    say_when_changed(&LAST, notice.map(|t| (t, NeglectedSide::None)));
}

/// Applies the prescription's `[patient]` table to the station's speaker and layout: speech
/// on or off, its volume, the neglected side.
pub fn for_patient(settings: Option<&PatientSettings>) {
    let settings = settings.cloned().unwrap_or_default();
    render::layout::set_neglected_side(settings.neglected_side);
    speaker().configure(&settings);
}

#[cfg(test)]
mod tests;
