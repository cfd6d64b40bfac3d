// Counts the pixels whose SSS mask exceeds 1/255 (the skip mask of seed 000
// §4: SSSS_STRENGTH_SOURCE / Subsurface Mask). The frame runs no SSS pass
// when the count is zero.

@group(0) @binding(0) var diffuse_tex: texture_2d<f32>;
@group(0) @binding(1) var<storage, read_write> counts: array<atomic<u32>, 4>;

@compute @workgroup_size(8, 8)
fn cs_classify(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(diffuse_tex);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    if (textureLoad(diffuse_tex, vec2<i32>(id.xy), 0).a > 1.0 / 255.0) {
        atomicAdd(&counts[0], 1u);
    }
}
