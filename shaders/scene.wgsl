// Scene pass: lights the mesh and writes the separate buffers the SSS
// methods read (as every engine does: specular is never blurred).
//   target 0: diffuse irradiance × albedo^pre (rgb), SSS mask (a; on eyes
//             and teeth DIFFUSE_ALPHA_NOT_SKIN, on the background the clear's
//             DIFFUSE_ALPHA_BACKGROUND)
//   target 1: specular radiance (rgb)
//   target 2: albedo^post (rgb), coverage 1 (a)
//   target 3: linear view depth in world units
// Twin of `render::gpu_types::SceneUniforms`.

// Modes, beside their Rust twins in render/gpu_types.rs.
const TRANSMISSION_OFF: u32 = 0u;
const TRANSMISSION_THIN: u32 = 1u;
const TRANSMISSION_THICK: u32 = 2u;
const PATTERN_LIT: u32 = 0u;
const PATTERN_STEP: u32 = 1u;
const PATTERN_CHECKERBOARD: u32 = 2u;
const SPECULAR_DUAL_GGX: u32 = 0u;
const SPECULAR_KELEMEN: u32 = 1u;
const MAP_MODULATES: u32 = 0u;
const MAP_ABSOLUTE: u32 = 1u;
const MAP_LOOK: u32 = 2u;
// The diffuse target's alpha where there is no skin (the SSS passes' edge
// convention, sss_common.wgsl), beside its Rust twin.
const DIFFUSE_ALPHA_NOT_SKIN: f32 = -1.0;

// Lengths in world units unless named otherwise; each field is documented
// on its twin.
struct SceneUniforms {
    clip_from_world: mat4x4<f32>,
    view_from_world: mat4x4<f32>,
    light_clip_from_world: mat4x4<f32>,
    camera_position: vec4<f32>,
    light_direction: vec4<f32>,   // xyz: towards a directional light (unit); point light: xyz position, w = 1
    light_radiance: vec4<f32>,    // rgb: irradiance at normal incidence
    rig_direction: array<vec4<f32>, 2>, // fill, rim: xyz towards each (directional, unshadowed)
    rig_radiance: array<vec4<f32>, 2>,  // rgb: each one's irradiance at normal incidence (0: off)
    surface_albedo: vec4<f32>,    // rgb: the look's colour (total reflectance), linear
    transmission_tint: vec4<f32>,
    blur_sigma_mm: vec4<f32>,     // rgb: per-channel σ (mm) picking each blurred normal's mip (preintegrated)
    environment_sh: array<vec4<f32>, 9>, // rgb: irradiance/π of the environment, order-2 SH (render::environment)
    eyes: array<vec4<f32>, 2>,    // eyeballs: xyz centre, w radius (0 = none)
    pre_scatter_exponent: f32,    // 0 or 0.5
    roughness0: f32,
    specular_f0: f32,
    roughness1: f32,
    lobe_mix: f32,                // Unreal's dual GGX
    specular_model: u32,          // SPECULAR_*
    pattern: u32,                 // PATTERN_*
    pattern_period: f32,
    shadow_texel: f32,            // 1 / shadow map size
    shadow_depth_bias: f32,
    shadow_normal_offset: f32,
    shadow_depth_range: f32,      // of the orthographic light projection
    light_near: f32,              // point light: shadow near/far planes
    light_far: f32,
    light_reference_distance: f32, // point light: where light_radiance is reached
    pad0: f32,
    transmission_mode: u32,       // TRANSMISSION_*
    transmittance_range_mm: f32,
    transmittance_entries: u32,
    mm_per_unit: f32,
    preintegrated: u32,           // 1 = the pre-integrated method
    lut_curvature_first: f32,     // 1/mm at the LUT's first and last rows
    lut_curvature_last: f32,
    penumbra_on: u32,
    albedo_map_mode: u32,         // MAP_*
    roughness_map_mode: u32,      // MAP_*
    thickness_map_range_mm: f32,  // 0 = per-vertex thickness
    detail_normal_strength: f32,
    penumbra_inv_width_first: f32, // 1/mm at the penumbra table's first and last rows
    penumbra_inv_width_last: f32,
    pcf_footprint_mm: f32,        // facing the light
    pad1: f32,
};

// The eye at `world` (material 1), drawn from the direction d to the
// nearer eyeball's centre against the gaze (+z, the head's front): a human
// eyeball is 24 mm across with an 11.7 mm iris and a 3–4 mm pupil (Atchison
// & Smith 2000), so the iris ends ~29° and the pupil ~8° off the gaze axis.
// Returns the albedo (linear) and, in w, 1 on the cornea (iris and pupil).
fn eye_albedo(world: vec3<f32>) -> vec4<f32> {
    var e = u.eyes[0];
    if (u.eyes[1].w > 0.0 && distance(world, u.eyes[1].xyz) < distance(world, e.xyz)) {
        e = u.eyes[1];
    }
    if (e.w <= 0.0) {
        return vec4<f32>(0.8, 0.78, 0.75, 0.0);
    }
    let d = normalize(world - e.xyz);
    let theta = acos(clamp(d.z, -1.0, 1.0));
    let phi = atan2(d.y, d.x);
    let iris_edge = 0.47;
    let pupil_edge = 0.15;
    // Sclera: off-white, warmer and pinker away from the cornea.
    let sclera = mix(vec3<f32>(0.78, 0.74, 0.70), vec3<f32>(0.72, 0.55, 0.50), smoothstep(0.9, 1.6, theta));
    // Iris: hazel-brown fibres (radial streaks), darker at the limbus.
    let fibres = 0.75 + 0.25 * sin(phi * 47.0 + 3.0 * sin(phi * 7.0)) * sin(phi * 23.0 + theta * 30.0);
    let radial = theta / iris_edge;
    var iris = mix(vec3<f32>(0.20, 0.11, 0.04), vec3<f32>(0.09, 0.06, 0.035), radial) * fibres;
    iris = iris * (1.0 - 0.75 * smoothstep(0.78, 1.0, radial));
    var a = mix(iris, sclera, smoothstep(iris_edge - 0.015, iris_edge + 0.015, theta));
    a = mix(vec3<f32>(0.012, 0.011, 0.010), a, smoothstep(pupil_edge - 0.01, pupil_edge + 0.01, theta));
    let cornea = 1.0 - smoothstep(iris_edge, iris_edge + 0.05, theta);
    return vec4<f32>(a, cornea);
}

// Direction towards the light from `world` (unit) and the radiance factor:
// 1 for a directional light, inverse square (1 at light_reference_distance) for a point.
fn light_at(world: vec3<f32>) -> vec4<f32> {
    if (u.light_direction.w < 0.5) {
        return vec4<f32>(u.light_direction.xyz, 1.0);
    }
    let d = u.light_direction.xyz - world;
    let r2 = max(dot(d, d), 1e-8);
    return vec4<f32>(d * inverseSqrt(r2), u.light_reference_distance * u.light_reference_distance / r2);
}

// Light clip space → (uv, depth) of the shadow map; a point light's map is
// a perspective one (divide by w).
fn light_space(p: vec4<f32>) -> vec3<f32> {
    let q = p.xyz / select(1.0, p.w, u.light_direction.w > 0.5);
    return vec3<f32>(q.x * 0.5 + 0.5, 0.5 - q.y * 0.5, q.z);
}

// Distance from the light along its axis (world units) of a shadow-map depth.
fn light_linear_depth(z: f32) -> f32 {
    if (u.light_direction.w < 0.5) {
        return z * u.shadow_depth_range;
    }
    let n = u.light_near;
    let f = u.light_far;
    return n * f / (f - z * (f - n));
}

// E(n)/π of the environment (Ramamoorthi & Hanrahan 2001): nine SH terms.
fn environment_irradiance(n: vec3<f32>) -> vec3<f32> {
    let c = u.environment_sh;
    var e = c[0].rgb * 0.282095;
    e = e + c[1].rgb * (0.488603 * n.y) + c[2].rgb * (0.488603 * n.z) + c[3].rgb * (0.488603 * n.x);
    e = e + c[4].rgb * (1.092548 * n.x * n.y) + c[5].rgb * (1.092548 * n.y * n.z);
    e = e + c[6].rgb * (0.315392 * (3.0 * n.z * n.z - 1.0)) + c[7].rgb * (1.092548 * n.x * n.z);
    e = e + c[8].rgb * (0.546274 * (n.x * n.x - n.y * n.y));
    return max(e, vec3<f32>(0.0));
}

@group(0) @binding(0) var<uniform> u: SceneUniforms;
@group(0) @binding(1) var shadow_map: texture_depth_2d;
@group(0) @binding(2) var shadow_sampler: sampler_comparison;
// Penner's D(θ, κ) − saturate(cos θ): x = N·L from −1 to 1 at texel
// centres, y = curvature κ (1/mm), linear RGB.
@group(0) @binding(3) var preintegrated_lut: texture_2d<f32>;
@group(0) @binding(4) var lut_sampler: sampler;
// Normalised thin-slab transmittance T(d)/total per channel, d = range·i/(size−1).
@group(0) @binding(5) var<storage, read> transmittance: array<vec4<f32>>;
// Surface maps (top-left UV origin), trilinear and repeating.
@group(0) @binding(6) var albedo_map: texture_2d<f32>;      // sRGB
@group(0) @binding(7) var normal_map: texture_2d<f32>;      // tangent space, green = +v (up)
@group(0) @binding(8) var roughness_map: texture_2d<f32>;
@group(0) @binding(9) var mask_map: texture_2d<f32>;
@group(0) @binding(10) var thickness_map: texture_2d<f32>;
@group(0) @binding(11) var surface_sampler: sampler;
// Penner's scattered shadow: x = unscattered shadow u, y = 1/penumbra width.
@group(0) @binding(12) var penumbra_lut: texture_2d<f32>;
// The shadow map again, as plain depth values (binding 1 is for comparison
// sampling; GLSL cannot textureLoad a comparison-bound depth texture).
@group(0) @binding(13) var shadow_depth: texture_2d<f32>;

fn transmittance_at(d_mm: f32) -> vec3<f32> {
    // The table ends at the profile's 0.999-energy radius: beyond it T(d)
    // is under 0.1 % of the total, and taking its last entry for every
    // longer path lit the whole shadowed side by that 0.1 %.
    if (d_mm >= u.transmittance_range_mm) {
        return vec3<f32>(0.0);
    }
    let n = f32(u.transmittance_entries);
    let t = clamp(d_mm / u.transmittance_range_mm, 0.0, 1.0) * (n - 1.0);
    let i = min(u32(t), u32(n) - 2u);
    return mix(transmittance[i].rgb, transmittance[i + 1u].rgb, t - f32(i));
}

// Thickness along the light from the shadow map (thick-object mode, Golubev
// 2018): light-space depth of this point minus the first occluder's, in mm.
fn shadow_thickness_mm(world: vec3<f32>) -> f32 {
    let q = light_space(u.light_clip_from_world * vec4<f32>(world, 1.0));
    let size = vec2<f32>(textureDimensions(shadow_map));
    let texel = clamp(vec2<i32>(q.xy * size), vec2<i32>(0), vec2<i32>(size) - vec2<i32>(1));
    let occluder = textureLoad(shadow_depth, texel, 0).r;
    let depth = light_linear_depth(q.z) - light_linear_depth(occluder);
    return max(depth, 0.0) * u.mm_per_unit;
}

// Whether a path through the part read from the shadow map is one: the map
// resolves the surface laterally only to the PCF's footprint, so a path
// shorter than it, just past the terminator, is the surface's own edge
// misread (it put T(0), the full light, there: issue 22's d → 0 floor of
// the back-lit ear), faded out below the footprint.
fn resolved_path(d_mm: f32) -> f32 {
    return smoothstep(0.5 * u.pcf_footprint_mm, u.pcf_footprint_mm, d_mm);
}

// PCF on the light's orthographic depth map: 3×3 bilinear comparison taps
// one texel apart, a tent filter over a 4×4-texel footprint.
fn shadow_factor(world: vec3<f32>, n: vec3<f32>) -> f32 {
    let q = light_space(u.light_clip_from_world * vec4<f32>(world + n * u.shadow_normal_offset, 1.0));
    let uv = q.xy;
    if (uv.x <= 0.0 || uv.x >= 1.0 || uv.y <= 0.0 || uv.y >= 1.0) {
        return 1.0;
    }
    let depth = q.z - u.shadow_depth_bias;
    var lit = 0.0;
    for (var y = -1; y <= 1; y = y + 1) {
        for (var x = -1; x <= 1; x = x + 1) {
            let o = vec2<f32>(f32(x), f32(y)) * u.shadow_texel;
            lit = lit + textureSampleCompareLevel(shadow_map, shadow_sampler, uv + o, depth);
        }
    }
    return lit / 9.0;
}

// Depth-only vertex shader for the shadow pass.
@vertex
fn vs_shadow(@location(0) position: vec3<f32>) -> @builtin(position) vec4<f32> {
    return u.light_clip_from_world * vec4<f32>(position, 1.0);
}

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) material: f32,   // 0 skin, 1 eye, 2 teeth
    @location(4) curvature: f32,  // 1/mm
    @location(5) thickness: f32,  // mm
    @location(6) tangent: vec4<f32>,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) material: f32,
    @location(4) view_depth: f32,
    @location(5) curvature: f32,
    @location(6) thickness: f32,
    @location(7) tangent: vec4<f32>,
};

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    var o: VertexOut;
    let world = vec4<f32>(v.position, 1.0);
    o.clip = u.clip_from_world * world;
    o.world = v.position;
    o.normal = v.normal;
    o.uv = v.uv;
    o.material = v.material;
    o.view_depth = -(u.view_from_world * world).z;
    o.curvature = v.curvature;
    o.thickness = v.thickness;
    o.tangent = v.tangent;
    return o;
}

struct TargetsOut {
    @location(0) diffuse: vec4<f32>,
    @location(1) specular: vec4<f32>,
    @location(2) albedo: vec4<f32>,
    @location(3) depth: f32,
};

const PI: f32 = 3.14159265;

// GGX / Trowbridge-Reitz specular with Smith height-correlated visibility.
fn ggx(n: vec3<f32>, v: vec3<f32>, l: vec3<f32>, roughness: f32, f0: f32) -> f32 {
    let h = normalize(v + l);
    let nl = max(dot(n, l), 0.0);
    let nv = max(dot(n, v), 1e-4);
    let nh = max(dot(n, h), 0.0);
    let a = roughness * roughness;
    let a2 = a * a;
    let d = a2 / (PI * pow(nh * nh * (a2 - 1.0) + 1.0, 2.0));
    let vis = 0.5 / (nl * sqrt(nv * nv * (1.0 - a2) + a2) + nv * sqrt(nl * nl * (1.0 - a2) + a2) + 1e-6);
    let f = f0 + (1.0 - f0) * pow(1.0 - max(dot(v, h), 0.0), 5.0);
    return d * vis * f * nl;
}

// Kelemen & Szirmay-Kalos 2001 as d'Eon 2007 (GPU Gems 3 §14.2) writes it:
// Beckmann distribution, Schlick Fresnel and the 1/|L+V|² visibility term.
fn kelemen(n: vec3<f32>, v: vec3<f32>, l: vec3<f32>, roughness: f32, f0: f32) -> f32 {
    let nl = max(dot(n, l), 0.0);
    if (nl <= 0.0) {
        return 0.0;
    }
    let hu = l + v;
    let h = normalize(hu);
    let nh = max(dot(n, h), 1e-4);
    let m = max(roughness * roughness, 1e-3);
    let tan2 = (1.0 - nh * nh) / (nh * nh);
    let beckmann = exp(-tan2 / (m * m)) / (PI * m * m * nh * nh * nh * nh);
    let f = f0 + (1.0 - f0) * pow(1.0 - max(dot(v, h), 0.0), 5.0);
    return max(beckmann * f / dot(hu, hu), 0.0) * nl;
}

// Penner's scattered shadow for the unscattered PCF value `lit` across a
// penumbra whose width on the surface is the PCF footprint / (N·L). The
// table (model::lut::bake_shadow) convolves a penumbra that has shadow on
// one side and light on the other right next to it, so its ends are not 0
// and 1; PCF cannot tell a fully lit pixel beside a penumbra from one far
// from any shadow, so the row is rescaled to run from 0 at its first
// column to 1 at its last: deep shadow stays black, open light stays
// white, and the colour fringe across the penumbra is kept.
fn scattered_shadow(lit: f32, n_dot_l: f32) -> vec3<f32> {
    if (u.pcf_footprint_mm <= 0.0) {
        return vec3<f32>(lit);
    }
    let width = u.pcf_footprint_mm / max(n_dot_l, 0.05);
    let y = clamp((1.0 / width - u.penumbra_inv_width_first) / (u.penumbra_inv_width_last - u.penumbra_inv_width_first), 0.0, 1.0);
    let lo = textureSampleLevel(penumbra_lut, lut_sampler, vec2<f32>(0.0, y), 0.0).rgb;
    let hi = textureSampleLevel(penumbra_lut, lut_sampler, vec2<f32>(1.0, y), 0.0).rgb;
    let v = textureSampleLevel(penumbra_lut, lut_sampler, vec2<f32>(lit, y), 0.0).rgb;
    return clamp((v - lo) / max(hi - lo, vec3<f32>(1e-4)), vec3<f32>(0.0), vec3<f32>(1.0));
}

// The surface maps at a point, as `shade` reads them.
struct Maps {
    albedo: vec3<f32>,
    normal: vec3<f32>,   // tangent space, −1..1
    roughness: f32,
    mask: f32,
    thickness: f32,
    // `preintegrated`: the normal map read per channel at the mip whose
    // texels are the profile's σ wide (tangent space, −1..1).
    blurred_r: vec3<f32>,
    blurred_g: vec3<f32>,
    blurred_b: vec3<f32>,
};

// The mip of the normal map whose texels are `sigma_mm` wide on the
// surface, never finer than the pixel's own: FaceWorks'
// GFSDK_FaceWorks_CalculateMipLevelForBlurredNormal, max(the hardware's
// level, log2(max(size·radius, uv_scale)/uv_scale)) (NVIDIAGameWorks/
// FaceWorks include/GFSDK_FaceWorks.hlsli and src/runtime.cpp lines
// 158–161), with the UV scale measured at the pixel from the derivatives
// (texels per mm = √(texel area / surface area) of the pixel's footprint)
// where FaceWorks averages it over the mesh.
fn blurred_level(sigma_mm: f32, hardware: f32, texels_per_mm: f32) -> f32 {
    return max(hardware, log2(max(sigma_mm * texels_per_mm, 1.0)));
}

// The maps as the scene pass reads them at a pixel (its derivatives: call
// in uniform control flow). texture_space_cloud.wgsl reads them again.
fn pixel_maps(i: VertexOut) -> Maps {
    // Every map is sampled first, in uniform control flow (derivatives).
    var maps: Maps;
    maps.albedo = textureSample(albedo_map, surface_sampler, i.uv).rgb;
    maps.normal = textureSample(normal_map, surface_sampler, i.uv).xyz * 2.0 - 1.0;
    maps.roughness = textureSample(roughness_map, surface_sampler, i.uv).r;
    maps.mask = textureSample(mask_map, surface_sampler, i.uv).r;
    maps.thickness = textureSample(thickness_map, surface_sampler, i.uv).r;
    maps.blurred_r = maps.normal;
    maps.blurred_g = maps.normal;
    maps.blurred_b = maps.normal;
    if (u.preintegrated == 1u) {
        let size = vec2<f32>(textureDimensions(normal_map, 0));
        let duvx = dpdx(i.uv) * size;
        let duvy = dpdy(i.uv) * size;
        let dwx = dpdx(i.world) * u.mm_per_unit;
        let dwy = dpdy(i.world) * u.mm_per_unit;
        let hardware = 0.5 * log2(max(max(dot(duvx, duvx), dot(duvy, duvy)), 1e-12));
        let texel_area = abs(duvx.x * duvy.y - duvx.y * duvy.x);
        let texels_per_mm = sqrt(texel_area / max(length(cross(dwx, dwy)), 1e-12));
        let s = u.blur_sigma_mm.xyz;
        maps.blurred_r = textureSampleLevel(normal_map, surface_sampler, i.uv, blurred_level(s.x, hardware, texels_per_mm)).xyz * 2.0 - 1.0;
        maps.blurred_g = textureSampleLevel(normal_map, surface_sampler, i.uv, blurred_level(s.y, hardware, texels_per_mm)).xyz * 2.0 - 1.0;
        maps.blurred_b = textureSampleLevel(normal_map, surface_sampler, i.uv, blurred_level(s.z, hardware, texels_per_mm)).xyz * 2.0 - 1.0;
    }
    return maps;
}

@fragment
fn fs_main(i: VertexOut) -> TargetsOut {
    return shade(i, pixel_maps(i), true);
}

// What the scene pass writes for a point of the surface with its maps
// read: the fragment shader's body, which the GPU ground truth
// (ground_truth_scene.wgsl) calls at points no pixel sees, with
// `transmission` off (the ground truth takes light through thin parts as
// irradiance on their far side's cells).
fn shade(i: VertexOut, maps: Maps, transmission: bool) -> TargetsOut {
    let albedo_tex = maps.albedo;
    let normal_tex = maps.normal;
    let rough_tex = maps.roughness;
    let mask_tex = maps.mask;
    let thickness_tex = maps.thickness;
    let ng = normalize(i.normal);
    let n = mapped_normal(ng, i.tangent, normal_tex);
    let v = normalize(u.camera_position.xyz - i.world);
    let light = light_at(i.world);
    let l = light.xyz;
    let light_radiance = u.light_radiance.rgb * light.w;
    var albedo = select(u.surface_albedo.rgb * 2.0 * albedo_tex, albedo_tex, u.albedo_map_mode == MAP_ABSOLUTE);
    if (u.albedo_map_mode == MAP_LOOK) {
        albedo = u.surface_albedo.rgb;
    }
    var mask = clamp(mask_tex, 0.0, 1.0);
    var cornea = 0.0;
    if (i.material > 0.5 && i.material < 1.5) {
        let eye = eye_albedo(i.world);
        albedo = eye.rgb;
        cornea = eye.w;
        mask = 0.0;
    } else if (i.material > 1.5) {
        albedo = vec3<f32>(0.85, 0.8, 0.7);
        mask = 0.0;
    }
    let rough_scale = select(2.0 * rough_tex, rough_tex / max(u.roughness0, 1e-3), u.roughness_map_mode == MAP_ABSOLUTE);
    var r0 = clamp(u.roughness0 * rough_scale, 0.02, 1.0);
    var r1 = clamp(u.roughness1 * rough_scale, 0.02, 1.0);
    var f0 = u.specular_f0;
    if (i.material > 0.5 && i.material < 1.5) {
        // The wet eye: a sharp highlight, glossier on the cornea (tear
        // film, n = 1.376: F0 = 0.025).
        r0 = mix(0.12, 0.04, cornea);
        r1 = r0;
        f0 = 0.025;
    }
    var thickness = i.thickness;
    if (u.thickness_map_range_mm > 0.0) {
        thickness = thickness_tex * u.thickness_map_range_mm;
    }
    // Irradiance/π: the directional light plus the SH environment.
    let shadow = shadow_factor(i.world, ng);
    let nl = max(dot(n, l), 0.0) * shadow;
    let hemi = environment_irradiance(n);
    // The fill and rim (directional, unshadowed): N·L each.
    var rig = vec3<f32>(0.0);
    for (var k = 0u; k < 2u; k = k + 1u) {
        if (any(u.rig_radiance[k].rgb > vec3<f32>(0.0))) {
            rig = rig + u.rig_radiance[k].rgb * max(dot(n, u.rig_direction[k].xyz), 0.0);
        }
    }
    var irradiance = (light_radiance * nl + rig) / PI + hemi;
    if (u.preintegrated == 1u && mask > 1.0 / 255.0) {
        // Pre-integrated skin (Penner 2011): D(θ, κ) per channel replaces
        // saturate(N·L), each channel with its own normal (the normal map
        // read at the mip as wide as that channel scatters, FaceWorks'
        // blurred normal; the vertex normal would throw away the shape a
        // coarse scan keeps in its map), and the penumbra table scatters
        // the shadow edge. κ is the mean curvature, 0 on hollows.
        let curv = clamp((i.curvature - u.lut_curvature_first) / (u.lut_curvature_last - u.lut_curvature_first), 0.0, 1.0);
        let nr = mapped_normal(ng, i.tangent, maps.blurred_r);
        let ngr = mapped_normal(ng, i.tangent, maps.blurred_g);
        let nb = mapped_normal(ng, i.tangent, maps.blurred_b);
        let lut_at = preintegrated_d(dot(nr, l), dot(ngr, l), dot(nb, l), curv);
        var s3 = vec3<f32>(shadow);
        if (u.penumbra_on == 1u) {
            s3 = scattered_shadow(shadow, max(dot(ng, l), 0.0));
        }
        // The fill and rim through the same table, unshadowed.
        var rig_d = vec3<f32>(0.0);
        for (var k = 0u; k < 2u; k = k + 1u) {
            if (any(u.rig_radiance[k].rgb > vec3<f32>(0.0))) {
                let lk = u.rig_direction[k].xyz;
                rig_d = rig_d + u.rig_radiance[k].rgb * preintegrated_d(dot(nr, lk), dot(ngr, lk), dot(nb, lk), curv);
            }
        }
        irradiance = (light_radiance * lut_at * s3 + rig_d) / PI + hemi;
    }
    if (transmission && u.transmission_mode != TRANSMISSION_OFF && mask > 0.0) {
        // Light through the back face (Jimenez 2010; Golubev 2018): thin
        // objects share the front's shadow; thick ones take max(baked,
        // shadow-map) thickness and are not shadowed by themselves.
        let back = max(-dot(ng, l), 0.0);
        var d = thickness;
        var reach = back;
        if (u.transmission_mode == TRANSMISSION_THICK) {
            // Unshadowed by the part itself, but only the light that did not
            // reach this point directly (as thin below).
            d = max(d, shadow_thickness_mm(i.world));
            reach = back * (1.0 - shadow) * resolved_path(d);
        } else if (back > 0.0) {
            // Thin objects take the shadow of the face the light enters,
            // looked up with the normal offset turned towards the light
            // (HDRP flips the shadow normal of lit back faces for
            // transmission: SHADOW_AUTO_FLIP_NORMAL, HDShadow.hlsl lines
            // 6–8 and 27–29, Unity Graphics 2c80a82; offsetting from this
            // point alone looked up the slab's own shadow: a back-lit 1 mm
            // slab got nothing, test
            // thin_transmission_lights_a_back_lit_slab_by_t_of_t). With a
            // thickness map the artist's thickness behind this point along
            // −N_g (HDRP's thin mode); without one, the distance the light
            // travels through the part to this point, from the shadow map
            // (d'Eon & Luebke 2007 §14.6, translucent shadow maps), entering
            // that far towards the light: the per-vertex bake along −N_g it
            // replaces was thin only at the ear's rim (issue 22). Only light
            // that did not reach this point directly goes through: where the
            // shadow map sees this point itself (the terminator, the
            // silhouette as the light sees it) the path is 0 and T(0) would
            // light it fully, so the unshadowed share is left out.
            var entry = i.world - ng * (thickness / u.mm_per_unit);
            var through = 1.0;
            if (u.thickness_map_range_mm <= 0.0) {
                d = shadow_thickness_mm(i.world);
                entry = i.world + l * (d / u.mm_per_unit);
                through = (1.0 - shadow) * resolved_path(d);
            }
            reach = back * shadow_factor(entry, -ng) * through;
        }
        irradiance = irradiance + light_radiance * reach * transmittance_at(d) * u.transmission_tint.rgb / PI;
    }
    // Test patterns (issue 5's plane scenes): flat irradiance of light_radiance/π.
    if (u.pattern == PATTERN_STEP) {
        irradiance = u.light_radiance.rgb / PI * select(0.0, 1.0, i.world.x > 0.0);
    } else if (u.pattern == PATTERN_CHECKERBOARD) {
        let cell = floor(i.world.xy / u.pattern_period);
        irradiance = u.light_radiance.rgb / PI * select(0.0, 1.0, (i32(cell.x) + i32(cell.y)) % 2 == 0);
    }
    // Light enters skin through albedo^pre wherever it is skin, the mask's
    // 0 included (skin scatters under brows and hair: the SSS passes and
    // the ground truth take its light); the composite multiplies
    // albedo^(1 − pre) back, so an unscattered pixel shows E·albedo
    // either way.
    let skin = i.material < 0.5;
    let pre = select(0.0, u.pre_scatter_exponent, skin);
    var o: TargetsOut;
    o.diffuse = vec4<f32>(irradiance * pow(albedo, vec3<f32>(pre)), select(DIFFUSE_ALPHA_NOT_SKIN, mask, skin));
    // Two lobes, never blurred: Unreal's dual GGX (lerp of two roughnesses)
    // or the Kelemen/Szirmay-Kalos lobe d'Eon 2007 uses for skin.
    var specular = light_radiance * specular_lobes(n, v, l, r0, r1, f0) * shadow;
    for (var k = 0u; k < 2u; k = k + 1u) {
        if (any(u.rig_radiance[k].rgb > vec3<f32>(0.0))) {
            specular = specular + u.rig_radiance[k].rgb * specular_lobes(n, v, u.rig_direction[k].xyz, r0, r1, f0);
        }
    }
    o.specular = vec4<f32>(specular, 1.0);
    o.albedo = vec4<f32>(pow(albedo, vec3<f32>(1.0 - pre)), 1.0);
    o.depth = i.view_depth;
    return o;
}

// The specular lobes for a light towards `l` (×N·L, per unit irradiance).
fn specular_lobes(n: vec3<f32>, v: vec3<f32>, l: vec3<f32>, r0: f32, r1: f32, f0: f32) -> f32 {
    if (u.specular_model == SPECULAR_KELEMEN) {
        return kelemen(n, v, l, r0, f0);
    }
    return mix(ggx(n, v, l, r0, f0), ggx(n, v, l, r1, f0), u.lobe_mix);
}

// The normal map's tangent-space normal in world space (glTF/MikkTSpace:
// B = w N × T), scaled by the detail strength; the geometric normal where
// there is no tangent frame.
fn mapped_normal(ng: vec3<f32>, tangent: vec4<f32>, normal_tex: vec3<f32>) -> vec3<f32> {
    let t_raw = tangent.xyz - ng * dot(ng, tangent.xyz);
    if (dot(t_raw, t_raw) > 1e-12 && u.detail_normal_strength > 0.0) {
        let t = normalize(t_raw);
        let b = cross(ng, t) * select(1.0, -1.0, tangent.w < 0.0);
        let d = vec3<f32>(normal_tex.xy * u.detail_normal_strength, max(normal_tex.z, 1e-3));
        return normalize(t * d.x + b * d.y + ng * d.z);
    }
    return ng;
}

// D(θ, κ) of each channel at its own N·L: the table holds
// D − saturate(N·L) (FaceWorks' delta), added back here.
fn preintegrated_d(nl_r: f32, nl_g: f32, nl_b: f32, curv: f32) -> vec3<f32> {
    let r = textureSampleLevel(preintegrated_lut, lut_sampler, vec2<f32>(0.5 * nl_r + 0.5, curv), 0.0).r;
    let g = textureSampleLevel(preintegrated_lut, lut_sampler, vec2<f32>(0.5 * nl_g + 0.5, curv), 0.0).g;
    let b = textureSampleLevel(preintegrated_lut, lut_sampler, vec2<f32>(0.5 * nl_b + 0.5, curv), 0.0).b;
    return vec3<f32>(r, g, b) + max(vec3<f32>(nl_r, nl_g, nl_b), vec3<f32>(0.0));
}
