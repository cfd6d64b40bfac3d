//! One frame's command recording: timed fullscreen passes, per-frame
//! uniform buffers and bind-group entries, shared by every method.

use super::timing::PassTimer;
use wgpu::util::DeviceExt;

/// The frame's encoder and pass timer.
pub(super) struct FrameEncoder<'a> {
    pub device: &'a wgpu::Device,
    pub encoder: wgpu::CommandEncoder,
    pub timer: PassTimer,
}

impl<'a> FrameEncoder<'a> {
    pub fn new(device: &'a wgpu::Device, timer: PassTimer) -> Self {
        Self {
            device,
            encoder: device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("frame"),
            }),
            timer,
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

    /// One fullscreen triangle into `target`, timed and counted as
    /// (pixels, samples). `load` keeps the target's contents (additive
    /// passes); otherwise it is cleared first.
    #[allow(clippy::too_many_arguments)]
    pub fn fullscreen(
        &mut self,
        target: &wgpu::TextureView,
        pipeline: &wgpu::RenderPipeline,
        bind_group: &wgpu::BindGroup,
        label: &'static str,
        (pixels, samples): (u64, u64),
        load: bool,
    ) {
        let mut pass = self.begin(target, label, (pixels, samples), load);
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, bind_group, &[]);
        pass.draw(0..3, 0..1);
    }

    /// A pass that only clears `target`.
    pub fn clear(&mut self, target: &wgpu::TextureView, label: &'static str, pixels: u64) {
        self.begin(target, label, (pixels, 0), false);
    }

    fn begin(
        &mut self,
        target: &wgpu::TextureView,
        label: &'static str,
        (pixels, samples): (u64, u64),
        load: bool,
    ) -> wgpu::RenderPass<'_> {
        self.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(label),
            color_attachments: &[Some(color_attachment(target, load))],
            timestamp_writes: self.timer.render(label, pixels, samples),
            ..Default::default()
        })
    }
}

/// A colour attachment that clears to transparent black, or keeps (`load`).
pub(super) fn color_attachment(
    view: &wgpu::TextureView,
    load: bool,
) -> wgpu::RenderPassColorAttachment<'_> {
    wgpu::RenderPassColorAttachment {
        view,
        resolve_target: None,
        depth_slice: None,
        ops: wgpu::Operations {
            load: if load {
                wgpu::LoadOp::Load
            } else {
                wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT)
            },
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
