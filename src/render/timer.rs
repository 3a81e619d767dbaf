//! GPU time of a frame from timestamp queries, where the adapter has them.
//!
//! - The adapter needs `TIMESTAMP_QUERY` and `TIMESTAMP_QUERY_INSIDE_ENCODERS` (Mesa's lavapipe
//!   has both).
//! - One timestamp is written before the frame's first submission and one after its last, so the
//!   span covers every pass a technique submits, in milliseconds of the GPU's clock.
//! - Reading it back waits for the GPU, so the renderer takes it only when a frame asks
//!   ([`super::FrameInput::time_gpu`]).

use super::target::QueryReadback;
use crate::error::Result;

/// The features a device needs for [`GpuTimer`].
pub const FEATURES: wgpu::Features =
    wgpu::Features::TIMESTAMP_QUERY.union(wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS);

pub(super) struct GpuTimer {
    queries: wgpu::QuerySet,
    readback: QueryReadback,
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
        Some(GpuTimer { queries, readback: QueryReadback::new(device, "frame time", 2) })
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
        self.readback.record(&mut encoder, &self.queries);
        queue.submit([encoder.finish()]);
        let stamps = self.readback.read(device, "frame time")?;
        let ticks = stamps[1].saturating_sub(stamps[0]);
        Ok(ticks as f64 * f64::from(queue.get_timestamp_period()) / 1e6)
    }
}
