//! `none`: plain diffuse, the baseline every method's cost and error is
//! measured from. The scene pass lights it with saturate(N·L); nothing
//! scatters. The renderer also draws any method as `none` when no SSS
//! pixel is on screen or the profile does not scatter.

/// `none` in the registry (`sss::Method::sss`).
pub(in crate::render) static METHOD: super::MethodInfo = super::MethodInfo {
    id: "none",
    label: "none (no scattering)",
    quality: super::Quality::Fixed,
    stochastic: super::Stochastic::Never,
    reads: super::Reads {
        separable_kernel: false,
        penner_tables: false,
        gaussians: false,
    },
    penner_in_scene_pass: false,
    ground_truth: false,
    baseline: true,
    variant: "",
    shader: None,
    colour: [120, 120, 120],
    encode: super::no_pass,
};
