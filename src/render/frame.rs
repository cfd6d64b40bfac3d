//! One frame's command recording: timed fullscreen passes, per-frame
//! uniform buffers and bind-group entries, shared by every method.

use super::timing::PassTimer;
use wgpu::util::DeviceExt;

/// The frame's encoder and pass timer.
pub(super) struct FrameEncoder<'a> {
    pub device: &'a wgpu::Device,
    pub encoder: wgpu::CommandEncoder,
    pub timer: PassTimer,
    /// The scene's depth-stencil view, whose stencil marks SSS pixels.
    pub stencil: Option<&'a wgpu::TextureView>,
}

impl<'a> FrameEncoder<'a> {
    pub fn new(device: &'a wgpu::Device, timer: PassTimer) -> Self {
        Self {
            device,
            encoder: device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("frame"),
            }),
            timer,
            stencil: None,
        }
    }

    /// Takes the recorded commands out (to submit them), leaving a fresh encoder.
    pub fn take(&mut self) -> wgpu::CommandEncoder {
        let fresh = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("frame"),
            });
        std::mem::replace(&mut self.encoder, fresh)
    }

    /// A small per-frame uniform buffer.
    pub fn uniform(&self, label: &'static str, bytes: &[u8]) -> wgpu::Buffer {
        self.device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytes,
                usage: wgpu::BufferUsages::UNIFORM,
            })
    }

    /// One fullscreen triangle into `target` (or into no colour target),
    /// timed and counted as (pixels, samples). `load` keeps the target's
    /// contents (additive passes); otherwise it is cleared first. With
    /// `stencil`, the scene's stencil is attached with reference 1: the
    /// pipeline decides whether it tests it (SSS passes) or writes it
    /// (classification).
    #[allow(clippy::too_many_arguments)]
    pub fn fullscreen(
        &mut self,
        target: Option<&wgpu::TextureView>,
        pipeline: &wgpu::RenderPipeline,
        bind_group: &wgpu::BindGroup,
        label: &'static str,
        (pixels, samples): (u64, u64),
        load: bool,
        stencil: bool,
    ) {
        let color = [target.map(|t| color_attachment(t, load))];
        let depth_stencil_attachment =
            self.stencil
                .filter(|_| stencil)
                .map(|view| wgpu::RenderPassDepthStencilAttachment {
                    view,
                    depth_ops: None,
                    stencil_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Load,
                        store: wgpu::StoreOp::Store,
                    }),
                });
        let mut pass = self.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(label),
            color_attachments: if target.is_some() { &color } else { &[] },
            depth_stencil_attachment,
            timestamp_writes: self.timer.render(label, pixels, samples),
            ..Default::default()
        });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, bind_group, &[]);
        pass.set_stencil_reference(1);
        pass.draw(0..3, 0..1);
    }
}

/// A colour attachment that clears to transparent black, or keeps (`load`).
pub(super) fn color_attachment(
    view: &wgpu::TextureView,
    load: bool,
) -> wgpu::RenderPassColorAttachment<'_> {
    let clear = (!load).then_some(wgpu::Color::TRANSPARENT);
    color_attachment_clearing(view, clear)
}

/// A colour attachment that clears to `clear`, or keeps (`None`).
pub(super) fn color_attachment_clearing(
    view: &wgpu::TextureView,
    clear: Option<wgpu::Color>,
) -> wgpu::RenderPassColorAttachment<'_> {
    wgpu::RenderPassColorAttachment {
        view,
        resolve_target: None,
        depth_slice: None,
        ops: wgpu::Operations {
            load: clear.map_or(wgpu::LoadOp::Load, wgpu::LoadOp::Clear),
            store: wgpu::StoreOp::Store,
        },
    }
}

/// A texture-view entry of a bind group.
pub(super) fn tex(binding: u32, view: &wgpu::TextureView) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry {
        binding,
        resource: wgpu::BindingResource::TextureView(view),
    }
}

/// A whole-buffer entry of a bind group.
pub(super) fn buf(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry {
        binding,
        resource: buffer.as_entire_binding(),
    }
}
