// Burley normalized diffusion in screen space (Golubev 2018): importance-
// sampled disk, per-pixel random rotation (switchable for tests), and
// energy-normalised bilateral weights that evaluate the profile at the
// Euclidean distance √(r² + Δz²).

struct Sample {
    radius_mm: f32,
    angle: f32,
    inv_pdf: f32,     // A_dom / R_dom(r): the planar importance weight's denominator
    pad: f32,
};

@group(0) @binding(3) var<storage, read> samples: array<Sample>;
// r·R_N(r) per channel at r = r_max·t², t = i/(size−1); then, at
// [size, 2·size), the CDF at the same radii.
@group(0) @binding(4) var<storage, read> profile_lut: array<vec4<f32>>;
// [0]: samples taken, [1]: pixels convolved, [2]: pixels skipped by the LOD.
@group(0) @binding(5) var<storage, read_write> counters: array<atomic<u32>, 4>;
// Sampling flags (render/settings.rs BurleySampling::shader_flags), beside
// their Rust twins in render/gpu_types.rs.
const SAMPLING_R2_ROTATION: u32 = 1u;
const SAMPLING_CENTRE_WEIGHT: u32 = 2u;
const SAMPLING_BILINEAR: u32 = 4u;

// The discrete LOD and the sampling flags. Twin of
// `render::gpu_types::BurleyUniforms`.
struct BurleyUniforms {
    low_count: u32,          // samples of the low-LOD pattern stored after the main one
    filter_radius_mm: f32,   // the widest channel's 0.997 radius
    lod_on: u32,
    flags: u32,              // SAMPLING_* bits
};
@group(0) @binding(6) var<uniform> lod: BurleyUniforms;

fn profile_rr(r_mm: f32) -> vec3<f32> {
    let n = f32(s.lut_entries);
    let t = sqrt(clamp(r_mm / s.lut_radius_mm, 0.0, 1.0)) * (n - 1.0);
    let i = min(u32(t), u32(n) - 2u);
    let f = t - f32(i);
    return mix(profile_lut[i].rgb, profile_lut[i + 1u].rgb, f);
}

// The CDF per channel (the table's second half).
fn profile_cdf(r_mm: f32) -> vec3<f32> {
    let n = f32(s.lut_entries);
    let t = sqrt(clamp(r_mm / s.lut_radius_mm, 0.0, 1.0)) * (n - 1.0);
    let i = min(u32(t), u32(n) - 2u);
    let f = t - f32(i);
    let o = u32(n);
    return mix(profile_lut[o + i].rgb, profile_lut[o + i + 1u].rgb, f);
}

// The light at a fractional position (pixel centres at +0.5), bilinear
// over the four nearest texels as `light_from` counts them; .a is the
// bilinear weight they count (0 when all four are background).
fn light_bilinear(pos: vec2<f32>) -> vec4<f32> {
    let f = pos - vec2<f32>(0.5);
    let i = vec2<i32>(floor(f));
    let t = f - floor(f);
    var col = vec3<f32>(0.0);
    var covered = 0.0;
    for (var k = 0; k < 4; k = k + 1) {
        let o = vec2<i32>(k & 1, k >> 1u);
        let bw = select(1.0 - t.x, t.x, o.x == 1) * select(1.0 - t.y, t.y, o.y == 1);
        let l = light_from(load_diffuse(i + o));
        col = col + bw * l.a * l.rgb;
        covered = covered + bw * l.a;
    }
    return vec4<f32>(col / max(covered, 1e-6), covered);
}

// The R2 sequence (Roberts 2018) over the pixel grid: plastic-number
// steps along x and y give neighbouring pixels well-spread values.
fn r2(p: vec2<i32>) -> f32 {
    return fract(0.5 + f32(p.x) * 0.7548776662 + f32(p.y) * 0.5698402910);
}

@fragment
fn fs_burley(in: FullscreenOut) -> @location(0) vec4<f32> {
    let p = vec2<i32>(in.clip.xy);
    let centre = load_diffuse(p);
    if (centre.a <= 1.0 / 255.0) {
        return centre;
    }
    let z = load_depth(p);
    let ppm = pixels_per_mm(z) * centre.a;
    // Discrete LOD (Golubev 2018): no convolution when the disk fits in a
    // pixel, the short pattern when it fits in a 4×4 footprint.
    var first = 0u;
    var n = s.sample_count;
    let radius_px = lod.filter_radius_mm * ppm;
    if (lod.lod_on == 1u) {
        if (radius_px < 1.0) {
            atomicAdd(&counters[2], 1u);
            return centre;
        }
        if (radius_px < 4.0) {
            first = n;
            n = lod.low_count;
        }
    }
    atomicAdd(&counters[1], 1u);
    let flags = lod.flags;
    var rotation = 0.0;
    if (s.deterministic == 0u) {
        if ((flags & SAMPLING_R2_ROTATION) != 0u) {
            rotation = 6.28318531 * rotation_turns(r2(p));
        } else {
            rotation = 6.28318531 * rotation_turns(hash(vec2<u32>(p)));
        }
    }
    // Centre weight: the pixel's own footprint (a disk of one pixel's
    // area) holds CDF(r_px) of the energy, taken from the centre exactly;
    // samples inside it would land on the centre pixel and are skipped.
    // Without it, the centre keeps the profile's Dirac share, CDF(0) per
    // channel (Jimenez 2012's 1 − strength; 0 for most profiles): the
    // pattern samples only the continuous part.
    var r_centre = 0.0;
    var w_centre = profile_cdf(0.0);
    if ((flags & SAMPLING_CENTRE_WEIGHT) != 0u) {
        r_centre = 0.5641896 / ppm;
        w_centre = profile_cdf(r_centre);
    }
    var sum = vec3<f32>(0.0);
    var wsum = vec3<f32>(0.0);
    var taken = 0u;
    for (var i = 0u; i < n; i = i + 1u) {
        let smp = samples[first + i];
        if (smp.radius_mm < r_centre) {
            continue;
        }
        taken = taken + 1u;
        let a = smp.angle + rotation;
        let off = vec2<f32>(cos(a), sin(a)) * smp.radius_mm * ppm;
        let q = p + vec2<i32>(round(off));
        var c = light_from(load_diffuse(q));
        if ((flags & SAMPLING_BILINEAR) != 0u) {
            // Bilinear at the exact offset instead of the nearest pixel.
            c = light_bilinear(vec2<f32>(p) + vec2<f32>(0.5) + off);
        }
        let coverage = c.a;
        let dz_mm = (load_depth(q) - z) * s.mm_per_unit;
        let rho = sqrt(smp.radius_mm * smp.radius_mm + dz_mm * dz_mm);
        // R(ρ)/pdf(r): r·R(ρ)/ρ divided by the planar density, times the
        // share of the fetch whose weight counts (`light_from`).
        let w = profile_rr(rho) / max(rho, 1e-6) * smp.inv_pdf * coverage;
        sum = sum + w * c.rgb;
        wsum = wsum + w;
    }
    atomicAdd(&counters[0], taken);
    let ring = select(centre.rgb, sum / wsum, wsum > vec3<f32>(0.0));
    let blurred = mix(ring, centre.rgb, w_centre);
    return vec4<f32>(blurred, centre.a);
}
