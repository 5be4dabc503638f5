//! `docs/MEASURES.md` is the one table of measure words (`metrics::words::MEASURES`) with
//! every measure's definition and source, generated: this test fails when it is out of date
//! (as `docs/WORDS.md` is checked by the station's words test; here, since `metrics` is pure
//! and does no I/O, not even in its tests).

mod common;

#[test]
fn the_measures_doc_is_the_words_table() {
    common::assert_generated_doc_current(
        "MEASURES.md",
        &metrics::words::measures_markdown(),
        "measures_doc",
    );
}
