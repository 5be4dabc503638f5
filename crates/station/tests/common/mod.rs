//! Shared by the station's tests of its screens (each test binary uses part of it).
#![allow(dead_code)]

use record::TickRecord;
use station::render::{RenderError, Renderer};

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

/// An offscreen renderer of `width`×`height`, or `None` (with a SKIPPED line) on a machine
/// with no graphics adapter at all; any other failure fails the test.
pub fn renderer_or_skip(width: u32, height: u32) -> Option<Renderer> {
    match Renderer::new_headless(width, height) {
        Ok(r) => Some(r),
        Err(RenderError::NoAdapter(msg)) => {
            eprintln!("SKIPPED: no graphics adapter on this machine ({msg})");
            None
        }
        Err(e) => panic!("renderer: {e}"),
    }
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
