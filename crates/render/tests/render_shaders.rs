//! Every WGSL shader of the renderer parses and validates with naga, declares the entry
//! points the pipelines use, and agrees with the Rust side on the uniform block's size.

use std::path::PathBuf;

use naga::valid::{Capabilities, ValidationFlags, Validator};

fn shader_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("src/shaders")
}

fn parse_and_validate(name: &str, source: &str) -> naga::Module {
    let module = naga::front::wgsl::parse_str(source)
        .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)));
    Validator::new(ValidationFlags::all(), Capabilities::default())
        .validate(&module)
        .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)));
    module
}

#[test]
fn every_wgsl_file_in_the_shader_directory_validates() {
    let mut seen = 0;
    for entry in std::fs::read_dir(shader_dir()).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "wgsl") {
            let src = std::fs::read_to_string(&path).unwrap();
            parse_and_validate(&path.display().to_string(), &src);
            seen += 1;
        }
    }
    assert!(
        seen >= 2,
        "expected the world and sky shaders, found {seen} files"
    );
}

#[test]
fn compiled_in_shaders_have_vertex_and_fragment_entry_points() {
    for (name, src) in [("world", render::WORLD_WGSL), ("sky", render::SKY_WGSL)] {
        let module = parse_and_validate(name, src);
        let stages: Vec<_> = module
            .entry_points
            .iter()
            .map(|e| (e.name.as_str(), e.stage))
            .collect();
        assert!(
            stages.contains(&("vs_main", naga::ShaderStage::Vertex)),
            "{name}: {stages:?}"
        );
        assert!(
            stages.contains(&("fs_main", naga::ShaderStage::Fragment)),
            "{name}: {stages:?}"
        );
    }
}

#[test]
fn frame_uniform_block_matches_the_rust_struct_size() {
    for (name, src) in [("world", render::WORLD_WGSL), ("sky", render::SKY_WGSL)] {
        let module = parse_and_validate(name, src);
        let mut layouter = naga::proc::Layouter::default();
        layouter.update(module.to_ctx()).unwrap();
        let (handle, _) = module
            .types
            .iter()
            .find(|(_, t)| t.name.as_deref() == Some("Frame"))
            .unwrap_or_else(|| panic!("{name}: no Frame struct"));
        assert_eq!(
            layouter[handle].size as usize,
            render::FRAME_UNIFORM_BYTES,
            "{name}: WGSL Frame and Rust FrameUniform differ"
        );
    }
}
