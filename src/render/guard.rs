//! GPU errors as errors, never panics; and a target's size checked before it is made.
//!
//! - wgpu reports out-of-memory, validation and internal errors either to an error scope or,
//!   uncaught, to a handler whose default panics.
//! - [`guarded`] runs GPU work inside scopes and gives their first error as an [`Error`];
//!   [`log_uncaptured`] replaces the panicking handler of a device (headless or the viewer's) with
//!   one that reports on stderr.
//! - Before a target is made, [`check_target`] compares its size with the adapter's texture limit
//!   and its memory (an estimate per pixel) with what the machine can give: a software adapter
//!   (lavapipe) renders in system memory.

use crate::error::{Error, Result};
use std::sync::Arc;

/// Bytes of render targets per pixel, an upper bound over techniques: 4x MSAA colour and depth,
/// the resolved colour, picking IDs and depth, screen-door's float images (multisampled and
/// resolved), the outline mask, and room for peeling's layers.
pub const TARGET_BYTES_PER_PIXEL: u64 = 160;

/// The most memory vbrain gives one image's targets on any adapter (8 GiB).
pub const MAX_TARGET_BYTES: u64 = 8 << 30;

/// Runs `work` inside out-of-memory, validation and internal error scopes of `device`; a GPU error
/// raised meanwhile is the result (`what` names the work in its message).
pub fn guarded<T>(device: &wgpu::Device, what: &'static str, work: impl FnOnce() -> Result<T>) -> Result<T> {
    let oom = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
    let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let internal = device.push_error_scope(wgpu::ErrorFilter::Internal);
    let result = work();
    // Scopes pop innermost first; each pop takes effect at once.
    let errors: Vec<wgpu::Error> =
        [internal.pop(), validation.pop(), oom.pop()].into_iter().filter_map(pollster::block_on).collect();
    match cause(errors) {
        Some(wgpu::Error::OutOfMemory { .. }) => Err(Error::GpuMemory { what }),
        Some(e) => Err(Error::gpu(what, e)),
        None => result,
    }
}

/// The error that explains the others: running out of memory leaves the resource it was making
/// invalid, and every later use of it raises a validation error ("... is invalid") that would
/// hide the cause. So out-of-memory first, then the first of the rest.
fn cause(errors: Vec<wgpu::Error>) -> Option<wgpu::Error> {
    let oom = errors.iter().position(|e| matches!(e, wgpu::Error::OutOfMemory { .. }));
    errors.into_iter().nth(oom.unwrap_or(0))
}

/// Makes `device` report errors that no scope catches on stderr instead of panicking.
pub fn log_uncaptured(device: &wgpu::Device) {
    device.on_uncaptured_error(Arc::new(|e: wgpu::Error| eprintln!("GPU error: {e}")));
}

/// Refuses a `width` x `height` target the adapter cannot make: a side beyond its texture limit,
/// more than [`MAX_TARGET_BYTES`] of targets, or, on a software adapter, more than 70 % of the
/// memory the system has available (`available`, where known).
pub fn check_target(
    limits: &wgpu::Limits,
    software: bool,
    available: Option<u64>,
    width: u32,
    height: u32,
) -> Result<()> {
    let max = limits.max_texture_dimension_2d;
    if width == 0 || height == 0 || width > max || height > max {
        return Err(Error::ImageSize { width, height, max });
    }
    let bytes = u64::from(width) * u64::from(height) * TARGET_BYTES_PER_PIXEL;
    let budget = match available {
        Some(a) if software => (a / 10 * 7).min(MAX_TARGET_BYTES),
        _ => MAX_TARGET_BYTES,
    };
    if bytes > budget {
        return Err(Error::TargetMemory { width, height, bytes, budget });
    }
    Ok(())
}

/// The memory the system can give now ([`crate::input::available_memory`]).
pub fn available_memory() -> Option<u64> {
    crate::input::available_memory()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn running_out_of_memory_is_the_cause_over_the_invalid_uses_it_leaves() {
        let invalid = || wgpu::Error::Validation {
            source: Box::new(std::io::Error::other("Texture with '' label is invalid")),
            description: "Texture with '' label is invalid".into(),
        };
        let oom = wgpu::Error::OutOfMemory { source: Box::new(std::io::Error::other("out of memory")) };
        assert!(matches!(cause(vec![invalid(), oom]), Some(wgpu::Error::OutOfMemory { .. })));
        assert!(matches!(cause(vec![invalid()]), Some(wgpu::Error::Validation { .. })));
        assert!(cause(Vec::new()).is_none());
    }

    #[test]
    fn targets_beyond_the_limits_or_the_memory_are_refused() {
        let limits = wgpu::Limits { max_texture_dimension_2d: 16384, ..Default::default() };
        assert!(check_target(&limits, false, None, 1024, 1024).is_ok());
        let e = check_target(&limits, false, None, 16385, 10).unwrap_err();
        assert!(e.to_string().contains("16385x10"), "{e}");
        let e = check_target(&limits, false, None, 12000, 12000).unwrap_err().to_string();
        assert!(e.contains("12000x12000") && e.contains("GiB"), "{e}");
        // A software adapter renders in system memory: 2 GiB free refuses 4096^2 (2.5 GiB).
        assert!(check_target(&limits, true, Some(2 << 30), 4096, 4096).is_err());
        assert!(check_target(&limits, false, Some(2 << 30), 4096, 4096).is_ok());
    }
}
