// The GPU ground truth's irradiance: the scene pass's own `shade`
// (scene.wgsl, prefixed to this file, its bindings in group 0) at a point
// of an SSS triangle, with the mesh's vertices interpolated there as the
// rasteriser interpolates them and the maps read at the level of detail
// of the region the value stands for, by the rule of the CPU twin
// (`scene_cpu.rs`, `UvJacobian::level_of_detail`: Vulkan's ρ_max of the
// pixel's two steps, or the cell's width times the surface-to-texel
// stretch). ground_truth.wgsl follows this file.

// The mesh as `gpu_types::Vertex` (15 floats) and its triangles.
@group(1) @binding(0) var<storage, read> mesh_vertices: array<f32>;
@group(1) @binding(1) var<storage, read> mesh_indices: array<u32>;

struct MeshVertex {
    position: vec3<f32>,
    normal: vec3<f32>,
    uv: vec2<f32>,
    material: f32,
    curvature: f32,
    thickness: f32,
    tangent: vec4<f32>,
}

fn mesh_vertex(i: u32) -> MeshVertex {
    let b = 15u * i;
    var v: MeshVertex;
    v.position = vec3<f32>(mesh_vertices[b], mesh_vertices[b + 1u], mesh_vertices[b + 2u]);
    v.normal = vec3<f32>(mesh_vertices[b + 3u], mesh_vertices[b + 4u], mesh_vertices[b + 5u]);
    v.uv = vec2<f32>(mesh_vertices[b + 6u], mesh_vertices[b + 7u]);
    v.material = mesh_vertices[b + 8u];
    v.curvature = mesh_vertices[b + 9u];
    v.thickness = mesh_vertices[b + 10u];
    v.tangent = vec4<f32>(mesh_vertices[b + 11u], mesh_vertices[b + 12u], mesh_vertices[b + 13u], mesh_vertices[b + 14u]);
    return v;
}

// log2 ρ for a map of `size` texels (`UvJacobian::level_of_detail`).
fn level_of_detail(p0: vec3<f32>, p1: vec3<f32>, p2: vec3<f32>, uv0: vec2<f32>, uv1: vec2<f32>, uv2: vec2<f32>, size: vec2<f32>, fp: Footprint) -> f32 {
    let e1 = p1 - p0;
    let e2 = p2 - p0;
    let l1 = length(e1);
    let t1 = e1 / max(l1, 1e-30);
    let t2_raw = e2 - t1 * dot(e2, t1);
    let t2_len = length(t2_raw);
    var t2 = vec3<f32>(0.0);
    if t2_len > 0.0 {
        t2 = t2_raw / t2_len;
    }
    let a = l1;
    let b = dot(e2, t1);
    let c = dot(e2, t2);
    if a <= 0.0 || abs(c) <= 0.0 {
        return 0.0;
    }
    let j1 = (uv1 - uv0) / a * size;
    let j2 = ((uv2 - uv0) - (uv1 - uv0) / a * b) / c * size;
    let tx = length(j1 * dot(fp.pixel_dx_mm, t1) + j2 * dot(fp.pixel_dx_mm, t2));
    let ty = length(j1 * dot(fp.pixel_dy_mm, t1) + j2 * dot(fp.pixel_dy_mm, t2));
    let frob = dot(j1, j1) + dot(j2, j2);
    let det = j1.x * j2.y - j1.y * j2.x;
    let stretch = sqrt(0.5 * (frob + sqrt(max(frob * frob - 4.0 * det * det, 0.0))));
    // ρ = 0 (a point with no width) is level 0, as the twin clamps it.
    let rho = max(max(tx, ty), stretch * fp.width_mm);
    return log2(max(rho, 1e-30));
}

fn surface_irradiance(root: u32, tri: u32, bary: vec3<f32>, fp: Footprint) -> vec3<f32> {
    let a = mesh_vertex(mesh_indices[3u * tri]);
    let b = mesh_vertex(mesh_indices[3u * tri + 1u]);
    let c = mesh_vertex(mesh_indices[3u * tri + 2u]);
    let w = bary;
    // Eyes and teeth are not SSS surface (the twin's SurfaceKind::of).
    let material = a.material * w.x + b.material * w.y + c.material * w.z;
    if material >= 0.5 {
        return vec3<f32>(0.0);
    }
    var i: VertexOut;
    i.world = a.position * w.x + b.position * w.y + c.position * w.z;
    i.clip = u.clip_from_world * vec4<f32>(i.world, 1.0);
    i.normal = a.normal * w.x + b.normal * w.y + c.normal * w.z;
    i.uv = a.uv * w.x + b.uv * w.y + c.uv * w.z;
    i.material = material;
    i.view_depth = -(u.view_from_world * vec4<f32>(i.world, 1.0)).z;
    i.curvature = a.curvature * w.x + b.curvature * w.y + c.curvature * w.z;
    i.thickness = a.thickness * w.x + b.thickness * w.y + c.thickness * w.z;
    i.tangent = a.tangent * w.x + b.tangent * w.y + c.tangent * w.z;
    let mm = u.mm_per_unit;
    let albedo_lod = level_of_detail(a.position * mm, b.position * mm, c.position * mm, a.uv, b.uv, c.uv, vec2<f32>(textureDimensions(albedo_map, 0)), fp);
    let normal_lod = level_of_detail(a.position * mm, b.position * mm, c.position * mm, a.uv, b.uv, c.uv, vec2<f32>(textureDimensions(normal_map, 0)), fp);
    var maps: Maps;
    maps.albedo = textureSampleLevel(albedo_map, surface_sampler, i.uv, albedo_lod).rgb;
    maps.normal = textureSampleLevel(normal_map, surface_sampler, i.uv, normal_lod).xyz * 2.0 - 1.0;
    maps.roughness = textureSampleLevel(roughness_map, surface_sampler, i.uv, normal_lod).r;
    maps.mask = textureSampleLevel(mask_map, surface_sampler, i.uv, normal_lod).r;
    maps.thickness = textureSampleLevel(thickness_map, surface_sampler, i.uv, normal_lod).r;
    // `preintegrated` is never the ground truth's shading.
    maps.blurred_r = maps.normal;
    maps.blurred_g = maps.normal;
    maps.blurred_b = maps.normal;
    return shade(i, maps, false).diffuse.rgb;
}
