use super::*;
use egui::{Context, Id, LayerId, Order};

/// "Well done today" in Arabic (two words, no lam-alef: one glyph a letter).
const ARABIC: &str = "أحسنت اليوم";

/// The same sentence in Arabic presentation forms, each letter in the form it takes at its
/// place in its word, in reading order: alef-hamza isolated, hah initial, seen medial, noon
/// medial, teh final; alef isolated, lam initial, yeh medial, waw final, meem isolated (waw
/// and alef never join the next letter).
const ARABIC_SHAPED: &str =
    "\u{FE83}\u{FEA3}\u{FEB4}\u{FEE8}\u{FE96} \u{FE8D}\u{FEDF}\u{FEF4}\u{FEEE}\u{FEE1}";

/// Runs `f` with a painter of a context holding the window's fonts; returns what it returns.
fn with_painter<T>(f: impl FnOnce(&Painter) -> T) -> T {
    let ctx = Context::default();
    ctx.set_fonts(crate::fonts::definitions());
    // The first pass builds the fonts; the second lays out with them.
    ctx.run_pass(egui::RawInput::default(), |_| {})
        .textures_delta
        .clear();
    let mut f = Some(f);
    let mut out = None;
    ctx.run_pass(egui::RawInput::default(), |ctx| {
        let p = ctx.layer_painter(LayerId::new(Order::Foreground, Id::unique("text")));
        if let Some(f) = f.take() {
            out = Some(f(&p));
        }
    })
    .textures_delta
    .clear();
    out.expect("laid out")
}

/// The characters of a galley's glyphs, row by row, left to right.
fn drawn_chars(g: &Galley) -> Vec<String> {
    g.rows
        .iter()
        .map(|r| r.glyphs.iter().map(|gl| gl.chr).collect())
        .collect()
}

fn piece(rtl: bool, text: &str) -> Piece {
    Piece {
        rtl,
        text: text.to_owned(),
    }
}

#[test]
fn an_arabic_sentence_is_drawn_last_word_first_each_word_in_reading_order() {
    let (pieces, rtl) = visual_pieces(ARABIC);
    assert!(rtl);
    assert_eq!(
        pieces,
        [
            piece(true, "اليوم"),
            piece(false, " "),
            piece(true, "أحسنت")
        ]
    );
}

#[test]
fn a_hebrew_sentence_reads_right_to_left_too() {
    let (pieces, rtl) = visual_pieces("שלום עולם");
    assert!(rtl);
    assert_eq!(
        pieces,
        [piece(true, "עולם"), piece(false, " "), piece(true, "שלום")]
    );
}

#[test]
fn arabic_in_an_english_line_keeps_the_line_left_to_right() {
    let (pieces, rtl) = visual_pieces("Message: أحسنت اليوم!");
    assert!(!rtl);
    assert_eq!(
        pieces,
        [
            piece(false, "Message: "),
            piece(true, "اليوم"),
            piece(false, " "),
            piece(true, "أحسنت"),
            piece(false, "!"),
        ]
    );
}

#[test]
fn numbers_and_latin_words_in_arabic_read_left_to_right_and_brackets_mirror() {
    // "Exercise 2 of 4 (Road)": the digits and the Latin word keep their order; the
    // paragraph's end punctuation and brackets sit where an Arabic reader expects them.
    let (pieces, rtl) = visual_pieces("تمرين 12 (Road)");
    assert!(rtl);
    assert_eq!(pieces, [piece(false, "(Road) 12 "), piece(true, "تمرين")]);
    // Arabic-Indic digits keep their order too: handed over reversed, the shaper turns them.
    let (pieces, _) = visual_pieces("بعد ١٢ ثانية");
    assert_eq!(
        pieces,
        [
            piece(true, "ثانية"),
            piece(false, " "),
            piece(true, "٢١"),
            piece(false, " "),
            piece(true, "بعد"),
        ]
    );
    let (pieces, _) = visual_pieces("(مرحبا)");
    assert_eq!(
        pieces,
        [piece(false, "("), piece(true, "مرحبا"), piece(false, ")")]
    );
}

#[test]
fn text_without_right_to_left_letters_is_laid_out_by_egui_unchanged() {
    for s in [
        "Gut gemacht, bis morgen!",
        "今天做得很好",
        "Сегодня хорошо",
        "Μπράβο",
    ] {
        let (ours, egui_own) = with_painter(|p| {
            let f = FontId::proportional(32.0);
            (
                layout(p, s, f.clone(), Color32::BLACK, 300.0, Align::Start),
                p.layout(s.to_owned(), f, Color32::BLACK, 300.0),
            )
        });
        assert_eq!(drawn_chars(&ours), drawn_chars(&egui_own), "{s}");
        assert_eq!(ours.size(), egui_own.size(), "{s}");
    }
}

#[test]
fn the_arabic_message_is_drawn_shaped_and_reordered_with_no_missing_glyph() {
    let font = FontId::proportional(40.0);
    let (ours, shaped, missing, atlas) = with_painter(|p| {
        let laid = (
            line(p, ARABIC, font.clone(), Color32::BLACK),
            line(p, ARABIC_SHAPED, font.clone(), Color32::BLACK),
            // A letter no font has: egui draws its box.
            line(p, "\u{10FFFD}", font.clone(), Color32::BLACK),
        );
        (laid.0, laid.1, laid.2, p.ctx().fonts(|f| f.image()))
    });
    // Drawn left to right: the last word first, each word's letters from its end. (egui
    // adds zero-width glyphs with no image after a right-to-left run, for its cursor: left
    // out, as the space is, which has no image either.)
    let inked = |g: &Galley| -> String {
        g.rows[0]
            .glyphs
            .iter()
            .filter(|gl| !gl.uv_rect.is_nothing())
            .map(|gl| gl.chr)
            .collect()
    };
    let reversed: String = ARABIC.chars().rev().filter(|c| *c != ' ').collect();
    assert_eq!(inked(&ours), reversed);
    // Every glyph is the one the presentation form names, where the form puts it: the
    // letters are joined as an Arabic reader writes them. (The joined forms are the very
    // glyphs the font maps the presentation forms to; an isolated form is a glyph of its own
    // with the same outline: compared by the image drawn.)
    let image = |gl: &egui::epaint::text::Glyph| -> Vec<Color32> {
        let (min, max) = (gl.uv_rect.min, gl.uv_rect.max);
        (usize::from(min[1])..usize::from(max[1]))
            .flat_map(|y| (usize::from(min[0])..usize::from(max[0])).map(move |x| (x, y)))
            .map(|(x, y)| atlas.pixels[y * atlas.size[0] + x])
            .collect()
    };
    let glyphs = |g: &Galley| -> Vec<(Vec<Color32>, i32)> {
        g.rows[0]
            .glyphs
            .iter()
            .filter(|gl| !gl.uv_rect.is_nothing())
            .map(|gl| (image(gl), (gl.pos.x * 4.0).round() as i32))
            .collect()
    };
    assert_eq!(glyphs(&ours).len(), 10);
    assert!(
        glyphs(&ours) == glyphs(&shaped),
        "the glyphs drawn differ from the presentation forms'"
    );
    // Unjoined, the letters would be drawn otherwise: the test can tell.
    let unjoined: String = ARABIC.chars().map(|c| format!("{c}\u{200C}")).collect();
    let apart = with_painter(|p| line(p, &unjoined, font.clone(), Color32::BLACK));
    assert_ne!(
        apart.rows[0]
            .glyphs
            .iter()
            .filter(|g| !g.uv_rect.is_nothing())
            .map(|g| g.uv_rect.size)
            .collect::<Vec<_>>(),
        ours.rows[0]
            .glyphs
            .iter()
            .filter(|g| !g.uv_rect.is_nothing())
            .map(|g| g.uv_rect.size)
            .collect::<Vec<_>>(),
    );
    // And none is the box of a missing letter.
    let tofu = missing.rows[0].glyphs[0].uv_rect;
    assert!(
        ours.rows[0].glyphs.iter().all(|g| g.uv_rect != tofu),
        "a box among {:?}",
        drawn_chars(&ours)
    );
}

#[test]
fn a_long_arabic_paragraph_wraps_from_its_first_words_and_sets_each_line_at_the_right() {
    // "Well done today. Rest a little, then drink water and see you tomorrow."
    let message = "أحسنت اليوم. استرح قليلا ثم اشرب الماء ونراك غدا";
    let width = 260.0;
    let g = with_painter(|p| {
        layout(
            p,
            message,
            FontId::proportional(32.0),
            Color32::BLACK,
            width,
            Align::Start,
        )
    });
    assert!(g.rows.len() >= 2, "{:?}", drawn_chars(&g));
    // The first line holds the first word (drawn reversed), the last line the last.
    let rows = drawn_chars(&g);
    let first: String = "أحسنت".chars().rev().collect();
    let last: String = "غدا".chars().rev().collect();
    assert!(rows[0].contains(&first), "{rows:?}");
    assert!(rows.last().unwrap().contains(&last), "{rows:?}");
    for row in &g.rows {
        let right = row.glyphs.last().unwrap().max_x() + row.pos.x;
        assert!(
            (right - width).abs() < 1.5,
            "a row ends at {right}, not at the box's right edge {width}"
        );
        assert!(row.size.x <= width + 1.0, "a row is wider than its box");
    }
}
