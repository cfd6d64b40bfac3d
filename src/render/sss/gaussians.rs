//! `gaussians` (d'Eon 2007, Jimenez 2009 in screen space): the profile as
//! a sum of Gaussians, each blurred in two depth-aware 1D passes and added
//! with its RGB weight into an accumulation target.

use super::{separable, Scattered, SssFrame, SssPipelines};
use crate::render::frame::FrameEncoder;
use crate::render::inputs::GAUSSIAN_TAPS;
use crate::render::renderer::HdrTarget;

pub(in crate::render) fn encode(
    f: &mut FrameEncoder,
    p: &SssPipelines,
    io: &SssFrame,
) -> Scattered {
    let t = io.targets;
    let (w, h) = t.size;
    let pixels = w as u64 * h as u64;
    let taps = GAUSSIAN_TAPS as u32;
    f.clear(t.view(HdrTarget::Accum), "sss gaussians clear", pixels);
    for (buffer, weight) in &io.profile.gaussians {
        separable::blur_xy(
            f,
            p,
            io,
            (buffer, taps),
            (HdrTarget::Diffuse, HdrTarget::Pong),
            ["sss gaussian x", "sss gaussian y"],
        );
        let u = f.uniform(
            "accumulate uniforms",
            bytemuck::bytes_of(&io.uniforms(taps as f32, [weight[0], weight[1], weight[2], 0.0])),
        );
        let label = "sss gaussian accumulate";
        let bg = separable::bind_group(
            f.device,
            p,
            &u,
            t.view(HdrTarget::Pong),
            &t.albedo_depth,
            buffer,
            label,
        );
        // One load per pixel, over the whole target.
        f.fullscreen(
            t.view(HdrTarget::Accum),
            &p.accumulate,
            &bg,
            label,
            (pixels, pixels),
            true,
        );
    }
    Scattered {
        target: HdrTarget::Accum,
        samples_per_pixel: 2 * taps * io.profile.gaussians.len() as u32,
        counted_pass: None,
    }
}
