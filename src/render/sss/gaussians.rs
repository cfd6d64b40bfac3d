//! `gaussians` (d'Eon 2007, Jimenez 2009 in screen space): the profile as
//! a sum of Gaussians, each blurred in two depth-aware 1D passes; each
//! vertical pass adds its Gaussian's RGB weight × result into the output
//! (additive blending), so N Gaussians cost 2N passes.

use super::separable::{self, Into};
use super::{Scattered, SssFrame, SssPipelines};
use crate::render::frame::FrameEncoder;
use crate::render::targets::HdrTarget;

pub(in crate::render) fn encode(
    f: &mut FrameEncoder,
    p: &SssPipelines,
    io: &SssFrame,
) -> Scattered {
    let taps = io.profile.gaussian_tap_count;
    if io.profile.gaussians.is_empty() {
        // No Gaussians set: nothing to add, the diffuse stays unscattered.
        return Scattered {
            target: HdrTarget::Diffuse,
            samples_per_pixel: 0,
            counted_pass: None,
        };
    }
    for (k, (buffer, weight, sigma)) in io.profile.gaussians.iter().enumerate() {
        // Each Gaussian follows the surface with its own σ (Jimenez 2015
        // eq. 7 before its σ_max approximation: exact for a Gaussian).
        separable::blur_xy(
            f,
            p,
            io,
            (buffer, taps),
            *sigma,
            Into::Add {
                weight: *weight,
                first: k == 0,
            },
            ["sss gaussian x", "sss gaussian y"],
        );
    }
    Scattered {
        target: HdrTarget::Pong,
        samples_per_pixel: 2 * taps * io.profile.gaussians.len() as u32,
        counted_pass: None,
    }
}
