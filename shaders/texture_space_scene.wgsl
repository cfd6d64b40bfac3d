// `texture-space` (d'Eon & Luebke 2007, GPU Gems 3 ch. 14), its two passes
// that draw the mesh; scene.wgsl is prefixed to this file, its bindings in
// group 0, and sss_texture_space.wgsl holds the blur between them.
//
// 1. `vs_atlas`/`fs_atlas` rasterise the mesh at its UVs into the atlas
//    (d'Eon & Luebke 2007 §14.4.1: "the irradiance texture"), every
//    triangle, seen or not: the lid margin and the back of the ear get
//    their light although the camera cannot see them. Each texel gets what
//    the scene pass would write there (`shade`, transmission included),
//    its surface position (mm) and the map from its texel steps to the
//    surface (mm): the stretch map of §14.4.2, here the whole 2×2 Jacobian
//    in an orthonormal frame of the tangent plane, from the rasteriser's
//    derivatives of the position (exact per triangle: UV and position are
//    both linear across it).
// 2. `fs_lookup` draws the mesh again with the scene pass's vertex shader
//    and depth (compare Equal), and reads the blurred atlas at the
//    pixel's UV, bilinear over the covered texels only.

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
    // xyz: the surface point (mm), w: 1 where a triangle covers the texel.
    @location(1) position_mm: vec4<f32>,
    // x = |W_x|, y = W_y·e1, z = W_y·e2 (mm per texel step): the texel
    // steps W_x (along u) and W_y (along v) in the frame e1 = W_x/|W_x|,
    // e2 ⟂ e1 in the triangle's plane. A surface offset (s1, s2) in mm is
    // the texel offset t with t_y = s2/z, t_x = (s1 − y·t_y)/x.
    @location(2) frame_mm: vec4<f32>,
};

@fragment
fn fs_atlas(i: VertexOut) -> AtlasOut {
    var maps: Maps;
    maps.albedo = textureSample(albedo_map, surface_sampler, i.uv).rgb;
    maps.normal = textureSample(normal_map, surface_sampler, i.uv).xyz * 2.0 - 1.0;
    maps.roughness = textureSample(roughness_map, surface_sampler, i.uv).r;
    maps.mask = textureSample(mask_map, surface_sampler, i.uv).r;
    maps.thickness = textureSample(thickness_map, surface_sampler, i.uv).r;
    maps.blurred_r = maps.normal;
    maps.blurred_g = maps.normal;
    maps.blurred_b = maps.normal;
    let wx = dpdx(i.world) * u.mm_per_unit;
    let wy = dpdy(i.world) * u.mm_per_unit;
    let lx = length(wx);
    let e1 = wx / max(lx, 1e-12);
    let along = dot(wy, e1);
    let across = length(wy - e1 * along);
    var o: AtlasOut;
    o.diffuse = shade(i, maps, true).diffuse;
    o.position_mm = vec4<f32>(i.world * u.mm_per_unit, 1.0);
    o.frame_mm = vec4<f32>(lx, along, across, 1.0);
    return o;
}

// The blurred atlas (sss_texture_space.wgsl's output).
@group(1) @binding(0) var atlas_scattered: texture_2d<f32>;

@fragment
fn fs_lookup(i: VertexOut) -> @location(0) vec4<f32> {
    let size = vec2<i32>(textureDimensions(atlas_scattered, 0));
    let f = i.uv * vec2<f32>(size) - vec2<f32>(0.5);
    let base = vec2<i32>(floor(f));
    let t = f - floor(f);
    var col = vec3<f32>(0.0);
    var mask = 0.0;
    var covered = 0.0;
    for (var k = 0; k < 4; k = k + 1) {
        let o = vec2<i32>(k & 1, k >> 1u);
        let q = clamp(base + o, vec2<i32>(0), size - vec2<i32>(1));
        let c = textureLoad(atlas_scattered, q, 0);
        let bw = select(1.0 - t.x, t.x, o.x == 1) * select(1.0 - t.y, t.y, o.y == 1);
        // Only skin texels the atlas covered (alpha = the SSS mask there;
        // eyes, teeth and empty texels are negative).
        if (c.a > 1.0 / 255.0) {
            col = col + bw * c.rgb;
            mask = mask + bw * c.a;
            covered = covered + bw;
        }
    }
    if (covered <= 0.0) {
        // No covered skin texel here (a sliver thinner than a texel): the
        // composite keeps the scene's unscattered value.
        return vec4<f32>(0.0);
    }
    return vec4<f32>(col / covered, mask / covered);
}
