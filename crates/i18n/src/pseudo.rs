//! The pseudo-locale's text: every letter accented, every text 40 % longer.

use std::borrow::Cow;

/// How much longer the pseudo-locale makes each text: translations run up to 40 % longer
/// than English (German, Spanish), so a screen that fits this fits them.
pub const EXPANSION: f64 = 0.4;

/// Fluent's transform for [`crate::PSEUDO`]: `Rest` → `Řêšŧ~~`.
pub fn transform(text: &str) -> Cow<'_, str> {
    let letters = text.chars().filter(|c| !c.is_whitespace()).count();
    if letters == 0 {
        return Cow::Borrowed(text);
    }
    let mut out: String = text.chars().map(accent).collect();
    let extra = (letters as f64 * EXPANSION).ceil() as usize;
    out.extend(std::iter::repeat_n('~', extra));
    Cow::Owned(out)
}

fn accent(c: char) -> char {
    const PLAIN: &str = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ";
    const ACCENTED: &str = "åƀçđéƒĝĥîĵķľɱñöþǫřšŧûṽŵẋýžÅƁÇĐÉƑĜĤÎĴĶĽṀÑÖÞǪŘŠŦÛṼŴẊÝŽ";
    PLAIN
        .chars()
        .position(|p| p == c)
        .and_then(|i| ACCENTED.chars().nth(i))
        .unwrap_or(c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pseudo_text_is_accented_and_forty_percent_longer() {
        let t = transform("Rest now");
        assert_eq!(t, "Řéšŧ ñöŵ~~~");
        assert!(t.chars().count() as f64 >= "Rest now".len() as f64 * 1.3);
        assert_eq!(transform(" "), " ");
    }
}
