//! The set on the GPU: per-organ vertex and index buffers (organ space), the frame uniform's slots
//! and the organ uniforms' sections, and the draw calls every technique shares.

use super::pipelines::{clear_colour, OrganPipelines};
use super::target::Target;
use super::uniforms::{FrameUniform, OrganUniform, CAPPED, CLIPPED, FRAME_SLOTS, SLOT, UNMOVED};
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

struct GpuMesh {
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    index_count: u32,
    /// Organ-space centre, for back-to-front sorting of translucent organs.
    center: Vec3,
    /// Drawn with back faces culled ([`crate::organ_set::Organ::closed`]).
    closed: bool,
    /// Organ-space bounds, to tell which organs the clip planes cut.
    bounds: crate::mesh::Bounds,
}

pub(super) struct GpuScene {
    meshes: Vec<GpuMesh>,
    frame_buffer: wgpu::Buffer,
    frame_bind: wgpu::BindGroup,
    organ_buffer: wgpu::Buffer,
    organ_bind: wgpu::BindGroup,
    pub frame_layout: wgpu::BindGroupLayout,
    pub organ_layout: wgpu::BindGroupLayout,
    /// The pipeline layout of organ pipelines: frame, then organ.
    pub layout: wgpu::PipelineLayout,
    /// Per organ, whether the last upload made it capped (drawn again for its cut faces).
    capped: std::sync::Mutex<Vec<bool>>,
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
        let mut meshes = Vec::with_capacity(set.organs.len());
        for o in &set.organs {
            let vertices: Vec<[f32; 6]> = o
                .mesh
                .positions
                .iter()
                .zip(&o.mesh.normals)
                .map(|(p, n)| [p[0], p[1], p[2], n[0], n[1], n[2]])
                .collect();
            let bytes = (vertices.len() * 24).max(o.mesh.indices.len() * 4) as u64;
            if bytes > max {
                return Err(Error::BufferTooLarge { organ: o.id.clone(), bytes, max });
            }
            meshes.push(GpuMesh {
                vertices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(&o.id),
                    contents: bytemuck::cast_slice(&vertices),
                    usage: wgpu::BufferUsages::VERTEX,
                }),
                indices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(&o.id),
                    contents: bytemuck::cast_slice(&o.mesh.indices),
                    usage: wgpu::BufferUsages::INDEX,
                }),
                index_count: o.mesh.indices.len() as u32,
                center: o.mesh.bounds().center(),
                closed: o.closed(),
                bounds: o.mesh.bounds(),
            });
        }
        let layout_of = |label| {
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(label),
                entries: &[uniform_entry(wgpu::ShaderStages::VERTEX_FRAGMENT)],
            })
        };
        let frame_layout = layout_of("frame");
        let organ_layout = layout_of("organ");
        let uniforms = |label, size| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let frame_buffer = uniforms("frame uniforms", SLOT * FRAME_SLOTS);
        // Sections of per-organ uniforms: 0 as shown, 1 and 2 for the culling debug view.
        let organ_buffer = uniforms("organ uniforms", SLOT * SECTIONS * set.organs.len().max(1) as u64);
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
        let frame_bind = bind(&frame_layout, &frame_buffer, std::mem::size_of::<FrameUniform>());
        let organ_bind = bind(&organ_layout, &organ_buffer, std::mem::size_of::<OrganUniform>());
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("organ"),
            bind_group_layouts: &[Some(&frame_layout), Some(&organ_layout)],
            immediate_size: 0,
        });
        let capped = std::sync::Mutex::new(vec![false; meshes.len()]);
        Ok(GpuScene {
            meshes,
            frame_buffer,
            frame_bind,
            organ_buffer,
            organ_bind,
            frame_layout,
            organ_layout,
            layout,
            capped,
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
    pub fn upload(&self, queue: &wgpu::Queue, frame: &FrameInput, aspect: f32) {
        self.write_frame(queue, frame, aspect, 0, UNMOVED);
        self.upload_organs(queue, frame, 0, |_, s| {
            let c = s.colour.map(super::srgb_to_linear);
            [c[0], c[1], c[2], s.opacity]
        });
    }

    /// Writes frame slot `slot`: the image moved by `jitter` (NDC x' = x * zw + xy, x right, y up).
    pub fn write_frame(&self, queue: &wgpu::Queue, frame: &FrameInput, aspect: f32, slot: u64, jitter: [f32; 4]) {
        debug_assert!(slot < FRAME_SLOTS);
        let vp = frame.camera.view_projection(aspect);
        let fu = FrameUniform {
            view_proj: vp.to_cols_array_2d(),
            eye: frame.camera.eye.extend(1.0).to_array(),
            jitter,
            clip: crate::clip::uniform(frame.clip),
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
    ) {
        let mut data = vec![0u8; SLOT as usize * self.meshes.len()];
        let planes = &frame.clip[..frame.clip.len().min(crate::clip::MAX_PLANES)];
        let mut capped = self.capped.lock().unwrap_or_else(|e| e.into_inner());
        capped.iter_mut().for_each(|c| *c = false);
        for (i, s) in frame.layout.organs.iter().enumerate().take(self.meshes.len()) {
            let model = s.transform.matrix();
            let mut flags = 0;
            if !planes.is_empty() && !frame.whole.contains(&i) {
                flags |= CLIPPED;
                let bounds = self.meshes[i].bounds.transformed(&model);
                let cut = crate::clip::side(planes, &bounds) == crate::clip::Side::Cut;
                if frame.caps && cut && self.meshes[i].closed {
                    flags |= CAPPED;
                    capped[i] = true;
                }
            }
            let normal = Mat4::from_mat3(Mat3::from_mat4(model).inverse().transpose());
            let u = OrganUniform {
                model: model.to_cols_array_2d(),
                normal_matrix: normal.to_cols_array_2d(),
                colour: Vec4::from(colour(i, s)).to_array(),
                id: [i as u32 + 1, flags, 0, 0],
            };
            let at = i * SLOT as usize;
            data[at..at + std::mem::size_of::<OrganUniform>()].copy_from_slice(bytemuck::bytes_of(&u));
        }
        queue.write_buffer(&self.organ_buffer, section * SLOT * self.meshes.len() as u64, &data);
    }

    /// Index ranges of an organ to draw: the draw list's, or all of it.
    pub fn ranges<'a>(&self, organ: usize, draw: Option<&'a DrawList>) -> Cow<'a, [Range<u32>]> {
        match draw.and_then(|d| d.ranges.get(organ)) {
            Some(r) => Cow::Borrowed(r.as_slice()),
            None => Cow::Owned(std::iter::once(0..self.meshes[organ].index_count).collect()),
        }
    }

    /// Selects frame slot `slot` for the draws that follow.
    pub fn set_frame(&self, pass: &mut wgpu::RenderPass, slot: u64) {
        pass.set_bind_group(0, &self.frame_bind, &[(slot * SLOT) as u32]);
    }

    /// Draws `ranges` of an organ as shown, with the pipeline of its kind (closed or open).
    pub fn draw(&self, pass: &mut wgpu::RenderPass, pipelines: &OrganPipelines, organ: usize, ranges: &[Range<u32>]) {
        self.draw_in(pass, pipelines, 0, organ, ranges);
    }

    /// Draws with the organ uniforms of a section.
    pub fn draw_in(
        &self,
        pass: &mut wgpu::RenderPass,
        pipelines: &OrganPipelines,
        section: u64,
        organ: usize,
        ranges: &[Range<u32>],
    ) {
        if ranges.is_empty() {
            return;
        }
        self.bind_organ(pass, pipelines, section, organ);
        for r in ranges {
            pass.draw_indexed(r.clone(), 0, 0..1);
        }
        if self.capped.lock().is_ok_and(|c| c.get(organ).copied().unwrap_or(false)) {
            // The faces turned away, seen through the cut: the solid cut face.
            pass.set_pipeline(&pipelines.caps);
            for r in ranges {
                pass.draw_indexed(r.clone(), 0, 0..1);
            }
        }
    }

    /// Binds the pipeline of an organ's kind, its uniforms (of a section) and buffers, for draws
    /// the caller makes.
    pub fn bind_organ(&self, pass: &mut wgpu::RenderPass, pipelines: &OrganPipelines, section: u64, organ: usize) {
        let m = &self.meshes[organ];
        pass.set_pipeline(pipelines.get(m.closed));
        let slot = section * self.meshes.len() as u64 + organ as u64;
        pass.set_bind_group(1, &self.organ_bind, &[(slot * SLOT) as u32]);
        pass.set_vertex_buffer(0, m.vertices.slice(..));
        pass.set_index_buffer(m.indices.slice(..), wgpu::IndexFormat::Uint32);
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
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("organs"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: colour[0],
                depth_slice: None,
                resolve_target: Some(colour[1]),
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(clear_colour(background)),
                    store: wgpu::StoreOp::Discard,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &target.msaa_depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: if keep_depth { wgpu::StoreOp::Store } else { wgpu::StoreOp::Discard },
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        self.set_frame(&mut pass, 0);
        pass
    }
}
