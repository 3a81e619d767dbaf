//! Pipelines and per-organ GPU meshes, created once per device and organ set; [`Renderer::render`]
//! draws one frame from plain per-frame data ([`FrameInput`]: camera, layout, draw list,
//! transparency settings) into a [`Target`]. Opaque drawing, sorted blending, the culling debug view
//! and the ID passes are here; the other transparency modes are in `oit.rs`.

use super::target::{Target, COLOR_FORMAT, DEPTH_FORMAT, ID_FORMAT};
use crate::camera::Camera;
use crate::cull::DrawList;
use crate::error::{Error, Result};
use crate::layout::{Layout, OrganState};
use crate::organ_set::OrganSet;
use crate::transparency::{TransparencyMode, TransparencySettings};
use glam::{Mat3, Mat4, Vec3, Vec4};
use wgpu::util::DeviceExt;

/// Samples per pixel of the colour target (4x MSAA, supported everywhere, lavapipe included).
pub const SAMPLE_COUNT: u32 = 4;

/// Keep in sync with `Frame` in shaders/organ.wgsl.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct FrameUniform {
    view_proj: [[f32; 4]; 4],
    eye: [f32; 4],
    jitter: [f32; 4],
}

/// Keep in sync with `Organ` in shaders/organ.wgsl.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct OrganUniform {
    model: [[f32; 4]; 4],
    normal_matrix: [[f32; 4]; 4],
    colour: [f32; 4],
    id: [u32; 4],
}

/// Distance between organ uniforms in the dynamic-offset buffer (the largest alignment allowed).
const ORGAN_STRIDE: u64 = 256;
/// Sets of organ uniforms: the organs as shown, and two recoloured sets for the culling debug view.
const SECTIONS: u64 = 3;

struct GpuMesh {
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    index_count: u32,
    /// Organ-space centre, for back-to-front sorting of translucent organs.
    center: Vec3,
}

/// What one frame shows.
#[derive(Clone, Copy)]
pub struct FrameInput<'a> {
    /// The set the renderer was made for (screen-door masks are built from its meshes).
    pub set: &'a OrganSet,
    pub camera: &'a Camera,
    pub layout: &'a Layout,
    /// What survived culling; `None` draws every drawn organ whole.
    pub draw: Option<&'a DrawList>,
    /// Linear RGBA clear colour; alpha 0 gives a transparent background.
    pub background: [f32; 4],
    /// How transparent organs are drawn.
    pub transparency: TransparencySettings,
    /// The camera or an organ is moving: screen-door uses its interactive sub-sample count.
    pub moving: bool,
    /// Order in which organs are drawn (a permutation of organ indices); `None` is index order.
    pub draw_order: Option<&'a [usize]>,
}

impl<'a> FrameInput<'a> {
    /// A still frame of every drawn organ on a transparent background, default transparency.
    pub fn new(set: &'a OrganSet, camera: &'a Camera, layout: &'a Layout) -> FrameInput<'a> {
        FrameInput {
            set,
            camera,
            layout,
            draw: None,
            background: [0.0; 4],
            transparency: TransparencySettings::default(),
            moving: false,
            draw_order: None,
        }
    }

    /// Organ indices in drawing order.
    pub(crate) fn order(&self, count: usize) -> Vec<usize> {
        match self.draw_order {
            Some(o) if o.len() == count && o.iter().all(|&i| i < count) => o.to_vec(),
            _ => (0..count).collect(),
        }
    }

    /// Whether any drawn organ is faded.
    pub fn has_transparent(&self) -> bool {
        self.layout.organs.iter().any(|s| s.is_drawn() && !s.is_opaque())
    }
}

/// The parts of `0..end` not in the sorted, disjoint `ranges`.
fn complement(ranges: &[std::ops::Range<u32>], end: u32) -> Vec<std::ops::Range<u32>> {
    let mut out = Vec::new();
    let mut at = 0;
    for r in ranges {
        if r.start > at {
            out.push(at..r.start);
        }
        at = at.max(r.end);
    }
    if at < end {
        out.push(at..end);
    }
    out
}

/// Counts of one rendered frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RenderStats {
    pub organs_drawn: usize,
    pub triangles_drawn: usize,
    /// Passes over the scene (screen-door draws one per 4 sub-samples).
    pub passes: usize,
    /// Screen-door mask regeneration: milliseconds and distinct region configurations.
    pub mask_ms: f64,
    pub mask_configs: usize,
}

pub struct Renderer {
    meshes: Vec<GpuMesh>,
    frame_buffer: wgpu::Buffer,
    frame_bind: wgpu::BindGroup,
    organ_buffer: wgpu::Buffer,
    organ_bind: wgpu::BindGroup,
    opaque: wgpu::RenderPipeline,
    blend: wgpu::RenderPipeline,
    pick: wgpu::RenderPipeline,
    pick_leaf: wgpu::RenderPipeline,
    /// Pipelines of the transparency modes other than sorted blending.
    pub(super) oit: super::oit::OitPipelines,
}

/// What differs between the organ pipelines.
struct PipelineSpec<'a> {
    label: &'a str,
    fragment: &'a str,
    targets: &'a [Option<wgpu::ColorTargetState>],
    depth_write: bool,
    cull: Option<wgpu::Face>,
    samples: u32,
    layout: &'a wgpu::PipelineLayout,
}

/// Builds organ pipelines from organ.wgsl; shared with the transparency module.
pub(super) struct PipelineFactory<'a> {
    device: &'a wgpu::Device,
    shader: wgpu::ShaderModule,
}

impl PipelineFactory<'_> {
    fn build(&self, spec: PipelineSpec) -> wgpu::RenderPipeline {
        let vertex_attributes = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3];
        self.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(spec.label),
            layout: Some(spec.layout),
            vertex: wgpu::VertexState {
                module: &self.shader,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: 24,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &vertex_attributes,
                })],
            },
            primitive: wgpu::PrimitiveState { cull_mode: spec.cull, ..Default::default() },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(spec.depth_write),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: wgpu::MultisampleState { count: spec.samples, ..Default::default() },
            fragment: Some(wgpu::FragmentState {
                module: &self.shader,
                entry_point: Some(spec.fragment),
                compilation_options: Default::default(),
                targets: spec.targets,
            }),
            multiview_mask: None,
            cache: None,
        })
    }

    /// A pipeline with one colour target.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn single(
        &self,
        label: &str,
        fragment: &str,
        format: wgpu::TextureFormat,
        blend: Option<wgpu::BlendState>,
        depth_write: bool,
        cull: Option<wgpu::Face>,
        samples: u32,
        layout: &wgpu::PipelineLayout,
    ) -> wgpu::RenderPipeline {
        let targets = [Some(wgpu::ColorTargetState { format, blend, write_mask: wgpu::ColorWrites::ALL })];
        self.build(PipelineSpec { label, fragment, targets: &targets, depth_write, cull, samples, layout })
    }

    pub(super) fn multi(
        &self,
        label: &str,
        fragment: &str,
        targets: &[Option<wgpu::ColorTargetState>],
        depth_write: bool,
        layout: &wgpu::PipelineLayout,
    ) -> wgpu::RenderPipeline {
        self.build(PipelineSpec { label, fragment, targets, depth_write, cull: None, samples: SAMPLE_COUNT, layout })
    }
}

/// A linear RGBA clear colour for wgpu.
pub(super) fn clear_colour(c: [f32; 4]) -> wgpu::Color {
    wgpu::Color { r: c[0] as f64, g: c[1] as f64, b: c[2] as f64, a: c[3] as f64 }
}

/// Plain alpha blending ("over").
pub(super) const OVER: wgpu::BlendState = wgpu::BlendState {
    color: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::SrcAlpha,
        dst_factor: wgpu::BlendFactor::OneMinusSrcAlpha,
        operation: wgpu::BlendOperation::Add,
    },
    alpha: wgpu::BlendComponent::OVER,
};

impl Renderer {
    /// Creates the pipelines and uploads the set's meshes.
    pub fn new(device: &wgpu::Device, set: &OrganSet) -> Result<Renderer> {
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
                return Err(Error::Other(format!(
                    "organ \"{}\" needs a {bytes}-byte buffer; this GPU allows {max}",
                    o.id
                )));
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
            });
        }
        let uniform_layout = |label, dynamic| {
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(label),
                entries: &[wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: dynamic,
                        min_binding_size: None,
                    },
                    count: None,
                }],
            })
        };
        let frame_layout = uniform_layout("frame", false);
        let organ_layout = uniform_layout("organ", true);
        let frame_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("frame uniform"),
            size: std::mem::size_of::<FrameUniform>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let organ_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("organ uniforms"),
            // Sections of per-organ uniforms: 0 as shown, 1 and 2 for the culling debug view.
            size: ORGAN_STRIDE * SECTIONS * set.organs.len().max(1) as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let bind = |layout: &wgpu::BindGroupLayout, buffer: &wgpu::Buffer, size: Option<u64>| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: None,
                layout,
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                        buffer,
                        offset: 0,
                        size: size.and_then(wgpu::BufferSize::new),
                    }),
                }],
            })
        };
        let frame_bind = bind(&frame_layout, &frame_buffer, None);
        let organ_bind = bind(&organ_layout, &organ_buffer, Some(std::mem::size_of::<OrganUniform>() as u64));
        let factory = PipelineFactory {
            device,
            shader: device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("organ.wgsl"),
                source: wgpu::ShaderSource::Wgsl(super::SHADERS[0].1.into()),
            }),
        };
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("organ"),
            bind_group_layouts: &[Some(&frame_layout), Some(&organ_layout)],
            immediate_size: 0,
        });
        let opaque = factory.single("organ opaque", "fs_shade", COLOR_FORMAT, None, true, None, SAMPLE_COUNT, &layout);
        // Sorted alpha blending: organs back to front, back faces culled.
        let blend = factory.single(
            "organ blend",
            "fs_shade",
            COLOR_FORMAT,
            Some(OVER),
            false,
            Some(wgpu::Face::Back),
            SAMPLE_COUNT,
            &layout,
        );
        let pick = factory.single("organ pick", "fs_pick", ID_FORMAT, None, true, None, 1, &layout);
        let pick_leaf = factory.single("leaf pick", "fs_pick_instance", ID_FORMAT, None, true, None, 1, &layout);
        let oit = super::oit::OitPipelines::new(device, &factory, &frame_layout, &organ_layout, &layout);
        Ok(Renderer { meshes, frame_buffer, frame_bind, organ_buffer, organ_bind, opaque, blend, pick, pick_leaf, oit })
    }

    pub(super) fn upload(&self, queue: &wgpu::Queue, frame: &FrameInput, aspect: f32) {
        self.upload_frame(queue, frame, aspect, [0.0, 0.0]);
        self.upload_organs(queue, frame, 0, |_, s| {
            let c = s.colour.map(super::srgb_to_linear);
            [c[0], c[1], c[2], s.opacity]
        });
    }

    pub(super) fn organ_count(&self) -> usize {
        self.meshes.len()
    }

    pub(super) fn frame_bind(&self) -> &wgpu::BindGroup {
        &self.frame_bind
    }

    /// Writes the frame uniform, the image shifted by `jitter` (x right, y up, NDC units).
    pub(super) fn upload_frame(&self, queue: &wgpu::Queue, frame: &FrameInput, aspect: f32, jitter: [f32; 2]) {
        let vp = frame.camera.view_projection(aspect);
        let fu = FrameUniform {
            view_proj: vp.to_cols_array_2d(),
            eye: frame.camera.eye.extend(1.0).to_array(),
            jitter: [jitter[0], jitter[1], 0.0, 0.0],
        };
        queue.write_buffer(&self.frame_buffer, 0, bytemuck::bytes_of(&fu));
    }

    /// Writes one section of organ uniforms with colours (linear RGBA) from `colour`.
    pub(super) fn upload_organs(
        &self,
        queue: &wgpu::Queue,
        frame: &FrameInput,
        section: u64,
        colour: impl Fn(usize, &OrganState) -> [f32; 4],
    ) {
        let mut data = vec![0u8; ORGAN_STRIDE as usize * self.meshes.len()];
        for (i, s) in frame.layout.organs.iter().enumerate().take(self.meshes.len()) {
            let model = s.transform.matrix();
            let normal = Mat4::from_mat3(Mat3::from_mat4(model).inverse().transpose());
            let u = OrganUniform {
                model: model.to_cols_array_2d(),
                normal_matrix: normal.to_cols_array_2d(),
                colour: Vec4::from(colour(i, s)).to_array(),
                id: [i as u32 + 1, 0, 0, 0],
            };
            let at = i * ORGAN_STRIDE as usize;
            data[at..at + std::mem::size_of::<OrganUniform>()].copy_from_slice(bytemuck::bytes_of(&u));
        }
        queue.write_buffer(&self.organ_buffer, section * ORGAN_STRIDE * self.meshes.len() as u64, &data);
    }

    /// Index ranges of an organ to draw: the draw list's, or all of it. Returns triangles drawn.
    pub(super) fn ranges<'a>(
        &self,
        organ: usize,
        draw: Option<&'a DrawList>,
    ) -> std::borrow::Cow<'a, [std::ops::Range<u32>]> {
        match draw.and_then(|d| d.ranges.get(organ)) {
            Some(r) => std::borrow::Cow::Borrowed(r.as_slice()),
            None => std::borrow::Cow::Owned(std::iter::once(0..self.meshes[organ].index_count).collect()),
        }
    }

    pub(super) fn draw(&self, pass: &mut wgpu::RenderPass, organ: usize, ranges: &[std::ops::Range<u32>]) {
        self.draw_in(pass, 0, organ, ranges);
    }

    /// Draws with the organ uniforms of a section.
    fn draw_in(&self, pass: &mut wgpu::RenderPass, section: u64, organ: usize, ranges: &[std::ops::Range<u32>]) {
        if ranges.is_empty() {
            return;
        }
        let m = &self.meshes[organ];
        let slot = section * self.meshes.len() as u64 + organ as u64;
        pass.set_bind_group(1, &self.organ_bind, &[(slot * ORGAN_STRIDE) as u32]);
        pass.set_vertex_buffer(0, m.vertices.slice(..));
        pass.set_index_buffer(m.indices.slice(..), wgpu::IndexFormat::Uint32);
        for r in ranges {
            pass.draw_indexed(r.clone(), 0, 0..1);
        }
    }

    /// Draws the frame into `target`'s colour image: opaque organs with depth, then transparent ones
    /// as `frame.transparency` says.
    pub fn render(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        target: &Target,
        frame: &FrameInput,
    ) -> Result<RenderStats> {
        let mut stats = if !frame.has_transparent() {
            self.render_blended(device, queue, target, frame, true)
        } else {
            match frame.transparency.mode {
                TransparencyMode::AlphaSorted => self.render_blended(device, queue, target, frame, true),
                TransparencyMode::AlphaUnsorted => self.render_blended(device, queue, target, frame, false),
                TransparencyMode::WeightedBlended => self.render_weighted(device, queue, target, frame),
                TransparencyMode::Exact => self.render_exact(device, queue, target, frame)?,
                _ => self.render_screendoor(device, queue, target, frame),
            }
        };
        let states = &frame.layout.organs;
        for i in (0..self.meshes.len().min(states.len())).filter(|&i| states[i].is_drawn()) {
            let triangles: u32 = self.ranges(i, frame.draw).iter().map(|r| (r.end - r.start) / 3).sum();
            stats.organs_drawn += usize::from(triangles > 0);
            stats.triangles_drawn += triangles as usize;
        }
        Ok(stats)
    }

    /// Opaque organs with depth, then transparent ones alpha blended: back to front by centre with
    /// back faces culled (`sorted`), or in drawing order with depth written.
    fn render_blended(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        target: &Target,
        frame: &FrameInput,
        sorted: bool,
    ) -> RenderStats {
        self.upload(queue, frame, target.aspect());
        let states = &frame.layout.organs;
        let order = frame.order(self.meshes.len().min(states.len()));
        let opaque: Vec<usize> = order.iter().copied().filter(|&i| states[i].is_opaque()).collect();
        let mut translucent: Vec<usize> =
            order.iter().copied().filter(|&i| states[i].is_drawn() && !states[i].is_opaque()).collect();
        if sorted {
            let eye = frame.camera.eye;
            let distance = |i: usize| {
                let c = states[i].transform.matrix().transform_point3(self.meshes[i].center);
                (c - eye).length_squared()
            };
            translucent.sort_by(|&a, &b| distance(b).total_cmp(&distance(a)).then(a.cmp(&b)));
        }
        self.colour_pass(device, queue, target, frame.background, |pass| {
            pass.set_pipeline(&self.opaque);
            for &i in &opaque {
                self.draw(pass, i, &self.ranges(i, frame.draw));
            }
            pass.set_pipeline(if sorted { &self.blend } else { &self.oit.blend_unsorted });
            for &i in &translucent {
                self.draw(pass, i, &self.ranges(i, frame.draw));
            }
        });
        RenderStats { passes: 1, ..Default::default() }
    }

    /// Runs one pass into `target`'s multisampled colour and depth (cleared to `background` and far),
    /// resolved into its colour image; `draw` records the draws with the frame bind group set.
    fn colour_pass(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        target: &Target,
        background: [f32; 4],
        draw: impl FnOnce(&mut wgpu::RenderPass),
    ) {
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let colour = [&target.msaa_color, &target.color_view];
            let mut pass = self.begin_organ_pass(&mut encoder, colour, target, background, false);
            draw(&mut pass);
        }
        queue.submit([encoder.finish()]);
    }

    /// Begins a pass drawing organs into a multisampled colour image (`colour[0]`, cleared to
    /// `background`, resolved into `colour[1]`) and `target`'s depth (cleared to far; kept after the
    /// pass if `keep_depth`), with the frame bind group set.
    pub(super) fn begin_organ_pass<'e>(
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
        pass.set_bind_group(0, &self.frame_bind, &[]);
        pass
    }

    /// The culling debug view (thesis Figure 21): what culling removed, in bright colours, seen
    /// through every drawn organ as a translucent grey model. `frame.draw` is what survived culling.
    pub fn render_cull_debug(&self, device: &wgpu::Device, queue: &wgpu::Queue, target: &Target, frame: &FrameInput) {
        self.upload(queue, frame, target.aspect());
        self.upload_organs(queue, frame, 1, |_, _| [0.35, 0.35, 0.35, 0.22]);
        self.upload_organs(queue, frame, 2, |i, _| {
            let h = (i as f32 * 0.618_034) % 1.0;
            let hue = |o: f32| (((h + o) * std::f32::consts::TAU).sin() * 0.5 + 0.5).powf(0.8);
            [hue(0.0), hue(0.33), hue(0.67), 1.0]
        });
        let states = &frame.layout.organs;
        let drawn: Vec<usize> = (0..self.meshes.len().min(states.len())).filter(|&i| states[i].is_drawn()).collect();
        self.colour_pass(device, queue, target, frame.background, |pass| {
            pass.set_pipeline(&self.opaque);
            for &i in &drawn {
                let kept = self.ranges(i, frame.draw);
                let culled = complement(&kept, self.meshes[i].index_count);
                self.draw_in(pass, 2, i, &culled);
            }
            pass.set_pipeline(&self.blend);
            for &i in &drawn {
                self.draw_in(pass, 1, i, &self.ranges(i, None));
            }
        });
    }

    /// Runs one pass into `target`'s ID buffer (cleared to 0, with its own depth) after uploading
    /// the frame's uniforms; `draw` records the draws with the frame bind group set.
    fn id_pass(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        target: &Target,
        frame: &FrameInput,
        label: &str,
        draw: impl FnOnce(&mut wgpu::RenderPass),
    ) {
        self.upload(queue, frame, target.aspect());
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some(label),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &target.ids_view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &target.ids_depth,
                    depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Discard }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_bind_group(0, &self.frame_bind, &[]);
            draw(&mut pass);
        }
        queue.submit([encoder.finish()]);
    }

    /// Draws organ IDs into `target`'s ID buffer: for each pixel the nearest drawn organ whose
    /// opacity is at least `min_opacity` (so clicking through a faded organ reaches what is inside).
    pub fn render_ids(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        target: &Target,
        frame: &FrameInput,
        min_opacity: f32,
    ) {
        self.id_pass(device, queue, target, frame, "organ ids", |pass| {
            pass.set_pipeline(&self.pick);
            for (i, s) in frame.layout.organs.iter().enumerate().take(self.meshes.len()) {
                if s.is_drawn() && s.opacity >= min_opacity {
                    self.draw(pass, i, &self.ranges(i, frame.draw));
                }
            }
        });
    }

    /// Draws leaf numbers into `target`'s ID buffer: `first_id[organ] + leaf + 1` of the nearest
    /// leaf of a drawn organ per pixel (0 = background), for measuring exact visibility. Every leaf
    /// of every drawn organ is drawn, as one instance numbered by the leaf.
    pub fn render_leaf_ids(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        target: &Target,
        frame: &FrameInput,
        set: &crate::organ_set::OrganSet,
        first_id: &[u32],
    ) {
        self.id_pass(device, queue, target, frame, "leaf ids", |pass| {
            pass.set_pipeline(&self.pick_leaf);
            for (i, s) in frame.layout.organs.iter().enumerate().take(self.meshes.len()) {
                if !s.is_drawn() {
                    continue;
                }
                let m = &self.meshes[i];
                pass.set_bind_group(1, &self.organ_bind, &[(i as u64 * ORGAN_STRIDE) as u32]);
                pass.set_vertex_buffer(0, m.vertices.slice(..));
                pass.set_index_buffer(m.indices.slice(..), wgpu::IndexFormat::Uint32);
                let bvh = &set.organs[i].bvh;
                for l in 0..bvh.leaves.len() as u32 {
                    let id = first_id[i] + l + 1;
                    pass.draw_indexed(bvh.leaf_range(l), 0, id..id + 1);
                }
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use super::complement;

    #[test]
    fn complements() {
        assert_eq!(complement(&[3..6, 9..12], 15), vec![0..3, 6..9, 12..15]);
        let whole = std::iter::once(0..15).collect::<Vec<_>>();
        assert_eq!(complement(&whole, 15), vec![]);
        assert_eq!(complement(&[], 6), vec![0..6]);
    }
}
