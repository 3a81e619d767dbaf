//! Render passes described by what they draw into: the one way the techniques begin a pass.
//!
//! - A colour attachment is stored after the pass; a multisampled one resolved into another image
//!   is stored only when asked (`keep`), as is depth.
//! - Loads are wgpu's: `LoadOp::Clear(value)` or `LoadOp::Load` (what the image holds).

use wgpu::{Color, LoadOp, TextureView};

/// A render pass being described; [`Pass::begin`] records it.
pub(super) struct Pass<'a> {
    label: &'static str,
    colours: Vec<Option<wgpu::RenderPassColorAttachment<'a>>>,
    depth: Option<wgpu::RenderPassDepthStencilAttachment<'a>>,
    query: Option<&'a wgpu::QuerySet>,
}

fn store(keep: bool) -> wgpu::StoreOp {
    if keep {
        wgpu::StoreOp::Store
    } else {
        wgpu::StoreOp::Discard
    }
}

impl<'a> Pass<'a> {
    pub fn new(label: &'static str) -> Pass<'a> {
        Pass { label, colours: Vec::new(), depth: None, query: None }
    }

    /// Draws into `view` (the next colour location), starting from `load`; stored.
    pub fn colour(self, view: &'a TextureView, load: LoadOp<Color>) -> Pass<'a> {
        self.attach(view, None, load, true)
    }

    /// Draws into the multisampled `view`, resolved into `resolve` at the end; `view` itself is
    /// stored only if `keep`.
    pub fn resolved(
        self,
        view: &'a TextureView,
        resolve: &'a TextureView,
        load: LoadOp<Color>,
        keep: bool,
    ) -> Pass<'a> {
        self.attach(view, Some(resolve), load, keep)
    }

    fn attach(
        mut self,
        view: &'a TextureView,
        resolve_target: Option<&'a TextureView>,
        load: LoadOp<Color>,
        keep: bool,
    ) -> Pass<'a> {
        self.colours.push(Some(wgpu::RenderPassColorAttachment {
            view,
            depth_slice: None,
            resolve_target,
            ops: wgpu::Operations { load, store: store(keep) },
        }));
        self
    }

    /// Tests against (and writes, where the pipeline does) the depth in `view`, starting from
    /// `load`; stored only if `keep`.
    pub fn depth(mut self, view: &'a TextureView, load: LoadOp<f32>, keep: bool) -> Pass<'a> {
        self.depth = Some(wgpu::RenderPassDepthStencilAttachment {
            view,
            depth_ops: Some(wgpu::Operations { load, store: store(keep) }),
            stencil_ops: None,
        });
        self
    }

    /// Counts the samples that pass, in `query`'s occlusion queries.
    pub fn counting(mut self, query: &'a wgpu::QuerySet) -> Pass<'a> {
        self.query = Some(query);
        self
    }

    /// Records the pass into `encoder`.
    pub fn begin<'e>(self, encoder: &'e mut wgpu::CommandEncoder) -> wgpu::RenderPass<'e> {
        encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(self.label),
            color_attachments: &self.colours,
            depth_stencil_attachment: self.depth,
            timestamp_writes: None,
            occlusion_query_set: self.query,
            multiview_mask: None,
        })
    }
}
