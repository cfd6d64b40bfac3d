// `texture-space --neighbours 3d` (render/sss/texture_space/cloud.rs):
// the gather by 3D neighbourhood. scene.wgsl and texture_space_scene.wgsl
// come first; this file's own bindings are in group 2.
//
// The UV layout's gather finds the pixel's neighbours along the surface
// in UV, so it misses skin that is near in 3D but far in UV: the other lid
// of a closed eye, the other lip, the far side of a thin ear (issue 53's
// diagnosis, docs/accuracy.md). Here the atlas's texels are the point
// cloud of Jensen & Buhler 2002 (§3), every texel a surface element with
// its point, area A and light E (texture_space_tree.wgsl builds their
// hierarchy), and the pixel at x takes what the ground truth integrates
// (render/ground_truth.rs),
//   M(x) = CDF(0)·E(x) + ∫ R(‖x − y‖) E(y) dA(y) over every sheet of skin,
// unnormalised: two sheets within reach give more light than one. It is
// split at the near-field radius r₀ (`--near-field-mm`, at least 1 mm
// here):
// - within r₀, the pixel's own sheet at pixel resolution: burley's disk
//   samples under r₀, read on screen as `fs_burley` reads them and
//   normalised among themselves, carry the profile's energy between 0 and
//   r₀, CDF(r₀) − CDF(0) (the atlas's texels, 0.5–1 mm, are too coarse for
//   the green and blue cores);
// - beyond r₀, Σ R(‖x − y‖)·(A·E) over the tree (Jensen & Buhler's
//   hierarchical gather, their octree here the atlas's quadtree): a node
//   whose bounding sphere lies beyond r₀ and whose radius is at most
//   θ·‖x − centroid‖ counts whole at its centroid; otherwise its four
//   children are visited, down to single texels. A texel across r₀ counts
//   for the part of its width beyond it (`band_mean`: its distances taken
//   as spread evenly over d ± half its width), and texels wide for their
//   distance are split 4 × 4 (`texel_sum`), so that the hand-over does not
//   alias on the texel grid. Nodes wholly
//   beyond the profile's reach (the table's radius, its 0.999 energy)
//   are skipped, as the ground truth skips them.
// R is the profile's areal density (mm⁻², ∫ R 2πr dr = 1 − CDF(0)), read
// from burley's table (r·R(r) and the CDF; `sss::burley`), and the SSS
// mask m scales its radii as everywhere (R_m(r) = R(r/m)/m²).

// Twin of `Node` in texture_space_tree.wgsl.
struct Node {
    light: vec4<f32>,
    sphere: vec4<f32>,
    spread: vec4<f32>,
};

// Twin of `cloud::CloudUniforms`.
struct CloudUniforms {
    // Level l's offset in `nodes` (l ≥ 1): offsets[l / 4][l % 4].
    offsets: array<vec4<u32>, 4>,
    // The root's level (its side is 1 node).
    top: u32,
    // A node counts whole where its radius is at most θ times its
    // centroid's distance.
    theta: f32,
    // The near field's radius (mm, before the mask scales it).
    near_mm: f32,
    // The most surface (mm²) one texel stands for (texture_space_tree.wgsl).
    max_area_mm2: f32,
};

@group(2) @binding(0) var<storage, read> nodes: array<Node>;
@group(2) @binding(1) var<uniform> cloud: CloudUniforms;
// The resolved 4× atlas: Σ A·E and Σ A over each texel's samples.
@group(2) @binding(2) var atlas_coverage: texture_2d<f32>;

// The levels' codes on the traversal stack: level above bit 27, the
// node's index within its level below.
const LEVEL_SHIFT: u32 = 27u;
const INDEX_MASK: u32 = 0x7ffffffu;
// 3 per level under the root, and room: the atlas is at most 4096² (12
// levels).
const STACK: u32 = 48u;

// The profile's CDF at r (mm), from the table's second half.
fn profile_cdf(r_mm: f32) -> vec3<f32> {
    let n = f32(s.lut_entries);
    let t = sqrt(clamp(r_mm / s.lut_radius_mm, 0.0, 1.0)) * (n - 1.0);
    let i = min(u32(t), u32(n) - 2u);
    let f = t - f32(i);
    return mix(profile_lut[s.lut_entries + i].rgb, profile_lut[s.lut_entries + i + 1u].rgb, f);
}

// R_m at the distance d (mm): the areal density with the mask's scale.
fn density(d: f32, m: f32) -> vec3<f32> {
    let rho = max(d / m, 1e-6);
    return profile_rr(rho) / (rho * m * m);
}

// A texel as a node (texture_space_tree.wgsl's `texel_node`, whose twin
// this is: the gather reads level 0 from the atlas itself). A texel
// covered only off its centre takes its point from its neighbours: one
// step on from the first covered one (within two texels' width of it),
// or that one's point.
fn leaf(q: vec2<i32>) -> Node {
    var n: Node;
    let cov = textureLoad(atlas_coverage, q, 0);
    let area = clamp(cov.a, 0.0, cloud.max_area_mm2);
    n.light = vec4<f32>(select(vec3<f32>(0.0), cov.rgb * (area / cov.a), cov.a > 0.0), area);
    n.spread = vec4<f32>(area / 6.0, 0.0, 0.0, 0.0);
    var y = texel_point(q);
    if (y.w == 0.0 && area > 0.0) {
        let width = sqrt(area);
        let steps = array<vec2<i32>, 4>(vec2<i32>(1, 0), vec2<i32>(-1, 0), vec2<i32>(0, 1), vec2<i32>(0, -1));
        for (var k = 0; k < 4; k = k + 1) {
            let one = texel_point(q + steps[k]);
            if (one.w > 0.0) {
                let two = texel_point(q + 2 * steps[k]);
                let on = two.w > 0.0 && length(two.xyz - one.xyz) < 2.0 * width;
                y = vec4<f32>(select(one.xyz, 2.0 * one.xyz - two.xyz, on), 1.0);
                break;
            }
        }
    }
    n.sphere = vec4<f32>(y.xyz, sqrt(0.5 * area));
    if (y.w == 0.0) {
        n.light = vec4<f32>(0.0);
    }
    return n;
}

// What a node at distance d (mm) from x gives, per unit of Σ A·E, of its
// part beyond `near`: its surface spreads over distances d ± a, with
// a = √(3/2)·(its RMS distance from its centroid) (a flat cluster's spread
// along one direction has variance rms²/2, a uniform band's a²/3), at most
// its bounding radius; R_m is averaged over the band beyond `near` by
// Simpson's rule (exact for cubics; within 0.5 % of an exponential's mean
// over a band of one decay length either side, where the midpoint rule is
// 15 % low), times the share of the band beyond `near`.
fn band(n: Node, d: f32, near: f32, m: f32) -> vec3<f32> {
    return band_mean(d, min(sqrt(1.5 * n.spread.x), n.sphere.w), near, m);
}

fn band_mean(d: f32, a: f32, near: f32, m: f32) -> vec3<f32> {
    let lo = max(d - a, near);
    let hi = d + a;
    if (hi <= lo) {
        return vec3<f32>(0.0);
    }
    let share = select(1.0, (hi - lo) / (2.0 * a), a > 0.0);
    let mean = (density(lo, m) + 4.0 * density(0.5 * (lo + hi), m) + density(hi, m)) / 6.0;
    return mean * share;
}

// A texel's point (mm), or w = 0 where no surface covers it.
fn texel_point(q: vec2<i32>) -> vec4<f32> {
    let size = vec2<i32>(textureDimensions(atlas_irradiance, 0));
    if (any(q < vec2<i32>(0)) || any(q >= size)) {
        return vec4<f32>(0.0);
    }
    let hi = textureLoad(atlas_position_hi, q, 0);
    let lo = textureLoad(atlas_position_lo, q, 0);
    return vec4<f32>(hi.xyz + lo.xyz, select(0.0, 1.0, hi.w > 0.5));
}

// The step (mm) to the texel `dq` away, or its opposite's negated, where
// that one lies on the same sheet (no further than 2 texels' width); zero
// where neither does.
fn texel_step(q: vec2<i32>, dq: vec2<i32>, y: vec3<f32>, width: f32) -> vec3<f32> {
    let ahead = texel_point(q + dq);
    if (ahead.w > 0.0 && length(ahead.xyz - y) < 2.0 * width) {
        return ahead.xyz - y;
    }
    let behind = texel_point(q - dq);
    if (behind.w > 0.0 && length(behind.xyz - y) < 2.0 * width) {
        return y - behind.xyz;
    }
    return vec3<f32>(0.0);
}

// Sub-texels a side where a texel is too wide for its distance.
const SUB: i32 = 4;

// What a texel gives beyond `near`: as a node (`band`) where its half
// width is under half its distance beyond the near field; otherwise (the
// texels about x, where a texel of 0.5–1 mm spans much of the profile's
// core) split into SUB × SUB parts laid along the steps to its
// neighbours (the surface's own parametrisation, so a part lies where the
// surface is), each a band of its own.
fn texel_sum(n: Node, q: vec2<i32>, x: vec3<f32>, d: f32, near: f32, m: f32) -> vec3<f32> {
    let width = sqrt(n.light.w);
    let a = 0.5 * width;
    if (a <= 0.5 * (d - near)) {
        return band(n, d, near, m) * n.light.rgb;
    }
    let y = n.sphere.xyz;
    let du = texel_step(q, vec2<i32>(1, 0), y, width);
    let dv = texel_step(q, vec2<i32>(0, 1), y, width);
    if (all(du == vec3<f32>(0.0)) || all(dv == vec3<f32>(0.0))) {
        return band(n, d, near, m) * n.light.rgb;
    }
    var sum = vec3<f32>(0.0);
    let k = f32(SUB);
    for (var j = 0; j < SUB; j = j + 1) {
        for (var i = 0; i < SUB; i = i + 1) {
            let p = y + du * ((f32(i) + 0.5) / k - 0.5) + dv * ((f32(j) + 0.5) / k - 0.5);
            sum = sum + band_mean(length(p - x), a / k, near, m);
        }
    }
    return sum * (n.light.rgb / (k * k));
}

// Σ R_m(‖x − y‖)·A·E beyond `near` (mm) and within `reach` (mm).
fn cloud_sum(x: vec3<f32>, near: f32, reach: f32, m: f32) -> vec3<f32> {
    let size = textureDimensions(atlas_irradiance, 0).x;
    var stack: array<u32, STACK>;
    stack[0] = cloud.top << LEVEL_SHIFT;
    var depth = 1u;
    var sum = vec3<f32>(0.0);
    while (depth > 0u) {
        depth = depth - 1u;
        let code = stack[depth];
        let level = code >> LEVEL_SHIFT;
        let index = code & INDEX_MASK;
        let side = size >> level;
        var n: Node;
        if (level == 0u) {
            n = leaf(vec2<i32>(i32(index % side), i32(index / side)));
        } else {
            n = nodes[cloud.offsets[level / 4u][level % 4u] + index];
        }
        if (n.light.w <= 0.0) {
            continue;
        }
        let d = length(n.sphere.xyz - x);
        let radius = n.sphere.w;
        if (d - radius > reach) {
            continue;
        }
        if (level == 0u) {
            if (d <= reach) {
                let q = vec2<i32>(i32(index % side), i32(index / side));
                sum = sum + texel_sum(n, q, x, d, near, m);
            }
            continue;
        }
        if (radius <= cloud.theta * d && d - radius >= near) {
            if (d <= reach) {
                sum = sum + band(n, d, near, m) * n.light.rgb;
            }
            continue;
        }
        if (depth + 4u > STACK) {
            continue;
        }
        let child = ((level - 1u) << LEVEL_SHIFT);
        let q = vec2<u32>(index % side, index / side) * 2u;
        let below = side * 2u;
        for (var k = 0u; k < 4u; k = k + 1u) {
            stack[depth] = child | ((q.y + (k >> 1u)) * below + q.x + (k & 1u));
            depth = depth + 1u;
        }
    }
    return sum;
}

@fragment
fn fs_gather_cloud(i: VertexOut) -> @location(0) vec4<f32> {
    let t = triangle_maps(i);
    // The pixel's light without the scene pass's transmission term (the
    // atlas is drawn without it too: the light through a thin part comes
    // from its far side's texels, as the ground truth's does), and what
    // that leaves of the screen's light, by which the near field's
    // samples, read on screen, are scaled.
    let direct = shade(i, pixel_maps(i), false).diffuse;
    let pixel = textureLoad(scene_diffuse, vec2<i32>(i.clip.xy), 0);
    let f = uv_frame(i, t, pixel);
    let m = f.m;
    let centre = direct.rgb;
    let kept = select(vec3<f32>(1.0), min(direct.rgb / pixel.rgb, vec3<f32>(1.0)), pixel.rgb > vec3<f32>(0.0));
    if (m <= 0.0) {
        return vec4<f32>(centre, pixel.a);
    }
    // Within r₀: the near field's samples, normalised. r₀ is never under
    // the near field's radius in mm, whatever the mask: a mask that
    // shrinks the profile under a texel leaves it all to the near field.
    let r0 = max(cloud.near_mm * m, cloud.near_mm);
    let rho0 = r0 / m;
    // Every one of them read on screen (`uv_sample_below` with rho0), and
    // none where the triangle's map is degenerate (the pixel's own light
    // stands in).
    var sum = vec3<f32>(0.0);
    var wsum = vec3<f32>(0.0);
    for (var k = 0u; k < s.sample_count; k = k + 1u) {
        if (f.valid && samples[k].radius_mm < rho0) {
            let o = uv_sample_below(i, t, f, k, rho0);
            sum = sum + o.light;
            wsum = wsum + o.w;
        }
    }
    let near = select(centre, kept * sum / wsum, wsum > vec3<f32>(0.0));
    let c0 = profile_lut[s.lut_entries].rgb;
    let share = max(profile_cdf(rho0) - c0, vec3<f32>(0.0));
    // Beyond it: every sheet in reach, by 3D distance.
    let far = cloud_sum(f.x, r0, s.lut_radius_mm * m, m);
    return vec4<f32>(centre * c0 + near * share + far, pixel.a);
}
