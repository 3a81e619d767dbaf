//! Triangle meshes: a [`Mesh`] is an indexed triangle list with one normal per vertex.
//!
//! - Organ space: millimetres, RAS (+x right, +y anterior, +z superior).
//! - Normals are always present: loaders that find none call [`Mesh::compute_normals`] (smooth,
//!   area-weighted).

use glam::Vec3;

/// An indexed triangle mesh. Invariants: `normals.len() == positions.len()`, `indices.len() % 3 == 0`,
/// every index `< positions.len()`, every coordinate finite.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    pub positions: Vec<[f32; 3]>,
    pub normals: Vec<[f32; 3]>,
    pub indices: Vec<u32>,
}

/// An axis-aligned box; `min > max` on some axis means empty.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Bounds {
    pub min: [f32; 3],
    pub max: [f32; 3],
}

impl Bounds {
    pub const EMPTY: Bounds = Bounds { min: [f32::INFINITY; 3], max: [f32::NEG_INFINITY; 3] };

    pub fn is_empty(&self) -> bool {
        (0..3).any(|i| self.min[i] > self.max[i])
    }

    pub fn include(&mut self, p: [f32; 3]) {
        for i in 0..3 {
            self.min[i] = self.min[i].min(p[i]);
            self.max[i] = self.max[i].max(p[i]);
        }
    }

    pub fn union(mut self, other: Bounds) -> Bounds {
        if !other.is_empty() {
            self.include(other.min);
            self.include(other.max);
        }
        self
    }

    pub fn center(&self) -> Vec3 {
        (Vec3::from(self.min) + Vec3::from(self.max)) * 0.5
    }

    pub fn size(&self) -> Vec3 {
        Vec3::from(self.max) - Vec3::from(self.min)
    }

    /// The eight corners, for transforming the box.
    pub fn corners(&self) -> [Vec3; 8] {
        let (a, b) = (self.min, self.max);
        std::array::from_fn(|i| {
            Vec3::new(
                if i & 1 == 0 { a[0] } else { b[0] },
                if i & 2 == 0 { a[1] } else { b[1] },
                if i & 4 == 0 { a[2] } else { b[2] },
            )
        })
    }

    /// Bounds of this box after an affine transform.
    pub fn transformed(&self, m: &glam::Mat4) -> Bounds {
        let mut out = Bounds::EMPTY;
        if !self.is_empty() {
            for c in self.corners() {
                out.include(m.transform_point3(c).to_array());
            }
        }
        out
    }
}

impl Mesh {
    /// The corners of triangle `t`.
    pub fn triangle(&self, t: usize) -> [Vec3; 3] {
        [0, 1, 2].map(|k| Vec3::from(self.positions[self.indices[3 * t + k] as usize]))
    }

    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    pub fn bounds(&self) -> Bounds {
        let mut b = Bounds::EMPTY;
        for &p in &self.positions {
            b.include(p);
        }
        b
    }

    /// Replaces the normals by smooth, area-weighted vertex normals: each triangle adds its
    /// unnormalised face normal (length = twice its area) to its three vertices.
    pub fn compute_normals(&mut self) {
        let mut acc = vec![Vec3::ZERO; self.positions.len()];
        for t in self.indices.chunks_exact(3) {
            let [a, b, c] = [t[0], t[1], t[2]].map(|i| Vec3::from(self.positions[i as usize]));
            let n = (b - a).cross(c - a);
            for &i in t {
                acc[i as usize] += n;
            }
        }
        self.normals = acc.into_iter().map(|n| n.try_normalize().unwrap_or(Vec3::Z).to_array()).collect();
    }

    /// The enclosed volume (mm³) of a closed mesh: positive when its triangles wind counter-clockwise
    /// seen from outside, negative when inside out.
    pub fn signed_volume(&self) -> f32 {
        let c = self.bounds().center();
        self.indices
            .chunks_exact(3)
            .map(|t| {
                let [a, b, d] = [t[0], t[1], t[2]].map(|i| Vec3::from(self.positions[i as usize]) - c);
                a.dot(b.cross(d)) / 6.0
            })
            .sum()
    }

    /// Directed edges (a, b) of the welded mesh used more often than (b, a): none where the surface
    /// is closed (every ray from outside to a point inside crosses it), even where more than two
    /// triangles share an edge.
    pub fn open_edges(&self) -> usize {
        let (remap, _) = weld(&self.positions);
        let mut balance: std::collections::HashMap<(u32, u32), i32> =
            std::collections::HashMap::with_capacity(self.indices.len());
        for t in self.indices.chunks_exact(3) {
            for k in 0..3 {
                let (a, b) = (remap[t[k] as usize], remap[t[(k + 1) % 3] as usize]);
                if a != b {
                    *balance.entry((a.min(b), a.max(b))).or_insert(0) += if a < b { 1 } else { -1 };
                }
            }
        }
        balance.values().filter(|&&d| d != 0).count()
    }

    /// Closed and wound counter-clockwise seen from outside: from outside, only its front faces can
    /// be seen (the renderer culls the back ones).
    pub fn is_closed_outward(&self) -> bool {
        !self.indices.is_empty() && self.open_edges() == 0 && self.signed_volume() > 0.0
    }

    /// Appends another mesh (indices shifted).
    pub fn append(&mut self, other: &Mesh) {
        let base = self.positions.len() as u32;
        self.positions.extend_from_slice(&other.positions);
        self.normals.extend_from_slice(&other.normals);
        self.indices.extend(other.indices.iter().map(|i| i + base));
    }

    /// The unit octahedron: closed, wound counter-clockwise seen from outside, with normals.
    pub fn octahedron() -> Mesh {
        let mut m = Mesh {
            positions: vec![[1., 0., 0.], [-1., 0., 0.], [0., 1., 0.], [0., -1., 0.], [0., 0., 1.], [0., 0., -1.]],
            normals: vec![],
            indices: vec![0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5],
        };
        m.compute_normals();
        m
    }

    /// A closed UV sphere of `radius` at the origin, `rings` x `segments`, wound outward, vertices
    /// shared, with normals.
    pub fn uv_sphere(radius: f32, rings: u32, segments: u32) -> Mesh {
        let mut positions = vec![[0.0, 0.0, radius]];
        for r in 1..rings {
            let theta = std::f32::consts::PI * r as f32 / rings as f32;
            for s in 0..segments {
                let phi = std::f32::consts::TAU * s as f32 / segments as f32;
                positions.push(
                    (glam::Vec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos()) * radius)
                        .to_array(),
                );
            }
        }
        positions.push([0.0, 0.0, -radius]);
        let (ring, south) = (|r: u32, s: u32| 1 + (r - 1) * segments + s % segments, positions.len() as u32 - 1);
        let mut indices = Vec::new();
        for s in 0..segments {
            indices.extend([0, ring(1, s), ring(1, s + 1)]);
            indices.extend([south, ring(rings - 1, s + 1), ring(rings - 1, s)]);
            for r in 1..rings - 1 {
                let (a, b, c, d) = (ring(r, s), ring(r, s + 1), ring(r + 1, s), ring(r + 1, s + 1));
                indices.extend([a, c, d, a, d, b]);
            }
        }
        let mut m = Mesh { positions, normals: vec![], indices };
        m.compute_normals();
        m
    }

    /// Checks the invariants stated on [`Mesh`]; returns the first violation.
    pub fn validate(&self) -> Result<(), MeshDefect> {
        if self.normals.len() != self.positions.len() {
            return Err(MeshDefect::Normals { normals: self.normals.len(), vertices: self.positions.len() });
        }
        if !self.indices.len().is_multiple_of(3) {
            return Err(MeshDefect::Indices(self.indices.len()));
        }
        if let Some(&index) = self.indices.iter().find(|&&i| i as usize >= self.positions.len()) {
            return Err(MeshDefect::IndexOutOfRange { index, vertices: self.positions.len() });
        }
        if self.positions.iter().chain(&self.normals).flatten().any(|v| !v.is_finite()) {
            return Err(MeshDefect::NonFinite);
        }
        Ok(())
    }
}

/// A broken invariant of a [`Mesh`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum MeshDefect {
    #[error("{normals} normals for {vertices} vertices")]
    Normals { normals: usize, vertices: usize },
    #[error("{0} indices is not a multiple of 3")]
    Indices(usize),
    #[error("index {index} out of range ({vertices} vertices)")]
    IndexOutOfRange { index: u32, vertices: usize },
    #[error("non-finite coordinate")]
    NonFinite,
}

/// Vertices welded by position (-0 and +0 alike): per vertex, its welded index (numbered in order
/// of first use), and the welded positions.
pub fn weld(positions: &[[f32; 3]]) -> (Vec<u32>, Vec<[f32; 3]>) {
    let mut ids: std::collections::HashMap<[u32; 3], u32> = std::collections::HashMap::with_capacity(positions.len());
    let mut welded = Vec::new();
    let remap = positions
        .iter()
        .map(|p| {
            *ids.entry(p.map(|c| if c == 0.0 { 0 } else { c.to_bits() })).or_insert_with(|| {
                welded.push(*p);
                welded.len() as u32 - 1
            })
        })
        .collect();
    (remap, welded)
}

/// Slab test: where the ray `origin + t dir` (t >= 0, `inv` = 1 / dir) enters the box `b`, if it
/// meets it (0 from inside).
pub fn ray_box_entry(origin: Vec3, inv: Vec3, b: &Bounds) -> Option<f32> {
    let (lo, hi) = ((Vec3::from(b.min) - origin) * inv, (Vec3::from(b.max) - origin) * inv);
    let (near, far) = (lo.min(hi).max_element(), lo.max(hi).min_element());
    // NaN (a zero direction component on the slab's plane) compares false: treated as meeting.
    (!(near > far || far < 0.0)).then_some(near.max(0.0))
}

/// Möller-Trumbore: the distance along the ray `origin + t dir` (any sign of t) at which it
/// crosses the triangle, if it does (either side; none where the ray runs parallel to it).
pub fn ray_triangle(origin: Vec3, dir: Vec3, [a, b, c]: [Vec3; 3]) -> Option<f32> {
    let (e1, e2) = (b - a, c - a);
    let p = dir.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-12 {
        return None;
    }
    let s = origin - a;
    let u = s.dot(p) / det;
    let q = s.cross(e1);
    let v = dir.dot(q) / det;
    let t = e2.dot(q) / det;
    (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t.is_finite()).then_some(t)
}

#[cfg(test)]
/// A closed box surface, counter-clockwise from outside, split into `n` x `n` squares a side.
pub(crate) fn split_box(n: usize, half: Vec3) -> Mesh {
    let mut m = Mesh::default();
    for axis in 0..3 {
        for sign in [-1.0f32, 1.0] {
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            let base = m.positions.len() as u32;
            for j in 0..=n {
                for i in 0..=n {
                    let mut p = Vec3::ZERO;
                    p[axis] = sign * half[axis];
                    p[u] = half[u] * (2.0 * i as f32 / n as f32 - 1.0);
                    p[v] = half[v] * (2.0 * j as f32 / n as f32 - 1.0);
                    m.positions.push(p.to_array());
                }
            }
            let at = |i: usize, j: usize| base + (j * (n + 1) + i) as u32;
            for j in 0..n {
                for i in 0..n {
                    let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                    // u x v = axis: counter-clockwise seen from +axis.
                    if sign > 0.0 {
                        m.indices.extend([a, b, c, a, c, d]);
                    } else {
                        m.indices.extend([a, c, b, a, d, c]);
                    }
                }
            }
        }
    }
    m.compute_normals();
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn area_weighted_normals() {
        // Two triangles sharing vertex 0: a large one in the xy-plane, a small one in the xz-plane.
        let mut m = Mesh {
            positions: vec![[0., 0., 0.], [10., 0., 0.], [0., 10., 0.], [0., 0., 1.], [1., 0., 0.]],
            normals: vec![],
            indices: vec![0, 1, 2, 0, 3, 4],
        };
        m.compute_normals();
        let n0 = Vec3::from(m.normals[0]);
        // Area 50 along +z, area 0.5 along +y: the shared normal leans to +z by 100:1.
        assert!((n0 - Vec3::new(0.0, 1.0, 100.0).normalize()).length() < 1e-5, "{n0}");
        assert_eq!(m.normals[1], [0., 0., 1.]);
        assert!(m.validate().is_ok());
    }

    #[test]
    fn bounds_transform() {
        let b = Bounds { min: [-1., -2., -3.], max: [1., 2., 3.] };
        let t = b.transformed(&glam::Mat4::from_translation(Vec3::new(10., 0., 0.)));
        assert_eq!(t.min, [9., -2., -3.]);
        assert!(Bounds::EMPTY.is_empty());
    }
}
