//! Shared by the renderer's tests and the station's tests of its screens (which include this
//! file by path).
#![allow(dead_code)]

use render::{RenderError, Renderer};

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
