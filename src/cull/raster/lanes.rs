//! One occluder triangle over four pixels of a row at a time: its edge functions, whether it holds
//! each pixel's centre, which of its edges touch each pixel, and its farthest depth there.
//!
//! - Culling pixels (x right, y down), pixel (i, j) covering [i, i+1) x [j, j+1); depth = NDC z.
//! - Two paths: SIMD over the four pixels (glam's `Vec4`: SSE2 on x86-64, NEON on AArch64,
//!   simd128 on WebAssembly) and a scalar one for targets without, chosen by [`Path::native`].
//! - Both do the same IEEE operations in the same order (no fused multiply-add; min and max as
//!   SSE's `minps` and `maxps` take them), so they agree bit for bit (a property test compares
//!   them).

use glam::{BVec4A, Vec3, Vec4};

/// A projected occluder triangle: x, y in culling pixels, z = NDC depth.
pub type Triangle = [Vec3; 3];

/// Margin (in pixel widths) by which triangles and edges are widened against rounding.
pub(super) const EPS: f32 = 1e-3;

/// Which code evaluates the pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Path {
    /// Four pixels at once in SIMD registers.
    Simd,
    /// One pixel after another.
    Scalar,
}

impl Path {
    /// SIMD where glam has SIMD registers for the target, scalar elsewhere.
    pub fn native() -> Path {
        if cfg!(any(target_feature = "sse2", target_feature = "neon", target_feature = "simd128")) {
            Path::Simd
        } else {
            Path::Scalar
        }
    }
}

/// One edge of a triangle: its edge function a x + b y + c (positive inside), how far from its
/// line a widened pixel square may reach, and its box widened by [`EPS`].
#[derive(Clone, Copy, Debug)]
struct Edge {
    a: f32,
    b: f32,
    c: f32,
    reach: f32,
    x_lo: f32,
    x_hi: f32,
    y_lo: f32,
    y_hi: f32,
}

impl Edge {
    /// The edge from `p` to `q` of a triangle whose signed area has sign `s`.
    fn new(p: Vec3, q: Vec3, s: f32) -> Edge {
        let (a, b) = ((p.y - q.y) * s, (q.x - p.x) * s);
        Edge {
            a,
            b,
            c: -(a * p.x + b * p.y),
            reach: (0.5 + EPS) * (a.abs() + b.abs()),
            x_lo: p.x.min(q.x) - EPS,
            x_hi: p.x.max(q.x) + EPS,
            y_lo: p.y.min(q.y) - EPS,
            y_hi: p.y.max(q.y) + EPS,
        }
    }
}

/// Four pixels of a row that a triangle may reach, as bits 0..4 (the first pixel in bit 0): those
/// whose centre it holds, and per edge those the edge touches (the triangle reaches a pixel where
/// either holds); its farthest depth over each; `i`: the first pixel's index (set by the caller).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct Lanes {
    pub i: usize,
    pub centre: u32,
    pub edges: [u32; 3],
    pub z: [f32; 4],
}

impl Lanes {
    pub fn reached(&self) -> u32 {
        self.centre | self.edges[0] | self.edges[1] | self.edges[2]
    }
}

/// A triangle made ready to evaluate: edges, and its depth plane
/// z = z0 + dzdx (x - x0) + dzdy (y - y0), whose farthest over a pixel is at the centre plus
/// `slope`, and never beyond the farthest corner `zmax`.
pub(super) struct Setup {
    edges: [Edge; 3],
    dzdx: f32,
    dzdy: f32,
    slope: f32,
    zmax: f32,
    first: Vec3,
}

/// One row's share of the edge functions and depth.
pub(super) struct Row {
    by: [f32; 3],
    z: f32,
    /// The edges whose box reaches the row (bit k).
    mask: u8,
}

/// The offsets of the four pixels' centres from the first pixel's left side.
const CENTRES: [f32; 4] = [0.5, 1.5, 2.5, 3.5];

/// SSE's `minps` and `maxps`: the second operand unless the first is smaller (larger).
fn min_ps(a: f32, b: f32) -> f32 {
    if a < b {
        a
    } else {
        b
    }
}

pub(super) fn max_ps(a: f32, b: f32) -> f32 {
    if a > b {
        a
    } else {
        b
    }
}

impl Setup {
    /// `t`, of non-zero area: edge functions positive inside whatever the winding.
    pub fn new(t: &Triangle) -> Setup {
        let area = (t[1].x - t[0].x) * (t[2].y - t[0].y) - (t[2].x - t[0].x) * (t[1].y - t[0].y);
        let s = area.signum();
        let edges = [0, 1, 2].map(|k| Edge::new(t[k], t[(k + 1) % 3], s));
        let dzdx = ((t[1].z - t[0].z) * (t[2].y - t[0].y) - (t[2].z - t[0].z) * (t[1].y - t[0].y)) / area;
        let dzdy = ((t[2].z - t[0].z) * (t[1].x - t[0].x) - (t[1].z - t[0].z) * (t[2].x - t[0].x)) / area;
        let slope = 0.5 * (dzdx.abs() + dzdy.abs());
        Setup { edges, dzdx, dzdy, slope, zmax: t[0].z.max(t[1].z).max(t[2].z), first: t[0] }
    }

    /// Row `y`'s values.
    #[inline]
    pub fn row(&self, y: usize) -> Row {
        let cy = y as f32 + 0.5;
        let e = &self.edges;
        let mask = (0..3).fold(0u8, |m, k| m | (u8::from(e[k].y_lo <= cy + 0.5 && e[k].y_hi >= cy - 0.5) << k));
        Row {
            by: [0, 1, 2].map(|k| e[k].b * cy + e[k].c),
            z: self.first.z + self.dzdy * (cy - self.first.y) + self.slope,
            mask,
        }
    }

    /// Pixels `x..x + 4` of `row`, if the triangle touches any (widened by [`EPS`]).
    #[inline]
    pub fn four(&self, path: Path, row: &Row, x: usize) -> Option<Lanes> {
        match path {
            Path::Simd => self.four_simd(row, x),
            Path::Scalar => self.four_scalar(row, x),
        }
    }

    #[inline]
    fn four_simd(&self, row: &Row, x: usize) -> Option<Lanes> {
        let e = &self.edges;
        let cx = Vec4::splat(x as f32) + Vec4::from_array(CENTRES);
        let f = [0, 1, 2].map(|k| Vec4::splat(e[k].a) * cx + Vec4::splat(row.by[k]));
        // Touches the (widened) square: no edge has the whole square outside.
        let reach = [0, 1, 2].map(|k| Vec4::splat(-e[k].reach));
        let touch = f[0].cmpge(reach[0]) & f[1].cmpge(reach[1]) & f[2].cmpge(reach[2]);
        if !touch.any() {
            return None;
        }
        let centre = f[0].cmpge(Vec4::ZERO) & f[1].cmpge(Vec4::ZERO) & f[2].cmpge(Vec4::ZERO);
        // An edge touches the square where its line passes within reach of the centre and its box
        // meets the square.
        let mut edges = [BVec4A::FALSE; 3];
        for k in (0..3).filter(|k| row.mask & (1 << k) != 0) {
            edges[k] = touch
                & f[k].cmple(Vec4::splat(e[k].reach))
                & cx.cmpge(Vec4::splat(e[k].x_lo - 0.5))
                & cx.cmple(Vec4::splat(e[k].x_hi + 0.5));
        }
        let zmax = Vec4::splat(self.zmax);
        let z = Vec4::splat(row.z) + Vec4::splat(self.dzdx) * (cx - Vec4::splat(self.first.x));
        let z = Vec4::select(z.is_finite_mask(), z.min(zmax), zmax);
        Some(Lanes { i: 0, centre: centre.bitmask(), edges: edges.map(|m| m.bitmask()), z: z.to_array() })
    }

    #[inline]
    fn four_scalar(&self, row: &Row, x: usize) -> Option<Lanes> {
        let e = &self.edges;
        let mut l = Lanes::default();
        let mut touched = false;
        for (j, &offset) in CENTRES.iter().enumerate() {
            let cx = x as f32 + offset;
            let f = [0, 1, 2].map(|k| e[k].a * cx + row.by[k]);
            let touch = (0..3).all(|k| f[k] >= -e[k].reach);
            touched |= touch;
            l.centre |= u32::from(f.iter().all(|&f| f >= 0.0)) << j;
            for k in (0..3).filter(|k| row.mask & (1 << k) != 0) {
                let there = touch && f[k] <= e[k].reach && cx >= e[k].x_lo - 0.5 && cx <= e[k].x_hi + 0.5;
                l.edges[k] |= u32::from(there) << j;
            }
            let z = row.z + self.dzdx * (cx - self.first.x);
            l.z[j] = if z.abs() < f32::INFINITY { min_ps(z, self.zmax) } else { self.zmax };
        }
        touched.then_some(l)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Lanes as bits, depth included.
    fn bits(l: Option<Lanes>) -> Option<(u32, [u32; 3], [u32; 4])> {
        l.map(|l| (l.centre, l.edges, l.z.map(f32::to_bits)))
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]

        #[test]
        fn simd_and_scalar_lanes_agree_bit_for_bit(
            corners in prop::array::uniform3((-4.0f32..40.0, -4.0f32..40.0, 0.0f32..1.0)),
            // Slivers and near-degenerate depth planes as well as plain triangles.
            squash in prop_oneof![Just(1.0f32), 1e-4f32..1e-2],
            y in 0usize..40,
            x in 0usize..40,
        ) {
            let t = corners.map(|(x, y, z)| Vec3::new(x, y * squash, z));
            let area = (t[1].x - t[0].x) * (t[2].y - t[0].y) - (t[2].x - t[0].x) * (t[1].y - t[0].y);
            prop_assume!(area != 0.0);
            let setup = Setup::new(&t);
            let row = setup.row(y);
            prop_assert_eq!(bits(setup.four(Path::Simd, &row, x)), bits(setup.four(Path::Scalar, &row, x)));
        }
    }
}
