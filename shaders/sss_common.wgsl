// Shared by the screen-space SSS passes. Twin of `render::gpu_types::SssUniforms`.

struct SssUniforms {
    size: vec4<f32>,        // x: width, y: height, z: 1/width, w: 1/height
    projection: vec4<f32>,  // x: pixels per world unit at depth 1 (height / (2 tan(fovy/2))), y: mm per world unit, z: rotation offset (turns) of this progressive-refinement frame
    params: vec4<f32>,      // x: sample count, y: deterministic (1) or rotated (0), z: lut radius max (mm), w: lut size
    direction: vec4<f32>,   // xy: blur direction for separable passes, z: follow surface (> 0: 2012 lerp per mm; < 0: −1/(2σ²) of Jimenez 2015 eq. 7), w: 1 = stochastic axis rotation
    weight: vec4<f32>,      // rgb: output multiplier (a Gaussian's weight when accumulating; 1 otherwise)
};

@group(0) @binding(0) var<uniform> s: SssUniforms;
@group(0) @binding(1) var diffuse_tex: texture_2d<f32>;
// Linear view depth (world units), 0 on the background.
@group(0) @binding(2) var depth_tex: texture_2d<f32>;

fn load_diffuse(p: vec2<i32>) -> vec4<f32> {
    let c = clamp(p, vec2<i32>(0), vec2<i32>(s.size.xy) - vec2<i32>(1));
    return textureLoad(diffuse_tex, c, 0);
}

fn load_depth(p: vec2<i32>) -> f32 {
    let c = clamp(p, vec2<i32>(0), vec2<i32>(s.size.xy) - vec2<i32>(1));
    return textureLoad(depth_tex, c, 0).r;
}

// Pixels per millimetre on a surface at view depth z (world units).
fn pixels_per_mm(z: f32) -> f32 {
    return s.projection.x / (max(z, 1e-6) * s.projection.y);
}

// A per-pixel hash in [0, 1) (PCG), for random rotations.
fn hash(p: vec2<u32>) -> f32 {
    var v = p.x * 1973u + p.y * 9277u + 26699u;
    v = v * 747796405u + 2891336453u;
    let w = ((v >> ((v >> 28u) + 4u)) ^ v) * 277803737u;
    return f32((w >> 22u) ^ w) / 4294967296.0;
}

// A pixel's random rotation (turns) for this frame: the hash, offset by
// the progressive-refinement frame's rank-1 step (0 for a lone frame).
fn rotation_turns(h: f32) -> f32 {
    return fract(h + s.projection.z);
}
