// `texture-space`'s probe-ray gather (render/sss/texture_space/rays.rs):
// `enable wgpu_ray_query;`, scene.wgsl and texture_space_scene.wgsl come
// first; this file's own bindings are in group 2.
//
// At each SSS pixel x (mm) the UV layout's gather runs first
// (texture_space_scene.wgsl's `uv_gather`: the near field on screen, the
// rest of burley's samples through the triangle's surface-to-UV map).
// It finds the surface on x's own UV sheet and misses what is near in 3D
// but far in UV: the other lid of a closed eye, the other lip, the folds
// of the ear (issue 53's diagnosis). So each of burley's samples (Golubev
// 2018: areal density p(r) ∝ R_dom(r), the profile of channel
// `ts.dom_channel`) also casts a probe ray along the normal n through its
// point on x's tangent plane, across the profile's sphere (radius r_max,
// the table's), as NVIDIA's RTX Character Rendering SDK does (its SSS
// guide: a disk sample, a probe ray, only skin accepted). Every skin
// triangle it crosses at y inside the sphere whose UV is far from x's
// (further than the UV gather could have walked: more than 2|y − x| + 1
// mm of x's sheet away) adds
//     R(|y − x|) · E(y) / (p(r_n) · max(|n_y · n|, 0.2)),
// r_n its distance from x across n and |n_y · n| the projection of its
// area onto the disk (pbrt-v3 §15.4.1, `SeparableBSSRDF::Pdf_Sp` for the
// normal's axis; the floor at 0.2 bounds the weight of a wall the ray
// grazes, which the one axis samples sparsely), over Σ R(r_k)/p(r_k),
// what the same samples weigh on x's tangent plane. That sum is added to
// the UV gather's normalised mean, not averaged into it: the ground truth
// integrates R over every sheet within reach, so a pixel between two
// sheets (the lid's margin over the other lid) holds more than one
// sheet's weight of light. The hits near in UV are left to the UV gather.
//
// Measured (docs/accuracy.md) it gains 2–10 points on the scan and loses
// 11–14 on the procedural head, and it is off by default (`--probe-rays
// on`).
//
// E(y) is the screen's diffuse where y is the surface seen at its pixel
// (the depth there agrees), at pixel resolution; otherwise the atlas's
// texel at y's UV (the barycentric mix of its triangle's UVs).

@group(2) @binding(0) var probe_scene: acceleration_structure;

// Twin of `triangle_records` (rays.rs): unit normal; u0 v0 u1 v1; u2 v2.
struct RayTriangle {
    normal: vec4<f32>,
    uv01: vec4<f32>,
    uv2: vec4<f32>,
};
@group(2) @binding(1) var<storage, read> probe_triangles: array<RayTriangle>;

// The areal density of burley's radii at r (mm, in the profile's frame),
// up to a constant: R_dom(r) = (r·R)/r from the table. The constant
// cancels, as every weight below is divided by it and so is the tangent
// plane's weight they are taken over.
fn disk_density(r: f32) -> f32 {
    return profile_rr(r)[ts.dom_channel] / max(r, 1e-4);
}

// The light at a hit y (mm) on skin triangle `tri` at barycentrics `b`:
// rgb the light, a 1 where it was found (0: an empty atlas texel).
fn light_at_hit(y: vec3<f32>, tri: u32, b: vec2<f32>) -> vec4<f32> {
    let world = y / u.mm_per_unit;
    let clip = u.clip_from_world * vec4<f32>(world, 1.0);
    let screen = vec2<f32>(textureDimensions(scene_diffuse, 0));
    if (clip.w > 0.0) {
        let ndc = clip.xy / clip.w;
        let q = vec2<i32>(floor(vec2<f32>(0.5 + 0.5 * ndc.x, 0.5 - 0.5 * ndc.y) * screen));
        if (all(q >= vec2<i32>(0)) && all(q < vec2<i32>(screen))) {
            let e = textureLoad(scene_diffuse, q, 0);
            let depth = -(u.view_from_world * vec4<f32>(world, 1.0)).z;
            let seen = textureLoad(scene_depth, q, 0).r;
            // Seen there: the depths agree within half a millimetre and
            // two pixels' footprint (the pixel's centre is not y).
            let pixel_mm = depth * u.mm_per_unit / s.pixels_per_unit_at_depth_1;
            if (e.a > 0.0 && abs(seen - depth) * u.mm_per_unit < 0.5 + 2.0 * pixel_mm) {
                return vec4<f32>(e.rgb, 1.0);
            }
        }
    }
    let t = probe_triangles[tri];
    let uv = t.uv01.xy * (1.0 - b.x - b.y) + t.uv01.zw * b.x + t.uv2.xy * b.y;
    let size = vec2<f32>(textureDimensions(atlas_irradiance, 0));
    let e = textureLoad(atlas_irradiance, clamp(vec2<i32>(floor(uv * size)), vec2<i32>(0), vec2<i32>(size) - vec2<i32>(1)), 0);
    if (e.a > 0.0) {
        return vec4<f32>(e.rgb, 1.0);
    }
    return vec4<f32>(0.0);
}

@fragment
fn fs_gather_rays(i: VertexOut) -> @location(0) vec4<f32> {
    // Declared at the function's top level: wgpu 30.0.1's naga emits
    // invalid SPIR-V for a ray query declared inside a loop.
    var rq: ray_query;
    let t = triangle_maps(i);
    let p = vec2<i32>(i.clip.xy);
    let pixel = textureLoad(scene_diffuse, p, 0);
    let g = uv_gather(i, t, pixel);
    // The other sheets' light, and what the samples would weigh on x's
    // tangent plane.
    var far = vec3<f32>(0.0);
    var plane = vec3<f32>(0.0);
    let m = pixel.a;
    let n_len = length(i.normal);
    let x = i.world * u.mm_per_unit;
    let n = i.normal / max(n_len, 1e-20);
    // Any tangent frame: the per-pixel rotation turns the samples.
    var helper = vec3<f32>(1.0, 0.0, 0.0);
    if (abs(n.x) > 0.9) {
        helper = vec3<f32>(0.0, 1.0, 0.0);
    }
    let e1 = normalize(cross(helper, n));
    let e2 = cross(n, e1);
    var rotation = 0.0;
    if (s.deterministic == 0u) {
        rotation = 6.28318531 * fract(r2(p) + s.rotation_offset_turns);
    }
    let mm_uv = mm_per_uv(t);
    // The profile's sphere (mm): its table's last radius, scaled by the
    // SSS mask as every method scales the radii.
    let big_r = s.lut_radius_mm * m;
    var count = s.sample_count;
    if (m <= 0.0 || n_len <= 0.0 || g[1].x + g[1].y + g[1].z <= 0.0) {
        count = 0u;
    }
    for (var k = 0u; k < count; k = k + 1u) {
        let smp = samples[k];
        let r = smp.radius_mm * m;
        if (r >= big_r) {
            continue;
        }
        plane = plane + profile_rr(r / m) / max(r / m, 1e-6) / disk_density(r / m);
        let angle = smp.angle + rotation;
        let h = sqrt(big_r * big_r - r * r);
        let origin = x + (cos(angle) * e1 + sin(angle) * e2) * r - n * h;
        rayQueryInitialize(&rq, probe_scene, RayDesc(RAY_FLAG_FORCE_NO_OPAQUE, 0xffu, 0.0, 2.0 * h / u.mm_per_unit, origin / u.mm_per_unit, n));
        while (rayQueryProceed(&rq)) {
            let c = rayQueryGetCandidateIntersection(&rq);
            let y = origin + n * (c.t * u.mm_per_unit);
            let d = y - x;
            let rho = length(d);
            if (rho >= big_r) {
                continue;
            }
            let tri = probe_triangles[c.primitive_index];
            let b = c.barycentrics;
            let uv = tri.uv01.xy * (1.0 - b.x - b.y) + tri.uv01.zw * b.x + tri.uv2.xy * b.y;
            if (length(uv - i.uv) * mm_uv < 2.0 * rho + 1.0) {
                continue;
            }
            let r_n = length(d - n * dot(d, n)) / m;
            let cos_y = max(abs(dot(tri.normal.xyz, n)), 0.2);
            let light = light_at_hit(y, c.primitive_index, b);
            let w = profile_rr(rho / m) / max(rho / m, 1e-6) / (disk_density(r_n) * cos_y) * light.a;
            far = far + w * light.rgb;
        }
    }
    // The centre carries the profile's Dirac share, CDF(0), as fs_gather's.
    let centre = pixel.rgb;
    var ring = select(centre, g[0] / g[1], g[1] > vec3<f32>(0.0));
    ring = ring + select(vec3<f32>(0.0), far / plane, plane > vec3<f32>(0.0));
    return vec4<f32>(mix(ring, centre, profile_lut[s.lut_entries].rgb), pixel.a);
}
