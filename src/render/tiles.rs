//! Where screen-door's passes draw (thesis §4.2, made cheap): each pass into its own tile of an
//! atlas, each tile a copy of the rectangle of the screen that the faded organs cover.
//!
//! - Pixels, origin top left, x right and y down; NDC y up.
//! - The faded organs are drawn once per pass; the opaque organs once, into the screen.
//! - Pure layout, no GPU.

/// A rectangle of pixels.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Rect {
    pub x: u32,
    pub y: u32,
    pub w: u32,
    pub h: u32,
}

impl Rect {
    pub fn is_empty(&self) -> bool {
        self.w == 0 || self.h == 0
    }

    fn pixels(&self) -> u64 {
        u64::from(self.w) * u64::from(self.h)
    }
}

/// How the passes of a frame are laid out in the atlas: `per_round` tiles side by side,
/// `tiles_x` to a row; passes beyond `per_round` draw in further rounds into the same tiles.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Tiling {
    /// The screen rectangle every tile copies.
    pub rect: Rect,
    pub tiles_x: u32,
    pub per_round: usize,
    /// The atlas size this tiling needs (pixels).
    pub atlas: [u32; 2],
}

/// Pixels left between tiles: some rasterisers let a scissored full-screen pass reach a pixel
/// past the scissor (llvmpipe with per-sample shading), which would overwrite a neighbour's edge.
pub const GAP: u32 = 1;

/// Atlas pixels a frame may use: tiles of a small rectangle all fit; a rectangle the size of the
/// screen takes a few rounds (16 MSAA passes of 1920x1080 at once would need 400 MB).
pub const ATLAS_BUDGET_PX: u64 = 1 << 21;

/// The tiling for `passes` passes over `rect`, within `budget` atlas pixels and `max_side` pixels
/// a side (at least one tile a round, whatever the budget).
pub fn tiling(rect: Rect, passes: usize, budget: u64, max_side: u32) -> Tiling {
    let (w, h) = (rect.w.max(1) + GAP, rect.h.max(1) + GAP);
    let fit = (budget / rect.pixels().max(1)).max(1) as usize;
    let mut per_round = fit.clamp(1, passes.max(1));
    let tiles_x = (per_round as u32).min(max_side / w).max(1);
    let rows = (per_round as u32).div_ceil(tiles_x).min((max_side / h).max(1));
    per_round = per_round.min((tiles_x * rows) as usize);
    Tiling { rect, tiles_x, per_round, atlas: [tiles_x * w, rows * h] }
}

impl Tiling {
    /// Top-left atlas pixel of tile `t`.
    pub fn corner(&self, t: usize) -> [u32; 2] {
        let t = t as u32;
        [(t % self.tiles_x) * (self.rect.w + GAP), (t / self.tiles_x) * (self.rect.h + GAP)]
    }

    /// Atlas pixel minus screen pixel in tile `t`.
    pub fn offset(&self, t: usize) -> [i32; 2] {
        let c = self.corner(t);
        [c[0] as i32 - self.rect.x as i32, c[1] as i32 - self.rect.y as i32]
    }

    /// The frame uniform's `jitter` (NDC x' = x * zw + xy) that draws a `screen`-sized image into
    /// tile `t` of an atlas of `atlas` pixels, pixel for pixel: the tile shows `rect`.
    pub fn place(&self, t: usize, screen: [u32; 2], atlas: [u32; 2]) -> [f32; 4] {
        let [dx, dy] = self.offset(t).map(|v| v as f32);
        let (sx, sy) = (screen[0] as f32 / atlas[0] as f32, screen[1] as f32 / atlas[1] as f32);
        [sx - 1.0 + 2.0 * dx / atlas[0] as f32, 1.0 - sy - 2.0 * dy / atlas[1] as f32, sx, sy]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Screen pixel centre -> NDC -> placed -> atlas pixel.
    fn to_atlas(px: [f32; 2], screen: [u32; 2], atlas: [u32; 2], place: [f32; 4]) -> [f32; 2] {
        let ndc = [px[0] / screen[0] as f32 * 2.0 - 1.0, 1.0 - px[1] / screen[1] as f32 * 2.0];
        let moved = [ndc[0] * place[2] + place[0], ndc[1] * place[3] + place[1]];
        [(moved[0] + 1.0) * 0.5 * atlas[0] as f32, (1.0 - moved[1]) * 0.5 * atlas[1] as f32]
    }

    #[test]
    fn tiles_show_the_rectangle_pixel_for_pixel() {
        let rect = Rect { x: 100, y: 40, w: 120, h: 90 };
        let t = tiling(rect, 16, ATLAS_BUDGET_PX, 8192);
        assert_eq!(t.per_round, 16);
        let (screen, atlas) = ([800, 600], [1024, 512]);
        for tile in [0, 5, 15] {
            let c = t.corner(tile);
            let got = to_atlas([100.5, 40.5], screen, atlas, t.place(tile, screen, atlas));
            assert!((got[0] - (c[0] as f32 + 0.5)).abs() < 1e-3 && (got[1] - (c[1] as f32 + 0.5)).abs() < 1e-3);
            let far = to_atlas([219.25, 129.75], screen, atlas, t.place(tile, screen, atlas));
            assert!((far[0] - (c[0] as f32 + 119.25)).abs() < 1e-3 && (far[1] - (c[1] as f32 + 89.75)).abs() < 1e-3);
            assert!(c[0] + rect.w <= t.atlas[0] && c[1] + rect.h <= t.atlas[1]);
        }
    }

    #[test]
    fn a_large_rectangle_takes_rounds_within_the_budget() {
        let rect = Rect { x: 0, y: 0, w: 1920, h: 1080 };
        let t = tiling(rect, 16, ATLAS_BUDGET_PX, 8192);
        assert_eq!(t.per_round, 1);
        let t = tiling(Rect { w: 500, h: 500, ..rect }, 16, ATLAS_BUDGET_PX, 1200);
        assert!(t.per_round >= 1 && t.atlas[0] <= 1200 && t.atlas[1] <= 1200);
        assert!(t.per_round as u64 * 250_000 <= ATLAS_BUDGET_PX);
    }
}
