// World pass: flat-shaded triangles of the road scene, a ground checker, distance haze.

struct Frame {
    view_proj: mat4x4<f32>,
    // Camera position (xyz), w unused.
    camera_pos: vec4<f32>,
    // Camera basis for the sky ray: forward.xyz + tan(fov_y / 2) in w.
    cam_forward: vec4<f32>,
    // right.xyz + aspect in w.
    cam_right: vec4<f32>,
    // up.xyz, w unused.
    cam_up: vec4<f32>,
    sky_horizon: vec4<f32>,
    sky_zenith: vec4<f32>,
    grass_a: vec4<f32>,
    grass_b: vec4<f32>,
    // x = haze start (m), y = haze end (m), z = checker cell size (m).
    params: vec4<f32>,
};

@group(0) @binding(0) var<uniform> frame: Frame;

struct VsIn {
    @location(0) pos: vec3<f32>,
    @location(1) pattern: f32,
    @location(2) color: vec4<f32>,
};

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) pattern: f32,
    @location(2) color: vec4<f32>,
};

@vertex
fn vs_main(v: VsIn) -> VsOut {
    var out: VsOut;
    out.clip = frame.view_proj * vec4<f32>(v.pos, 1.0);
    out.world = v.pos;
    out.pattern = v.pattern;
    out.color = v.color;
    return out;
}

@fragment
fn fs_main(in: VsOut) -> @location(0) vec4<f32> {
    var rgb = in.color.rgb;
    if (in.pattern > 0.5) {
        let cell = floor(in.world.xy / frame.params.z);
        var odd = abs(cell.x + cell.y) % 2.0;
        // Fade the checker to its mean where cells get smaller than a few pixels (no moiré).
        let footprint = fwidth(in.world.xy) / frame.params.z;
        let fade = clamp(max(footprint.x, footprint.y) * 3.0, 0.0, 1.0);
        odd = mix(odd, 0.5, fade);
        rgb = mix(frame.grass_a.rgb, frame.grass_b.rgb, odd);
    }
    let d = distance(in.world, frame.camera_pos.xyz);
    let haze = clamp((d - frame.params.x) / (frame.params.y - frame.params.x), 0.0, 1.0);
    rgb = mix(rgb, frame.sky_horizon.rgb, haze * haze * (3.0 - 2.0 * haze));
    return vec4<f32>(rgb, 1.0);
}
