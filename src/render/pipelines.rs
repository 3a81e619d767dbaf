//! Pipeline construction shared by the techniques: organ pipelines from `organ.wgsl`, full-screen
//! passes from `composite.wgsl`, and the blend states and clear colours they use.
//!
//! - The organ pipelines share one vertex layout: organ-space position and normal.
//! - Colour targets are 4x MSAA (`SAMPLE_COUNT`); closed organs cull their back faces, open ones
//!   draw both sides.

use super::target::DEPTH_FORMAT;
use super::Shader;

/// Samples per pixel of the colour target (4x MSAA, supported everywhere, lavapipe included).
pub const SAMPLE_COUNT: u32 = 4;

/// A shader module of one of [`super::SHADERS`].
pub(super) fn module(device: &wgpu::Device, shader: &Shader) -> wgpu::ShaderModule {
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(shader.name),
        source: wgpu::ShaderSource::Wgsl(shader.source.into()),
    })
}

/// What differs between the organ pipelines.
pub(super) struct OrganPipeline<'a> {
    pub label: &'a str,
    /// Entry point in organ.wgsl.
    pub fragment: &'a str,
    pub targets: &'a [Option<wgpu::ColorTargetState>],
    pub depth_write: bool,
    pub samples: u32,
    pub layout: &'a wgpu::PipelineLayout,
}

/// One colour target of `format` written whole, blended by `blend`.
pub(super) fn target(
    format: wgpu::TextureFormat,
    blend: Option<wgpu::BlendState>,
) -> [Option<wgpu::ColorTargetState>; 1] {
    [Some(wgpu::ColorTargetState { format, blend, write_mask: wgpu::ColorWrites::ALL })]
}

/// An organ pipeline for closed organs, which cull their back faces (never seen from outside; where
/// two organs touch, the back of one's face would tie in depth with the other's front, and the
/// drawing order would pick the pixel), and one for open organs, which draw both sides.
#[derive(Clone)]
pub(super) struct OrganPipelines {
    closed: wgpu::RenderPipeline,
    open: wgpu::RenderPipeline,
    /// A closed organ's back faces only, pulled slightly toward the eye: its cut faces where clip
    /// planes open it (a back face seen through the cut wins the tie with the front face of the
    /// neighbour it touches, so the cut shows this organ's inside).
    pub caps: wgpu::RenderPipeline,
}

impl OrganPipelines {
    pub fn get(&self, closed: bool) -> &wgpu::RenderPipeline {
        if closed {
            &self.closed
        } else {
            &self.open
        }
    }
}

/// How far cut faces are pulled toward the eye (depth units): enough to win the tie with a
/// neighbour's coincident face, no slope term (at grazing angles it would pull a cut face through
/// an uncut organ in front of it).
const CAP_BIAS: wgpu::DepthBiasState = wgpu::DepthBiasState { constant: -4, slope_scale: 0.0, clamp: 0.0 };

/// Builds organ pipelines from organ.wgsl.
pub(super) struct PipelineFactory<'a> {
    pub device: &'a wgpu::Device,
    pub shader: wgpu::ShaderModule,
    /// The vertex entry point of every organ pipeline: `vs_clipped` where the device has clip
    /// distances (triangles cut at the clip planes), else `vs_main`.
    pub vertex: &'static str,
}

impl<'a> PipelineFactory<'a> {
    /// The organ shader for `device`, with clip distances where it has them.
    pub fn new(device: &'a wgpu::Device) -> PipelineFactory<'a> {
        let clip_distances = device.features().contains(wgpu::Features::CLIP_DISTANCES);
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(super::ORGAN_SHADER.name),
            source: wgpu::ShaderSource::Wgsl(super::organ_source(clip_distances).into()),
        });
        PipelineFactory { device, shader, vertex: if clip_distances { "vs_clipped" } else { "vs_main" } }
    }

    /// Whether the organ pipelines cut triangles at the clip planes (see [`Self::vertex`]).
    pub fn cuts_geometry(&self) -> bool {
        self.vertex == "vs_clipped"
    }
}

impl PipelineFactory<'_> {
    pub fn build(&self, spec: OrganPipeline) -> OrganPipelines {
        OrganPipelines {
            closed: self.build_one(&spec, Some(wgpu::Face::Back), Some(Default::default())),
            open: self.build_one(&spec, None, Some(Default::default())),
            caps: self.build_one(&spec, Some(wgpu::Face::Front), Some(CAP_BIAS)),
        }
    }

    /// One pipeline for passes that test depth and faces in the shader (they write storage, so
    /// the tests must come before the writes): no face culling, no depth attachment.
    pub fn build_unculled_without_depth(&self, spec: OrganPipeline) -> wgpu::RenderPipeline {
        self.build_one(&spec, None, None)
    }

    /// A pipeline culling `cull`, with a depth attachment biased by `depth` where given.
    fn build_one(
        &self,
        spec: &OrganPipeline,
        cull: Option<wgpu::Face>,
        depth: Option<wgpu::DepthBiasState>,
    ) -> wgpu::RenderPipeline {
        let vertex_attributes = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Uint32, 3 => Uint32];
        self.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(spec.label),
            layout: Some(spec.layout),
            vertex: wgpu::VertexState {
                module: &self.shader,
                entry_point: Some(self.vertex),
                compilation_options: Default::default(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: std::mem::size_of::<super::uniforms::Vertex>() as u64,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &vertex_attributes,
                })],
            },
            primitive: wgpu::PrimitiveState { cull_mode: cull, ..Default::default() },
            depth_stencil: depth.map(|bias| wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(spec.depth_write),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: Default::default(),
                bias,
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
}

/// A linear RGBA clear colour for wgpu.
pub(super) fn clear_colour(c: [f32; 4]) -> wgpu::Color {
    wgpu::Color { r: c[0] as f64, g: c[1] as f64, b: c[2] as f64, a: c[3] as f64 }
}

/// Plain alpha blending ("over").
/// One blend equation for colour and alpha alike: `src * src_factor (op) dst * dst_factor`.
pub(super) fn blend(
    src_factor: wgpu::BlendFactor,
    dst_factor: wgpu::BlendFactor,
    operation: wgpu::BlendOperation,
) -> Option<wgpu::BlendState> {
    let c = wgpu::BlendComponent { src_factor, dst_factor, operation };
    Some(wgpu::BlendState { color: c, alpha: c })
}

pub(super) const OVER: wgpu::BlendState = wgpu::BlendState {
    color: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::SrcAlpha,
        dst_factor: wgpu::BlendFactor::OneMinusSrcAlpha,
        operation: wgpu::BlendOperation::Add,
    },
    alpha: wgpu::BlendComponent::OVER,
};

/// What differs between full-screen pipelines: one triangle over the target from the module's
/// `vs_fullscreen`, reading one bind group.
pub(super) struct FullscreenPipeline<'a> {
    pub label: &'a str,
    pub module: &'a wgpu::ShaderModule,
    pub layout: &'a wgpu::BindGroupLayout,
    pub fragment: &'a str,
    pub targets: &'a [Option<wgpu::ColorTargetState>],
    pub depth_stencil: Option<wgpu::DepthStencilState>,
    pub samples: u32,
}

pub(super) fn fullscreen_pipeline(device: &wgpu::Device, spec: FullscreenPipeline) -> wgpu::RenderPipeline {
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(spec.label),
        bind_group_layouts: &[Some(spec.layout)],
        immediate_size: 0,
    });
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(spec.label),
        layout: Some(&layout),
        vertex: wgpu::VertexState {
            module: spec.module,
            entry_point: Some("vs_fullscreen"),
            compilation_options: Default::default(),
            buffers: &[],
        },
        primitive: Default::default(),
        depth_stencil: spec.depth_stencil,
        multisample: wgpu::MultisampleState { count: spec.samples, ..Default::default() },
        fragment: Some(wgpu::FragmentState {
            module: spec.module,
            entry_point: Some(spec.fragment),
            compilation_options: Default::default(),
            targets: spec.targets,
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// Full-screen passes over up to three float images (composite.wgsl).
pub(super) struct Composite {
    pub images_layout: wgpu::BindGroupLayout,
    module: wgpu::ShaderModule,
}

impl Composite {
    pub fn new(device: &wgpu::Device) -> Composite {
        let texture = |binding| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: false },
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        };
        let images_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("images"),
            entries: &[texture(0), texture(1), texture(2)],
        });
        Composite { images_layout, module: module(device, &super::COMPOSITE_SHADER) }
    }

    /// A full-screen pipeline of fragment entry point `fragment` into `format`.
    pub fn pipeline(
        &self,
        device: &wgpu::Device,
        label: &str,
        fragment: &str,
        format: wgpu::TextureFormat,
        blend: Option<wgpu::BlendState>,
    ) -> wgpu::RenderPipeline {
        fullscreen_pipeline(
            device,
            FullscreenPipeline {
                label,
                module: &self.module,
                layout: &self.images_layout,
                fragment,
                targets: &target(format, blend),
                depth_stencil: None,
                samples: 1,
            },
        )
    }

    /// The bind group of three images (`image`, `accum`, `reveal` in composite.wgsl).
    pub fn images(&self, device: &wgpu::Device, views: [&wgpu::TextureView; 3]) -> wgpu::BindGroup {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("images"),
            layout: &self.images_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(views[0]) },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(views[1]) },
                wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::TextureView(views[2]) },
            ],
        })
    }
}

/// A full-screen pass of `pipeline` over `images` into `view` (cleared first unless `load`), its
/// blend constant `blend_constant` in every channel.
pub(super) fn fullscreen_pass(
    encoder: &mut wgpu::CommandEncoder,
    view: &wgpu::TextureView,
    pipeline: &wgpu::RenderPipeline,
    images: &wgpu::BindGroup,
    load: bool,
    blend_constant: f64,
) {
    let load = if load { wgpu::LoadOp::Load } else { wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT) };
    let mut pass = super::passes::Pass::new("full screen").colour(view, load).begin(encoder);
    pass.set_pipeline(pipeline);
    pass.set_bind_group(0, images, &[]);
    let w = blend_constant;
    pass.set_blend_constant(wgpu::Color { r: w, g: w, b: w, a: w });
    pass.draw(0..3, 0..1);
}
