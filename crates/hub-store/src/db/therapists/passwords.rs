//! The password policy, after NIST SP 800-63B (§5.1.1.2, "Memorized Secret Verifiers"): a
//! minimum length counted in characters, no composition rules, and every new password
//! compared against "values known to be commonly-used, expected, or compromised" —
//! breach corpora, dictionary words, repetitive or sequential characters, context-specific
//! words (the account's e-mail, the product's name). Unicode is allowed: a password is
//! NFKC-normalised before it is checked (§5.1.1.2 asks for NFKC or NFKD), and invisible
//! characters are refused rather than silently counted.
//!
//! # Why zxcvbn and not only a shipped list
//!
//! A list of the 10 000 commonest passwords alone still accepts `Password1!` (a listed word
//! with a digit and a symbol) and `correcthorse` (two dictionary words). The `zxcvbn` crate
//! (the Rust port of Dropbox's estimator, MIT) carries the lists — 30 000 passwords of the
//! Xato corpus, English words, names, film and TV words — and matches them case-insensitively,
//! reversed, with l33t substitutions, and in combination with keyboard runs, sequences,
//! repeats and dates, giving an estimate of the guesses an attacker who knows these patterns
//! needs. A password must need at least [`MIN_GUESSES_LOG10`] (10⁸: zxcvbn's score 3, "safely
//! unguessable" with a slow hash such as argon2). The plain rules before it (invisible
//! characters, length, repeats, sequences, the e-mail, [`COMMON_PASSWORDS`]) answer the
//! common mistakes with a message naming the rule.

use unicode_general_category::{GeneralCategory, get_general_category};
use unicode_normalization::UnicodeNormalization;
use zxcvbn::matching::patterns::MatchPattern;

use crate::error::HubError;
use crate::refusal::{Code, Why};

/// Passwords refused whatever their length (compared NFKC-normalised, lowercased, spaces
/// removed): the product's own names and the commonest passwords of at least ten characters
/// (zxcvbn's lists hold many more).
pub const COMMON_PASSWORDS: &[&str] = &[
    "1234567890",
    "0123456789",
    "0987654321",
    "1111111111",
    "0000000000",
    "1q2w3e4r5t",
    "qwertyuiop",
    "asdfghjkl;",
    "1qaz2wsx3edc",
    "password123",
    "password1234",
    "password12345",
    "passw0rd123",
    "qwerty12345",
    "qwerty123456",
    "iloveyou123",
    "123456789a",
    "abcdefghij",
    "letmein123",
    "welcome123",
    "changeme123",
    "administrator",
    "telerehab",
    "telerehab123",
    "therapist1",
    "therapist123",
];

/// Shortest password accepted, visible characters after NFKC normalisation.
pub const MIN_PASSWORD_CHARS: usize = 10;

/// Longest password accepted, bytes (argon2 hashes any length; this bounds the work).
pub const MAX_PASSWORD_BYTES: usize = 1024;

/// Fewest different characters (spaces and case aside) a password must have.
pub const MIN_DISTINCT_CHARS: usize = 4;

/// Fewest guesses, as a power of ten, that zxcvbn must estimate for a password (10⁸).
pub const MIN_GUESSES_LOG10: f64 = 8.0;

/// Characters of a password zxcvbn looks at (its matching grows faster than the length; a
/// password that is strong in its first 100 characters is strong).
const ESTIMATED_CHARS: usize = 100;

/// True for a character that shows nothing: a format character (Unicode category Cf — zero
/// width spaces and joiners, direction marks, the byte order mark, soft hyphens…) or a
/// control character other than whitespace.
fn is_invisible(c: char) -> bool {
    matches!(get_general_category(c), GeneralCategory::Format)
        || (c.is_control() && !c.is_whitespace())
}

/// True for a mark drawn on the character before it (an accent typed separately): not a
/// character of its own for the length.
fn is_mark(c: char) -> bool {
    matches!(
        get_general_category(c),
        GeneralCategory::NonspacingMark | GeneralCategory::EnclosingMark
    )
}

/// A password a therapist may choose (see the module's documentation): at least
/// [`MIN_PASSWORD_CHARS`] visible characters after NFKC normalisation, of which some are not
/// whitespace, at most [`MAX_PASSWORD_BYTES`] bytes; no invisible characters; not one
/// character or a short group repeated, nor a run of consecutive characters; not the
/// account's e-mail, not one of [`COMMON_PASSWORDS`], and at least 10^[`MIN_GUESSES_LOG10`]
/// guesses for zxcvbn. Each refusal names its rule in plain words.
pub fn check_new_password(password: &str, email: &str) -> Result<(), HubError> {
    let refuse = |why: Why, words: String| Err(HubError::refused("password", words, why));
    if password.chars().any(is_invisible) {
        return refuse(
            Why::new(Code::PasswordInvisible),
            "must not contain invisible characters (zero-width spaces or joiners, direction \
             marks, control characters): type only characters you can see"
                .to_owned(),
        );
    }
    let normalised: String = password.nfkc().collect();
    let visible = normalised.chars().filter(|&c| !is_mark(c)).count();
    if visible < MIN_PASSWORD_CHARS || password.len() > MAX_PASSWORD_BYTES {
        return refuse(
            Why::new(Code::PasswordLength).with("min", MIN_PASSWORD_CHARS),
            format!(
                "must have at least {MIN_PASSWORD_CHARS} characters and at most \
             {MAX_PASSWORD_BYTES} bytes"
            ),
        );
    }
    let squeezed: Vec<char> = normalised
        .chars()
        .filter(|c| !c.is_whitespace())
        .flat_map(char::to_lowercase)
        .collect();
    if squeezed.len() < MIN_PASSWORD_CHARS / 2 {
        return refuse(
            Why::new(Code::PasswordSpaces),
            format!(
                "must not be only spaces: at least {} characters that are not whitespace",
                MIN_PASSWORD_CHARS / 2
            ),
        );
    }
    let email = email.trim().to_lowercase();
    let squeezed_text: String = squeezed.iter().collect();
    if !email.is_empty() && (squeezed_text == email || normalised.trim().to_lowercase() == email) {
        return refuse(
            Why::new(Code::PasswordEmail),
            "must not be the account's e-mail address".to_owned(),
        );
    }
    if COMMON_PASSWORDS.contains(&squeezed_text.as_str()) {
        return refuse(
            Why::new(Code::PasswordCommon),
            "is one of the most common passwords; choose another".to_owned(),
        );
    }
    if is_repeated(&squeezed) {
        return refuse(
            Why::new(Code::PasswordRepeated).with("min", MIN_DISTINCT_CHARS),
            format!(
                "must not be one character or a short group of characters repeated (like \
             aaaaaaaaaa or abcabcabc): use at least {MIN_DISTINCT_CHARS} different characters \
             in no repeating pattern"
            ),
        );
    }
    if is_sequential(&squeezed) {
        return refuse(
            Why::new(Code::PasswordSequence),
            "must not be a run of consecutive letters or digits (like abcdefghij or \
             1234567890)"
                .to_owned(),
        );
    }
    let estimated: String = normalised.chars().take(ESTIMATED_CHARS).collect();
    let context: Vec<&str> = email
        .split(['@', '.', '-', '_', '+'])
        .filter(|w| w.len() >= 3)
        .chain(["telerehab", "therapist", "clinic", "rehab"])
        .collect();
    let estimate = zxcvbn::zxcvbn(&estimated, &context);
    if estimate.guesses_log10() < MIN_GUESSES_LOG10 {
        return refuse(
            Why::new(Code::PasswordGuessable),
            format!(
                "is too easy to guess: {} (about {} guesses would find it, at least 100 million \
             are needed); a phrase of a few unrelated words is long enough and easy to \
             remember",
                weakest_part(estimate.sequence(), estimated.chars().count()),
                plain_count(estimate.guesses_log10())
            ),
        );
    }
    Ok(())
}

/// True if `chars` has fewer than [`MIN_DISTINCT_CHARS`] different characters or is a group
/// of at most half its length repeated (`abcabcabc`, `abcdabcdab`).
fn is_repeated(chars: &[char]) -> bool {
    let mut distinct: Vec<char> = chars.to_vec();
    distinct.sort_unstable();
    distinct.dedup();
    if distinct.len() < MIN_DISTINCT_CHARS {
        return true;
    }
    (1..=chars.len() / 2).any(|period| chars.iter().zip(&chars[period..]).all(|(a, b)| a == b))
}

/// True if `chars` is at most two runs of consecutive characters (each next one up or down
/// by one: `abcdefghij`, `9876543210`, `1234abcd`).
fn is_sequential(chars: &[char]) -> bool {
    let breaks = chars
        .windows(2)
        .filter(|w| (i64::from(u32::from(w[1])) - i64::from(u32::from(w[0]))).abs() > 1)
        .count();
    breaks <= 1
}

/// What makes a weak password weak, in plain words: the pattern covering most of it.
fn weakest_part(sequence: &[zxcvbn::Match], length: usize) -> String {
    let biggest = sequence
        .iter()
        .filter(|m| !matches!(m.pattern, MatchPattern::BruteForce))
        .max_by_key(|m| m.j.saturating_sub(m.i));
    let Some(m) = biggest else {
        return format!("{length} characters are too few for its kind of characters");
    };
    let whole = m.j.saturating_sub(m.i) + 1 >= length;
    match &m.pattern {
        // zxcvbn names its dictionaries with a type it does not export: read its name.
        MatchPattern::Dictionary(d) => match format!("{:?}", d.dictionary_name).as_str() {
            "Passwords" if whole => "it is one of the most common passwords".to_owned(),
            "Passwords" => {
                "it is a common password with a few characters added or changed".to_owned()
            }
            "UserInputs" => "it is made from the e-mail address or the clinic's name".to_owned(),
            "FemaleNames" | "MaleNames" | "Surnames" => "it is mostly a common name".to_owned(),
            _ => "it is one or two common words, which are guessed first".to_owned(),
        },
        MatchPattern::Spatial(_) => {
            "it is mostly a run of neighbouring keys (like qwerty)".to_owned()
        }
        MatchPattern::Repeat(_) => "it repeats characters (like aaa or abcabc)".to_owned(),
        MatchPattern::Sequence(_) => "it is mostly a sequence (like abcd or 6543)".to_owned(),
        MatchPattern::Date(_) | MatchPattern::Regex(_) => {
            "it is mostly a date or a year".to_owned()
        }
        MatchPattern::BruteForce => "it is too short for its kind of characters".to_owned(),
    }
}

/// 10^`log10` in words (`a thousand`, `3 million`).
fn plain_count(log10: f64) -> String {
    let n = 10f64.powf(log10);
    let (value, unit) = if n >= 1e9 {
        (n / 1e9, " billion")
    } else if n >= 1e6 {
        (n / 1e6, " million")
    } else if n >= 1e3 {
        (n / 1e3, " thousand")
    } else {
        (n, "")
    };
    format!("{}{unit}", value.round().max(1.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn why(password: &str) -> String {
        check_new_password(password, "bob@clinic.example")
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn the_second_hostile_rounds_passwords_are_refused_naming_the_rule() {
        assert!(
            why("aaaaaaaaaa").contains("repeated"),
            "{}",
            why("aaaaaaaaaa")
        );
        assert!(
            why("Password1!").contains("common password"),
            "{}",
            why("Password1!")
        );
        assert!(
            why("correcthorse").contains("common words"),
            "{}",
            why("correcthorse")
        );
        let hidden = "a\u{200b}\u{200b}\u{200b}\u{200b}\u{200b}";
        assert!(
            why(hidden).contains("invisible characters"),
            "{}",
            why(hidden)
        );
    }

    #[test]
    fn invisible_characters_are_refused_and_marks_do_not_count() {
        for c in [
            '\u{200b}', '\u{200d}', '\u{2060}', '\u{feff}', '\u{202e}', '\u{00ad}', '\u{7}',
        ] {
            let p = format!("a long enough{c} passphrase");
            assert!(why(&p).contains("invisible"), "{c:?}: {}", why(&p));
        }
        // NFKC: fullwidth letters are their ASCII selves, so a common password in them is
        // still common; combining marks are not characters of their own.
        assert!(why("ｐａｓｓｗｏｒｄ１２３").contains("common"));
        let accents = format!("abc{}", "\u{301}".repeat(20));
        assert!(
            why(&accents).contains("at least 10 characters"),
            "{}",
            why(&accents)
        );
        // Unicode passphrases are welcome.
        assert!(check_new_password("über den grünen Fluß gehen", "bob@clinic.example").is_ok());
    }

    #[test]
    fn repeats_and_sequences_are_refused() {
        for p in [
            "abababababab",
            "abcabcabcabc",
            "abcdabcdabcd",
            "zzzz zzzz zz",
            "aaaabbbbcccc",
        ] {
            assert!(why(p).contains("repeated"), "{p}: {}", why(p));
        }
        for p in ["abcdefghijk", "9876543210", "1234567abcdefg", "qrstuvwxyz"] {
            assert!(why(p).contains("consecutive"), "{p}: {}", why(p));
        }
    }

    #[test]
    fn the_passwords_used_in_tests_and_one_time_passwords_pass() {
        for p in [
            "correct horse battery",
            "correct horse battery staple",
            "ana's own passphrase",
            "an audited passphrase",
            "a clinic passphrase of my own",
            "a quieter clinic morning",
            "a brand new passphrase",
            "another long pass",
            "a passphrase of my own",
            "a new passphrase",
            "correct horse battery renewed",
        ] {
            assert_eq!(
                check_new_password(p, "ada@clinic.example").map_err(|e| e.to_string()),
                Ok(()),
                "{p}"
            );
        }
        for _ in 0..200 {
            let p = crate::db::one_time_password().unwrap();
            assert!(check_new_password(&p, "ada@clinic.example").is_ok(), "{p}");
            let renewed = format!("{p} renewed");
            assert!(
                check_new_password(&renewed, "ada@clinic.example").is_ok(),
                "{renewed}"
            );
        }
    }

    #[test]
    fn a_long_password_is_checked_quickly_and_bounded() {
        let long: String = (0..MAX_PASSWORD_BYTES)
            .map(|i| char::from(b'a' + (i * 7 % 26) as u8))
            .collect();
        let _ = check_new_password(&long, "bob@clinic.example");
        assert!(why(&"x".repeat(MAX_PASSWORD_BYTES + 1)).contains("at most 1024 bytes"));
    }
}
