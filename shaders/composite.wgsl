// Recombine: scattered diffuse × albedo^post + specular, then exposure and
// the ACES filmic curve (Narkowicz 2015 fit); the sRGB target encodes.

struct CompositeUniforms {
    exposure: vec4<f32>,   // x: exposure multiplier
};

@group(0) @binding(0) var<uniform> c: CompositeUniforms;
@group(0) @binding(1) var diffuse_tex: texture_2d<f32>;
@group(0) @binding(2) var specular_tex: texture_2d<f32>;
@group(0) @binding(3) var albedo_depth_tex: texture_2d<f32>;

fn aces(x: vec3<f32>) -> vec3<f32> {
    let a = 2.51;
    let b = 0.03;
    let cc = 2.43;
    let d = 0.59;
    let e = 0.14;
    return clamp((x * (a * x + b)) / (x * (cc * x + d) + e), vec3<f32>(0.0), vec3<f32>(1.0));
}

@fragment
fn fs_composite(in: FullscreenOut) -> @location(0) vec4<f32> {
    let p = vec2<i32>(in.clip.xy);
    let d = textureLoad(diffuse_tex, p, 0);
    let sp = textureLoad(specular_tex, p, 0);
    let ad = textureLoad(albedo_depth_tex, p, 0);
    if (ad.a <= 0.0) {
        // Background: a dim studio grey.
        return vec4<f32>(aces(vec3<f32>(0.05, 0.055, 0.06) * c.exposure.x), 1.0);
    }
    let hdr = d.rgb * ad.rgb + sp.rgb;
    return vec4<f32>(aces(hdr * c.exposure.x), 1.0);
}
