// Classification (the engines' skip mask: SSSS_STRENGTH_SOURCE / Subsurface
// Mask): a fullscreen pass that writes stencil 1 where the SSS mask exceeds
// 1/255 (the pipeline replaces the stencil of every fragment that survives)
// and counts those pixels. Every SSS pass then tests stencil = 1, so it
// shades only masked pixels, and the frame runs no SSS pass at all when the
// count is zero.

@group(0) @binding(0) var diffuse_tex: texture_2d<f32>;
@group(0) @binding(1) var<storage, read_write> counts: array<atomic<u32>, 4>;

@fragment
fn fs_classify(in: FullscreenOut) {
    if (textureLoad(diffuse_tex, vec2<i32>(in.clip.xy), 0).a <= 1.0 / 255.0) {
        discard;
    }
    atomicAdd(&counts[0], 1u);
}
