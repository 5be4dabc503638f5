//! The direct block encoder against the reflective one it replaced (issue 47): the same bytes
//! on every block channel, and a same-run ratio that keeps it ahead. Outside `blocks` because
//! they walk the channel table, which is built on `blocks`' layouts.

mod matches_reflective {
    use crate::blocks::flatten::Prim;
    use crate::blocks::*;
    use crate::channels::CHANNELS;

    /// Cells of every kind a sample may hold, chosen by a small deterministic generator:
    /// smooth and jumping floats, NaN, infinities, absent values, huge integers, flags, labels.
    fn cell(kind: Kind, state: &mut u64) -> Prim {
        *state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        let r = *state >> 33;
        match kind {
            Kind::Float => match r % 11 {
                0 => Prim::Absent,
                1 => Prim::Float(f64::NAN),
                2 => Prim::Float(f64::INFINITY),
                3 => Prim::Float(f64::NEG_INFINITY),
                4 => Prim::Float(1e300),
                _ => Prim::Float((r as f64) * 1e-7 - 50.0),
            },
            Kind::Int => Prim::Int(if r.is_multiple_of(5) { u64::MAX - r } else { r }),
            Kind::Bool => Prim::Bool(r.is_multiple_of(3)),
            Kind::Text => Prim::Text(["ok", "", "stalled", "lost-sensor"][(r % 4) as usize]),
        }
    }

    /// The direct encoder writes, byte for byte, what the reflective encoder of the same
    /// descriptor writes, on every block channel, for blocks of 1 to 300 samples, also with
    /// one builder's scratch reused from block to block.
    #[test]
    fn encoder_matches_prost_reflect() {
        let mut state = 7;
        let mut scratch = Scratch::default();
        let mut out = Vec::new();
        for spec in &CHANNELS {
            let Some(layout) = spec.block_layout() else {
                continue;
            };
            let layout = layout.unwrap();
            for rows in [1, 2, 17, 300] {
                let mut prims = Vec::new();
                for _ in 0..rows {
                    for c in layout.columns() {
                        for _ in 0..c.elements {
                            prims.push(cell(c.kind, &mut state));
                        }
                    }
                }
                layout.encode_into(&prims, rows, &mut out, &mut scratch);
                assert_eq!(
                    out,
                    layout.encode_reflective(&prims, rows),
                    "{} with {rows} samples",
                    spec.topic
                );
            }
        }
    }
}

mod speed {
    use crate::blocks::flatten::Prim;
    use crate::blocks::*;
    use crate::channels::{BLOCK_SAMPLES, CHANNELS};
    use std::time::Instant;

    /// The recorder's cost at `--speed max` (issue 47) is kept from sliding back: encoding a
    /// block directly must stay several times faster than the reflective encoder measured in
    /// the same run (each the best of 15 alternating rounds, so a loaded machine slows both
    /// alike). Measured 2026-12-07 in a debug build (this crate unoptimised, prost-reflect at
    /// opt-level 1, as CI runs it): 1.5–1.8×, hence the floor of 1.2 (the reflective encoder
    /// itself would give 1.0); in the release build the recorder's encoding share fell from
    /// ~14 % of all samples to 8.5 % (BENCHMARKS.md, issue 47).
    #[test]
    fn the_direct_encoder_stays_several_times_faster_than_the_reflective_one() {
        let layout = CHANNELS
            .iter()
            .filter_map(|c| c.block_layout())
            .map(Result::unwrap)
            .max_by_key(|l| l.columns().len())
            .unwrap();
        let rows = BLOCK_SAMPLES;
        let mut prims = Vec::new();
        for r in 0..rows {
            for c in layout.columns() {
                for e in 0..c.elements {
                    prims.push(match c.kind {
                        Kind::Float => Prim::Float((r as f64 * 1e-3 + e as f64).sin()),
                        Kind::Int => Prim::Int(r as u64),
                        Kind::Bool => Prim::Bool(r.is_multiple_of(7)),
                        Kind::Text => Prim::Text("ok"),
                    });
                }
            }
        }
        let (mut direct, mut reflective) = (f64::MAX, f64::MAX);
        let (mut out, mut scratch) = (Vec::new(), Scratch::default());
        for _ in 0..15 {
            let t = Instant::now();
            layout.encode_into(&prims, rows, &mut out, &mut scratch);
            direct = direct.min(t.elapsed().as_secs_f64());
            let t = Instant::now();
            let bytes = layout.encode_reflective(&prims, rows);
            reflective = reflective.min(t.elapsed().as_secs_f64());
            assert_eq!(bytes, out);
        }
        let ratio = reflective / direct;
        println!(
            "block encoding: direct {direct:.2e} s, reflective {reflective:.2e} s: {ratio:.1}×"
        );
        assert!(
            ratio >= 1.2,
            "the direct encoder is only {ratio:.1}× the reflective one"
        );
    }
}
