// `texture-space`'s blur (d'Eon & Luebke 2007 §14.4, with Golubev 2018's
// importance-sampled Burley disk in place of the sum of Gaussians): over
// the irradiance atlas that texture_space_scene.wgsl's `fs_atlas` wrote,
// each covered skin texel gathers the profile's samples, placed on its
// tangent plane in mm and carried into texel steps by the texel's own
// 2×2 frame (the stretch map), weighted by the profile at the 3D distance
// between the two surface points: across a UV seam the sample lands on
// another island far away in 3D and weighs nearly nothing, and the
// weights are normalised as `fs_burley`'s are. Here `diffuse_tex` is the
// atlas's irradiance, `depth_tex` its surface positions (mm; w = 1 where
// covered) and `s.size` the atlas's size.

struct Sample {
    radius_mm: f32,
    angle: f32,
    inv_pdf: f32,
    pad: f32,
};

@group(0) @binding(3) var<storage, read> samples: array<Sample>;
// burley's table: r·R_N(r) per channel, then the CDF (sss_burley.wgsl).
@group(0) @binding(4) var<storage, read> profile_lut: array<vec4<f32>>;
@group(0) @binding(5) var frame_tex: texture_2d<f32>;

fn profile_rr(r_mm: f32) -> vec3<f32> {
    let n = f32(s.lut_entries);
    let t = sqrt(clamp(r_mm / s.lut_radius_mm, 0.0, 1.0)) * (n - 1.0);
    let i = min(u32(t), u32(n) - 2u);
    let f = t - f32(i);
    return mix(profile_lut[i].rgb, profile_lut[i + 1u].rgb, f);
}

fn profile_cdf0() -> vec3<f32> {
    return profile_lut[s.lut_entries].rgb;
}

fn load_position(p: vec2<i32>) -> vec4<f32> {
    let c = clamp(p, vec2<i32>(0), vec2<i32>(s.size) - vec2<i32>(1));
    return textureLoad(depth_tex, c, 0);
}

fn r2(p: vec2<i32>) -> f32 {
    return fract(0.5 + f32(p.x) * 0.7548776662 + f32(p.y) * 0.5698402910);
}

@fragment
fn fs_atlas_blur(in: FullscreenOut) -> @location(0) vec4<f32> {
    let p = vec2<i32>(in.clip.xy);
    let centre = load_diffuse(p);
    if (centre.a <= 1.0 / 255.0) {
        return centre;
    }
    let x = load_position(p).xyz;
    let fr = textureLoad(frame_tex, p, 0).xyz;
    if (fr.x <= 0.0 || fr.z <= 0.0) {
        return centre;
    }
    var rotation = 0.0;
    if (s.deterministic == 0u) {
        rotation = 6.28318531 * rotation_turns(r2(p));
    }
    var sum = vec3<f32>(0.0);
    var wsum = vec3<f32>(0.0);
    for (var i = 0u; i < s.sample_count; i = i + 1u) {
        let smp = samples[i];
        let a = smp.angle + rotation;
        let d = vec2<f32>(cos(a), sin(a)) * smp.radius_mm;
        let ty = d.y / fr.z;
        let tx = (d.x - fr.y * ty) / fr.x;
        let q = p + vec2<i32>(round(vec2<f32>(tx, ty)));
        let c = light_from(load_diffuse(q));
        let y = load_position(q);
        // The profile at the 3D distance, never nearer than the sample's
        // own radius (a sample rounded onto the centre texel).
        let rho = max(length(y.xyz - x), smp.radius_mm);
        let w = profile_rr(rho) / max(rho, 1e-6) * smp.inv_pdf * c.a * y.w;
        sum = sum + w * c.rgb;
        wsum = wsum + w;
    }
    let ring = select(centre.rgb, sum / wsum, wsum > vec3<f32>(0.0));
    return vec4<f32>(mix(ring, centre.rgb, profile_cdf0()), centre.a);
}
