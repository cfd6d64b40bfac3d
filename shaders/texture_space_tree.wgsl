// `texture-space --neighbours 3d` (render/sss/texture_space/cloud.rs):
// the irradiance atlas's texels as the point cloud of Jensen & Buhler 2002
// (§3), and its hierarchy. A texel is a surface element: its point (mm),
// its area A (mm², what `fs_atlas` writes in position_lo.w: the surface
// its texel covers) and its light E. Level l of the tree has (N/2^l)²
// nodes, each the four below it merged:
// - Σ A·E and Σ A (Jensen & Buhler's "total irradiance" and area);
// - the area-weighted centroid of its surface, and the radius (mm) of a
//   sphere about it that holds every texel below (each child's distance
//   from the centroid plus its own radius; a texel's is half its
//   diagonal, √(A/2)), so that the gather can bound how far the node's
//   surface is from a pixel.
// Level 1 is built from the atlas's textures, each further level from the
// one below it in `nodes`.

// Twin of `Node` in texture_space_cloud.wgsl.
struct Node {
    // Σ A·E (rgb), Σ A (mm²).
    light: vec4<f32>,
    // The area-weighted centroid (mm) and the bounding radius (mm).
    sphere: vec4<f32>,
    // x: the area-weighted mean squared distance of its surface from the
    // centroid (mm²): how far its light spreads in distance from a pixel.
    spread: vec4<f32>,
};

// Twin of `cloud::TreeLevel`.
struct TreeLevel {
    // This level's side in nodes.
    side: u32,
    // 1: built from the atlas's texels; above: from `nodes` at `below`.
    level: u32,
    below: u32,
    // This level's offset in `nodes`.
    at: u32,
    // The most surface (mm²) one texel stands for: a sliver triangle that
    // covers one texel's centre would otherwise lend it its whole
    // surface-to-UV stretch.
    max_area_mm2: f32,
    pad0: f32,
    pad1: f32,
    pad2: f32,
};

@group(0) @binding(0) var<uniform> lv: TreeLevel;
@group(0) @binding(1) var<storage, read_write> nodes: array<Node>;
@group(0) @binding(2) var atlas_irradiance: texture_2d<f32>;
@group(0) @binding(3) var atlas_position_hi: texture_2d<f32>;
@group(0) @binding(4) var atlas_position_lo: texture_2d<f32>;
// The resolved 4× atlas: Σ A·E and Σ A over each texel's samples
// (texture_space_scene.wgsl's `fs_atlas_coverage`).
@group(0) @binding(5) var atlas_coverage: texture_2d<f32>;

// A texel's point (mm), or w = 0 where its centre is not covered.
fn texel_point(q: vec2<i32>) -> vec4<f32> {
    let size = vec2<i32>(textureDimensions(atlas_position_hi, 0));
    if (any(q < vec2<i32>(0)) || any(q >= size)) {
        return vec4<f32>(0.0);
    }
    let hi = textureLoad(atlas_position_hi, q, 0);
    let lo = textureLoad(atlas_position_lo, q, 0);
    return vec4<f32>(hi.xyz + lo.xyz, select(0.0, 1.0, hi.w > 0.5));
}

// A texel as a node: its surface and light from the resolved 4× atlas
// (skin gives its light, eyes and teeth none: they do not scatter, as in
// the ground truth), each texel's area at most `max_area_mm2`, and its
// point. A texel covered only off its centre (at an island's edge) has no
// point of its own in the single-sample atlas: it is placed one step on
// from its first covered neighbour (+u, −u, +v, −v), extrapolated from
// the next texel beyond where that lies within two texels' width, or at
// the neighbour's point; with no covered neighbour it is dropped.
// texture_space_cloud.wgsl's `leaf` is its twin.
fn texel_node(q: vec2<i32>) -> Node {
    var n: Node;
    let cov = textureLoad(atlas_coverage, q, 0);
    let area = clamp(cov.a, 0.0, lv.max_area_mm2);
    let light = select(vec3<f32>(0.0), cov.rgb * (area / cov.a), cov.a > 0.0);
    n.light = vec4<f32>(light, area);
    // A square of side s: s²/6.
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
        n.spread = vec4<f32>(0.0);
    }
    return n;
}

@compute @workgroup_size(8, 8)
fn cs_tree(@builtin(global_invocation_id) g: vec3<u32>) {
    if (g.x >= lv.side || g.y >= lv.side) {
        return;
    }
    var c: array<Node, 4>;
    for (var k = 0u; k < 4u; k = k + 1u) {
        let q = vec2<u32>(2u * g.x + (k & 1u), 2u * g.y + (k >> 1u));
        if (lv.level == 1u) {
            c[k] = texel_node(vec2<i32>(q));
        } else {
            c[k] = nodes[lv.below + q.y * 2u * lv.side + q.x];
        }
    }
    var light = vec4<f32>(0.0);
    var centroid = vec3<f32>(0.0);
    for (var k = 0u; k < 4u; k = k + 1u) {
        light = light + c[k].light;
        centroid = centroid + c[k].sphere.xyz * c[k].light.w;
    }
    var n: Node;
    n.light = light;
    n.sphere = vec4<f32>(0.0);
    n.spread = vec4<f32>(0.0);
    if (light.w > 0.0) {
        centroid = centroid / light.w;
        var radius = 0.0;
        var spread = 0.0;
        for (var k = 0u; k < 4u; k = k + 1u) {
            if (c[k].light.w > 0.0) {
                let off = length(c[k].sphere.xyz - centroid);
                radius = max(radius, off + c[k].sphere.w);
                // The parallel-axis theorem.
                spread = spread + c[k].light.w * (c[k].spread.x + off * off);
            }
        }
        n.sphere = vec4<f32>(centroid, radius);
        n.spread = vec4<f32>(spread / light.w, 0.0, 0.0, 0.0);
    }
    nodes[lv.at + g.y * lv.side + g.x] = n;
}
