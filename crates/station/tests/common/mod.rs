//! Shared by the station's tests of its screens (each test binary uses part of it).
#![allow(dead_code)]

use record::TickRecord;

#[path = "../../../render/tests/common/mod.rs"]
mod headless;
#[allow(unused_imports)] // each test binary uses part of this module
pub use headless::renderer_or_skip;

/// A tick `tick` of exercise `index` with `active_s` of exercise time, paused or not.
pub fn tick(tick: u64, index: u32, active_s: f64, paused: bool) -> TickRecord {
    let mut rec = TickRecord {
        tick,
        ..TickRecord::default()
    };
    rec.score.exercise_index = index;
    rec.score.active_s = active_s;
    rec.score.paused = paused;
    rec
}

/// Fails unless the generated doc `docs/<doc>` is `now`, naming the command that regenerates
/// it (`UPDATE_SNAPSHOTS=1 cargo test -p station --test <test>`); with `UPDATE_SNAPSHOTS=1` it
/// writes `now` there first.
pub fn assert_generated_doc_current(doc: &str, now: &str, test: &str) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../docs")
        .join(doc);
    if std::env::var_os("UPDATE_SNAPSHOTS").is_some_and(|v| v == "1") {
        std::fs::write(&path, now).unwrap();
    }
    let written = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        written == now,
        "docs/{doc} is out of date: run \
         `UPDATE_SNAPSHOTS=1 cargo test -p station --test {test}` and commit the diff"
    );
}
