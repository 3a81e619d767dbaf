//! One patch's working state in the raster: per pixel of its bounding rectangle the farthest
//! depth, the flags of the first pass, and which pixels are left to the exact test.
//!
//! - Patch coordinates: culling pixels from the rectangle's top-left corner (x right, y down).

use crate::bvh::NONE;
use crate::cull::rect::PixelRect;

/// Per pixel of a patch: a triangle holds its centre; two or more do (the patch overlaps itself
/// there); an outline edge touches it.
pub(super) const CENTRE: u8 = 1;
pub(super) const SECOND: u8 = 2;
pub(super) const BORDER: u8 = 4;

/// The pixels of one patch's bounding rectangle, filled triangle by triangle.
#[derive(Default)]
pub(super) struct Patch {
    /// The rectangle: where it starts, its width and height (rows lie `stride` apart, three
    /// more than the width, so four pixels from any column fit).
    pub at: Window,
    pub w: usize,
    pub h: usize,
    /// Per pixel: the farthest depth of any triangle over it (-inf where none reaches it).
    pub far: Vec<f32>,
    /// Per pixel: [`CENTRE`], [`SECOND`], [`BORDER`].
    pub flags: Vec<u8>,
    /// Per pixel left to the exact test: its place among them (else NONE).
    pub slot: Vec<u32>,
    /// The same pixels as bits, row by row ([`Patch::words`] 64-bit words a row).
    pub exact_bits: Vec<u64>,
}

/// Where a patch's rectangle starts in the image, and how far apart its rows lie.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Window {
    pub x0: usize,
    pub y0: usize,
    pub stride: usize,
}

impl Patch {
    /// Does the patch overlap itself at a pixel next to (x, y) (patch coordinates)?
    pub fn overlaps_near(&self, x: usize, y: usize) -> bool {
        let (xs, ys) = (x.saturating_sub(1)..=(x + 1).min(self.w - 1), y.saturating_sub(1)..=(y + 1).min(self.h - 1));
        ys.into_iter().any(|y| self.flags[y * self.at.stride..][xs.clone()].iter().any(|&f| f & SECOND != 0))
    }

    /// 64-bit words per row of [`Patch::exact_bits`].
    pub fn words(&self) -> usize {
        self.w.div_ceil(64)
    }

    /// Leaves pixel (x, y) (patch coordinates) to the exact test, as the `slot`-th.
    pub fn leave_to_exact(&mut self, x: usize, y: usize, slot: u32) {
        self.slot[y * self.at.stride + x] = slot;
        let words = self.words();
        self.exact_bits[y * words + x / 64] |= 1 << (x % 64);
    }

    /// Is any pixel of the inclusive rectangle (patch coordinates) left to the exact test?
    pub fn any_exact(&self, PixelRect { x0, y0, x1, y1 }: PixelRect) -> bool {
        (y0..=y1).any(|y| self.exact_span(y, x0, x1).is_some())
    }

    /// The first and the last of columns `x0..=x1` of row `y` (patch coordinates) left to the
    /// exact test, if any is.
    pub fn exact_span(&self, y: usize, x0: usize, x1: usize) -> Option<(usize, usize)> {
        let words = self.words();
        let row = &self.exact_bits[y * words..(y + 1) * words];
        // The bits of columns x0..=x1 within word k.
        let bits = |k: usize| {
            let (lo, hi) = (x0.max(64 * k) - 64 * k, x1.min(64 * k + 63) - 64 * k);
            Some(row[k] & (u64::MAX >> (63 - hi)) & (u64::MAX << lo)).filter(|&b| b != 0)
        };
        let ks = x0 / 64..=x1 / 64;
        let first = ks.clone().find_map(|k| bits(k).map(|b| 64 * k + b.trailing_zeros() as usize))?;
        let last = ks.rev().find_map(|k| bits(k).map(|b| 64 * k + 63 - b.leading_zeros() as usize))?;
        Some((first, last))
    }

    pub fn reset(&mut self, x0: usize, y0: usize, w: usize, h: usize) {
        (self.at, self.w, self.h) = (Window { x0, y0, stride: w + 3 }, w, h);
        self.exact_bits.clear();
        self.exact_bits.resize(self.words() * h, 0);
        let n = self.at.stride * h;
        self.far.clear();
        self.far.resize(n, f32::NEG_INFINITY);
        self.flags.clear();
        self.flags.resize(n, 0);
        self.slot.clear();
        self.slot.resize(n, NONE);
    }
}
