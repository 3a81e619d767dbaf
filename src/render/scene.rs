//! The set on the GPU: the organs' vertices and indices merged into a few large buffers (batches),
//! the frame uniform's slots, the organs' data in a storage buffer (one section per use), and the
//! draw calls every technique shares.
//!
//! - Vertices in organ space, each with its organ's index.
//! - Organs next to each other in a batch are drawn by one call where their index ranges meet, so
//!   a frame's draw calls grow with the runs of organs drawn, not with the organs.

use super::passes::Pass;
use super::pipelines::{clear_colour, OrganPipelines};
use super::target::Target;
use super::uniforms::{FrameUniform, OrganUniform, Vertex, CAPPED, CLIPPED, CLOSED, FRAME_SLOTS, SLOT, UNMOVED};
use super::FrameInput;
use crate::cull::DrawList;
use crate::error::{Error, Result};
use crate::layout::OrganState;
use crate::organ_set::OrganSet;
use glam::{Mat3, Mat4, Vec3, Vec4};
use std::borrow::Cow;
use std::ops::Range;
use wgpu::util::DeviceExt;

/// Sections of organ uniforms: the organs as shown, and two recoloured sets for the culling debug
/// view.
pub(super) const SECTIONS: u64 = 3;

/// Most bytes of one batch's vertex or index buffer (and at most the device's buffer size).
const BATCH_BYTES: u64 = 128 << 20;

struct Batch {
    vertices: wgpu::Buffer,
    /// Indices into the batch's vertices (the organ's vertex offset added).
    indices: wgpu::Buffer,
    /// The same indices, three per triangle, and each triangle's centroid in organ space, for
    /// drawing triangles in depth order ([`GpuScene::triangle_stream`]).
    triangles: Vec<[u32; 3]>,
    centroids: Vec<Vec3>,
}

struct GpuMesh {
    batch: usize,
    /// Where the organ's indices start in its batch's index buffer.
    first_index: u32,
    index_count: u32,
    /// Organ-space centre, for back-to-front sorting of translucent organs.
    center: Vec3,
    /// Drawn with back faces culled ([`crate::organ_set::Organ::closed`]).
    closed: bool,
    /// Organ-space bounds, to tell which organs the clip planes cut.
    bounds: crate::mesh::Bounds,
    /// Its levels of detail ([`crate::lod`]), coarsest last: index ranges relative to
    /// `first_index`, after every organ's full mesh in the batch (so that full meshes stay
    /// neighbours, and runs of them one draw call).
    levels: Vec<Range<u32>>,
}

pub(super) struct GpuScene {
    meshes: Vec<GpuMesh>,
    batches: Vec<Batch>,
    /// Bytes between sections of the organ storage buffer.
    section_bytes: u64,
    frame_buffer: wgpu::Buffer,
    frame_bind: wgpu::BindGroup,
    organ_buffer: wgpu::Buffer,
    organ_bind: wgpu::BindGroup,
    pub frame_layout: wgpu::BindGroupLayout,
    pub organ_layout: wgpu::BindGroupLayout,
    /// The pipeline layout of organ pipelines: frame, then organ.
    pub layout: wgpu::PipelineLayout,
    mri: GpuMri,
}

/// The set's MRI as a 3-D texture (frame group, bindings 1 and 2), written on the first frame
/// (making the scene has no queue). A set without one, or with one larger than the device's 3-D
/// textures, gets a single black voxel and cut faces in colour.
struct GpuMri {
    texture: wgpu::Texture,
    /// The voxels still to write, and organ space -> texture coordinates.
    pending: std::sync::Mutex<Option<std::sync::Arc<crate::mri::Mri>>>,
    to_texture: Option<Mat4>,
}

impl GpuMri {
    fn new(device: &wgpu::Device, mri: Option<&std::sync::Arc<crate::mri::Mri>>) -> GpuMri {
        let max = device.limits().max_texture_dimension_3d as usize;
        let mri = mri.filter(|m| m.dims().iter().all(|&d| d <= max));
        let [x, y, z] = mri.map_or([1, 1, 1], |m| m.dims().map(|d| d as u32));
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("mri"),
            size: wgpu::Extent3d { width: x, height: y, depth_or_array_layers: z },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D3,
            format: wgpu::TextureFormat::R8Unorm,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        let to_texture = mri.map(|m| {
            let dims = Vec3::new(x as f32, y as f32, z as f32);
            Mat4::from_scale(dims.recip()) * Mat4::from_translation(Vec3::splat(0.5)) * m.to_world().inverse()
        });
        GpuMri { texture, pending: std::sync::Mutex::new(mri.cloned()), to_texture }
    }

    /// Writes the voxels once.
    fn upload(&self, queue: &wgpu::Queue) {
        let Some(mri) = self.pending.lock().ok().and_then(|mut p| p.take()) else { return };
        let [x, y, z] = mri.dims().map(|d| d as u32);
        queue.write_texture(
            self.texture.as_image_copy(),
            mri.voxels(),
            wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(x), rows_per_image: Some(y) },
            wgpu::Extent3d { width: x, height: y, depth_or_array_layers: z },
        );
    }
}

/// What an upload of the organs' uniforms decided for the draws that follow: per organ, whether it
/// is capped (drawn again for its cut faces). Draws take it, so no other upload in between can
/// change what they draw.
pub(super) struct Shown {
    capped: Vec<bool>,
}

impl Shown {
    fn capped(&self, organ: usize) -> bool {
        self.capped.get(organ).copied().unwrap_or(false)
    }
}

/// A uniform-buffer bind group layout entry at binding 0, with a dynamic offset.
pub(super) fn uniform_entry(visibility: wgpu::ShaderStages) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding: 0,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: true,
            min_binding_size: None,
        },
        count: None,
    }
}

impl GpuScene {
    /// Uploads the set's meshes and makes its uniform buffers.
    pub fn new(device: &wgpu::Device, set: &OrganSet) -> Result<GpuScene> {
        let max = device.limits().max_buffer_size;
        let cap = max.min(BATCH_BYTES);
        let mut meshes = Vec::with_capacity(set.organs.len());
        let (mut batches, mut vertices, mut indices) = (Vec::new(), Vec::<Vertex>::new(), Vec::<u32>::new());
        let vertex_bytes = std::mem::size_of::<Vertex>() as u64;
        // The organs of the batch being filled, with their vertices' base: their levels of detail
        // go after all of the batch's full meshes, when the batch is closed.
        let (mut pending, mut pending_levels): (Vec<(usize, u32)>, u64) = (Vec::new(), 0);
        let close = |vertices: &mut Vec<Vertex>,
                     indices: &mut Vec<u32>,
                     (meshes, pending): (&mut Vec<GpuMesh>, &mut Vec<(usize, u32)>),
                     batches: &mut Vec<Batch>| {
            for (organ, base) in pending.drain(..) {
                let m = &mut meshes[organ];
                for level in set.organs[organ].lods() {
                    let start = indices.len() as u32 - m.first_index;
                    indices.extend(level.iter().map(|&v| v + base));
                    m.levels.push(start..indices.len() as u32 - m.first_index);
                }
            }
            let buffer = |contents: &[u8], usage| {
                device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some("organs"), contents, usage })
            };
            let triangles: Vec<[u32; 3]> = indices.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
            let at = |v: u32| Vec3::from(vertices[v as usize].position);
            let centroids = triangles.iter().map(|t| (at(t[0]) + at(t[1]) + at(t[2])) / 3.0).collect();
            batches.push(Batch {
                vertices: buffer(bytemuck::cast_slice(vertices), wgpu::BufferUsages::VERTEX),
                indices: buffer(bytemuck::cast_slice(indices), wgpu::BufferUsages::INDEX),
                triangles,
                centroids,
            });
            vertices.clear();
            indices.clear();
        };
        for (i, o) in set.organs.iter().enumerate() {
            let (nv, ni) = (o.mesh.positions.len() as u64, o.mesh.indices.len() as u64);
            let nl: u64 = o.lods().iter().map(|l| l.len() as u64).sum();
            let bytes = (nv * vertex_bytes).max((ni + nl) * 4);
            if bytes > max {
                return Err(Error::BufferTooLarge { organ: o.id.clone(), bytes, max });
            }
            let full = (vertices.len() as u64 + nv) * vertex_bytes > cap
                || (indices.len() as u64 + pending_levels + ni + nl) * 4 > cap;
            if full && !vertices.is_empty() {
                close(&mut vertices, &mut indices, (&mut meshes, &mut pending), &mut batches);
                pending_levels = 0;
            }
            let base = vertices.len() as u32;
            let first_index = indices.len() as u32;
            let territories = set
                .territories
                .as_ref()
                .and_then(|t| crate::colouring::packed_territory_colours(t, &o.mesh))
                .unwrap_or_default();
            vertices.extend(o.mesh.positions.iter().zip(&o.mesh.normals).enumerate().map(|(v, (p, n))| Vertex {
                position: *p,
                normal: *n,
                organ: i as u32,
                territory: territories.get(v).copied().unwrap_or(0),
            }));
            indices.extend(o.mesh.indices.iter().map(|&v| v + base));
            meshes.push(GpuMesh {
                batch: batches.len(),
                first_index,
                index_count: ni as u32,
                center: o.mesh.bounds().center(),
                closed: o.closed(),
                bounds: o.mesh.bounds(),
                levels: Vec::new(),
            });
            pending.push((i, base));
            pending_levels += nl;
        }
        if !vertices.is_empty() || batches.is_empty() {
            close(&mut vertices, &mut indices, (&mut meshes, &mut pending), &mut batches);
        }
        let layout_of = |label, ty| {
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(label),
                entries: &[wgpu::BindGroupLayoutEntry {
                    ty: wgpu::BindingType::Buffer { ty, has_dynamic_offset: true, min_binding_size: None },
                    ..uniform_entry(wgpu::ShaderStages::VERTEX_FRAGMENT)
                }],
            })
        };
        let frame_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("frame"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: true,
                        min_binding_size: None,
                    },
                    ..uniform_entry(wgpu::ShaderStages::VERTEX_FRAGMENT)
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: true },
                        view_dimension: wgpu::TextureViewDimension::D3,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 2,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
            ],
        });
        let organ_layout = layout_of("organ", wgpu::BufferBindingType::Storage { read_only: true });
        let buffer = |label, size, usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: usage | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let frame_buffer = buffer("frame uniforms", SLOT * FRAME_SLOTS, wgpu::BufferUsages::UNIFORM);
        // Sections of the organs' data: 0 as shown, 1 and 2 for the culling debug view.
        let organ_bytes = std::mem::size_of::<OrganUniform>() as u64;
        let section_bytes = (organ_bytes * set.organs.len().max(1) as u64).next_multiple_of(SLOT);
        let organ_buffer = buffer("organs", section_bytes * SECTIONS, wgpu::BufferUsages::STORAGE);
        let bind = |layout: &wgpu::BindGroupLayout, buffer: &wgpu::Buffer, size: usize| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: None,
                layout,
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                        buffer,
                        offset: 0,
                        size: wgpu::BufferSize::new(size as u64),
                    }),
                }],
            })
        };
        let mri = GpuMri::new(device, set.mri.as_ref());
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("mri"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        let mri_view = mri.texture.create_view(&wgpu::TextureViewDescriptor::default());
        let frame_bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("frame"),
            layout: &frame_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                        buffer: &frame_buffer,
                        offset: 0,
                        size: wgpu::BufferSize::new(std::mem::size_of::<FrameUniform>() as u64),
                    }),
                },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(&mri_view) },
                wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::Sampler(&sampler) },
            ],
        });
        let organ_bind = bind(&organ_layout, &organ_buffer, section_bytes as usize);
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("organ"),
            bind_group_layouts: &[Some(&frame_layout), Some(&organ_layout)],
            immediate_size: 0,
        });
        Ok(GpuScene {
            meshes,
            batches,
            section_bytes,
            frame_buffer,
            frame_bind,
            organ_buffer,
            organ_bind,
            frame_layout,
            organ_layout,
            layout,
            mri,
        })
    }

    pub fn organ_count(&self) -> usize {
        self.meshes.len()
    }

    /// Organ `i`'s centre in organ space.
    pub fn center(&self, i: usize) -> Vec3 {
        self.meshes[i].center
    }

    pub fn index_count(&self, i: usize) -> u32 {
        self.meshes[i].index_count
    }

    /// Writes frame slot 0 (unmoved) and the organs as shown (section 0).
    pub fn upload(&self, queue: &wgpu::Queue, frame: &FrameInput, aspect: f32) -> Shown {
        self.write_frame(queue, frame, aspect, 0, UNMOVED);
        let colours = crate::colouring::organ_colours(frame.set, frame.layout);
        self.upload_organs(queue, frame, 0, |i, s| {
            let c = colours.get(i).copied().unwrap_or(s.colour).map(super::srgb_to_linear);
            [c[0], c[1], c[2], s.opacity]
        })
    }

    /// Writes frame slot `slot`: the image moved by `jitter` (NDC x' = x * zw + xy, x right, y up).
    pub fn write_frame(&self, queue: &wgpu::Queue, frame: &FrameInput, aspect: f32, slot: u64, jitter: [f32; 4]) {
        debug_assert!(slot < FRAME_SLOTS);
        let vp = frame.camera.view_projection(aspect);
        self.mri.upload(queue);
        let faces = frame.section.faces;
        let show = match (self.mri.to_texture, faces.show) {
            (None, _) | (_, crate::clip::CutFaceShows::Colour) => 0.0,
            (_, crate::clip::CutFaceShows::Mri) => 1.0,
            (_, crate::clip::CutFaceShows::Tinted) => 2.0,
        };
        let fu = FrameUniform {
            view_proj: vp.to_cols_array_2d(),
            eye: frame.camera.eye.extend(1.0).to_array(),
            jitter,
            clip: crate::clip::uniform(&frame.section.planes),
            mri: self.mri.to_texture.unwrap_or(Mat4::ZERO).to_cols_array_2d(),
            cut_face: [show, faces.window.window, faces.window.level, 0.0],
            colour_by: [(frame.layout.colour_by == crate::layout::ColourBy::Territory) as u32, 0, 0, 0],
        };
        queue.write_buffer(&self.frame_buffer, slot * SLOT, bytemuck::bytes_of(&fu));
    }

    /// Writes one section of organ uniforms with colours (linear RGBA) from `colour`.
    pub fn upload_organs(
        &self,
        queue: &wgpu::Queue,
        frame: &FrameInput,
        section: u64,
        colour: impl Fn(usize, &OrganState) -> [f32; 4],
    ) -> Shown {
        let mut data = Vec::with_capacity(self.meshes.len());
        let mut capped = vec![false; self.meshes.len()];
        for (i, s) in frame.layout.organs.iter().enumerate().take(self.meshes.len()) {
            let model = s.transform.matrix();
            let clip = frame.section.organ(i, &self.meshes[i].bounds.transformed(&model), self.meshes[i].closed);
            let flags = if clip.clipped { CLIPPED } else { 0 }
                | if clip.capped { CAPPED } else { 0 }
                | if self.meshes[i].closed { CLOSED } else { 0 };
            capped[i] = clip.capped;
            let normal = Mat4::from_mat3(Mat3::from_mat4(model).inverse().transpose());
            let u = OrganUniform {
                model: model.to_cols_array_2d(),
                normal_matrix: normal.to_cols_array_2d(),
                colour: Vec4::from(colour(i, s)).to_array(),
                id: [i as u32 + 1, flags, 0, 0],
            };
            data.push(u);
        }
        queue.write_buffer(&self.organ_buffer, section * self.section_bytes, bytemuck::cast_slice(&data));
        Shown { capped }
    }

    /// Its levels of detail, coarsest last, as index ranges a draw list may hold.
    pub fn levels(&self, organ: usize) -> &[Range<u32>] {
        self.meshes.get(organ).map_or(&[], |m| m.levels.as_slice())
    }

    /// Index ranges of an organ to draw: the draw list's, or all of it.
    pub fn ranges<'a>(&self, organ: usize, draw: Option<&'a DrawList>) -> Cow<'a, [Range<u32>]> {
        match draw.and_then(|d| d.ranges.get(organ)) {
            Some(r) => Cow::Borrowed(r.as_slice()),
            None => Cow::Owned(std::iter::once(0..self.meshes[organ].index_count).collect()),
        }
    }

    /// The triangles of `organs` (the ranges `frame.draw` keeps of each) per batch, as indices into
    /// the batch's vertices. `sorted`: farthest first by the distance of their centroids from the
    /// eye, the nearly sorted stream of HAVS (Callahan 2005, §4.2), sorted per frame on the CPU;
    /// else in the order of `organs`, each organ's triangles as stored.
    pub fn triangle_stream(&self, frame: &FrameInput, organs: &[usize], sorted: bool) -> Vec<Vec<u32>> {
        let draw = frame.draw;
        let mut keyed: Vec<Vec<(f32, u32)>> = vec![Vec::new(); self.batches.len()];
        for &organ in organs {
            let m = &self.meshes[organ];
            let model = frame.layout.organs[organ].transform.matrix();
            let batch = &self.batches[m.batch];
            for r in self.ranges(organ, draw).iter() {
                let triangles = (m.first_index + r.start) / 3..(m.first_index + r.end) / 3;
                keyed[m.batch].extend(triangles.map(|t| {
                    let c = model.transform_point3(batch.centroids[t as usize]);
                    (c.distance_squared(frame.camera.eye), t)
                }));
            }
        }
        keyed
            .into_iter()
            .enumerate()
            .map(|(b, mut keys)| {
                if sorted {
                    keys.sort_unstable_by(|x, y| y.0.total_cmp(&x.0).then(x.1.cmp(&y.1)));
                }
                keys.iter().flat_map(|&(_, t)| self.batches[b].triangles[t as usize]).collect()
            })
            .collect()
    }

    /// Draws whole triangles of batch `batch` from `indices` (indices into the batch's vertices,
    /// as [`Self::triangle_stream`] gives them) with one pipeline, as shown in section 0.
    pub fn draw_indices(&self, pass: &mut wgpu::RenderPass, batch: usize, indices: &wgpu::Buffer, count: u32) {
        pass.set_bind_group(1, &self.organ_bind, &[0]);
        pass.set_vertex_buffer(0, self.batches[batch].vertices.slice(..));
        pass.set_index_buffer(indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..count, 0, 0..1);
    }

    /// Selects frame slot `slot` for the draws that follow.
    pub fn set_frame(&self, pass: &mut wgpu::RenderPass, slot: u64) {
        pass.set_bind_group(0, &self.frame_bind, &[(slot * SLOT) as u32]);
    }

    /// Draws `ranges` of an organ as shown, with the pipeline of its kind (closed or open).
    pub fn draw(
        &self,
        (pass, shown): (&mut wgpu::RenderPass, &Shown),
        pipelines: &OrganPipelines,
        organ: usize,
        ranges: &[Range<u32>],
    ) {
        self.draw_in((pass, shown), pipelines, 0, organ, ranges);
    }

    /// Draws with the organs' data of a section.
    pub fn draw_in(
        &self,
        (pass, shown): (&mut wgpu::RenderPass, &Shown),
        pipelines: &OrganPipelines,
        section: u64,
        organ: usize,
        ranges: &[Range<u32>],
    ) {
        self.draw_many((pass, shown), pipelines, section, [(organ, Cow::Borrowed(ranges))]);
    }

    /// Draws `organs` in the order given, each as far as `draw` keeps it (what survived culling;
    /// `None` draws it whole), as shown in `section`.
    pub fn draw_organs(
        &self,
        (pass, shown): (&mut wgpu::RenderPass, &Shown),
        pipelines: &OrganPipelines,
        section: u64,
        organs: &[usize],
        draw: Option<&DrawList>,
    ) {
        self.draw_many((pass, shown), pipelines, section, organs.iter().map(|&i| (i, self.ranges(i, draw))));
    }

    /// Draws organs in the order given, each its `ranges` (of its own indices), as shown in
    /// `section`: ranges that meet in a batch, of organs of one kind, go in one draw call.
    pub fn draw_many<'r>(
        &self,
        (pass, shown): (&mut wgpu::RenderPass, &Shown),
        pipelines: &OrganPipelines,
        section: u64,
        organs: impl IntoIterator<Item = (usize, Cow<'r, [Range<u32>]>)>,
    ) {
        pass.set_bind_group(1, &self.organ_bind, &[(section * self.section_bytes) as u32]);
        let (mut batch, mut closed, mut run): (Option<usize>, Option<bool>, Option<Range<u32>>) = (None, None, None);
        let flush = |pass: &mut wgpu::RenderPass, run: &mut Option<Range<u32>>| {
            if let Some(r) = run.take() {
                pass.draw_indexed(r, 0, 0..1);
            }
        };
        for (organ, ranges) in organs {
            let m = &self.meshes[organ];
            if ranges.is_empty() {
                continue;
            }
            if batch != Some(m.batch) {
                flush(pass, &mut run);
                let b = &self.batches[m.batch];
                pass.set_vertex_buffer(0, b.vertices.slice(..));
                pass.set_index_buffer(b.indices.slice(..), wgpu::IndexFormat::Uint32);
                batch = Some(m.batch);
            }
            if closed != Some(m.closed) {
                flush(pass, &mut run);
                pass.set_pipeline(pipelines.get(m.closed));
                closed = Some(m.closed);
            }
            let shifted = ranges.iter().map(|r| r.start + m.first_index..r.end + m.first_index);
            if shown.capped(organ) {
                // The faces turned away, seen through the cut: the solid cut face.
                flush(pass, &mut run);
                for r in shifted.clone() {
                    pass.draw_indexed(r, 0, 0..1);
                }
                pass.set_pipeline(&pipelines.caps);
                for r in shifted {
                    pass.draw_indexed(r, 0, 0..1);
                }
                closed = None;
                continue;
            }
            for r in shifted {
                match &mut run {
                    Some(open) if open.end == r.start => open.end = r.end,
                    _ => {
                        flush(pass, &mut run);
                        run = Some(r);
                    }
                }
            }
        }
        flush(pass, &mut run);
    }

    /// Binds the pipeline of an organ's kind, the organs' data (of a section) and the organ's
    /// batch, for draws the caller makes; returns the index offset to add to the organ's ranges.
    pub fn bind_organ(
        &self,
        pass: &mut wgpu::RenderPass,
        pipelines: &OrganPipelines,
        section: u64,
        organ: usize,
    ) -> u32 {
        let m = &self.meshes[organ];
        pass.set_pipeline(pipelines.get(m.closed));
        pass.set_bind_group(1, &self.organ_bind, &[(section * self.section_bytes) as u32]);
        let b = &self.batches[m.batch];
        pass.set_vertex_buffer(0, b.vertices.slice(..));
        pass.set_index_buffer(b.indices.slice(..), wgpu::IndexFormat::Uint32);
        m.first_index
    }

    /// Begins a pass drawing organs into a multisampled colour image (`colour[0]`, cleared to
    /// `background`, resolved into `colour[1]`) and `target`'s depth (cleared to far; kept after the
    /// pass if `keep_depth`), with frame slot 0 set.
    pub fn begin_organ_pass<'e>(
        &self,
        encoder: &'e mut wgpu::CommandEncoder,
        colour: [&wgpu::TextureView; 2],
        target: &Target,
        background: [f32; 4],
        keep_depth: bool,
    ) -> wgpu::RenderPass<'e> {
        let mut pass = Pass::new("organs")
            .resolved(colour[0], colour[1], wgpu::LoadOp::Clear(clear_colour(background)), false)
            .depth(&target.msaa_depth, wgpu::LoadOp::Clear(1.0), keep_depth)
            .begin(encoder);
        self.set_frame(&mut pass, 0);
        pass
    }
}
