//! `docs/MEASURES.md` is the one table of measure words (`metrics::words::MEASURES`) with
//! every measure's definition and source, generated: this test fails when it is out of date
//! (as `docs/WORDS.md` is checked by the station's words test; here, since `metrics` is pure
//! and does no I/O, not even in its tests).

#[test]
fn the_measures_doc_is_the_words_table() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/MEASURES.md");
    let now = metrics::words::measures_markdown();
    if std::env::var_os("UPDATE_SNAPSHOTS").is_some_and(|v| v == "1") {
        std::fs::write(&path, &now).unwrap();
    }
    let written = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        written == now,
        "docs/MEASURES.md is out of date: run \
         `UPDATE_SNAPSHOTS=1 cargo test -p station --test measures_doc` and commit the diff"
    );
}
