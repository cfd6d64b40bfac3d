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
    /// The environment map drawn behind the head (a black texel until one
    /// is set) and its mip levels.
    background: (wgpu::TextureView, u32),
    background_sampler: wgpu::Sampler,
}

/// How a frame shows its background ([`super::super::RenderSettings::background`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BackgroundTerms {
    pub on: bool,
    /// 0 sharp … 1 the coarsest level.
    pub blur: f32,
    pub turn_rad: f32,
    pub intensity: f32,
    pub direction_from_clip: glam::Mat4,
}

/// The background map's levels uploaded as RGBA half floats.
fn upload_background(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    map: &crate::render::environment::BackgroundMap,
) -> (wgpu::TextureView, u32) {
    use crate::render::readback::f32_to_half;
    let mut levels = vec![map.clone()];
    while levels.last().is_some_and(|l| l.width > 8 && l.height > 4) {
        let next = levels
            .last()
            .map(|l| l.half())
            .unwrap_or_else(|| map.clone());
        levels.push(next);
    }
    let data: Vec<u8> = levels
        .iter()
        .flat_map(|l| l.texels.iter())
        // A sun (10⁵–10⁶) is past half floats' largest finite value,
        // which would become ∞ and NaN in filtering: held at 65504.
        .flat_map(|t| [t[0], t[1], t[2], 1.0].map(|v| f32_to_half(v.min(65504.0))))
        .flat_map(u16::to_le_bytes)
        .collect();
    let view = crate::render::textures::sampled_texture(
        device,
        queue,
        "background",
        (map.width, map.height, levels.len() as u32),
        wgpu::TextureFormat::Rgba16Float,
        &data,
    );
    (view, levels.len() as u32)
}

impl CompositePass {
    /// Draws `map` behind the head from now on (`None`: a plain grey).
    pub fn set_background(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        map: Option<&crate::render::environment::BackgroundMap>,
    ) {
        let black = crate::render::environment::BackgroundMap {
            width: 1,
            height: 1,
            texels: vec![[0.0; 3]],
        };
        self.background = upload_background(device, queue, map.unwrap_or(&black));
    }

    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, module: &wgpu::ShaderModule) -> Self {
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("composite"),
            entries: &[
                uniform_entry::<CompositeUniforms>(0, wgpu::ShaderStages::FRAGMENT),
                texture_entry(1),
                texture_entry(2),
                texture_entry(3),
                texture_entry(4),
                wgpu::BindGroupLayoutEntry {
                    binding: 5,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: true },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 6,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
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
            background: upload_background(
                device,
                queue,
                &crate::render::environment::BackgroundMap {
                    width: 1,
                    height: 1,
                    texels: vec![[0.0; 3]],
                },
            ),
            background_sampler: device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("background"),
                address_mode_u: wgpu::AddressMode::Repeat,
                address_mode_v: wgpu::AddressMode::ClampToEdge,
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                mipmap_filter: wgpu::MipmapFilterMode::Linear,
                ..Default::default()
            }),
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
        (exposure, tone_map, background): (f32, super::super::tonemap::ToneMap, BackgroundTerms),
        scattered: HdrTarget,
    ) -> Result<&'t wgpu::Texture, GpuError> {
        let (texture, view) = match progressive {
            Some(p) => self.accumulate(f, t, p, scattered)?,
            None => (t.texture(scattered), t.view(scattered)),
        };
        let uniforms = CompositeUniforms {
            exposure,
            tone_map: tone_map.shader_id(),
            background_on: background.on as u32,
            background_lod: background.blur.clamp(0.0, 1.0)
                * (self.background.1.saturating_sub(1)) as f32,
            background_turn: background.turn_rad / std::f32::consts::TAU,
            background_intensity: background.intensity,
            direction_from_clip: background.direction_from_clip.to_cols_array_2d(),
            frame_width: t.size.0 as f32,
            frame_height: t.size.1 as f32,
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
                tex(5, &self.background.0),
                wgpu::BindGroupEntry {
                    binding: 6,
                    resource: wgpu::BindingResource::Sampler(&self.background_sampler),
                },
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
