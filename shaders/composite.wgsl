// Recombine: scattered diffuse × albedo^post + specular, then exposure and
// the ACES filmic curve (Narkowicz 2015 fit); the sRGB target encodes.

struct CompositeUniforms {
    exposure: f32,   // multiplier
    pad0: f32,
    pad1: f32,
    pad2: f32,
};

@group(0) @binding(0) var<uniform> c: CompositeUniforms;
// The method's output: written only on SSS pixels (alpha > 0 there).
@group(0) @binding(1) var scattered_tex: texture_2d<f32>;
@group(0) @binding(2) var specular_tex: texture_2d<f32>;
// rgb: albedo^post, a: 1 on the mesh, 0 on the background.
@group(0) @binding(3) var albedo_tex: texture_2d<f32>;
// The scene's diffuse irradiance, used where no SSS pass wrote.
@group(0) @binding(4) var diffuse_tex: texture_2d<f32>;

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
    let scattered = textureLoad(scattered_tex, p, 0);
    let d = select(textureLoad(diffuse_tex, p, 0), scattered, scattered.a > 1.0 / 255.0);
    let sp = textureLoad(specular_tex, p, 0);
    let ad = textureLoad(albedo_tex, p, 0);
    if (ad.a <= 0.0) {
        // Background: a dim studio grey.
        return vec4<f32>(aces(vec3<f32>(0.05, 0.055, 0.06) * c.exposure), 1.0);
    }
    let hdr = d.rgb * ad.rgb + sp.rgb;
    return vec4<f32>(aces(hdr * c.exposure), 1.0);
}

// Progressive refinement: the method's output joins the running mean of
// the frames before it. The pipeline blends with the constant c = 1/(n+1)
// (`pipelines::Output::Mean`): mean_{n+1} = c·x + (1 − c)·mean_n, the
// incremental mean. Alpha (the SSS mask, the same every frame) stays.
@fragment
fn fs_accumulate(in: FullscreenOut) -> @location(0) vec4<f32> {
    return textureLoad(scattered_tex, vec2<i32>(in.clip.xy), 0);
}
