"""The Cycles settings the real-client scripts share (blender_edge.py,
blender_head.py): a CPU render with every sample kept as it is, so that
what is measured is Cycles' estimator and nothing after it."""

import os


def unbiased_cpu_cycles(scene, width, height, samples):
    """Cycles on the CPU at width x height, `samples` a pixel, with no
    adaptive sampling, no denoiser and no firefly clamping (it would clip
    the rare, bright samples that carry a profile's tail into the
    shadow); a pixel filter of 0.01 px, so that every sample goes through
    the pixel's centre as a rasteriser samples; the Standard view
    transform (the EXR is linear either way). Bounces and the output
    format are the caller's."""
    r = scene.render
    r.engine = "CYCLES"
    r.resolution_x = width
    r.resolution_y = height
    r.resolution_percentage = 100
    r.threads_mode = "FIXED"
    r.threads = os.cpu_count() or 2
    c = scene.cycles
    c.device = "CPU"
    c.samples = samples
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.seed = 1
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    c.filter_width = 0.01
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    return r, c
