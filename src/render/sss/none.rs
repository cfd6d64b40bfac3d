//! `none`: plain diffuse, the baseline every method's cost and error is
//! measured from. The scene pass lights it with saturate(N·L); nothing
//! scatters. The renderer also draws any method as `none` when no SSS
//! pixel is on screen or the profile does not scatter.

/// `none` in the registry (`sss::Method::sss`).
pub(in crate::render) static METHOD: super::MethodInfo = super::MethodInfo {
    id: "none",
    label: "none (no scattering)",
    baseline: true,
    colour: [120, 120, 120],
    ..super::MethodInfo::BASE
};

/// Nothing of its own: no inputs, buffers, pipelines, options or state.
pub type Inputs = ();
pub(in crate::render) type Buffers = ();
pub(in crate::render) type Pipelines = ();
pub type Options = super::NoOptions;
pub(in crate::render) type State = ();
