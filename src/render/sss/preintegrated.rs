//! `preintegrated` (Penner 2011): no screen-space pass. The scene pass
//! (`shaders/scene.wgsl`) looks Penner's D(θ, κ) up from the profile
//! core's ring-integral table (uploaded in `profile_gpu.rs`) with the
//! per-vertex curvature FaceWorks computes, instead of saturate(N·L).

use crate::model::lut::LutLayout;
use crate::render::settings::Method;

/// `SceneUniforms::preintegrated`: x = 1 for this method; y, z: the
/// curvature 1/r (1/mm) of the table's first and last rows.
pub(in crate::render) fn uniforms(method: Method, layout: &LutLayout) -> [f32; 4] {
    [
        if method == Method::Preintegrated {
            1.0
        } else {
            0.0
        },
        1.0 / layout.curvature_radius(0) as f32,
        1.0 / layout.curvature_radius(layout.height - 1) as f32,
        0.0,
    ]
}
