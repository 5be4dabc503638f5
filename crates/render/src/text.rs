//! Text in every script the clinic may write in, laid out for the patient's window.
//!
//! egui shapes each run of one font with harfrust (Arabic letters join), guessing the run's
//! direction from its script, but it has no bidirectional algorithm: it places the runs left
//! to right in the order they are stored and wraps them in that order. An Arabic or Hebrew
//! sentence then shows its words in reverse and wraps from the wrong end. Here each line is
//! ordered by the Unicode bidi algorithm (`unicode-bidi`, rules L1–L2, mirrored brackets for
//! L4) and handed to egui as *pieces* in visual order, each its own layout section so no font
//! run spans two of them: a piece of right-to-left letters is handed over in reading order
//! (harfrust shapes it, joined, and draws it right to left), everything else already in the
//! order it is drawn. A right-to-left paragraph is wrapped here, line by line, and each line
//! is set against the right edge of its box ([`Align::Start`]).
//!
//! Text with no right-to-left letter goes straight to egui, unchanged.

use egui::epaint::text::{LayoutJob, LayoutSection, TextFormat};
use egui::{Align2, Color32, FontId, Galley, Painter, Pos2, Rect};
use std::ops::Range;
use std::sync::Arc;
use unicode_bidi::{BidiClass, BidiInfo, bidi_class};
use unicode_segmentation::UnicodeSegmentation;

/// Where a paragraph's lines sit in their box.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Align {
    /// At the side the paragraph starts reading from: left for left-to-right text, right for
    /// right-to-left text (its lines end at the right of the wrap width).
    Start,
    /// Shrink-wrapped to the widest line, which the caller places (a caption or a choice's
    /// label, centred): right-to-left lines set at its right, as left-to-right ones at its left.
    Block,
}

/// Whether `c` reads right to left: a Hebrew or Arabic letter, or an Arabic digit.
fn reads_rtl(c: char) -> bool {
    matches!(bidi_class(c), BidiClass::R | BidiClass::AL | BidiClass::AN)
}

/// Whether `text` has anything to lay out right to left (else egui lays it out alone).
pub fn has_rtl(text: &str) -> bool {
    text.chars().any(reads_rtl)
}

/// The bidi controls (marks, embeddings, isolates): they order the text and are never drawn.
fn is_bidi_control(c: char) -> bool {
    matches!(
        c,
        '\u{200E}' | '\u{200F}' | '\u{061C}' | '\u{202A}'..='\u{202E}' | '\u{2066}'..='\u{2069}'
    )
}

/// A bracket or sign drawn mirrored in right-to-left text (rule L4; the common pairs).
fn mirrored(c: char) -> char {
    match c {
        '(' => ')',
        ')' => '(',
        '[' => ']',
        ']' => '[',
        '{' => '}',
        '}' => '{',
        '<' => '>',
        '>' => '<',
        '«' => '»',
        '»' => '«',
        '‹' => '›',
        '›' => '‹',
        other => other,
    }
}

/// A piece of a line, in the order the pieces are drawn (left to right).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Piece {
    /// Right-to-left letters, in reading order: the shaper joins them and draws them right to
    /// left. Otherwise the text in the order it is drawn.
    pub rtl: bool,
    /// The piece's characters.
    pub text: String,
}

/// One line (no line break in it) ordered for drawing: its pieces left to right, and whether
/// it reads right to left (its first strong letter, rule P2).
pub fn visual_pieces(line: &str) -> (Vec<Piece>, bool) {
    let bidi = BidiInfo::new(line, None);
    (pieces_of(&bidi, 0..line.len()), starts_rtl(&bidi))
}

/// Whether the (first) paragraph of `bidi` reads right to left.
fn starts_rtl(bidi: &BidiInfo) -> bool {
    bidi.paragraphs.first().is_some_and(|p| p.level.is_rtl())
}

/// The pieces, left to right, of the line at byte `range` of `bidi`'s text: its levels
/// resolved over the whole paragraph (rule L1–L2 a line at a time).
fn pieces_of(bidi: &BidiInfo, range: Range<usize>) -> Vec<Piece> {
    let mut drawn: Vec<(bool, String)> = Vec::new();
    for para in &bidi.paragraphs {
        let line = range.start.max(para.range.start)..range.end.min(para.range.end);
        if line.is_empty() {
            continue;
        }
        let (levels, runs) = bidi.visual_runs(para, line);
        for run in runs {
            let rtl_run = levels[run.start].is_rtl();
            let mut graphemes: Vec<&str> = bidi.text[run].graphemes(true).collect();
            if rtl_run {
                graphemes.reverse();
            }
            for g in graphemes {
                let g: String = g.chars().filter(|c| !is_bidi_control(*c)).collect();
                let Some(first) = g.chars().next() else {
                    continue;
                };
                let g = if rtl_run && g.chars().count() == 1 {
                    mirrored(first).to_string()
                } else {
                    g
                };
                drawn.push((reads_rtl(first), g));
            }
        }
    }
    // Group the drawn graphemes into pieces; a right-to-left piece back in reading order.
    let mut pieces: Vec<(bool, Vec<String>)> = Vec::new();
    for (rtl, g) in drawn {
        match pieces.last_mut() {
            Some((last_rtl, gs)) if *last_rtl == rtl => gs.push(g),
            _ => pieces.push((rtl, vec![g])),
        }
    }
    pieces
        .into_iter()
        .map(|(rtl, mut gs)| {
            if rtl {
                gs.reverse();
            }
            Piece {
                rtl,
                text: gs.concat(),
            }
        })
        .collect()
}

/// A layout job drawing `pieces` on one row, `leading` points in from the left.
fn push_row(job: &mut LayoutJob, pieces: &[Piece], format: &TextFormat, leading: f32) {
    for (i, piece) in pieces.iter().enumerate() {
        let start = job.text.len();
        job.text.push_str(&piece.text);
        // One section a piece, never merged: a font run must not span two pieces.
        job.sections.push(LayoutSection {
            leading_space: if i == 0 { leading } else { 0.0 },
            byte_range: start.into()..job.text.len().into(),
            format: format.clone(),
        });
    }
}

/// The drawn width of `pieces` on one row, points.
fn width_of(p: &Painter, pieces: &[Piece], format: &TextFormat) -> f32 {
    let mut job = LayoutJob::default();
    push_row(&mut job, pieces, format, 0.0);
    p.layout_job(job).size().x
}

/// The paragraph of `bidi` cut into lines no wider than `wrap_width` at its word bounds:
/// each line's pieces and drawn width, first line first. A word wider than the box gets a
/// line of its own.
fn wrapped(
    p: &Painter,
    bidi: &BidiInfo,
    format: &TextFormat,
    wrap_width: f32,
) -> Vec<(Vec<Piece>, f32)> {
    let text = bidi.text;
    let line = |range: Range<usize>| {
        let end = range.start + text[range.clone()].trim_end().len();
        let pieces = pieces_of(bidi, range.start..end);
        let w = width_of(p, &pieces, format);
        (pieces, w)
    };
    if !wrap_width.is_finite() {
        return vec![line(0..text.len())];
    }
    let mut lines = Vec::new();
    let (mut start, mut end) = (0, 0);
    for (at, word) in text.split_word_bound_indices() {
        if end > start && !word.trim().is_empty() {
            let candidate = line(start..at + word.len());
            if candidate.1 > wrap_width {
                lines.push(line(start..end));
                start = at;
            }
        }
        end = at + word.len();
    }
    lines.push(line(start..text.len()));
    lines
}

/// Lays out `text` in `font` and `color`, wrapped at `wrap_width` (infinite: one line a
/// paragraph), in any script: right-to-left text ordered and joined, a right-to-left
/// paragraph set as `align` says. Text with no right-to-left letter is laid out by egui as it
/// is.
pub fn layout(
    p: &Painter,
    text: &str,
    font: FontId,
    color: Color32,
    wrap_width: f32,
    align: Align,
) -> Arc<Galley> {
    if !has_rtl(text) {
        return p.layout(text.to_owned(), font, color, wrap_width);
    }
    let format = TextFormat::simple(font, color);
    let mut rows: Vec<(Vec<Piece>, bool, f32)> = Vec::new();
    for paragraph in text.split('\n') {
        let bidi = BidiInfo::new(paragraph, None);
        let rtl = starts_rtl(&bidi);
        for (pieces, w) in wrapped(p, &bidi, &format, wrap_width) {
            rows.push((pieces, rtl, w));
        }
    }
    let widest = rows.iter().map(|r| r.2).fold(0.0, f32::max);
    let mut job = LayoutJob::default();
    for (i, (pieces, rtl, w)) in rows.iter().enumerate() {
        if i > 0 {
            let start = job.text.len();
            job.text.push('\n');
            job.sections.push(LayoutSection {
                leading_space: 0.0,
                byte_range: start.into()..job.text.len().into(),
                format: format.clone(),
            });
        }
        let leading = match align {
            Align::Start if *rtl && wrap_width.is_finite() => (wrap_width - w).max(0.0),
            Align::Start => 0.0,
            Align::Block if *rtl => widest - w,
            Align::Block => 0.0,
        };
        push_row(&mut job, pieces, &format, leading);
    }
    p.layout_job(job)
}

/// One line of `text` (no wrapping) in any script.
pub fn line(p: &Painter, text: &str, font: FontId, color: Color32) -> Arc<Galley> {
    layout(p, text, font, color, f32::INFINITY, Align::Block)
}

/// Paints one line of `text` anchored at `pos` by `anchor` (as [`Painter::text`]); returns
/// its rectangle.
pub fn put(
    p: &Painter,
    pos: Pos2,
    anchor: Align2,
    text: &str,
    font: FontId,
    color: Color32,
) -> Rect {
    let g = line(p, text, font, color);
    let rect = anchor.anchor_size(pos, g.size());
    p.galley(rect.min, g, color);
    rect
}

#[cfg(test)]
mod tests;
