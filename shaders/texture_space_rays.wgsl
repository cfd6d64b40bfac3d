// `texture-space`'s probe-ray gather (render/sss/texture_space/rays.rs):
// `enable wgpu_ray_query;`, scene.wgsl and texture_space_scene.wgsl come
// first; this file's own bindings are in group 2.
//
// At each SSS pixel x (mm), each of burley's samples (Golubev 2018: a
// radius r_k and angle on the triangle's plane, weight 1/p(r_k), the
// disk's areal density) is read twice:
// - through the UV layout, as `fs_gather` reads it (texture_space_scene.wgsl's
//   `uv_sample`: the near field on screen, the rest through the
//   triangle's surface-to-UV map), which finds x's own sheet;
// - by a probe ray along the plane's normal n through the sample's point,
//   across the profile's sphere (radius r_max, the table's), as NVIDIA's
//   RTX Character Rendering SDK does (its SSS guide: a disk sample, a
//   probe ray, only skin accepted). A skin triangle it crosses at y inside
//   the sphere weighs R(|y − x|) / (p(r_k) · max(|n_y · n|, 0.2)):
//   |n_y · n| the projection of its area onto the disk (pbrt-v3 §15.4.1,
//   `SeparableBSSRDF::Pdf_Sp` for the normal's axis), floored at 0.2 so
//   that a wall the ray grazes, which the one axis samples sparsely,
//   cannot take an unbounded weight (a bias: such walls weigh less).
// The UV samples are normalised as `fs_gather` normalises them (a sample
// that lost x's sheet, across a UV seam or an outline, is renormalised
// away, its weight spread over the sheet found). The rays add the other
// sheets: the ray of a sample that found x's sheet through the UV map
// adds the hits far from x in UV (further than 2|y − x| + 1 mm of x's
// sheet): the other lid of a closed eye, the other lip, a fold of the ear
// (skin near in 3D but far in UV, issue 53's diagnosis). Their sum is
// taken over Σ R(r_k)/p(r_k), what the samples weigh on x's tangent
// plane, and added to the normalised mean, not averaged into it: the
// ground truth integrates R over every sheet within reach
// (render/ground_truth.rs), so a pixel between two sheets holds more than
// one sheet's weight of light. Two kinds of sample cast no ray:
// - a lost one: its sheet's weight is already spread, and its ray would
//   count the sheet past the seam a second time;
// - one of the near field, read on screen: the screen has no UV seams,
//   so its ray's hit on x's own sheet past a seam is far in UV and would
//   count twice, and it cannot be told from the sheet the sample read,
//   which lies on a disk facing the camera, not on the triangle's plane.
//   (Telling them apart by the surface point the sample read, within a
//   pixel, counted x's own sheet again on every slanted surface: −107 %
//   on `scan_front` at 640 × 360, docs/accuracy.md.) What the near field's
//   samples would have found on other sheets is not gathered: a bias
//   towards too little light where two sheets lie within the near field.
//
// E(y) at a hit is the atlas's texel at y's UV (the barycentric mix of its
// triangle's UVs): a hit is mostly hidden from the camera, and a screen
// pixel within a millimetre of depth may be another sheet's.
//
// Measured (docs/accuracy.md), it is off by default (`--probe-rays on`).

@group(2) @binding(0) var probe_scene: acceleration_structure;

// Twin of `triangle_records` (rays.rs): unit normal; u0 v0 u1 v1; u2 v2.
struct RayTriangle {
    normal: vec4<f32>,
    uv01: vec4<f32>,
    uv2: vec4<f32>,
};
@group(2) @binding(1) var<storage, read> probe_triangles: array<RayTriangle>;

// The hit's UV: its triangle's UVs mixed by the ray query's barycentrics
// (Vulkan's: b.x weighs the second vertex, b.y the third).
fn hit_uv(tri: RayTriangle, b: vec2<f32>) -> vec2<f32> {
    return tri.uv01.xy * (1.0 - b.x - b.y) + tri.uv01.zw * b.x + tri.uv2.xy * b.y;
}

// The atlas's light at a hit's `uv` on triangle `tri`: rgb, and a 1 where
// it was found. A hit within half a texel of its island's edge can fall on
// a texel whose centre is outside every triangle (never rasterised): it is
// read one texel in, towards its triangle's centre.
fn atlas_light(uv: vec2<f32>, tri: RayTriangle) -> vec4<f32> {
    let size = vec2<f32>(textureDimensions(atlas_irradiance, 0));
    let centre = (tri.uv01.xy + tri.uv01.zw + tri.uv2.xy) / 3.0;
    let inward = centre - uv;
    let step = inward / max(max(abs(inward.x), abs(inward.y)) * max(size.x, size.y), 1.0);
    for (var k = 0; k < 2; k = k + 1) {
        let at = uv + f32(k) * step;
        let e = textureLoad(atlas_irradiance, clamp(vec2<i32>(floor(at * size)), vec2<i32>(0), vec2<i32>(size) - vec2<i32>(1)), 0);
        if (e.a > 0.0) {
            return vec4<f32>(e.rgb, 1.0);
        }
    }
    return vec4<f32>(0.0);
}

@fragment
fn fs_gather_rays(i: VertexOut) -> @location(0) vec4<f32> {
    // Declared at the function's top level: wgpu 30.0.1's naga emits
    // invalid SPIR-V for a ray query declared inside a loop.
    var rq: ray_query;
    let t = triangle_maps(i);
    let pixel = textureLoad(scene_diffuse, vec2<i32>(i.clip.xy), 0);
    let f = uv_frame(i, t, pixel);
    let m = f.m;
    let centre = pixel.rgb;
    if (!f.valid || m <= 0.0) {
        return pixel;
    }
    // The samples' plane (the triangle's) and its normal, on the side the
    // surface faces.
    let e2 = (t.wy - f.e1 * f.b) / f.c;
    var n = normalize(cross(f.e1, e2));
    if (dot(n, i.normal) < 0.0) {
        n = -n;
    }
    let mm_uv = mm_per_uv(t);
    let big_r = s.lut_radius_mm * m;
    // The UV layout's normalised gather, as `fs_gather`'s, and the other
    // sheets' light over the tangent plane's weight.
    var sum = vec3<f32>(0.0);
    var wsum = vec3<f32>(0.0);
    var far = vec3<f32>(0.0);
    var plane = vec3<f32>(0.0);
    for (var k = 0u; k < s.sample_count; k = k + 1u) {
        let smp = samples[k];
        let r = smp.radius_mm * m;
        plane = plane + profile_rr(smp.radius_mm) / max(smp.radius_mm, 1e-6) * smp.inv_pdf;
        let o = uv_sample(i, t, f, k);
        sum = sum + o.light;
        wsum = wsum + o.w;
        // Lost samples and the near field's cast no ray (above).
        if (!o.found || o.screen || r >= big_r) {
            continue;
        }
        let angle = smp.angle + f.rotation;
        let h = sqrt(big_r * big_r - r * r);
        let origin = f.x + (cos(angle) * f.e1 + sin(angle) * e2) * r - n * h;
        rayQueryInitialize(&rq, probe_scene, RayDesc(RAY_FLAG_FORCE_NO_OPAQUE, 0xffu, 0.0, 2.0 * h / u.mm_per_unit, origin / u.mm_per_unit, n));
        while (rayQueryProceed(&rq)) {
            let c = rayQueryGetCandidateIntersection(&rq);
            let y = origin + n * (c.t * u.mm_per_unit);
            let rho = length(y - f.x);
            if (rho >= big_r) {
                continue;
            }
            let tri = probe_triangles[c.primitive_index];
            let uv = hit_uv(tri, c.barycentrics);
            if (length(uv - i.uv) * mm_uv < 2.0 * rho + 1.0) {
                // x's own sheet, which the sample read through the UV map.
                continue;
            }
            let cos_y = max(abs(dot(tri.normal.xyz, n)), 0.2);
            let light = atlas_light(uv, tri);
            let w = profile_rr(rho / m) / max(rho / m, 1e-6) * smp.inv_pdf / cos_y;
            far = far + w * light.rgb * light.a;
        }
    }
    // The centre carries the profile's Dirac share, CDF(0), as fs_gather's.
    var ring = select(centre, sum / wsum, wsum > vec3<f32>(0.0));
    ring = ring + select(vec3<f32>(0.0), far / plane, plane > vec3<f32>(0.0));
    return vec4<f32>(mix(ring, centre, profile_lut[s.lut_entries].rgb), pixel.a);
}
