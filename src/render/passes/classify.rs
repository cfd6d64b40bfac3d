//! The classify pass: counts the pixels whose SSS mask exceeds 1/255 and
//! marks them in the stencil, which every SSS pass then tests
//! (`shaders/classify.wgsl`). With none on screen no SSS pass runs.

use super::super::context::{GpuContext, GpuError};
use super::super::frame::{buf, tex, FrameEncoder};
use super::super::pipelines::{buffer_entry, fullscreen_pipeline, texture_entry, Output, Stencil};
use super::super::readback::read_u32x4;
use super::super::targets::{HdrTarget, Targets};
use super::counter_buffers;

pub(in crate::render) struct ClassifyPass {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
}

impl ClassifyPass {
    pub fn new(device: &wgpu::Device, module: &wgpu::ShaderModule) -> Self {
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("classify"),
            entries: &[
                texture_entry(0),
                buffer_entry(
                    1,
                    wgpu::BufferBindingType::Storage { read_only: false },
                    wgpu::ShaderStages::FRAGMENT,
                ),
            ],
        });
        Self {
            pipeline: fullscreen_pipeline(
                device,
                module,
                "fs_classify",
                &layout,
                Output::Nothing,
                Stencil::Mark,
            ),
            layout,
        }
    }

    /// Records the pass after the recorded work, submits, and reads the
    /// SSS pixel count back.
    pub fn count(
        &self,
        ctx: &GpuContext,
        f: &mut FrameEncoder,
        t: &Targets,
    ) -> Result<u64, GpuError> {
        let device = &ctx.device;
        let (counts, read) = counter_buffers(device, "sss counts");
        let bg = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("classify"),
            layout: &self.layout,
            entries: &[tex(0, t.view(HdrTarget::Diffuse)), buf(1, &counts)],
        });
        let (w, h) = t.size;
        f.fullscreen(
            None,
            &self.pipeline,
            &bg,
            "classify",
            (w as u64 * h as u64, 0),
            false,
            true,
        );
        f.encoder.copy_buffer_to_buffer(&counts, 0, &read, 0, 16);
        ctx.queue.submit([f.take().finish()]);
        read_u32x4(ctx, &read)
            .map(|c| c[0] as u64)
            .ok_or_else(|| GpuError::Readback("sss pixel count".into()))
    }
}
