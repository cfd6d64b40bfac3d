//! The composite pass: the scattered diffuse (or its running mean) times
//! albedo^post, plus specular, exposed and tonemapped into the 8-bit
//! output (`shaders/composite.wgsl`, `fs_composite`); and progressive
//! refinement's accumulation of a frame into the running mean
//! (`fs_accumulate`, blend constant 1/(n+1)).

use super::super::context::GpuError;
use super::super::frame::{buf, color_attachment, tex, FrameEncoder};
use super::super::gpu_types::CompositeUniforms;
use super::super::pipelines::{fullscreen_pipeline, texture_entry, uniform_entry, Output, Stencil};
use super::super::pipelines::{HDR, OUTPUT};
use super::super::settings::Progressive;
use super::super::targets::{HdrTarget, Targets};

pub(in crate::render) struct CompositePass {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
    accumulate_layout: wgpu::BindGroupLayout,
    accumulate_pipeline: wgpu::RenderPipeline,
}

impl CompositePass {
    pub fn new(device: &wgpu::Device, module: &wgpu::ShaderModule) -> Self {
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("composite"),
            entries: &[
                uniform_entry::<CompositeUniforms>(0, wgpu::ShaderStages::FRAGMENT),
                texture_entry(1),
                texture_entry(2),
                texture_entry(3),
                texture_entry(4),
            ],
        });
        let accumulate_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("accumulate"),
            entries: &[texture_entry(1)],
        });
        Self {
            pipeline: fullscreen_pipeline(
                device,
                module,
                "fs_composite",
                &layout,
                Output::Replace(OUTPUT),
                Stencil::None,
            ),
            accumulate_pipeline: fullscreen_pipeline(
                device,
                module,
                "fs_accumulate",
                &accumulate_layout,
                Output::Mean(HDR),
                Stencil::None,
            ),
            layout,
            accumulate_layout,
        }
    }

    /// Progressive refinement: blends the method's output (`scattered`)
    /// into running mean `p.slot` with weight 1/(n+1) for frame n, and
    /// returns the mean (what composite then shows).
    /// The frame's last step: the scattered irradiance, averaged into the
    /// progressive mean when there is one, composited into the output at
    /// `exposure`. Returns the texture shown (the mean or the irradiance).
    pub fn finish<'t>(
        &self,
        f: &mut FrameEncoder,
        t: &'t Targets,
        progressive: Option<Progressive>,
        exposure: f32,
        tone_map: super::super::tonemap::ToneMap,
        scattered: HdrTarget,
    ) -> Result<&'t wgpu::Texture, GpuError> {
        let (texture, view) = match progressive {
            Some(p) => self.accumulate(f, t, p, scattered)?,
            None => (t.texture(scattered), t.view(scattered)),
        };
        let uniforms = CompositeUniforms {
            exposure,
            tone_map: tone_map.shader_id(),
            ..bytemuck::Zeroable::zeroed()
        };
        self.encode(f, t, view, uniforms);
        Ok(texture)
    }

    pub fn accumulate<'t>(
        &self,
        f: &mut FrameEncoder,
        t: &'t Targets,
        p: Progressive,
        scattered: HdrTarget,
    ) -> Result<(&'t wgpu::Texture, &'t wgpu::TextureView), GpuError> {
        let Some((mean_texture, mean)) = t.accum[p.slot].as_ref() else {
            return Err(GpuError::Readback("no progressive target".into()));
        };
        let bg = f.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("accumulate"),
            layout: &self.accumulate_layout,
            entries: &[tex(1, t.view(scattered))],
        });
        let (w, h) = t.size;
        let mut pass = f.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("accumulate"),
            color_attachments: &[Some(color_attachment(mean, p.frame > 0))],
            timestamp_writes: f.timer.render("accumulate", w as u64 * h as u64, 0),
            ..Default::default()
        });
        pass.set_pipeline(&self.accumulate_pipeline);
        pass.set_bind_group(0, &bg, &[]);
        let c = 1.0 / (p.frame as f64 + 1.0);
        pass.set_blend_constant(wgpu::Color {
            r: c,
            g: c,
            b: c,
            a: c,
        });
        pass.draw(0..3, 0..1);
        Ok((mean_texture, mean))
    }

    /// Composites `shown` (the scattered diffuse) with the scene's
    /// specular and albedo into the output target.
    pub fn encode(
        &self,
        f: &mut FrameEncoder,
        t: &Targets,
        shown: &wgpu::TextureView,
        uniforms: CompositeUniforms,
    ) {
        let cu = f.uniform("composite uniforms", bytemuck::bytes_of(&uniforms));
        let output_view = t.output.create_view(&Default::default());
        let bg = f.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("composite"),
            layout: &self.layout,
            entries: &[
                buf(0, &cu),
                tex(1, shown),
                tex(2, &t.specular),
                tex(3, &t.albedo),
                tex(4, t.view(HdrTarget::Diffuse)),
            ],
        });
        let (w, h) = t.size;
        f.fullscreen(
            Some(&output_view),
            &self.pipeline,
            &bg,
            "composite",
            (w as u64 * h as u64, 0),
            false,
            false,
        );
    }
}
