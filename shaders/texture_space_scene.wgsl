// `texture-space` (d'Eon & Luebke 2007, GPU Gems 3 ch. 14: texture-space
// diffusion): scene.wgsl is prefixed to this file, its bindings in group
// 0; this file's own are in group 1.
//
// 1. `vs_atlas`/`fs_atlas` rasterise the mesh at its UVs into the atlas
//    (d'Eon & Luebke 2007 §14.4.1: "the irradiance texture"), every
//    triangle, seen or not: the lid margin and the back of the ear get
//    their light although the camera cannot see them. Each texel gets what
//    the scene pass would write there (`shade`, transmission included)
//    and its surface position (mm, as two half floats).
// 2. `fs_gather` draws the mesh again with the scene pass's vertex shader
//    and depth (compare Equal) on the SSS pixels (the classify pass's
//    stencil). At each pixel it places burley's importance-sampled disk
//    (Golubev 2018: its samples and profile table) on the surface's
//    tangent plane in mm, carries each sample into UV by the triangle's
//    own surface-to-UV map (from the rasteriser's derivatives of the
//    position and the UV: exact per triangle, d'Eon's stretch map without
//    its isotropy), reads the atlas there, and weighs the sample by the
//    profile at the 3D distance between the two surface points, with
//    weights normalised as `fs_burley`'s are: a sample that crosses a UV
//    seam lands on another island, far away in 3D, and weighs next to
//    nothing. Samples nearer than `--near-field-mm` (1 mm) are read on
//    screen instead, as fs_burley reads them: a screen-space near field
//    with an object-space middle field (the atlas's texels, about 1 mm on
//    the default head at 1024², are coarser than the green and blue
//    profiles). d'Eon blurs the whole atlas with six separable Gaussians
//    instead; gathering at the pixels on screen costs 35–47 ms on lavapipe
//    at 640 × 360, where blurring a 1024² atlas cost 78 ms
//    (docs/accuracy.md).

@vertex
fn vs_atlas(v: VertexIn) -> VertexOut {
    var o: VertexOut;
    o.world = v.position;
    o.normal = v.normal;
    o.uv = v.uv;
    o.material = v.material;
    o.view_depth = -(u.view_from_world * vec4<f32>(v.position, 1.0)).z;
    o.curvature = v.curvature;
    o.thickness = v.thickness;
    o.tangent = v.tangent;
    // Texel row y = v·N: NDC y runs up, so y_ndc = 1 − 2v.
    o.clip = vec4<f32>(2.0 * v.uv.x - 1.0, 1.0 - 2.0 * v.uv.y, 0.5, 1.0);
    return o;
}

struct AtlasOut {
    // What the scene pass writes to its diffuse target (scene.wgsl's head).
    @location(0) diffuse: vec4<f32>,
    // xyz: the surface point (mm) rounded to half floats, w: 1 where a
    // triangle covers the texel; and what the rounding left out, with the
    // texel's area (mm²) in w (half
    // floats: a 32-bit target is not renderable on every backend, GL's
    // included, and hi + lo keeps ~1e-4 mm where half floats alone would
    // keep 0.125 mm at 200 mm).
    @location(1) position_hi: vec4<f32>,
    @location(2) position_lo: vec4<f32>,
};

@fragment
fn fs_atlas(i: VertexOut) -> AtlasOut {
    return atlas_out(i, true);
}

// The atlas without the scene pass's transmission term, for the gather by
// 3D neighbourhood (texture_space_cloud.wgsl), which takes the light
// through thin parts from their far side's texels, as the ground truth
// does (render/scene_cpu.rs: transmission is not added).
@fragment
fn fs_atlas_untransmitted(i: VertexOut) -> AtlasOut {
    return atlas_out(i, false);
}

// The surface each sample of a 4× multisampled atlas stands for, and its
// light (without transmission; eyes and teeth give none): A_J·E and A_J,
// A_J the triangle's surface per texel. Resolved (the samples' mean), a
// texel holds the surface that lies in it, Σ over the triangles that cover
// its samples, whether or not its centre is covered, and that surface's
// light: the gather by 3D neighbourhood's areas (texture_space_tree.wgsl).
// The single-sample atlas gave a texel at an island's edge the whole
// texel's surface where its centre was covered and none where it was not,
// which lost up to 4.5 % of the light along a UV seam.
@fragment
fn fs_atlas_coverage(i: VertexOut) -> @location(0) vec4<f32> {
    let o = atlas_out(i, false);
    let skin = o.diffuse.a > 0.5 * DIFFUSE_ALPHA_NOT_SKIN;
    let area = o.position_lo.w;
    return vec4<f32>(select(vec3<f32>(0.0), o.diffuse.rgb, skin) * area, area);
}

fn atlas_out(i: VertexOut, transmission: bool) -> AtlasOut {
    var maps: Maps;
    maps.albedo = textureSample(albedo_map, surface_sampler, i.uv).rgb;
    maps.normal = textureSample(normal_map, surface_sampler, i.uv).xyz * 2.0 - 1.0;
    maps.roughness = textureSample(roughness_map, surface_sampler, i.uv).r;
    maps.mask = textureSample(mask_map, surface_sampler, i.uv).r;
    maps.thickness = textureSample(thickness_map, surface_sampler, i.uv).r;
    maps.blurred_r = maps.normal;
    maps.blurred_g = maps.normal;
    maps.blurred_b = maps.normal;
    var o: AtlasOut;
    o.diffuse = shade(i, maps, transmission).diffuse;
    let p = i.world * u.mm_per_unit;
    let hi = vec3<f32>(unpack2x16float(pack2x16float(p.xy)), unpack2x16float(pack2x16float(vec2<f32>(p.z, 0.0))).x);
    o.position_hi = vec4<f32>(hi, 1.0);
    // w: the surface the texel covers (mm²), for `--neighbours 3d`'s
    // point cloud (texture_space_tree.wgsl): a step of one texel moves
    // dpdx and dpdy over the surface.
    o.position_lo = vec4<f32>(p - hi, length(cross(dpdx(p), dpdy(p))));
    return o;
}

// Twin of `render::gpu_types::SssUniforms` (as sss_common.wgsl declares
// it; this module cannot include that file, whose bindings are scene.wgsl's).
struct SssUniforms {
    size: vec2<f32>,
    pixels_per_unit_at_depth_1: f32,
    mm_per_unit: f32,
    rotation_offset_turns: f32,
    deterministic: u32,
    sample_count: u32,
    lut_radius_mm: f32,
    lut_entries: u32,
    follow_surface: f32,
    direction: vec2<f32>,
    rotate_axis: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
    weight: vec4<f32>,
};

// Twin of `render::gpu_types::GpuSample` (sss_burley.wgsl's `Sample`).
struct Sample {
    radius_mm: f32,
    angle: f32,
    inv_pdf: f32,     // A_dom / R_dom(r)
    pad: f32,
};

@group(1) @binding(0) var<uniform> s: SssUniforms;
// The atlas: what `fs_atlas` wrote.
@group(1) @binding(1) var atlas_irradiance: texture_2d<f32>;
@group(1) @binding(2) var atlas_position_hi: texture_2d<f32>;
@group(1) @binding(3) var atlas_position_lo: texture_2d<f32>;
// The scene pass's diffuse target: the pixel's own light and SSS mask.
@group(1) @binding(4) var scene_diffuse: texture_2d<f32>;
// burley's pattern and table (sss_burley.wgsl): r·R_N(r) per channel,
// then the CDF.
@group(1) @binding(5) var<storage, read> samples: array<Sample>;
@group(1) @binding(6) var<storage, read> profile_lut: array<vec4<f32>>;
// The scene pass's linear view depth (world units).
@group(1) @binding(7) var scene_depth: texture_2d<f32>;

// Twin of `render::gpu_types::TextureSpaceUniforms`.
struct TextureSpaceUniforms {
    near_field_mm: f32,   // samples nearer are read on screen (0: none)
    pad0: f32,
    pad1: f32,
    pad2: f32,
};
@group(1) @binding(8) var<uniform> ts: TextureSpaceUniforms;

// The atlas's clear value where no triangle lies, and the background's on
// screen, beside its Rust twin (sss_common.wgsl's DIFFUSE_ALPHA_BACKGROUND).
const ATLAS_EMPTY: f32 = -2.0;

fn profile_rr(r_mm: f32) -> vec3<f32> {
    let n = f32(s.lut_entries);
    let t = sqrt(clamp(r_mm / s.lut_radius_mm, 0.0, 1.0)) * (n - 1.0);
    let i = min(u32(t), u32(n) - 2u);
    let f = t - f32(i);
    return mix(profile_lut[i].rgb, profile_lut[i + 1u].rgb, f);
}

// What a sample sees at a texel or pixel whose alpha is `a` (the scene
// pass's convention; sss_common.wgsl's `light_from`, the edge convention
// of issue 22): rgb its light, a its weight's share. Skin gives its light;
// eyes and teeth give none but count (the skin's medium ends there); no
// surface (an empty texel, the background) is renormalised away.
fn sees(a: f32, light: vec3<f32>) -> vec4<f32> {
    if (a > 0.5 * DIFFUSE_ALPHA_NOT_SKIN) {
        return vec4<f32>(light, 1.0);
    }
    if (a > 0.5 * (DIFFUSE_ALPHA_NOT_SKIN + ATLAS_EMPTY)) {
        return vec4<f32>(0.0, 0.0, 0.0, 1.0);
    }
    return vec4<f32>(0.0);
}

// One atlas texel as a sample sees it, and its surface point (mm; w = 1
// where covered).
fn atlas_texel(q: vec2<i32>) -> array<vec4<f32>, 2> {
    let size = vec2<i32>(textureDimensions(atlas_irradiance, 0));
    let c = clamp(q, vec2<i32>(0), size - vec2<i32>(1));
    let e = textureLoad(atlas_irradiance, c, 0);
    let hi = textureLoad(atlas_position_hi, c, 0);
    let p = vec4<f32>(hi.xyz + textureLoad(atlas_position_lo, c, 0).xyz, hi.w);
    return array<vec4<f32>, 2>(sees(e.a, e.rgb), p);
}

// The R2 sequence (Roberts 2018) over the pixel grid, as fs_burley's.
fn r2(p: vec2<i32>) -> f32 {
    return fract(0.5 + f32(p.x) * 0.7548776662 + f32(p.y) * 0.5698402910);
}

// The pixel's triangle maps (from the rasteriser's derivatives, taken
// by the entry point in uniform control flow): a step of one pixel moves
// W_x, W_y on the surface (mm) and D_x, D_y in UV.
struct TriangleMaps {
    wx: vec3<f32>,
    wy: vec3<f32>,
    dx: vec2<f32>,
    dy: vec2<f32>,
};

fn triangle_maps(i: VertexOut) -> TriangleMaps {
    var t: TriangleMaps;
    t.wx = dpdx(i.world) * u.mm_per_unit;
    t.wy = dpdy(i.world) * u.mm_per_unit;
    t.dx = dpdx(i.uv);
    t.dy = dpdy(i.uv);
    return t;
}

// mm of surface per unit of UV on the pixel's triangle (isotropic: √ of
// the area ratio).
fn mm_per_uv(t: TriangleMaps) -> f32 {
    return sqrt(length(cross(t.wx, t.wy)) / max(abs(t.dx.x * t.dy.y - t.dx.y * t.dy.x), 1e-30));
}

// What every one of the UV layout's samples at a pixel shares: the
// triangle's plane frame (e1 = W_x/|W_x|, e2 ⟂ e1 in the triangle's
// plane: W_x = (a, 0), W_y = (b, c) there, so a surface offset (s1, s2)
// mm is the pixel step (t_x, t_y) with t_y = s2/c, t_x = (s1 − b·t_y)/a,
// and the UV offset t_x·D_x + t_y·D_y), the surface point x (mm), the
// pixel's rotation and SSS mask m. `valid` is false where the triangle's
// map is degenerate.
struct UvFrame {
    valid: bool,
    x: vec3<f32>,
    e1: vec3<f32>,
    a: f32,
    b: f32,
    c: f32,
    // Half a texel's diagonal (mm): a sample is read at the nearest
    // texel's centre, up to this far from where it was placed (texel side
    // in mm: √(mm² per UV² of the triangle) / atlas size), so that much of
    // the 3D distance is rounding, not a step onto another sheet.
    rounding_mm: f32,
    rotation: f32,
    // Pixels per mm at the pixel's depth.
    ppm: f32,
    // The SSS mask m scales the profile's radii, as the ground truth's
    // (ρ_m(r) = ρ(r/m)/m², render/ground_truth/table.rs `Scaled`) and
    // fs_burley's disk do: the samples go out to r·m, and the weight
    // ρ_m/pdf_m is ρ(ρ/m)/pdf(r).
    m: f32,
};

fn uv_frame(i: VertexOut, t: TriangleMaps, pixel: vec4<f32>) -> UvFrame {
    var f: UvFrame;
    f.a = length(t.wx);
    f.e1 = t.wx / max(f.a, 1e-20);
    f.b = dot(t.wy, f.e1);
    f.c = length(t.wy - f.e1 * f.b);
    f.valid = f.a > 0.0 && f.c > 0.0;
    f.x = i.world * u.mm_per_unit;
    let size = vec2<f32>(textureDimensions(atlas_irradiance, 0));
    f.rounding_mm = 0.70710678 * mm_per_uv(t) / max(size.x, size.y);
    f.rotation = 0.0;
    if (s.deterministic == 0u) {
        f.rotation = 6.28318531 * fract(r2(vec2<i32>(i.clip.xy)) + s.rotation_offset_turns);
    }
    f.ppm = s.pixels_per_unit_at_depth_1 / (max(i.view_depth, 1e-6) * u.mm_per_unit);
    f.m = pixel.a;
    return f;
}

// One of burley's samples as the UV layout reads it: w·light, w, and
// whether it found the pixel's own sheet (a surface was there, no
// further than 2r + 1 mm from x in 3D: a sample that crossed a UV seam or
// an outline lands far away, and weighs next to nothing), and whether it
// was read on screen (the near field).
struct UvSample {
    light: vec3<f32>,
    w: vec3<f32>,
    found: bool,
    screen: bool,
};

fn uv_sample(i: VertexOut, t: TriangleMaps, f: UvFrame, k: u32) -> UvSample {
    return uv_sample_below(i, t, f, k, ts.near_field_mm);
}

// `uv_sample` with the samples under `screen_mm` (before the mask scales
// them) read on screen.
fn uv_sample_below(i: VertexOut, t: TriangleMaps, f: UvFrame, k: u32, screen_mm: f32) -> UvSample {
    var o: UvSample;
    let smp = samples[k];
    let angle = smp.angle + f.rotation;
    let dir = vec2<f32>(cos(angle), sin(angle));
    let r_mm = smp.radius_mm * f.m;
    if (smp.radius_mm < screen_mm) {
        // The near field on screen, as fs_burley reads it (pixel
        // resolution where the atlas's texels are coarser than the green
        // and blue profiles): the same sample on a disk facing the camera,
        // weighed at √(r² + Δz²).
        let screen = vec2<i32>(textureDimensions(scene_diffuse, 0));
        let p = vec2<i32>(i.clip.xy);
        let aimed = p + vec2<i32>(round(dir * r_mm * f.ppm));
        let q = clamp(aimed, vec2<i32>(0), screen - vec2<i32>(1));
        let e = textureLoad(scene_diffuse, q, 0);
        let seen = sees(e.a, e.rgb);
        let dz = (textureLoad(scene_depth, q, 0).r - i.view_depth) * u.mm_per_unit;
        let dist = sqrt(r_mm * r_mm + dz * dz);
        let rho = dist / f.m;
        o.w = profile_rr(rho) / max(rho, 1e-6) * smp.inv_pdf * seen.a;
        o.light = o.w * seen.rgb;
        // Off the frame the clamped pixel stands in for the sample (the
        // gather's convention); it did not find the surface there.
        o.found = seen.a > 0.0 && dist <= 2.0 * r_mm + 1.0 && all(aimed == q);
        o.screen = true;
        return o;
    }
    let d = dir * r_mm;
    let ty = d.y / f.c;
    let tx = (d.x - f.b * ty) / f.a;
    let uv = i.uv + tx * t.dx + ty * t.dy;
    let size = vec2<f32>(textureDimensions(atlas_irradiance, 0));
    let texel = atlas_texel(vec2<i32>(floor(uv * size)));
    let seen = texel[0];
    let y = texel[1];
    // The profile at the 3D distance less the rounding, never nearer than
    // the sample's own radius: r on the sample's own sheet, the 3D
    // distance where it crossed a seam onto another island.
    let dist = max(length(y.xyz - f.x) - f.rounding_mm, r_mm);
    let rho = dist / f.m;
    o.w = profile_rr(rho) / max(rho, 1e-6) * smp.inv_pdf * seen.a * y.w;
    o.light = o.w * seen.rgb;
    o.found = seen.a * y.w > 0.0 && dist <= 2.0 * r_mm + 1.0;
    return o;
}

// The UV layout's gather at the pixel: Σ w·light and Σ w over burley's
// samples (the near field on screen, the rest through the UV map), as
// `fs_gather` normalises them; w = 0 everywhere where the triangle's map
// is degenerate.
fn uv_gather(i: VertexOut, t: TriangleMaps, pixel: vec4<f32>) -> array<vec3<f32>, 2> {
    let f = uv_frame(i, t, pixel);
    var sum = vec3<f32>(0.0);
    var wsum = vec3<f32>(0.0);
    if (!f.valid) {
        return array<vec3<f32>, 2>(sum, wsum);
    }
    for (var k = 0u; k < s.sample_count; k = k + 1u) {
        let o = uv_sample(i, t, f, k);
        sum = sum + o.light;
        wsum = wsum + o.w;
    }
    return array<vec3<f32>, 2>(sum, wsum);
}

@fragment
fn fs_gather(i: VertexOut) -> @location(0) vec4<f32> {
    let t = triangle_maps(i);
    let pixel = textureLoad(scene_diffuse, vec2<i32>(i.clip.xy), 0);
    let g = uv_gather(i, t, pixel);
    // The centre carries the profile's Dirac share, CDF(0): the pixel's
    // own light, as fs_burley's centre (the atlas's texel there would
    // hand an unscattering share back at texel resolution, not as the
    // unscattered frame has it).
    let centre = pixel.rgb;
    let ring = select(centre, g[0] / g[1], g[1] > vec3<f32>(0.0));
    return vec4<f32>(mix(ring, centre, profile_lut[s.lut_entries].rgb), pixel.a);
}
