//! Frame time of the patient's screen at 1280×720 on whatever adapter wgpu picks (on a
//! CPU-only machine: lavapipe with `WGPU_BACKEND=vulkan`, llvmpipe with `WGPU_BACKEND=gl`).
//!
//! `frame/*` is a whole frame as the headless command produces it: world mesh, sky, world,
//! HUD, and the copy back to the CPU. `cpu/*` isolates the CPU parts (mesh build, HUD
//! layout) so the GPU share can be read off by difference.
//!
//! Run: `cargo bench -p render --bench render_frame -- --warm-up-time 1 --measurement-time 3`

use criterion::{Criterion, criterion_group, criterion_main};
use render::hud::HudPainter;
use render::mesh::{MeshBuilder, build_world};
use render::{Renderer, demo};

const W: u32 = 1280;
const H: u32 = 720;

fn frames(c: &mut Criterion) {
    let mut renderer = match Renderer::new_headless(W, H) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("render bench skipped: {e}");
            return;
        }
    };
    eprintln!("render bench adapter: {}", renderer.adapter());
    let mut group = c.benchmark_group("frame_1280x720");
    group.sample_size(20);
    for name in demo::NAMES {
        let scene = demo::by_name(name, 4.0).expect("demo name");
        group.bench_function(name, |b| {
            b.iter(|| renderer.render_to_rgba(&scene).expect("frame"));
        });
    }
    group.finish();
}

fn cpu_parts(c: &mut Criterion) {
    let mut group = c.benchmark_group("cpu");
    let scene = demo::slalom(4.0);
    let mut mesh = MeshBuilder::default();
    group.bench_function("mesh_slalom", |b| b.iter(|| build_world(&mut mesh, &scene)));
    let mut hud = HudPainter::new();
    group.bench_function("hud_layout_slalom", |b| b.iter(|| hud.run(&scene, W, H)));
    group.finish();
}

criterion_group!(benches, frames, cpu_parts);
criterion_main!(benches);
