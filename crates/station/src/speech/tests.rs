use super::*;

/// `sox FILE -n stat`'s figure named `name` (it writes them to standard error).
fn sox_stat(path: &std::path::Path, name: &str) -> f64 {
    let out = std::process::Command::new("sox")
        .arg(path)
        .args(["-n", "stat"])
        .output()
        .expect("sox runs (Debian package sox; scripts/setup.sh installs it)");
    let text = String::from_utf8_lossy(&out.stderr);
    text.lines()
        .find(|l| l.starts_with(name))
        .and_then(|l| l.split(':').nth(1))
        .and_then(|v| v.trim().parse().ok())
        .unwrap_or_else(|| panic!("sox stat has no {name:?}: {text}"))
}

#[test]
fn every_spoken_message_in_every_language_is_audible_speech() {
    let dir = tempfile::tempdir().unwrap();
    let mut checked = 0;
    for lang in i18n::LANGUAGES {
        let cat = i18n::Catalogue::load(lang).unwrap();
        for id in spoken() {
            assert!(cat.has(id), "{lang}: no message {id}");
            let text = cat.message(id, None);
            let wav = synthesise(voice(lang), &text).unwrap_or_else(|e| panic!("{lang} {id}: {e}"));
            let path = dir.path().join(format!("{lang}-{id}.wav"));
            std::fs::write(&path, &wav).unwrap();
            let seconds = sox_stat(&path, "Length (seconds)");
            let rms = sox_stat(&path, "RMS     amplitude");
            // At least a syllable's length, and louder than silence (-60 dBFS is 0.001).
            assert!(seconds > 0.3, "{lang} {id} {text:?}: {seconds} s");
            assert!(rms > 0.01, "{lang} {id} {text:?}: RMS {rms}");
            // And our own reader agrees there is sound in it.
            let w = Wav::parse(&wav).unwrap();
            assert!(w.samples.iter().any(|s| s.abs() > 0.05), "{lang} {id}");
            checked += 1;
        }
    }
    assert_eq!(checked, i18n::LANGUAGES.len() * spoken().len());
}

#[test]
fn the_voices_are_espeak_ngs_for_each_language() {
    assert_eq!(voice("en"), "en");
    assert_eq!(voice("de-AT"), "de");
    assert_eq!(voice("es"), "es");
    assert_eq!(voice("zh"), "cmn");
    assert_eq!(voice("en-XA"), "en");
}

#[test]
fn a_new_sentence_replaces_one_not_yet_spoken_and_saying_never_waits() {
    // A speaker whose thread never runs: only the queue.
    let s = Speaker {
        shared: Arc::new((
            Mutex::new(Slot {
                on: true,
                volume: 0.5,
                ..Slot::default()
            }),
            Condvar::new(),
        )),
    };
    for k in 0..1000 {
        s.say(&format!("page {k}"));
    }
    // A thousand pages queued nothing but the last.
    let (u, volume, generation) = s.take();
    assert_eq!(u.text, "page 999");
    assert_eq!(volume, 0.5);
    assert_eq!(generation, 1000);
    assert!(s.lock().next.is_none());
}

#[test]
fn speech_off_drops_what_was_waiting_and_speaks_nothing_new() {
    let s = Speaker {
        shared: Arc::new((Mutex::new(Slot::default()), Condvar::new())),
    };
    s.lock().on = true;
    s.say("hello");
    s.configure(&PatientSettings {
        speech: Some(false),
        speech_volume_pct: Some(30),
        ..PatientSettings::default()
    });
    s.say("again");
    let slot = s.lock();
    assert!(slot.next.is_none());
    assert!((slot.volume - 0.3).abs() < 1e-6);
}

#[test]
fn espeak_ngs_piped_wav_is_read_and_the_cue_plays_from_its_side() {
    let wav = Wav::parse(&synthesise("en", "Look here.").unwrap()).unwrap();
    assert_eq!(wav.channels, 1);
    assert!(wav.sample_rate >= 8000);
    let (ch, lr) = wav.stereo_from(NeglectedSide::Left);
    assert_eq!(ch, 2);
    let left: f32 = lr.iter().step_by(2).map(|s| s.abs()).sum();
    let right: f32 = lr.iter().skip(1).step_by(2).map(|s| s.abs()).sum();
    assert!(left > 5.0 * right, "left {left} right {right}");
}

#[test]
fn a_speaker_without_a_sound_card_goes_on_silently() {
    // Under test there is no sound card: saying must neither block nor panic.
    let s = Speaker::start();
    s.say("Rest.");
    s.say_from("Look here.", NeglectedSide::Left);
    std::thread::sleep(Duration::from_millis(300));
    s.say("Paused.");
}

#[test]
fn the_spoken_sentence_of_a_card_is_its_pictures_caption_and_the_cue_comes_first_from_the_neglected_side()
 {
    use render::{NextCard, ScreenState};
    let card = NextCard {
        movement: Movement::Slalom,
        ..NextCard::default()
    };
    let cat = i18n::current();
    let next = ScreenState::Next(card.clone());
    assert_eq!(
        utterance(&next, NeglectedSide::None),
        Some((
            cat.message("picture-road-slalom", None),
            NeglectedSide::None
        ))
    );
    let (text, side) = utterance(&next, NeglectedSide::Left).unwrap();
    assert!(text.starts_with(&cat.message(LOOK_HERE, None)), "{text}");
    assert!(
        text.ends_with(&cat.message("picture-road-slalom", None)),
        "{text}"
    );
    assert_eq!(side, NeglectedSide::Left);
    let rest = ScreenState::Next(NextCard {
        countdown_s: Some(20.0),
        ..card
    });
    assert_eq!(
        utterance(&rest, NeglectedSide::Left),
        Some((cat.message("picture-rest", None), NeglectedSide::None))
    );
    let pause = ScreenState::Pictured {
        picture: Picture::Pause,
        title: String::new(),
        lines: vec![],
    };
    assert_eq!(
        main_sentence(&pause),
        Some(cat.message("picture-pause", None))
    );
    assert_eq!(main_sentence(&ScreenState::Running), None);
}
