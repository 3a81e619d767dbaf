//! Render targets: a multisampled colour and depth buffer, the resolved colour texture (what the
//! viewer paints and the exporter reads back), and a single-sampled organ-ID buffer with its own
//! depth for picking.
//!
//! - Screen pixels, origin top left.
//! - Float images for the transparency modes are made on first use.

use crate::error::{Error, Result};

/// Colour format of the resolved image: 8-bit sRGB with alpha.
pub const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
pub(crate) const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
pub(crate) const ID_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;
/// The outline mask: the nearest highlighted organ's index + 1 in red, 1 for the selected one in
/// green.
pub(crate) const MASK_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg16Float;

pub struct Target {
    pub width: u32,
    pub height: u32,
    pub(crate) msaa_color: wgpu::TextureView,
    pub(crate) msaa_depth: wgpu::TextureView,
    /// The resolved image; `TEXTURE_BINDING` so a viewer can paint it.
    pub color: wgpu::Texture,
    pub color_view: wgpu::TextureView,
    /// The same image viewed as plain `Rgba8Unorm`: for painters such as egui that take texels as
    /// sRGB-encoded values (sampling the sRGB view would decode them to linear, and darken them).
    pub display_view: wgpu::TextureView,
    pub(crate) ids: wgpu::Texture,
    pub(crate) ids_view: wgpu::TextureView,
    pub(crate) ids_depth: wgpu::TextureView,
    /// Float images for the transparency modes, made on first use.
    hdr: std::sync::OnceLock<Hdr>,
    /// The outline mask, made on first use.
    mask: std::sync::OnceLock<wgpu::TextureView>,
    /// What the drawing techniques keep between frames drawn into this target.
    pub(crate) kept: Kept,
}

/// What the drawing techniques keep between frames drawn into one target: buffers, bind groups
/// over its images, a frame drawn in part. One value per technique, by its type, made on first
/// use; it lives with the target, so the caller who owns the target owns it, and two views never
/// share it.
pub(crate) type Kept = type_map::concurrent::TypeMap;

/// Float images of a target's size for screen-door accumulation and weighted blended OIT.
pub(crate) struct Hdr {
    /// Multisampled float colour (a screen-door pass; the weighted sums).
    pub msaa: wgpu::TextureView,
    /// `msaa` resolved (one screen-door pass; the opaque image under weighted blending).
    pub resolved: wgpu::TextureView,
    /// The sum over screen-door passes; the resolved weighted sums.
    pub accum: wgpu::TextureView,
    /// Revealage of weighted blending, multisampled and resolved.
    pub reveal_msaa: wgpu::TextureView,
    pub reveal: wgpu::TextureView,
}

pub(crate) const HDR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
pub(crate) const REVEAL_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R16Float;

impl Target {
    /// A target of `width` x `height` pixels, refused where the adapter cannot make it
    /// ([`super::guard::check_target`]); a GPU error while its images are made is an error too.
    pub fn new(device: &wgpu::Device, width: u32, height: u32) -> Result<Target> {
        let software = device.adapter_info().device_type == wgpu::DeviceType::Cpu;
        let available = software.then(super::guard::available_memory).flatten();
        super::guard::check_target(&device.limits(), software, available, width, height)?;
        super::guard::guarded(device, "making the render target", || Ok(Self::make(device, width, height)))
    }

    fn make(device: &wgpu::Device, width: u32, height: u32) -> Target {
        let make = |label, format, samples, usage, view_formats: &[wgpu::TextureFormat]| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
                mip_level_count: 1,
                sample_count: samples,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats,
            })
        };
        let attach = wgpu::TextureUsages::RENDER_ATTACHMENT;
        let view = |t: &wgpu::Texture| t.create_view(&wgpu::TextureViewDescriptor::default());
        let samples = super::SAMPLE_COUNT;
        let plain = wgpu::TextureFormat::Rgba8Unorm;
        let painted = attach
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC
            | wgpu::TextureUsages::COPY_DST;
        let color = make("target color", COLOR_FORMAT, 1, painted, &[plain]);
        let ids = make("target ids", ID_FORMAT, 1, attach | wgpu::TextureUsages::COPY_SRC, &[]);
        Target {
            width,
            height,
            msaa_color: view(&make("target msaa color", COLOR_FORMAT, samples, attach, &[])),
            // Read by screen-door's tiles, which start from the opaque organs' depth.
            msaa_depth: view(&make(
                "target msaa depth",
                DEPTH_FORMAT,
                samples,
                attach | wgpu::TextureUsages::TEXTURE_BINDING,
                &[],
            )),
            color_view: view(&color),
            display_view: color.create_view(&wgpu::TextureViewDescriptor { format: Some(plain), ..Default::default() }),
            color,
            ids_view: view(&ids),
            ids,
            ids_depth: view(&make("target ids depth", DEPTH_FORMAT, 1, attach, &[])),
            hdr: std::sync::OnceLock::new(),
            mask: std::sync::OnceLock::new(),
            kept: Kept::new(),
        }
    }

    /// The float images, made on first use.
    pub(crate) fn hdr(&self, device: &wgpu::Device) -> &Hdr {
        self.hdr.get_or_init(|| {
            // Multisampled ones too: screen-door's tiles read the opaque image per sample.
            let make = |label, format, samples| image_view(device, label, [self.width, self.height], format, samples);
            let samples = super::SAMPLE_COUNT;
            Hdr {
                msaa: make("hdr msaa", HDR_FORMAT, samples),
                resolved: make("hdr resolved", HDR_FORMAT, 1),
                accum: make("hdr accum", HDR_FORMAT, 1),
                reveal_msaa: make("reveal msaa", REVEAL_FORMAT, samples),
                reveal: make("reveal", REVEAL_FORMAT, 1),
            }
        })
    }

    /// The outline mask (single-sampled, [`MASK_FORMAT`]), made on first use.
    pub(crate) fn mask(&self, device: &wgpu::Device) -> &wgpu::TextureView {
        self.mask.get_or_init(|| image_view(device, "outline mask", [self.width, self.height], MASK_FORMAT, 1))
    }

    pub fn aspect(&self) -> f32 {
        self.width as f32 / self.height as f32
    }

    /// Reads the resolved colour image back (blocking).
    pub fn read_color(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> Result<image::RgbaImage> {
        let bytes =
            read_texture(device, queue, &self.color, 4, [0, 0], [self.width, self.height], wgpu::TextureAspect::All)?;
        image::RgbaImage::from_raw(self.width, self.height, bytes)
            .ok_or_else(|| Error::gpu("read-back", "size mismatch"))
    }

    /// Reads the organ-ID buffer back (blocking): organ index + 1 per pixel, 0 for background.
    pub fn read_ids(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> Result<Vec<u32>> {
        let bytes =
            read_texture(device, queue, &self.ids, 4, [0, 0], [self.width, self.height], wgpu::TextureAspect::All)?;
        Ok(bytemuck::pod_collect_to_vec(&bytes))
    }

    /// Reads one pixel of the organ-ID buffer (blocking); `None` outside the target.
    pub fn read_id_at(&self, device: &wgpu::Device, queue: &wgpu::Queue, x: u32, y: u32) -> Result<Option<u32>> {
        if x >= self.width || y >= self.height {
            return Ok(None);
        }
        let bytes = read_texture(device, queue, &self.ids, 4, [x, y], [1, 1], wgpu::TextureAspect::All)?;
        Ok(Some(u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]])))
    }
}

/// A view of a new 2D image of `size` pixels that passes draw into and later passes read
/// (`RENDER_ATTACHMENT | TEXTURE_BINDING`).
pub(crate) fn image_view(
    device: &wgpu::Device,
    label: &str,
    size: [u32; 2],
    format: wgpu::TextureFormat,
    samples: u32,
) -> wgpu::TextureView {
    device
        .create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d { width: size[0], height: size[1], depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: samples,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        })
        .create_view(&wgpu::TextureViewDescriptor::default())
}

/// Copies a `size` region at `origin` of a single-sampled 2D texture into host memory, removing the
/// row padding.
pub(crate) fn read_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
    bytes_per_pixel: u32,
    origin: [u32; 2],
    size: [u32; 2],
    aspect: wgpu::TextureAspect,
) -> Result<Vec<u8>> {
    let [w, h] = size;
    let row = w * bytes_per_pixel;
    let padded = row.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("read-back"),
        size: padded as u64 * h as u64,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    encoder.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: 0,
            origin: wgpu::Origin3d { x: origin[0], y: origin[1], z: 0 },
            aspect,
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(padded), rows_per_image: Some(h) },
        },
        wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
    );
    queue.submit([encoder.finish()]);
    read_mapped(device, &buffer, "read-back", |data| {
        let mut out = Vec::with_capacity((row * h) as usize);
        for r in 0..h as usize {
            out.extend_from_slice(&data[r * padded as usize..r * padded as usize + row as usize]);
        }
        out
    })
}

/// Copies a whole buffer (`COPY_SRC`) back to the CPU (blocking).
pub(crate) fn read_buffer(device: &wgpu::Device, queue: &wgpu::Queue, source: &wgpu::Buffer) -> Result<Vec<u8>> {
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("read-back"),
        size: source.size(),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    encoder.copy_buffer_to_buffer(source, 0, &buffer, 0, source.size());
    queue.submit([encoder.finish()]);
    read_mapped(device, &buffer, "read-back", |data| data.to_vec())
}

/// Maps a `MAP_READ` buffer whose copy has been submitted, waits for it, and hands its bytes to
/// `read`; `what` names the read in errors.
pub(super) fn read_mapped<T>(
    device: &wgpu::Device,
    buffer: &wgpu::Buffer,
    what: &'static str,
    read: impl FnOnce(&[u8]) -> T,
) -> Result<T> {
    let (tx, rx) = std::sync::mpsc::channel();
    buffer.map_async(wgpu::MapMode::Read, .., move |r| {
        let _ = tx.send(r);
    });
    device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| Error::gpu("poll", e))?;
    rx.recv().map_err(|e| Error::gpu(what, e))?.map_err(|e| Error::gpu(what, e))?;
    let data = buffer.get_mapped_range(..).map_err(|e| Error::gpu(what, e))?;
    let out = read(&data);
    drop(data);
    buffer.unmap();
    Ok(out)
}

/// Buffers that bring `count` query results (u64 each) back to the CPU: resolved into one, copied
/// into one it maps.
pub(super) struct QueryReadback {
    resolved: wgpu::Buffer,
    read: wgpu::Buffer,
    count: u32,
}

impl QueryReadback {
    pub fn new(device: &wgpu::Device, label: &'static str, count: u32) -> QueryReadback {
        let buffer = |usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: 8 * u64::from(count),
                usage,
                mapped_at_creation: false,
            })
        };
        let resolved = buffer(wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC);
        let read = buffer(wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST);
        QueryReadback { resolved, read, count }
    }

    /// Records resolving queries `0..count` of `set` and copying them out.
    pub fn record(&self, encoder: &mut wgpu::CommandEncoder, set: &wgpu::QuerySet) {
        encoder.resolve_query_set(set, 0..self.count, &self.resolved, 0);
        encoder.copy_buffer_to_buffer(&self.resolved, 0, &self.read, 0, 8 * u64::from(self.count));
    }

    /// The results, once the recording has been submitted (waits for the GPU); `what` names the
    /// read in errors.
    pub fn read(&self, device: &wgpu::Device, what: &'static str) -> Result<Vec<u64>> {
        read_mapped(device, &self.read, what, |data| {
            data.chunks_exact(8).map(|c| u64::from_le_bytes(c.try_into().unwrap_or([0; 8]))).collect()
        })
    }
}
