//! GPU time of a frame from timestamp queries, where the adapter has them
//! (`TIMESTAMP_QUERY` and `TIMESTAMP_QUERY_INSIDE_ENCODERS`; Mesa's lavapipe has both). One
//! timestamp is written before the frame's first submission and one after its last, so the span
//! covers every pass a technique submits, in milliseconds of the GPU's clock. Reading it back waits
//! for the GPU, so the renderer takes it only when a frame asks ([`super::FrameInput::time_gpu`]).

use crate::error::Result;

/// The features a device needs for [`GpuTimer`].
pub const FEATURES: wgpu::Features =
    wgpu::Features::TIMESTAMP_QUERY.union(wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS);

pub(super) struct GpuTimer {
    queries: wgpu::QuerySet,
    resolved: wgpu::Buffer,
    read: wgpu::Buffer,
}

impl GpuTimer {
    /// A timer, or `None` where the device lacks [`FEATURES`].
    pub fn new(device: &wgpu::Device) -> Option<GpuTimer> {
        if !device.features().contains(FEATURES) {
            return None;
        }
        let queries = device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("frame time"),
            ty: wgpu::QueryType::Timestamp,
            count: 2,
        });
        let buffer = |usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("frame time"),
                size: 16,
                usage,
                mapped_at_creation: false,
            })
        };
        let resolved = buffer(wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC);
        let read = buffer(wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST);
        Some(GpuTimer { queries, resolved, read })
    }

    /// Submits the frame's first timestamp.
    pub fn start(&self, device: &wgpu::Device, queue: &wgpu::Queue) {
        let mut encoder = device.create_command_encoder(&Default::default());
        encoder.write_timestamp(&self.queries, 0);
        queue.submit([encoder.finish()]);
    }

    /// Submits the frame's last timestamp and returns the milliseconds since the first (blocking).
    pub fn stop(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> Result<f64> {
        let mut encoder = device.create_command_encoder(&Default::default());
        encoder.write_timestamp(&self.queries, 1);
        encoder.resolve_query_set(&self.queries, 0..2, &self.resolved, 0);
        encoder.copy_buffer_to_buffer(&self.resolved, 0, &self.read, 0, 16);
        queue.submit([encoder.finish()]);
        let ticks = super::target::read_mapped(device, &self.read, "frame time", |data| {
            let at = |i: usize| u64::from_le_bytes(data[i * 8..i * 8 + 8].try_into().unwrap_or([0; 8]));
            at(1).saturating_sub(at(0))
        })?;
        Ok(ticks as f64 * f64::from(queue.get_timestamp_period()) / 1e6)
    }
}
