// Shared by the screen-space SSS passes. Twin of `render::gpu_types::SssUniforms`.

struct SssUniforms {
    size: vec2<f32>,                    // pixels
    pixels_per_unit_at_depth_1: f32,    // height / (2 tan(fovy/2))
    mm_per_unit: f32,
    rotation_offset_turns: f32,         // of this progressive-refinement frame
    deterministic: u32,                 // 1: no per-pixel rotation (tests)
    sample_count: u32,                  // samples or taps
    lut_radius_mm: f32,                 // the profile table's largest radius
    lut_entries: u32,
    follow_surface: f32,                // > 0: 2012 lerp per mm; < 0: −1/(2σ²) of Jimenez 2015 eq. 7
    direction: vec2<f32>,               // a separable pass's blur direction
    rotate_axis: u32,                   // 1 = stochastic axis rotation
    pad0: u32,
    pad1: u32,
    pad2: u32,
    weight: vec4<f32>,                  // rgb: output multiplier (a Gaussian's weight when accumulating; 1 otherwise)
};

@group(0) @binding(0) var<uniform> s: SssUniforms;
@group(0) @binding(1) var diffuse_tex: texture_2d<f32>;
// Linear view depth (world units), 0 on the background.
@group(0) @binding(2) var depth_tex: texture_2d<f32>;

// The diffuse target's alpha where there is no skin, beside their Rust
// twins in render/gpu_types.rs: eyes and teeth (the scene pass), and the
// background (the target's clear).
const DIFFUSE_ALPHA_NOT_SKIN: f32 = -1.0;
const DIFFUSE_ALPHA_BACKGROUND: f32 = -2.0;

// What a fetched pixel gives the skin around it (the edge convention of
// issue 22, the ground truth's too): rgb its light, a its weight's share.
// - Skin, inside the mask or not (skin scatters under brows): its light,
//   weight counted.
// - Eyes and teeth: the skin's medium ends there and they give it no
//   light, as in the ground truth, which integrates over the skin only: no
//   light, but the weight counted (the light is lost, not renormalised).
// - Background: no surface is seen, though the skin goes on beyond the
//   silhouette (the ground truth sees it): weight 0, renormalised away.
fn light_from(c: vec4<f32>) -> vec4<f32> {
    if (c.a > 0.5 * DIFFUSE_ALPHA_NOT_SKIN) {
        return vec4<f32>(c.rgb, 1.0);
    }
    if (c.a > 0.5 * (DIFFUSE_ALPHA_NOT_SKIN + DIFFUSE_ALPHA_BACKGROUND)) {
        return vec4<f32>(0.0, 0.0, 0.0, 1.0);
    }
    return vec4<f32>(0.0);
}

fn load_diffuse(p: vec2<i32>) -> vec4<f32> {
    let c = clamp(p, vec2<i32>(0), vec2<i32>(s.size) - vec2<i32>(1));
    return textureLoad(diffuse_tex, c, 0);
}

fn load_depth(p: vec2<i32>) -> f32 {
    let c = clamp(p, vec2<i32>(0), vec2<i32>(s.size) - vec2<i32>(1));
    return textureLoad(depth_tex, c, 0).r;
}

// Pixels per millimetre on a surface at view depth z (world units).
fn pixels_per_mm(z: f32) -> f32 {
    return s.pixels_per_unit_at_depth_1 / (max(z, 1e-6) * s.mm_per_unit);
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
    return fract(h + s.rotation_offset_turns);
}
