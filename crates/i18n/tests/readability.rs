//! Plain words: the English catalogue's patient-facing files read at or below school grade 6
//! by the Flesch–Kincaid grade level, and no patient sentence is longer than 12 words.
//!
//! Patient-facing: every English file except the clinician's (`console*.ftl`, `hub*.ftl`).
//! Each message is formatted with its arguments set to a number (so `{ $minutes }` reads
//! "2"), then split into sentences at `.`, `!`, `?` and `:` (a label and what follows it
//! are read as two phrases).

use i18n::{Catalogue, FluentArgs};

/// The highest grade level allowed.
const MAX_GRADE: f64 = 6.0;
/// The most words in one patient sentence.
const MAX_WORDS: usize = 12;

/// Whether `file` (`en/session.ftl`) holds the patient's words.
fn patient_facing(file: &str) -> bool {
    let name = file.rsplit('/').next().unwrap_or(file);
    !(name.starts_with("console") || name.starts_with("hub"))
}

/// Every patient-facing English message, formatted.
fn patient_messages() -> Vec<(String, String)> {
    let english = Catalogue::load("en").unwrap();
    Catalogue::messages_of("en")
        .into_iter()
        .filter(|m| patient_facing(&m.file))
        .map(|m| {
            let mut args = FluentArgs::new();
            for v in &m.variables {
                args.set(v.as_str(), 2);
            }
            let text = english.message(&m.id, Some(&args));
            (m.id, text)
        })
        .collect()
}

/// The sentences of `text`.
fn sentences(text: &str) -> Vec<String> {
    text.split(['.', '!', '?', ':', '…'])
        .map(str::trim)
        .filter(|s| words(s).next().is_some())
        .map(str::to_owned)
        .collect()
}

/// The words of `sentence` (runs with a letter; numbers and signs are not words).
fn words(sentence: &str) -> impl Iterator<Item = &str> {
    sentence
        .split(|c: char| c.is_whitespace() || c == '·' || c == '/')
        .filter(|w| w.chars().any(char::is_alphabetic))
}

/// Syllables of an English word by the usual rule: groups of vowels, less a silent final
/// `e` (not in `-le`), at least one.
pub fn syllables(word: &str) -> usize {
    let w: Vec<char> = word
        .to_lowercase()
        .chars()
        .filter(|c| c.is_ascii_alphabetic())
        .collect();
    if w.is_empty() {
        return 0;
    }
    let vowel = |c: char| "aeiouy".contains(c);
    let mut count = 0;
    let mut previous = false;
    for &c in &w {
        let v = vowel(c);
        if v && !previous {
            count += 1;
        }
        previous = v;
    }
    let n = w.len();
    // A final `e` is silent, except in a consonant + `le` ending (`middle`).
    let le_ending = n > 2 && w[n - 2] == 'l' && !vowel(w[n - 3]);
    if n > 2 && w[n - 1] == 'e' && !le_ending && count > 1 {
        count -= 1;
    }
    if n > 2 && w[n - 1] == 'd' && w[n - 2] == 'e' && !"td".contains(w[n - 3]) && count > 1 {
        count -= 1;
    }
    count.max(1)
}

/// The Flesch–Kincaid grade level of `sentences`:
/// 0.39 × words per sentence + 11.8 × syllables per word − 15.59.
pub fn grade_level(sentences: &[String]) -> f64 {
    let n_sentences = sentences.len().max(1) as f64;
    let all: Vec<&str> = sentences.iter().flat_map(|s| words(s)).collect();
    let n_words = all.len().max(1) as f64;
    let n_syllables: usize = all.iter().map(|w| syllables(w)).sum();
    0.39 * n_words / n_sentences + 11.8 * n_syllables as f64 / n_words - 15.59
}

#[test]
fn the_syllable_counter_counts_as_a_dictionary_does() {
    for (word, n) in [
        ("wheel", 1),
        ("rest", 1),
        ("exercise", 3),
        ("therapist", 3),
        ("comfortable", 4),
        ("middle", 2),
        ("paused", 1),
        ("started", 2),
        ("the", 1),
        ("session", 2),
    ] {
        assert_eq!(syllables(word), n, "{word}");
    }
    // A hard text reads far above grade 6, an easy one below.
    let hard =
        ["Rehabilitation necessitates individualised interdisciplinary prescriptions".to_owned()];
    assert!(grade_level(&hard) > 12.0, "{}", grade_level(&hard));
    let easy = ["Turn the wheel".to_owned(), "Then rest".to_owned()];
    assert!(grade_level(&easy) < 2.0, "{}", grade_level(&easy));
}

#[test]
fn the_english_patient_catalogue_reads_at_or_below_grade_6() {
    let all: Vec<String> = patient_messages()
        .iter()
        .flat_map(|(_, text)| sentences(text))
        .collect();
    assert!(all.len() > 50, "{} sentences", all.len());
    let grade = grade_level(&all);
    println!(
        "Flesch–Kincaid grade of the patient's English words: {grade:.1} ({} sentences)",
        all.len()
    );
    assert!(grade <= MAX_GRADE, "grade {grade:.1} > {MAX_GRADE}");
}

#[test]
fn every_english_patient_sentence_has_at_most_12_words() {
    let long: Vec<String> = patient_messages()
        .iter()
        .flat_map(|(id, text)| {
            sentences(text)
                .into_iter()
                .filter(|s| words(s).count() > MAX_WORDS)
                .map(move |s| format!("{id}: {s} ({} words)", words(&s).count()))
        })
        .collect();
    assert!(
        long.is_empty(),
        "sentences over {MAX_WORDS} words:\n{}",
        long.join("\n")
    );
}
