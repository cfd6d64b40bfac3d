//! Per-pass statistics: what each pass touched, and its GPU time from
//! timestamp queries where the adapter has them (on lavapipe the "GPU" is
//! the CPU, so its times are CPU times).

use super::context::GpuContext;

/// One pass of a frame, as `render --stats` reports it.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct PassStats {
    pub name: &'static str,
    /// Pixels (or shadow-map texels) the pass shaded.
    pub pixels: u64,
    /// Profile samples the pass took (convolution taps); 0 for passes that
    /// do not convolve.
    pub samples: u64,
    /// GPU time in ms, `None` where the adapter has no timestamp queries.
    pub gpu_ms: Option<f64>,
}

/// Most passes one frame runs: shadow, scene, classify, composite and, for
/// six Gaussians, a clear plus 3 passes each.
const MAX_PASSES: u32 = 32;

/// Hands each pass a pair of timestamp queries and collects its stats.
pub(super) struct PassTimer {
    queries: Option<(wgpu::QuerySet, wgpu::Buffer, wgpu::Buffer)>,
    passes: Vec<PassStats>,
}

impl PassTimer {
    pub fn new(ctx: &GpuContext) -> Self {
        let queries = ctx.timestamps.then(|| {
            let device = &ctx.device;
            let bytes = 8 * 2 * MAX_PASSES as u64;
            let set = device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("pass timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: 2 * MAX_PASSES,
            });
            let buffer = |label, usage| {
                device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(label),
                    size: bytes,
                    usage,
                    mapped_at_creation: false,
                })
            };
            let resolve = buffer(
                "timestamp resolve",
                wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            );
            let read = buffer(
                "timestamp readback",
                wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            );
            (set, resolve, read)
        });
        Self {
            queries,
            passes: Vec::new(),
        }
    }

    /// Records a pass and returns the index of its query pair, if timed.
    fn push(&mut self, name: &'static str, pixels: u64, samples: u64) -> Option<u32> {
        let index = self.passes.len() as u32;
        self.passes.push(PassStats {
            name,
            pixels,
            samples,
            gpu_ms: None,
        });
        (self.queries.is_some() && index < MAX_PASSES).then_some(index)
    }

    /// Timestamp writes for a new render pass.
    pub fn render(
        &mut self,
        name: &'static str,
        pixels: u64,
        samples: u64,
    ) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        let index = self.push(name, pixels, samples)?;
        let (set, _, _) = self.queries.as_ref()?;
        Some(wgpu::RenderPassTimestampWrites {
            query_set: set,
            beginning_of_pass_write_index: Some(2 * index),
            end_of_pass_write_index: Some(2 * index + 1),
        })
    }

    /// Timestamp writes for a new compute pass.
    pub fn compute(
        &mut self,
        name: &'static str,
        pixels: u64,
        samples: u64,
    ) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        let index = self.push(name, pixels, samples)?;
        let (set, _, _) = self.queries.as_ref()?;
        Some(wgpu::ComputePassTimestampWrites {
            query_set: set,
            beginning_of_pass_write_index: Some(2 * index),
            end_of_pass_write_index: Some(2 * index + 1),
        })
    }

    /// Overwrites the sample count of the last pass named `name` (for
    /// counts measured on the GPU after the frame).
    pub fn set_samples(&mut self, name: &str, samples: u64) {
        if let Some(p) = self.passes.iter_mut().rev().find(|p| p.name == name) {
            p.samples = samples;
        }
    }

    /// Copies the timestamps to the readback buffer (last command of a frame).
    pub fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        let n = (self.passes.len() as u32).min(MAX_PASSES);
        if let (Some((set, resolve, read)), true) = (&self.queries, n > 0) {
            encoder.resolve_query_set(set, 0..2 * n, resolve, 0);
            encoder.copy_buffer_to_buffer(resolve, 0, read, 0, 16 * n as u64);
        }
    }

    /// After the frame's submission: fills in each pass's GPU time.
    pub fn finish(mut self, ctx: &GpuContext) -> Vec<PassStats> {
        let n = self.passes.len().min(MAX_PASSES as usize);
        let ticks = match &self.queries {
            Some((_, _, read)) if n > 0 => super::readback::read_u64s(ctx, read, 2 * n),
            _ => None,
        };
        if let Some(t) = ticks {
            let ns_per_tick = ctx.queue.get_timestamp_period() as f64;
            for (k, p) in self.passes.iter_mut().take(n).enumerate() {
                p.gpu_ms = Some(t[2 * k + 1].saturating_sub(t[2 * k]) as f64 * ns_per_tick * 1e-6);
            }
        }
        self.passes
    }
}

/// Sum of the SSS passes' GPU times, where every one was timed.
pub(super) fn sss_gpu_ms(passes: &[PassStats]) -> Option<f64> {
    let sss: Vec<_> = passes
        .iter()
        .filter(|p| p.name.starts_with("sss"))
        .collect();
    (!sss.is_empty())
        .then(|| sss.iter().map(|p| p.gpu_ms).sum::<Option<f64>>())
        .flatten()
}
