// Recombine: scattered diffuse × albedo^post + specular, then exposure and
// a display transform (`tone_map`, TONE_*; CPU twins and sources in
// src/render/tonemap.rs); the sRGB target encodes.

const TONE_ACES_FIT: u32 = 0u;
const TONE_ACES: u32 = 1u;
const TONE_AGX: u32 = 2u;
const TONE_PBR_NEUTRAL: u32 = 3u;

struct CompositeUniforms {
    exposure: f32,   // multiplier
    tone_map: u32,   // TONE_*
    background_on: u32,
    background_lod: f32,
    background_turn: f32,
    background_intensity: f32,
    frame_width: f32,
    frame_height: f32,
    direction_from_clip: mat4x4<f32>,
};

@group(0) @binding(0) var<uniform> c: CompositeUniforms;
// The method's output: written only on SSS pixels (alpha > 0 there).
@group(0) @binding(1) var scattered_tex: texture_2d<f32>;
@group(0) @binding(2) var specular_tex: texture_2d<f32>;
// rgb: albedo^post, a: 1 on the mesh, 0 on the background.
@group(0) @binding(3) var albedo_tex: texture_2d<f32>;
// The scene's diffuse irradiance, used where no SSS pass wrote.
@group(0) @binding(4) var diffuse_tex: texture_2d<f32>;
// The environment map (equirectangular, linear, mipmapped) and its sampler
// (u repeats, v clamps).
@group(0) @binding(5) var background_tex: texture_2d<f32>;
@group(0) @binding(6) var background_sampler: sampler;

const TAU: f32 = 6.283185307;
const PI: f32 = 3.141592654;

// The environment seen through the pixel: the direction from the eye,
// mapped as `environment::direction_to_equirect` does, turned by
// background_turn.
fn background(clip: vec4<f32>) -> vec3<f32> {
    let dims = vec2<f32>(c.frame_width, c.frame_height);
    let ndc = vec2<f32>(clip.x / dims.x * 2.0 - 1.0, 1.0 - clip.y / dims.y * 2.0);
    let p = c.direction_from_clip * vec4<f32>(ndc, 0.5, 1.0);
    let d = normalize(p.xyz / p.w);
    let u = 0.5 + atan2(d.x, -d.z) / TAU - c.background_turn;
    let v = acos(clamp(d.y, -1.0, 1.0)) / PI;
    return textureSampleLevel(background_tex, background_sampler, vec2<f32>(u, v), c.background_lod).rgb * c.background_intensity;
}

// Narkowicz 2015's fit of ACES' filmic curve.
fn aces_fit(x: vec3<f32>) -> vec3<f32> {
    let a = 2.51;
    let b = 0.03;
    let cc = 2.43;
    let d = 0.59;
    let e = 0.14;
    return (x * (a * x + b)) / (x * (cc * x + d) + e);
}

// Hill's ACES RRT+ODT fit (BakingLab ACES.hlsl). WGSL's mat3x3 takes
// columns: each vec3 here is a column of the row-major matrices in
// tonemap.rs.
fn aces_hill(c: vec3<f32>) -> vec3<f32> {
    let input = mat3x3<f32>(
        vec3<f32>(0.59719, 0.07600, 0.02840),
        vec3<f32>(0.35458, 0.90834, 0.13383),
        vec3<f32>(0.04823, 0.01566, 0.83777));
    let output = mat3x3<f32>(
        vec3<f32>(1.60475, -0.10208, -0.00327),
        vec3<f32>(-0.53108, 1.10813, -0.07276),
        vec3<f32>(-0.07367, -0.00605, 1.07602));
    let v = input * c;
    let a = v * (v + 0.0245786) - 0.000090537;
    let b = v * (0.983729 * v + 0.4329510) + 0.238081;
    return output * (a / b);
}

fn srgb_decode(v: vec3<f32>) -> vec3<f32> {
    return select(pow((v + 0.055) / 1.055, vec3<f32>(2.4)), v / 12.92, v <= vec3<f32>(0.04045));
}

// Sobotka's AgX, Wrensch's 2024 minimal fit; decoded by sRGB's curve so
// the sRGB target writes the curve's display value.
fn agx(c: vec3<f32>) -> vec3<f32> {
    let inset = mat3x3<f32>(
        vec3<f32>(0.842479062253094, 0.0423282422610123, 0.0423756549057051),
        vec3<f32>(0.0784335999999992, 0.878468636469772, 0.0784336),
        vec3<f32>(0.0792237451477643, 0.0791661274605434, 0.879142973793104));
    let outset = mat3x3<f32>(
        vec3<f32>(1.19687900512017, -0.0528968517574562, -0.0529716355144438),
        vec3<f32>(-0.0980208811401368, 1.15190312990417, -0.0980434501171241),
        vec3<f32>(-0.0990297440797205, -0.0989611768448433, 1.15107367264116));
    let min_ev = -12.47393;
    let max_ev = 4.026069;
    var v = inset * c;
    v = clamp(log2(max(v, vec3<f32>(1e-10))), vec3<f32>(min_ev), vec3<f32>(max_ev));
    let x = (v - min_ev) / (max_ev - min_ev);
    let x2 = x * x;
    let x4 = x2 * x2;
    let y = 15.5 * x4 * x2 - 40.14 * x4 * x + 31.96 * x4 - 6.868 * x2 * x + 0.4298 * x2 + 0.1191 * x - 0.00232;
    return srgb_decode(clamp(outset * y, vec3<f32>(0.0), vec3<f32>(1.0)));
}

// Khronos PBR Neutral, by the README's equations (tonemap.rs).
fn pbr_neutral(c_in: vec3<f32>) -> vec3<f32> {
    let f90 = 0.04;
    let ks = 0.8 - f90;
    let kd = 0.15;
    let x = min(c_in.r, min(c_in.g, c_in.b));
    let f = select(f90, x - x * x / (4.0 * f90), x <= 2.0 * f90);
    let c = c_in - f;
    let p = max(c.r, max(c.g, c.b));
    if (p <= ks) {
        return c;
    }
    let pn = 1.0 - (1.0 - ks) * (1.0 - ks) / (p + 1.0 - 2.0 * ks);
    let g = 1.0 / (kd * (p - pn) + 1.0);
    return c * (pn / p * g) + vec3<f32>(pn * (1.0 - g));
}

fn tone_map(x_in: vec3<f32>) -> vec3<f32> {
    let x = max(x_in, vec3<f32>(0.0));
    var y: vec3<f32>;
    switch c.tone_map {
        case TONE_ACES: { y = aces_hill(x); }
        case TONE_AGX: { y = agx(x); }
        case TONE_PBR_NEUTRAL: { y = pbr_neutral(x); }
        default: { y = aces_fit(x); }
    }
    return clamp(y, vec3<f32>(0.0), vec3<f32>(1.0));
}

@fragment
fn fs_composite(in: FullscreenOut) -> @location(0) vec4<f32> {
    let p = vec2<i32>(in.clip.xy);
    let scattered = textureLoad(scattered_tex, p, 0);
    let d = select(textureLoad(diffuse_tex, p, 0), scattered, scattered.a > 1.0 / 255.0);
    let sp = textureLoad(specular_tex, p, 0);
    let ad = textureLoad(albedo_tex, p, 0);
    if (ad.a <= 0.0) {
        // Background: the environment map, else a dim studio grey.
        if (c.background_on == 1u) {
            return vec4<f32>(tone_map(background(in.clip) * c.exposure), 1.0);
        }
        return vec4<f32>(tone_map(vec3<f32>(0.05, 0.055, 0.06) * c.exposure), 1.0);
    }
    let hdr = d.rgb * ad.rgb + sp.rgb;
    return vec4<f32>(tone_map(hdr * c.exposure), 1.0);
}

// Progressive refinement: the method's output joins the running mean of
// the frames before it. The pipeline blends with the constant c = 1/(n+1)
// (`pipelines::Output::Mean`): mean_{n+1} = c·x + (1 − c)·mean_n, the
// incremental mean. Alpha (the SSS mask, the same every frame) stays.
@fragment
fn fs_accumulate(in: FullscreenOut) -> @location(0) vec4<f32> {
    return textureLoad(scattered_tex, vec2<i32>(in.clip.xy), 0);
}
