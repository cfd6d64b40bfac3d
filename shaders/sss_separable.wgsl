// Separable SSS (Jimenez 2012, SSSSBlurPS): one 1D pass along
// `s.direction.xy`, offsets in mm scaled to pixels by depth, and the
// follow-surface term that lerps back to the centre colour across depth
// discontinuities.

struct Tap {
    weight_offset: vec4<f32>,   // rgb weight, a: offset (mm)
};

@group(0) @binding(3) var<storage, read> taps: array<Tap>;

@fragment
fn fs_separable(in: FullscreenOut) -> @location(0) vec4<f32> {
    let p = vec2<i32>(in.clip.xy);
    let centre = load_diffuse(p);
    if (centre.a <= 1.0 / 255.0) {
        return centre;
    }
    let z = load_depth(p);
    // Stochastic axis rotation (Jimenez 2015 §6; rotate_axis = 1): both
    // passes turn their axes by the same per-pixel angle, trading the
    // kernel's banding for noise; the taps then read the nearest texel.
    var axis = s.direction.xy;
    let rotate = s.rotate_axis == 1u;
    if (rotate) {
        let a = 6.28318531 * rotation_turns(hash(vec2<u32>(p)));
        axis = vec2<f32>(axis.x * cos(a) - axis.y * sin(a), axis.x * sin(a) + axis.y * cos(a));
    }
    let step = axis * pixels_per_mm(z) * centre.a;
    let n = s.sample_count;
    var acc = centre.rgb * taps[0].weight_offset.rgb;
    for (var i = 1u; i < n; i = i + 1u) {
        let t = taps[i].weight_offset;
        // Linear interpolation along the blur axis between the two nearest
        // texels (what the demo's bilinear sampler does).
        let off = step * t.a;
        var base = floor(off);
        var f = dot(off - base, abs(s.direction.xy));
        if (rotate) {
            base = round(off);
            f = 0.0;
        }
        let q0 = p + vec2<i32>(base);
        let q1 = q0 + vec2<i32>(abs(s.direction.xy));
        // Each texel's light by the edge convention (`light_from`): skin
        // gives its own, eyes and teeth none with the weight kept, and the
        // background none with its weight moved to the centre (the demo's
        // renormalisation, as across depth below).
        let l0 = light_from(load_diffuse(q0));
        let l1 = light_from(load_diffuse(q1));
        let v0 = select(centre.rgb, l0.rgb, l0.a > 0.5);
        let v1 = select(centre.rgb, l1.rgb, l1.a > 0.5);
        let dz_mm = abs(mix(load_depth(q0), load_depth(q1), f) - z) * s.mm_per_unit;
        // Follow the surface: across a depth difference the tap's weight
        // moves to the centre. follow_surface > 0: the Jimenez 2012 demo's
        // lerp, strength per mm; < 0: −1/(2σ²) of Jimenez 2015 eq. 7's
        // e^(−Δz²/2σ²) with the kernel's σ.
        var k = clamp(s.follow_surface * dz_mm, 0.0, 1.0);
        if (s.follow_surface < 0.0) {
            k = 1.0 - exp(s.follow_surface * dz_mm * dz_mm);
        }
        let col = mix(mix(v0, v1, f), centre.rgb, k);
        acc = acc + t.rgb * col;
    }
    return vec4<f32>(acc * s.weight.rgb, centre.a);
}
