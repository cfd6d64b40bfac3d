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
// r·R_N(r) per channel at r = r_max·t², t = i/(size−1).
@group(0) @binding(4) var<storage, read> profile_lut: array<vec4<f32>>;
// [0]: samples taken, [1]: pixels convolved, [2]: pixels skipped by the LOD.
@group(0) @binding(5) var<storage, read_write> counters: array<atomic<u32>, 4>;
// x: samples of the low-LOD pattern stored after the main one; y: filter
// radius (mm, the widest channel's 0.997 radius); z: LOD on (1) or off (0).
@group(0) @binding(6) var<uniform> lod: vec4<f32>;

fn profile_rr(r_mm: f32) -> vec3<f32> {
    let n = s.params.w;
    let t = sqrt(clamp(r_mm / s.params.z, 0.0, 1.0)) * (n - 1.0);
    let i = min(u32(t), u32(n) - 2u);
    let f = t - f32(i);
    return mix(profile_lut[i].rgb, profile_lut[i + 1u].rgb, f);
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
    var n = u32(s.params.x);
    let radius_px = lod.y * ppm;
    if (lod.z > 0.5) {
        if (radius_px < 1.0) {
            atomicAdd(&counters[2], 1u);
            return centre;
        }
        if (radius_px < 4.0) {
            first = n;
            n = u32(lod.x);
        }
    }
    atomicAdd(&counters[1], 1u);
    atomicAdd(&counters[0], n);
    var rotation = 0.0;
    if (s.params.y < 0.5) {
        rotation = 6.28318531 * hash(vec2<u32>(p));
    }
    var sum = vec3<f32>(0.0);
    var wsum = vec3<f32>(0.0);
    for (var i = 0u; i < n; i = i + 1u) {
        let smp = samples[first + i];
        let a = smp.angle + rotation;
        let off = vec2<f32>(cos(a), sin(a)) * smp.radius_mm * ppm;
        let q = p + vec2<i32>(round(off));
        let c = load_diffuse(q);
        let dz_mm = (load_depth(q) - z) * s.projection.y;
        let rho = sqrt(smp.radius_mm * smp.radius_mm + dz_mm * dz_mm);
        // R(ρ)/pdf(r): r·R(ρ)/ρ divided by the planar density.
        var w = profile_rr(rho) / max(rho, 1e-6) * smp.inv_pdf;
        if (c.a <= 1.0 / 255.0) {
            w = vec3<f32>(0.0);
        }
        sum = sum + w * c.rgb;
        wsum = wsum + w;
    }
    let blurred = select(centre.rgb, sum / wsum, wsum > vec3<f32>(0.0));
    return vec4<f32>(blurred, centre.a);
}
