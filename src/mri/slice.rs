//! One axis-aligned slice through the set: which organ owns each pixel, and the MRI there.
//!
//! - A [`Pane`] is an image of the plane: pixels, origin top left, y down, `mm_per_px` square
//!   pixels, centred on a point of the plane. World space is the set's: millimetres, RAS.
//! - Axial: horizontal is x, up is +y (anterior); coronal: horizontal is x, up is +z; sagittal:
//!   horizontal is y, up is +z, anterior on the left.
//! - Radiological display (the default, as on the ward) puts the patient's right on the image's
//!   left in axial and coronal panes (horizontal = -x); neurological puts it on the right.
//! - A pixel belongs to an organ when its centre lies inside the organ's closed surface: the
//!   parity of the surface's crossings of the pixel's row left of the centre (half-open at
//!   vertices and rows, so shared edges count once). `organs/brain/build_mri.py` voxelises the
//!   white matter by the same rule.

use super::{Mri, Window};
use crate::mesh::{Bounds, Mesh};
use crate::organ_set::OrganSet;
use glam::{Vec2, Vec3};

/// The most pixels a pane may have (a 4096 x 4096 figure).
pub const MAX_PIXELS: usize = 4096 * 4096;

/// The axis a slice is perpendicular to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Axis {
    Sagittal,
    Coronal,
    Axial,
}

impl Axis {
    pub const ALL: [Axis; 3] = [Axis::Axial, Axis::Coronal, Axis::Sagittal];

    /// The world axis (0 = x, 1 = y, 2 = z) the plane is perpendicular to.
    pub fn normal(self) -> usize {
        match self {
            Axis::Sagittal => 0,
            Axis::Coronal => 1,
            Axis::Axial => 2,
        }
    }

    /// The world axes shown horizontally and vertically (up).
    pub fn in_plane(self) -> (usize, usize) {
        match self {
            Axis::Sagittal => (1, 2),
            Axis::Coronal => (0, 2),
            Axis::Axial => (0, 1),
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Axis::Sagittal => "sagittal",
            Axis::Coronal => "coronal",
            Axis::Axial => "axial",
        }
    }

    /// The world coordinate's letter ("x", "y", "z") that places the plane.
    pub fn coordinate(self) -> &'static str {
        ["x", "y", "z"][self.normal()]
    }
}

/// A plane `world[axis.normal()] = at` (millimetres).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SlicePlane {
    pub axis: Axis,
    pub at: f32,
}

impl SlicePlane {
    /// Parses `coronal=-10` (also `axial=...`, `sagittal=...`; millimetres, |at| <= 1000).
    pub fn parse(text: &str) -> Result<SlicePlane, String> {
        let (name, at) = text
            .split_once('=')
            .ok_or_else(|| format!("{text:?}: expected PLANE=MM, e.g. coronal=-10 (axial, coronal or sagittal)"))?;
        let axis = match name.trim().to_ascii_lowercase().as_str() {
            "axial" | "transverse" => Axis::Axial,
            "coronal" | "frontal" => Axis::Coronal,
            "sagittal" => Axis::Sagittal,
            other => return Err(format!("{other:?} is not a plane: axial, coronal or sagittal")),
        };
        let at: f32 = at.trim().parse().map_err(|_| format!("{at:?} is not a number of millimetres"))?;
        if !(at.is_finite() && at.abs() <= 1000.0) {
            return Err(format!("{at} mm is out of range: a plane lies within 1000 mm of the origin"));
        }
        Ok(SlicePlane { axis, at })
    }
}

/// An image of a slice plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pane {
    pub plane: SlicePlane,
    /// The world point at the image's centre, as (horizontal, vertical) world coordinates.
    pub centre: [f32; 2],
    pub mm_per_px: f32,
    pub width: u32,
    pub height: u32,
    pub radiological: bool,
}

impl Pane {
    /// A pane of `width x height` pixels showing `bounds`' extent in the plane, with a margin.
    pub fn fit(plane: SlicePlane, bounds: &Bounds, width: u32, height: u32, radiological: bool) -> Pane {
        let (h, v) = plane.axis.in_plane();
        let size = bounds.size();
        let span = (size[h] / width.max(1) as f32).max(size[v] / height.max(1) as f32) * 1.08;
        let c = bounds.center();
        Pane { plane, centre: [c[h], c[v]], mm_per_px: span.max(1e-3), width, height, radiological }
    }

    /// Does the image's x run against its horizontal world axis?
    fn mirrored(&self) -> bool {
        match self.plane.axis {
            Axis::Sagittal => true,
            _ => self.radiological,
        }
    }

    /// The world point at image position `(x, y)` (pixels, continuous: a pixel's centre is at
    /// `+0.5`).
    pub fn world(&self, x: f32, y: f32) -> Vec3 {
        let (h, v) = self.plane.axis.in_plane();
        let sign = if self.mirrored() { -1.0 } else { 1.0 };
        let mut p = Vec3::ZERO;
        p[h] = self.centre[0] + sign * (x - self.width as f32 / 2.0) * self.mm_per_px;
        p[v] = self.centre[1] - (y - self.height as f32 / 2.0) * self.mm_per_px;
        p[self.plane.axis.normal()] = self.plane.at;
        p
    }

    /// The image position of world point `p` (its projection onto the plane).
    pub fn pixel(&self, p: Vec3) -> Vec2 {
        let (h, v) = self.plane.axis.in_plane();
        let sign = if self.mirrored() { -1.0 } else { 1.0 };
        Vec2::new(
            sign * (p[h] - self.centre[0]) / self.mm_per_px + self.width as f32 / 2.0,
            -(p[v] - self.centre[1]) / self.mm_per_px + self.height as f32 / 2.0,
        )
    }

    /// The letters at the image's left and right edges: the patient's side (R/L) or, sagittal,
    /// anterior and posterior.
    pub fn edge_letters(&self) -> [&'static str; 2] {
        match (self.plane.axis, self.radiological) {
            (Axis::Sagittal, _) => ["A", "P"],
            (_, true) => ["R", "L"],
            (_, false) => ["L", "R"],
        }
    }

    fn pixels(&self) -> usize {
        self.width as usize * self.height as usize
    }
}

/// The pixels of `pane` whose centres lie inside the closed `mesh` (row-major).
pub fn inside(mesh: &Mesh, pane: &Pane) -> Vec<bool> {
    let mut mask = vec![false; pane.pixels()];
    fill(mesh, 0..mesh.triangle_count() as u32, pane, &mut Vec::new(), |i| mask[i] = true);
    mask
}

/// The triangles of `organ` whose hierarchy nodes reach the plane `world[axis] = at`.
fn near_plane(organ: &crate::organ_set::Organ, axis: usize, at: f32) -> Vec<u32> {
    let nodes = &organ.bvh.nodes;
    let mut out = Vec::new();
    let mut stack = vec![0u32];
    while let Some(n) = stack.pop() {
        let Some(node) = nodes.get(n as usize) else { continue };
        if node.bounds.min[axis] > at || node.bounds.max[axis] < at {
            continue;
        }
        if node.is_leaf() {
            out.extend(node.first..node.first + node.count);
        } else {
            stack.extend(node.children);
        }
    }
    out
}

/// Per pixel of `pane`, the organ whose surface holds its centre, as index + 1 (0 for none), over
/// `organs` of `set` (organ space, the set at rest). Where organs nest, the smaller one wins.
pub fn organ_ids(set: &OrganSet, organs: &[usize], pane: &Pane) -> Vec<u32> {
    let mut ids = vec![0u32; pane.pixels().min(MAX_PIXELS)];
    if ids.len() != pane.pixels() {
        return ids;
    }
    let (axis, at) = (pane.plane.axis.normal(), pane.plane.at);
    let mut order: Vec<(usize, Bounds)> = organs
        .iter()
        .filter_map(|&o| set.organs.get(o).map(|organ| (o, organ.bounds())))
        .filter(|(_, b)| b.min[axis] <= at && at <= b.max[axis])
        .collect();
    let volume = |b: &Bounds| b.size().x * b.size().y * b.size().z;
    order.sort_by(|a, b| volume(&b.1).total_cmp(&volume(&a.1)));
    let mut toggles = Vec::new();
    for (o, _) in order {
        let organ = &set.organs[o];
        fill(organ.mesh(), near_plane(organ, axis, at).into_iter(), pane, &mut toggles, |i| ids[i] = o as u32 + 1);
    }
    ids
}

/// Calls `paint` with each pixel inside `mesh` ([`inside`]'s rule), given `triangles` that hold
/// every triangle crossing the plane; `toggles` is scratch space.
fn fill(
    mesh: &Mesh,
    triangles: impl Iterator<Item = u32>,
    pane: &Pane,
    toggles: &mut Vec<u8>,
    mut paint: impl FnMut(usize),
) {
    let (w, h) = (pane.width as usize, pane.height as usize);
    if w * h == 0 || w * h > MAX_PIXELS {
        return;
    }
    let (axis, at) = (pane.plane.axis.normal(), pane.plane.at);
    toggles.clear();
    toggles.resize(h * (w + 1), 0);
    let (mut first, mut last) = (h, 0);
    for t in triangles {
        let p = mesh.triangle(t as usize);
        let above = p.map(|q| q[axis] > at);
        if above[0] == above[1] && above[1] == above[2] {
            continue;
        }
        let mut ends = [Vec2::ZERO; 2];
        let mut n = 0;
        for (i, j) in [(0, 1), (1, 2), (2, 0)] {
            if above[i] != above[j] && n < 2 {
                let s = (at - p[i][axis]) / (p[j][axis] - p[i][axis]);
                ends[n] = pane.pixel(p[i] + (p[j] - p[i]) * s);
                n += 1;
            }
        }
        let [a, b] = ends;
        if a.y == b.y || !(a.is_finite() && b.is_finite()) {
            continue;
        }
        // Rows whose centre y + 0.5 lies in [min y, max y).
        let lo = ((a.y.min(b.y) - 0.5).ceil().max(0.0)) as usize;
        let hi = ((a.y.max(b.y) - 0.5).ceil().clamp(0.0, h as f32)) as usize;
        for r in lo..hi {
            let yc = r as f32 + 0.5;
            let x = a.x + (yc - a.y) * (b.x - a.x) / (b.y - a.y);
            let col = (x - 0.5).ceil().clamp(0.0, w as f32) as usize;
            toggles[r * (w + 1) + col] ^= 1;
            first = first.min(r);
            last = last.max(r + 1);
        }
    }
    for r in first..last {
        let mut odd = 0u8;
        for c in 0..w {
            odd ^= toggles[r * (w + 1) + c];
            if odd == 1 {
                paint(r * w + c);
            }
        }
    }
}

/// The MRI's grey (0..=1, through `window`) at each pixel of `pane`; `None` outside the volume.
/// Rows in parallel; along a row the voxel position steps by a constant.
pub fn greys(mri: &Mri, pane: &Pane, window: Window) -> Vec<Option<f32>> {
    use rayon::prelude::*;
    if pane.pixels() > MAX_PIXELS {
        return Vec::new();
    }
    let m = mri.to_voxel();
    let origin = m.transform_point3(pane.world(0.5, 0.5));
    let dx = m.transform_vector3(pane.world(1.5, 0.5) - pane.world(0.5, 0.5));
    let dy = m.transform_vector3(pane.world(0.5, 1.5) - pane.world(0.5, 0.5));
    let w = pane.width as usize;
    (0..pane.height as usize)
        .into_par_iter()
        .flat_map_iter(|y| {
            let row = origin + dy * y as f32;
            (0..w).map(move |x| mri.sample_voxel(row + dx * x as f32).map(|v| window.grey(v)))
        })
        .collect()
}

/// Pixels on an organ's outline: inside an organ (id > 0) and within `radius` pixels (a square)
/// of one of its pixels with a 4-neighbour of another id. Radius 0 gives a line one pixel wide on
/// each side of a border.
pub fn outline(ids: &[u32], width: u32, radius: usize) -> Vec<bool> {
    let w = width as usize;
    let h = ids.len().checked_div(w).unwrap_or(0);
    let border: Vec<bool> = (0..w * h)
        .map(|i| {
            let (x, y, id) = (i % w, i / w, ids[i]);
            id != 0
                && ((x > 0 && ids[i - 1] != id)
                    || (x + 1 < w && ids[i + 1] != id)
                    || (y > 0 && ids[i - w] != id)
                    || (y + 1 < h && ids[i + w] != id))
        })
        .collect();
    if radius == 0 {
        return border;
    }
    (0..w * h)
        .map(|i| {
            let (x, y, id) = (i % w, i / w, ids[i]);
            id != 0
                && (y.saturating_sub(radius)..(y + radius + 1).min(h)).any(|yy| {
                    (x.saturating_sub(radius)..(x + radius + 1).min(w)).any(|xx| {
                        let j = yy * w + xx;
                        border[j] && ids[j] == id
                    })
                })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A closed octahedron of `radius` about `centre`.
    fn solid(centre: Vec3, radius: f32) -> Mesh {
        let mut m = Mesh::octahedron();
        m.positions.iter_mut().for_each(|p| *p = (Vec3::from(*p) * radius + centre).into());
        m
    }

    fn pane(axis: Axis, at: f32, radiological: bool) -> Pane {
        Pane { plane: SlicePlane { axis, at }, centre: [0.0, 0.0], mm_per_px: 1.0, width: 40, height: 30, radiological }
    }

    #[test]
    fn pixels_and_world_points_round_trip() {
        for axis in Axis::ALL {
            for radiological in [false, true] {
                let p = pane(axis, 3.0, radiological);
                let w = p.world(7.5, 11.5);
                assert_eq!(w[axis.normal()], 3.0);
                assert!((p.pixel(w) - Vec2::new(7.5, 11.5)).length() < 1e-4);
            }
        }
    }

    #[test]
    fn radiological_axial_puts_the_patients_right_on_the_left() {
        let p = pane(Axis::Axial, 0.0, true);
        assert!(p.world(0.5, 15.0).x > 0.0, "left edge shows +x, the patient's right");
        assert_eq!(p.edge_letters(), ["R", "L"]);
        let n = pane(Axis::Axial, 0.0, false);
        assert!(n.world(0.5, 15.0).x < 0.0);
        assert!(p.world(20.0, 0.5).y > 0.0, "anterior is up");
    }

    #[test]
    fn a_solid_fills_its_cross_section_and_nothing_else() {
        // An octahedron of radius 10 at the origin: on z = 0 its section is the diamond |x|+|y| <= 10.
        let mesh = solid(Vec3::ZERO, 10.0);
        let p = pane(Axis::Axial, 0.0, false);
        let mask = inside(&mesh, &p);
        let mut count = 0;
        for (i, &m) in mask.iter().enumerate() {
            let c = p.world((i % 40) as f32 + 0.5, (i / 40) as f32 + 0.5);
            let d = c.x.abs() + c.y.abs();
            if d < 9.5 {
                assert!(m, "{c} is inside the diamond");
            }
            if d > 10.5 {
                assert!(!m, "{c} is outside the diamond");
            }
            count += m as usize;
        }
        // The diamond's area is 2 r^2 = 200 mm^2.
        assert!((180..=220).contains(&count), "{count}");
        // A plane that misses it fills nothing.
        assert!(!inside(&mesh, &pane(Axis::Axial, 11.0, false)).iter().any(|&m| m));
    }

    #[test]
    fn nested_organs_show_the_inner_one_and_outlines_follow_borders() {
        use crate::organ_set::Organ;
        let outer = Organ::new("outer".into(), "Outer".into(), [0.5; 3], solid(Vec3::ZERO, 12.0));
        let inner = Organ::new("inner".into(), "Inner".into(), [0.5; 3], solid(Vec3::ZERO, 4.0));
        let set = OrganSet { organs: vec![inner, outer], ..Default::default() };
        let p = pane(Axis::Coronal, 0.0, true);
        let ids = organ_ids(&set, &[0, 1], &p);
        let at = |x: f32, y: f32| ids[(y as usize) * 40 + x as usize];
        let centre = p.pixel(Vec3::ZERO);
        assert_eq!(at(centre.x, centre.y), 1, "the inner organ wins at the centre");
        assert_eq!(at(centre.x + 8.0, centre.y), 2, "the outer organ around it");
        assert_eq!(at(0.0, 0.0), 0);
        let line = outline(&ids, 40, 0);
        assert!(outline(&ids, 40, 1).iter().filter(|&&l| l).count() > line.iter().filter(|&&l| l).count());
        assert!(!line[(centre.y as usize) * 40 + centre.x as usize]);
        assert!(line.iter().filter(|&&l| l).count() > 20);
    }
}
