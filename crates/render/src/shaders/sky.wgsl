// Sky pass: one full-screen triangle, coloured by the elevation of each pixel's view ray.

struct Frame {
    view_proj: mat4x4<f32>,
    camera_pos: vec4<f32>,
    cam_forward: vec4<f32>,
    cam_right: vec4<f32>,
    cam_up: vec4<f32>,
    sky_horizon: vec4<f32>,
    sky_zenith: vec4<f32>,
    grass_a: vec4<f32>,
    grass_b: vec4<f32>,
    params: vec4<f32>,
};

@group(0) @binding(0) var<uniform> frame: Frame;

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) ndc: vec2<f32>,
};

@vertex
fn vs_main(@builtin(vertex_index) i: u32) -> VsOut {
    // Vertices (-1,-1), (3,-1), (-1,3) cover the whole viewport.
    let x = f32(i32(i & 1u) * 4 - 1);
    let y = f32(i32(i >> 1u) * 4 - 1);
    var out: VsOut;
    // Depth 1: behind everything the world pass draws.
    out.clip = vec4<f32>(x, y, 1.0, 1.0);
    out.ndc = vec2<f32>(x, y);
    return out;
}

@fragment
fn fs_main(in: VsOut) -> @location(0) vec4<f32> {
    let t = frame.cam_forward.w;
    let aspect = frame.cam_right.w;
    let ray = normalize(
        frame.cam_forward.xyz
        + frame.cam_right.xyz * (in.ndc.x * t * aspect)
        + frame.cam_up.xyz * (in.ndc.y * t)
    );
    // Elevation 0 at the horizon, 1 overhead; below the horizon the ground covers the sky.
    let e = clamp(ray.z, 0.0, 1.0);
    let k = sqrt(e);
    return vec4<f32>(mix(frame.sky_horizon.rgb, frame.sky_zenith.rgb, k), 1.0);
}
