// The ground truth's gather on the GPU: the walk of
// `src/render/ground_truth/gather.rs` (`Cloud::visit` and
// `Cloud::integrate`) over the same cells, clusters and profile table,
// one invocation per point, by the same rules and constants. The CPU path
// is the reference the tests hold this to (`ground_truth/gpu.rs`).
//
// A walk that does not end by emptying its stack is reported, never
// summed: Mesa's llvmpipe (lavapipe) ends every loop of an invocation
// once all its loops together have run 65,535 iterations
// (LP_MAX_TGSI_LOOP_ITERATIONS, gallivm/lp_bld_limits.h; the counter is
// decremented in lp_exec_endloop, lp_bld_ir_common.c) and carries on
// after them as if they had finished. On the default head a gather at
// the lips needed about 4,300 pops, each with inner loops, and stopped
// after 2,912 with a fiftieth of its light. So the four children are
// pushed without a loop, and `finished` is set only by the walk's own
// end: the caller gathers an unfinished point again elsewhere (`gpu.rs`).
//
// Differences from the CPU, all of rounding: f32 throughout (the CPU
// walks distances and sums in f64), an explicit stack in place of
// recursion (children pushed in reverse, so the order of the terms is the
// CPU's), and each fresh irradiance evaluated again where the CPU's memo
// would return the same value.
//
// This file is prefixed by a module that defines
//   fn surface_irradiance(root: u32, tri: u32, bary: vec3<f32>, fp: Footprint) -> vec3<f32>
// (the scene pass's diffuse target at a point of an SSS triangle, over
// the region `fp`), which may use `root_point` below and bindings of its
// own in group 1.

struct Footprint {
    pixel_dx_mm: vec3<f32>,
    pixel_dy_mm: vec3<f32>,
    width_mm: f32,
}

struct GatherParams {
    // The table's grid (`ProfileTable`): ln r₀, 1/step, r₀ (mm).
    ln_r0: f32,
    inv_step: f32,
    r0_mm: f32,
    // Truncation radius, smallest split (mm) and the cloud's reach.
    r_max_mm: f32,
    epsilon_mm: f32,
    reach_mm: f32,
    // Points in this dispatch and the first of them.
    count: u32,
    first: u32,
    // CDF at r = 0 (rgb).
    cdf_zero: vec4<f32>,
    // Where the roots and the leaf order start in `tree` (vec4s), and the
    // number of clusters.
    roots_at: u32,
    order_at: u32,
    clusters: u32,
    // A near piece is split where a corner differs from its mean by more
    // than this, over its share of the energy (`TruthBound::uneven`).
    uneven: f32,
    // 8-point Gauss–Legendre on [−1, 1] (`model::quad::gl8`).
    gl_nodes: array<vec4<f32>, 2>,
    gl_weights: array<vec4<f32>, 2>,
}

// One entry of the table: density ρ (rgb, mm⁻²) and the largest leaf side
// (mm); the CDF (rgb) and the decay length (mm); dρ/dr (rgb, mm⁻³).
struct TableEntry {
    density_leaf: vec4<f32>,
    cdf_decay: vec4<f32>,
    slope: vec4<f32>,
}

@group(0) @binding(0) var<uniform> g: GatherParams;
// Clusters (5 vec4s each), roots (4 vec4s each), then the leaf order
// (4 a vec4), floats as their bits.
@group(0) @binding(1) var<storage, read> tree: array<vec4<u32>>;
// Every root's quadtree of mean irradiance, 3 floats a node.
@group(0) @binding(2) var<storage, read> node_e: array<f32>;
@group(0) @binding(3) var<storage, read> table: array<TableEntry>;
// Per point: (x (mm), profile scale), (pixel step x (mm), 0), (pixel
// step y (mm), 0); the result (rgb) is written over the first.
@group(0) @binding(4) var<storage, read_write> points: array<vec4<f32>>;

const TABLE_SIZE: u32 = 2048u;
// `table.rs`: THETA; `cluster.rs`: CLUSTER_THETA, CLUSTER_LEAF,
// CLUSTER_DECAY (the bound's τ is in the table's leaf sizes, its
// splitting tolerance in `g.uneven`).
const THETA: f32 = 1.0;
const CLUSTER_THETA: f32 = 0.25;
const CLUSTER_LEAF: f32 = 0.25;
const CLUSTER_DECAY: f32 = 0.25;
const GATHER_PI: f32 = 3.14159265358979;
const STACK: u32 = 128u;

fn f4(v: vec4<u32>) -> vec4<f32> {
    return bitcast<vec4<f32>>(v);
}

// A root's corners (mm), longest side, reach (mm) and area (mm²), and
// (triangle, levels, offset).
struct Root {
    c0: vec3<f32>,
    c1: vec3<f32>,
    c2: vec3<f32>,
    side_mm: f32,
    reach_mm: f32,
    area_mm2: f32,
    tri: u32,
    levels: u32,
    offset: u32,
}

fn root_at(i: u32) -> Root {
    let at = g.roots_at + 4u * i;
    let a = f4(tree[at]);
    let b = f4(tree[at + 1u]);
    let c = f4(tree[at + 2u]);
    let d = tree[at + 3u];
    return Root(a.xyz, b.xyz, c.xyz, a.w, b.w, c.w, d.x, d.y, d.z);
}

// The point of root `i`'s triangle at barycentric `bary` (mm).
fn root_point(i: u32, bary: vec3<f32>) -> vec3<f32> {
    let r = root_at(i);
    return r.c0 * bary.x + r.c1 * bary.y + r.c2 * bary.z;
}

fn order_at(k: u32) -> u32 {
    return tree[g.order_at + k / 4u][k % 4u];
}

// ---- The profile (`table.rs`) ----

// `fast_ln`: x = m·2^e, m in [√½, √2), ln m = 2 atanh z to z⁷.
fn fast_ln(x: f32) -> f32 {
    let bits = bitcast<u32>(clamp(x, 1e-30, 3.4028235e38));
    var e = i32((bits >> 23u) & 0xffu) - 127;
    var m = bitcast<f32>((bits & 0x007fffffu) | 0x3f800000u);
    if m > 1.41421356 {
        m = m * 0.5;
        e = e + 1;
    }
    let z = (m - 1.0) / (m + 1.0);
    let z2 = z * z;
    return f32(e) * 0.693147181 + 2.0 * z * (1.0 + z2 * (1.0 / 3.0 + z2 * (1.0 / 5.0 + z2 / 7.0)));
}

struct At {
    i: u32,
    f: f32,
}

fn locate_ln(ln_r: f32) -> At {
    let t = clamp((ln_r - g.ln_r0) * g.inv_step, 0.0, f32(TABLE_SIZE - 1u));
    let i = min(u32(t), TABLE_SIZE - 2u);
    return At(i, min(t - f32(i), 1.0));
}

fn lerp_density(a: At) -> vec3<f32> {
    let lo = table[a.i].density_leaf.xyz;
    return lo + a.f * (table[a.i + 1u].density_leaf.xyz - lo);
}

fn lerp_cdf(a: At) -> vec3<f32> {
    let lo = table[a.i].cdf_decay.xyz;
    return lo + a.f * (table[a.i + 1u].cdf_decay.xyz - lo);
}

fn lerp_slope(a: At) -> vec3<f32> {
    let lo = table[a.i].slope.xyz;
    return lo + a.f * (table[a.i + 1u].slope.xyz - lo);
}

// `ProfileTable::cdf`, unscaled.
fn table_cdf(r_mm: f32) -> vec3<f32> {
    if r_mm < g.r0_mm {
        let f = max(r_mm, 0.0) / g.r0_mm;
        return g.cdf_zero.xyz + f * (table[0].cdf_decay.xyz - g.cdf_zero.xyz);
    }
    return lerp_cdf(locate_ln(fast_ln(r_mm)));
}

// The profile at a point, its radii scaled by m (`Scaled`).
struct Scaled {
    m: f32,
    ln_m: f32,
    inv_m2: f32,
}

fn density_sq(s: Scaled, r2_mm2: f32) -> vec3<f32> {
    return lerp_density(locate_ln(0.5 * fast_ln(r2_mm2) - s.ln_m)) * s.inv_m2;
}

fn scaled_cdf(s: Scaled, r_mm: f32) -> vec3<f32> {
    return table_cdf(r_mm / s.m);
}

fn cdf_sq(s: Scaled, r2_mm2: f32) -> vec3<f32> {
    let r0 = g.r0_mm * s.m;
    if r2_mm2 < r0 * r0 {
        return scaled_cdf(s, sqrt(max(r2_mm2, 0.0)));
    }
    return lerp_cdf(locate_ln(0.5 * fast_ln(r2_mm2) - s.ln_m));
}

fn leaf_mm(s: Scaled, r_mm: f32) -> f32 {
    let r = r_mm / s.m;
    let a = locate_ln(fast_ln(r));
    return min(table[a.i].density_leaf.w, THETA * r) * s.m;
}

fn decay_mm(s: Scaled, r_mm: f32) -> f32 {
    let a = locate_ln(fast_ln(r_mm / s.m));
    return table[a.i].cdf_decay.w * s.m;
}

// ---- The exact polar near field (`Scaled::polar_weight`, `edge_fan`) ----

fn edge_fan(s: Scaled, a: vec3<f32>, b: vec3<f32>, n: vec3<f32>, h: f32, cdf_h: vec3<f32>) -> vec3<f32> {
    let edge = b - a;
    let len2 = dot(edge, edge);
    if len2 <= 0.0 {
        return vec3<f32>(0.0);
    }
    let t_foot = -dot(a, edge) / len2;
    let foot = a + edge * t_foot;
    let p = length(foot);
    let orientation = dot(cross(a, b), n);
    if p <= 1e-9 * sqrt(len2) || orientation == 0.0 {
        return vec3<f32>(0.0);
    }
    let sgn = sign(orientation);
    let len = sqrt(len2);
    let psi_a = atan((0.0 - t_foot) * len / p);
    let psi_b = atan((1.0 - t_foot) * len / p);
    let p2 = p * p;
    var w = vec3<f32>(0.0);
    // Split at the foot (ψ = 0) when the edge runs across it.
    var los = array<f32, 2>(psi_a, psi_a);
    var his = array<f32, 2>(psi_b, psi_b);
    var spans = 1u;
    if psi_a < 0.0 && psi_b > 0.0 {
        his[0] = 0.0;
        los[1] = 0.0;
        spans = 2u;
    }
    for (var sp = 0u; sp < spans; sp++) {
        let lo = los[sp];
        let hi = his[sp];
        let pieces = max(ceil((hi - lo) / (GATHER_PI / 4.0)), 1.0);
        let step = (hi - lo) / pieces;
        for (var k = 0u; k < u32(pieces); k++) {
            let mid = lo + (f32(k) + 0.5) * step;
            for (var q = 0u; q < 8u; q++) {
                let node = g.gl_nodes[q / 4u][q % 4u];
                let weight = g.gl_weights[q / 4u][q % 4u];
                let c = cos(mid + 0.5 * step * node);
                let cdf = cdf_sq(s, p2 / (c * c) + h * h);
                w = w + (sgn * 0.5 * step * weight) * (cdf - cdf_h);
            }
        }
    }
    return w;
}

fn polar_weight(s: Scaled, x: vec3<f32>, c0: vec3<f32>, c1: vec3<f32>, c2: vec3<f32>) -> vec3<f32> {
    let n = cross(c1 - c0, c2 - c0);
    let n2 = dot(n, n);
    if n2 <= 0.0 {
        return vec3<f32>(0.0);
    }
    let along = dot(x - c0, n) / n2;
    var h = abs(along) * sqrt(n2);
    if h < 1e-3 {
        h = 0.0;
    }
    var cdf_h = vec3<f32>(0.0);
    if h > 0.0 {
        cdf_h = scaled_cdf(s, h);
    }
    let foot = x - n * along;
    let unit_n = n / sqrt(n2);
    var w = edge_fan(s, c0 - foot, c1 - foot, unit_n, h, cdf_h);
    w = w + edge_fan(s, c1 - foot, c2 - foot, unit_n, h, cdf_h);
    w = w + edge_fan(s, c2 - foot, c0 - foot, unit_n, h, cdf_h);
    return w / (2.0 * GATHER_PI);
}

// ---- The walk (`Cloud::visit`, `Cloud::integrate`) ----

// A cluster (kind 0) or a quadtree node (kind 1) still to be added.
struct Item {
    kind: u32,
    // The cluster, or the node's root.
    id: u32,
    level: u32,
    index: u32,
    b0: vec3<f32>,
    b1: vec3<f32>,
    b2: vec3<f32>,
}

fn level_start(level: u32) -> u32 {
    return ((1u << (2u * level)) - 1u) / 3u;
}

var<private> stack: array<Item, STACK>;
var<private> depth: u32;
// Set when a walk needed more than the stack holds (the result is then
// NaN, never a silent wrong value).
var<private> overflow: bool;
// Set only where the walk ends by emptying its stack.
var<private> finished: bool;

fn push(item: Item) {
    if depth >= STACK {
        overflow = true;
        return;
    }
    stack[depth] = item;
    depth = depth + 1u;
}

fn midpoint_split(b0: vec3<f32>, b1: vec3<f32>, b2: vec3<f32>, k: u32) -> array<vec3<f32>, 3> {
    let m0 = (b0 + b1) * 0.5;
    let m1 = (b1 + b2) * 0.5;
    let m2 = (b2 + b0) * 0.5;
    switch k {
        case 0u: { return array<vec3<f32>, 3>(b0, m0, m2); }
        case 1u: { return array<vec3<f32>, 3>(m0, b1, m1); }
        case 2u: { return array<vec3<f32>, 3>(m2, m1, b2); }
        default: { return array<vec3<f32>, 3>(m0, m1, m2); }
    }
}

// Child k of a quadtree node (its index only down to the cells).
fn push_child(it: Item, deeper: bool, k: u32) {
    let b = midpoint_split(it.b0, it.b1, it.b2, k);
    push(Item(1u, it.id, it.level + 1u, select(0u, 4u * it.index + k, deeper), b[0], b[1], b[2]));
}

fn gather(x: vec3<f32>, dx: vec3<f32>, dy: vec3<f32>, profile_scale: f32) -> vec3<f32> {
    let m = clamp(profile_scale, 1e-3, 1.0);
    let s = Scaled(m, log(m), 1.0 / (m * m));
    let pixel_mm = max(length(dx), length(dy));
    let r_max = g.r_max_mm * m;
    let eps = g.epsilon_mm * m;
    let reach_all = g.reach_mm * m;
    var acc = vec3<f32>(0.0);
    depth = 0u;
    overflow = false;
    finished = false;
    if g.clusters > 0u {
        push(Item(0u, 0u, 0u, 0u, vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0)));
    }
    loop {
        if depth == 0u {
            finished = true;
            break;
        }
        depth = depth - 1u;
        let it = stack[depth];
        if it.kind == 0u {
            // A cluster: by its expansion where it is small enough.
            let at = 5u * it.id;
            let q0 = f4(tree[at]);
            let q1 = tree[at + 1u];
            let q2 = tree[at + 2u];
            let q3 = tree[at + 3u];
            let q4 = f4(tree[at + 4u]);
            let to = q0.xyz - x;
            let d = length(to);
            let radius = q0.w;
            if d - radius > reach_all {
                continue;
            }
            let near = max(d - radius, 0.0);
            if radius <= CLUSTER_THETA * d && radius <= CLUSTER_LEAF * leaf_mm(s, near)
                && radius <= CLUSTER_DECAY * decay_mm(s, near) {
                // `Scaled::density_and_slope` at d.
                let a = locate_ln(fast_ln(d / m));
                let k = 1.0 / m;
                let rho = lerp_density(a) * (k * k);
                let d1 = lerp_slope(a) * (k * k * k);
                let dir = to / d;
                let power = f4(q1).xyz;
                let dip = vec3<f32>(dot(dir, f4(q2).xyz), dot(dir, f4(q3).xyz), dot(dir, q4.xyz));
                acc = acc + power * rho + d1 * dip;
                continue;
            }
            if q1.w == 0u {
                let left = q2.w;
                push(Item(0u, left + 1u, 0u, 0u, vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0)));
                push(Item(0u, left, 0u, 0u, vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0)));
            } else {
                let first = q2.w;
                let count = q3.w;
                for (var j = count; j > 0u; j--) {
                    let r = order_at(first + j - 1u);
                    push(Item(1u, r, 0u, 0u, vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(0.0, 0.0, 1.0)));
                }
            }
            continue;
        }
        // A node of a root's quadtree, or a piece below its cells.
        let root = root_at(it.id);
        let c0 = root.c0 * it.b0.x + root.c1 * it.b0.y + root.c2 * it.b0.z;
        let c1 = root.c0 * it.b1.x + root.c1 * it.b1.y + root.c2 * it.b1.z;
        let c2 = root.c0 * it.b2.x + root.c1 * it.b2.y + root.c2 * it.b2.z;
        let centre = (c0 + c1 + c2) / 3.0;
        let side = ldexp(root.side_mm, -i32(it.level));
        let reach = max(ldexp(root.reach_mm, -i32(it.level)), 1e-9);
        let area = ldexp(root.area_mm2, -2 * i32(it.level));
        let dist = length(x - centre);
        if dist - reach >= r_max {
            continue;
        }
        let inside = min((r_max - (dist - reach)) / (2.0 * reach), 1.0);
        let leaf = side <= THETA * dist && side <= leaf_mm(s, dist);
        let near = it.level >= root.levels && !leaf;
        let by_pixel = near && pixel_mm > side && dist - reach < pixel_mm;
        var fp = Footprint(vec3<f32>(0.0), vec3<f32>(0.0), side);
        if by_pixel {
            fp = Footprint(dx, dy, side);
        }
        // The piece's irradiance (the cells' mean, or afresh at its
        // centroid) and, for a near piece whose share of the energy is
        // large enough, its corners afresh until one differs from the mean
        // (the CPU's `even`). One call site of the scene's shading: each
        // one is a copy of `shade` that lavapipe compiles and, in a
        // divergent loop, runs for every lane.
        var e = vec3<f32>(0.0);
        let from_cells = it.level <= root.levels && !by_pixel;
        if from_cells {
            let n = 3u * (root.offset + level_start(it.level) + it.index);
            e = vec3<f32>(node_e[n], node_e[n + 1u], node_e[n + 2u]);
        }
        var share = vec3<f32>(0.0);
        if near {
            let lo = scaled_cdf(s, max(dist - reach, 0.0));
            let hi = scaled_cdf(s, dist + reach);
            share = max(hi - lo, vec3<f32>(0.0));
        }
        let checked = near && !(side <= eps || all(share <= vec3<f32>(g.uneven)));
        var even = true;
        var slot = select(0u, 1u, from_cells);
        let last = select(0u, 3u, checked);
        loop {
            if slot > last || !even {
                break;
            }
            var b = (it.b0 + it.b1 + it.b2) / 3.0;
            if slot == 1u {
                b = it.b0;
            } else if slot == 2u {
                b = it.b1;
            } else if slot == 3u {
                b = it.b2;
            }
            let v = surface_irradiance(it.id, root.tri, b, fp);
            if slot == 0u {
                e = v;
            } else {
                even = all(abs(v - e) * share <= g.uneven * max(abs(e), vec3<f32>(1e-6)));
            }
            slot = slot + 1u;
        }
        if near {
            if even {
                if any(e != vec3<f32>(0.0)) {
                    acc = acc + e * polar_weight(s, x, c0, c1, c2);
                }
                continue;
            }
        } else if leaf {
            if all(e == vec3<f32>(0.0)) {
                continue;
            }
            // The edge-midpoint rule, exact for quadratics on a triangle.
            let w = density_sq(s, dot(x - 0.5 * (c0 + c1), x - 0.5 * (c0 + c1)))
                + density_sq(s, dot(x - 0.5 * (c1 + c2), x - 0.5 * (c1 + c2)))
                + density_sq(s, dot(x - 0.5 * (c2 + c0), x - 0.5 * (c2 + c0)));
            acc = acc + e * w * (area / 3.0 * inside);
            continue;
        }
        // Split into four, pushed last first so that child 0 is added
        // first, as the CPU's recursion adds them.
        let deeper = it.level < root.levels;
        push_child(it, deeper, 3u);
        push_child(it, deeper, 2u);
        push_child(it, deeper, 1u);
        push_child(it, deeper, 0u);
    }
    if overflow {
        return vec3<f32>(bitcast<f32>(0x7fc00000u));
    }
    return acc;
}

@compute @workgroup_size(64)
fn cs_gather(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= g.count {
        return;
    }
    let i = 3u * (g.first + id.x);
    let p = points[i];
    let dx = points[i + 1u].xyz;
    let dy = points[i + 2u].xyz;
    let v = gather(p.xyz, dx, dy, p.w);
    // w: 1 the sum, 2 a walk that outgrew the stack (v is then NaN), 3 a
    // walk the driver ended before its stack was empty.
    var state = 1.0;
    if overflow {
        state = 2.0;
    } else if !finished {
        state = 3.0;
    }
    points[i] = vec4<f32>(v, state);
}
