//! Fonts for every language the clinic may write in. egui's built-in fonts cover Latin and
//! little else: a therapist's message in Chinese or Arabic would show as boxes. The window
//! adds Debian's Noto fonts as fallbacks behind them (Greek and Cyrillic, Arabic, Hebrew,
//! Chinese), read from their fixed paths in `fonts-noto-core` and `fonts-noto-cjk` (the
//! package depends on both; fixed paths rather than fontconfig: the same faces on every
//! station). Right-to-left lines are ordered before egui lays them out: `render::text`.
//! A missing file is logged and the window still opens with the fonts it has.

use egui::{FontData, FontDefinitions, FontFamily};
use std::sync::{Arc, OnceLock};

/// One fallback face: its name in egui, its file and the face's index in a collection.
struct Fallback {
    name: &'static str,
    path: &'static str,
    /// Which face of a `.ttc` collection (Noto Sans CJK: 0 Japanese, 1 Korean, 2 simplified
    /// Chinese, 3 traditional Chinese).
    index: u32,
}

/// The fallbacks in the order egui tries them, after its own fonts.
const FALLBACKS: &[Fallback] = &[
    Fallback {
        name: "noto-sans",
        path: "/usr/share/fonts/truetype/noto/NotoSans-Regular.ttf",
        index: 0,
    },
    Fallback {
        name: "noto-sans-arabic",
        path: "/usr/share/fonts/truetype/noto/NotoSansArabic-Regular.ttf",
        index: 0,
    },
    Fallback {
        name: "noto-sans-hebrew",
        path: "/usr/share/fonts/truetype/noto/NotoSansHebrew-Regular.ttf",
        index: 0,
    },
    Fallback {
        name: "noto-sans-cjk-sc",
        path: "/usr/share/fonts/opentype/noto/NotoSansCJK-Regular.ttc",
        index: 2,
    },
];

/// The fallback faces this machine has, read once per process (the CJK collection is
/// 19 MB).
fn loaded() -> &'static [(&'static str, Arc<FontData>)] {
    static LOADED: OnceLock<Vec<(&'static str, Arc<FontData>)>> = OnceLock::new();
    LOADED.get_or_init(|| {
        FALLBACKS
            .iter()
            .filter_map(|f| match std::fs::read(f.path) {
                Ok(bytes) => Some((
                    f.name,
                    Arc::new(FontData::from_blob(Arc::new(bytes), f.index)),
                )),
                Err(e) => {
                    tracing::warn!(
                        path = f.path,
                        "font not found ({e}); text in its scripts shows as boxes \
                         (install fonts-noto-core and fonts-noto-cjk)"
                    );
                    None
                }
            })
            .collect()
    })
}

/// egui's built-in fonts with the fallbacks for other scripts behind them, in both the
/// proportional and the monospace families.
pub fn definitions() -> FontDefinitions {
    let mut defs = FontDefinitions::default();
    for (name, data) in loaded() {
        defs.font_data.insert((*name).to_owned(), data.clone());
        for family in [FontFamily::Proportional, FontFamily::Monospace] {
            defs.families
                .entry(family)
                .or_default()
                .push((*name).to_owned());
        }
    }
    defs
}

#[cfg(test)]
mod tests {
    use super::*;
    use egui::FontId;

    /// Runs one pass of `ctx` so its fonts are built (the atlas's uploads dropped).
    fn built(ctx: &egui::Context) {
        ctx.run_pass(egui::RawInput::default(), |_| {})
            .textures_delta
            .clear();
    }

    /// A context with the window's fonts, its atlas built.
    fn context() -> egui::Context {
        let ctx = egui::Context::default();
        ctx.set_fonts(definitions());
        built(&ctx);
        ctx
    }

    #[test]
    fn a_therapists_message_in_chinese_arabic_hebrew_greek_or_russian_has_a_glyph_for_every_letter()
    {
        let ctx = context();
        let messages = [
            "今天做得很好，明天见！",
            "أحسنت اليوم، نراك غدا",
            "כל הכבוד היום, נתראה מחר",
            "Μπράβο σήμερα, τα λέμε αύριο",
            "Сегодня хорошо, до завтра",
            "Gut gemacht, bis morgen! ¿Mañana?",
        ];
        let font = FontId::proportional(32.0);
        for m in messages {
            let missing: Vec<char> = ctx.fonts_mut(|f| {
                m.chars()
                    .filter(|c| !c.is_whitespace() && !f.has_glyph(&font, *c))
                    .collect()
            });
            assert!(missing.is_empty(), "{m}: no glyph for {missing:?}");
        }
    }

    #[test]
    fn every_message_in_every_language_has_a_glyph_for_every_letter() {
        let ctx = context();
        let font = FontId::proportional(32.0);
        let languages = i18n::LANGUAGES.iter().copied().chain([i18n::PSEUDO]);
        for language in languages {
            let catalogue = i18n::Catalogue::load(language).unwrap();
            for m in i18n::Catalogue::messages_of(i18n::FALLBACK) {
                let mut args = i18n::FluentArgs::new();
                for v in &m.variables {
                    args.set(v.as_str(), 2);
                }
                let text = catalogue.message(&m.id, Some(&args));
                let missing: Vec<char> = ctx.fonts_mut(|f| {
                    text.chars()
                        .filter(|c| !c.is_whitespace() && !f.has_glyph(&font, *c))
                        .collect()
                });
                assert!(
                    missing.is_empty(),
                    "{language} {}: {text}: no glyph for {missing:?}",
                    m.id
                );
            }
        }
    }

    #[test]
    fn without_the_fallbacks_chinese_shows_boxes() {
        let ctx = egui::Context::default();
        built(&ctx);
        let font = FontId::proportional(32.0);
        assert!(!ctx.fonts_mut(|f| f.has_glyph(&font, '今')));
    }
}
