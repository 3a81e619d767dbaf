//! Arterial territories (issue: blood supply and pathways): which artery supplies each point of a
//! set, from an atlas registered to the set when the set was built.
//!
//! - Points are in organ space: millimetres, RAS (a moved organ keeps its territories).
//! - The set's `territories.json` (format [`FORMAT`]) lists the arteries and names a label volume;
//!   territory id `2k + 1` is artery `k`'s on the left, `2k + 2` on the right, 0 none.
//! - A point takes the id of the voxel whose cell holds it (labels are never interpolated).
//! - A mesh takes territories only where at least [`MIN_SHARE`] of its vertices lie in one: the
//!   brain's organs do, the skull and scalp around it do not.

use crate::error::{Error, Result};
use crate::mesh::Mesh;
use glam::{Mat4, Vec3};
use serde::Deserialize;
use std::path::Path;

/// The format tag of a territories file.
pub const FORMAT: &str = "vbrain-territories/1";

/// The most arteries a file may list (two ids each must fit in a byte).
pub const MAX_ARTERIES: usize = 127;

/// The most voxels a territory volume may have.
pub const MAX_VOXELS: usize = crate::mri::MAX_VOXELS;

/// The share of a mesh's vertices that must lie in a territory for it to take territories.
pub const MIN_SHARE: f32 = 0.5;

/// One artery (or, where [`Artery::is_artery`] is false, a region of the atlas no artery supplies).
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Artery {
    /// Its id in files: lowercase, e.g. `mca_frontal`.
    pub key: String,
    /// "Middle cerebral artery, frontal branches".
    pub name: String,
    /// "MCA frontal".
    pub short: String,
    /// Terminologia Anatomica's name, where it has one.
    #[serde(default)]
    pub latin: String,
    /// `#rrggbb` in the file.
    #[serde(deserialize_with = "colour")]
    pub colour: [f32; 3],
    #[serde(default)]
    pub synonyms: Vec<String>,
    /// Teaching text: the artery and its branches, what it supplies, the deficits of its occlusion.
    pub info: String,
    #[serde(default = "crate::json_file::yes", rename = "artery")]
    pub is_artery: bool,
}

fn colour<'de, D: serde::Deserializer<'de>>(d: D) -> std::result::Result<[f32; 3], D::Error> {
    let s = String::deserialize(d)?;
    super::manifest::parse_colour(&s).ok_or_else(|| serde::de::Error::custom(format!("colour \"{s}\" is not #rrggbb")))
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TerritoryFile {
    #[allow(dead_code)]
    format: String,
    volume: String,
    arteries: Vec<Artery>,
    #[serde(default)]
    unasked: Vec<String>,
}

/// Left or right: which of an artery's two territories an id is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    Left,
    Right,
}

impl Side {
    pub fn name(self) -> &'static str {
        match self {
            Side::Left => "Left",
            Side::Right => "Right",
        }
    }
}

/// The set's arteries and its territory volume.
#[derive(Clone, Debug)]
pub struct Territories {
    pub arteries: Vec<Artery>,
    /// Organ ids no supply question asks about: where the registered atlas departs from the
    /// textbook's supply (the file's `unasked`).
    pub unasked: Vec<String>,
    dims: [usize; 3],
    to_voxel: Mat4,
    /// Territory ids, x fastest.
    ids: Vec<u8>,
}

impl Territories {
    /// Reads `file` (a territories file inside the set's folder `dir`) and the volume it names.
    pub fn open(dir: &Path, file: &str) -> Result<Territories> {
        let path = crate::input::inside(dir, file)?;
        let text = crate::input::read_text(&path, crate::input::Kind::Manifest)?;
        let parsed: TerritoryFile = crate::json_file::parse(&text, &path, FORMAT, "territories file")?;
        let bad = |m: String| Error::parse(&path, None, m);
        if parsed.arteries.is_empty() || parsed.arteries.len() > MAX_ARTERIES {
            return Err(bad(format!("{} arteries: a file lists 1 to {MAX_ARTERIES}", parsed.arteries.len())));
        }
        for (i, a) in parsed.arteries.iter().enumerate() {
            if !super::manifest::id_ok(&a.key) || parsed.arteries[..i].iter().any(|b| b.key == a.key) {
                return Err(bad(format!("artery {}: key \"{}\" is not a new valid id", i + 1, a.key)));
            }
            if a.name.trim().is_empty() || a.info.trim().is_empty() {
                return Err(bad(format!("artery \"{}\" has no name or no text", a.key)));
            }
        }
        super::manifest::mesh_path_ok(&parsed.volume).map_err(|e| bad(format!("volume {}: {e}", parsed.volume)))?;
        let volume_path = crate::input::inside(path.parent().unwrap_or(dir), &parsed.volume)?;
        let raw = crate::nifti_file::read(&volume_path, "territory volume", MAX_VOXELS)?;
        let most = 2 * parsed.arteries.len();
        let mut ids = Vec::with_capacity(raw.len());
        for i in 0..raw.len() {
            let v = raw.value(i);
            if !(v >= 0.0 && v <= most as f64 && v.fract() == 0.0) {
                return Err(Error::parse(
                    &volume_path,
                    None,
                    format!(
                        "voxel {i} holds {v}: territory ids are whole numbers 0 to {most} for {} arteries",
                        most / 2
                    ),
                ));
            }
            ids.push(v as u8);
        }
        if !(raw.affine.is_finite() && raw.affine.determinant().abs() > 1e-12) {
            return Err(Error::parse(&volume_path, None, "the voxel-to-world transform is singular"));
        }
        Ok(Territories {
            arteries: parsed.arteries,
            unasked: parsed.unasked,
            dims: raw.dims,
            to_voxel: raw.affine.inverse(),
            ids,
        })
    }

    /// A set of territories from parts (tests, generated sets): `ids` x fastest on a grid of
    /// `dims` placed by `to_world` (voxel indices -> millimetres).
    pub fn from_parts(arteries: Vec<Artery>, dims: [usize; 3], to_world: Mat4, ids: Vec<u8>) -> Territories {
        assert_eq!(ids.len(), dims[0] * dims[1] * dims[2], "one id per voxel");
        Territories { arteries, unasked: Vec::new(), dims, to_voxel: to_world.inverse(), ids }
    }

    /// The territory id at `p` (organ space), 0 outside every territory.
    pub fn at(&self, p: Vec3) -> u8 {
        let v = self.to_voxel.transform_point3(p).round();
        if !v.is_finite() || v.min_element() < 0.0 {
            return 0;
        }
        let [x, y, z] = [v.x as usize, v.y as usize, v.z as usize];
        if x >= self.dims[0] || y >= self.dims[1] || z >= self.dims[2] {
            return 0;
        }
        self.ids[x + self.dims[0] * (y + self.dims[1] * z)]
    }

    /// The artery and side of territory `id`, `None` for 0 or an id beyond the file's.
    pub fn artery(&self, id: u8) -> Option<(&Artery, Side)> {
        let k = (id as usize).checked_sub(1)?;
        let side = if k % 2 == 0 { Side::Left } else { Side::Right };
        self.arteries.get(k / 2).map(|a| (a, side))
    }

    /// "Left middle cerebral artery, frontal branches" (the artery's name lowered after the side).
    pub fn name(&self, id: u8) -> Option<String> {
        self.artery(id).map(|(a, side)| sided(side, &a.name))
    }

    /// The arteries any of whose names (name, short name, key, Latin name, synonyms) contain
    /// `query`, compared as organ names are ([`super::names::fold`]); none for an empty
    /// query.
    pub fn find(&self, query: &str) -> Vec<&Artery> {
        let fold = super::names::fold;
        let q = fold(query);
        if q.is_empty() {
            return Vec::new();
        }
        let names = |a: &Artery| {
            let own = [a.name.as_str(), a.short.as_str(), a.key.as_str(), a.latin.as_str()];
            own.into_iter().chain(a.synonyms.iter().map(String::as_str)).any(|n| fold(n).contains(&q))
        };
        self.arteries.iter().filter(|a| names(a)).collect()
    }

    /// The artery (index into [`Territories::arteries`], a true artery) that supplies the most of
    /// a mesh's vertices, either side, with the share of its vertices it supplies; `None` where
    /// no artery supplies any.
    pub fn supplier(&self, mesh: &Mesh) -> Option<(usize, f32)> {
        let counts = self.counts(mesh);
        let (k, &n) = counts
            .iter()
            .enumerate()
            .filter(|(k, _)| self.arteries[*k].is_artery)
            .max_by_key(|(k, &n)| (n, std::cmp::Reverse(*k)))?;
        (n > 0).then(|| (k, n as f32 / mesh.positions.len().max(1) as f32))
    }

    /// Vertices of a mesh in each artery's territory (both sides), index-aligned with the arteries.
    fn counts(&self, mesh: &Mesh) -> Vec<usize> {
        let mut counts = vec![0; self.arteries.len()];
        for &p in &mesh.positions {
            if let Some(k) = (self.at(Vec3::from(p)) as usize).checked_sub(1) {
                if let Some(c) = counts.get_mut(k / 2) {
                    *c += 1;
                }
            }
        }
        counts
    }

    /// `n` arteries to choose from for the supply of a mesh whose supplier is `answer`: it, then
    /// the true arteries that supply most of the rest of the mesh, then the others in an order
    /// drawn from `rng`; shuffled.
    pub fn choices(&self, mesh: &Mesh, answer: usize, n: usize, rng: &mut crate::rng::XorShift) -> Vec<usize> {
        let counts = self.counts(mesh);
        let mut others: Vec<usize> =
            (0..self.arteries.len()).filter(|&k| k != answer && self.arteries[k].is_artery).collect();
        rng.shuffle(&mut others);
        others.sort_by_key(|&k| std::cmp::Reverse(counts[k]));
        let mut out: Vec<usize> = std::iter::once(answer).chain(others).take(n).collect();
        rng.shuffle(&mut out);
        out
    }

    /// Territory ids of a mesh's vertices, or `None` where under [`MIN_SHARE`] of them lie in one.
    pub fn of_mesh(&self, mesh: &Mesh) -> Option<Vec<u8>> {
        let ids: Vec<u8> = mesh.positions.iter().map(|&p| self.at(Vec3::from(p))).collect();
        let inside = ids.iter().filter(|&&t| t != 0).count();
        (!ids.is_empty() && inside as f32 >= MIN_SHARE * ids.len() as f32).then_some(ids)
    }
}

/// The territory where a ray first meets a mesh placed by `model` (organ space to world space),
/// at a point `kept` keeps (the clip planes' kept side, world space): what a click on the organ
/// points at. `None` where the ray misses or no territory covers the point.
pub fn under_ray(
    territories: &Territories,
    mesh: &Mesh,
    model: Mat4,
    (origin, dir): (Vec3, Vec3),
    kept: impl Fn(Vec3) -> bool,
) -> Option<u8> {
    let corner = |v: u32| model.transform_point3(Vec3::from(mesh.positions[v as usize]));
    let mut hits: Vec<(f32, [u32; 3])> = mesh
        .indices
        .chunks_exact(3)
        .filter_map(|t| {
            let t = [t[0], t[1], t[2]];
            let d = crate::mesh::ray_triangle(origin, dir, t.map(corner))?;
            (d >= 0.0).then_some((d, t))
        })
        .collect();
    hits.sort_by(|a, b| a.0.total_cmp(&b.0));
    let inverse = model.inverse();
    hits.into_iter()
        .map(|(d, _)| origin + dir * d)
        .find(|&p| kept(p))
        .map(|p| territories.at(inverse.transform_point3(p)))
        .filter(|&id| id != 0)
}

/// "Left middle cerebral artery" from a side and "Middle cerebral artery".
pub fn sided(side: Side, name: &str) -> String {
    let mut chars = name.chars();
    let rest: String = match chars.next() {
        Some(c) => c.to_lowercase().chain(chars).collect(),
        None => String::new(),
    };
    format!("{} {rest}", side.name())
}

#[cfg(test)]
mod tests {
    use super::*;

    pub(crate) fn artery(key: &str) -> Artery {
        Artery {
            key: key.into(),
            name: format!("{key} artery"),
            short: key.to_uppercase(),
            latin: String::new(),
            colour: [1.0, 0.0, 0.0],
            synonyms: Vec::new(),
            info: "Supplies. Occlusion hurts.".into(),
            is_artery: true,
        }
    }

    /// 2 x 1 x 1 voxels, 10 mm apart along x: x < 5 mm is voxel 0 (left ACA), above voxel 1
    /// (right MCA).
    fn aca_then_mca() -> Territories {
        Territories::from_parts(
            vec![artery("aca"), artery("mca")],
            [2, 1, 1],
            Mat4::from_scale(Vec3::new(10.0, 1.0, 1.0)),
            vec![1, 4],
        )
    }

    #[test]
    fn ids_name_a_side_and_points_take_the_nearest_voxel() {
        let t = aca_then_mca();
        assert_eq!(t.at(Vec3::new(4.9, 0.0, 0.0)), 1);
        assert_eq!(t.at(Vec3::new(5.1, 0.2, -0.4)), 4);
        assert_eq!(t.at(Vec3::new(15.1, 0.0, 0.0)), 0, "outside the grid");
        assert_eq!(t.at(Vec3::new(-5.1, 0.0, 0.0)), 0);
        assert_eq!(t.at(Vec3::NAN), 0);
        assert_eq!(t.name(1).as_deref(), Some("Left aca artery"));
        assert_eq!(t.name(4).as_deref(), Some("Right mca artery"));
        assert_eq!(t.name(0), None);
        assert_eq!(t.name(5), None);
        assert_eq!(sided(Side::Left, "Middle cerebral artery"), "Left middle cerebral artery");
        let found = |q: &str| t.find(q).iter().map(|a| a.key.clone()).collect::<Vec<_>>();
        assert_eq!(found("MCA"), ["mca"]);
        assert_eq!(found("  Aca  Artery"), ["aca"]);
        assert_eq!(found("artery"), ["aca", "mca"]);
        assert!(found("").is_empty() && found("pca").is_empty());
    }

    #[test]
    fn a_ray_names_the_territory_of_the_first_kept_point_it_meets() {
        // A square at z = 0 from x 0 to 10, half in each territory.
        let t = aca_then_mca();
        let square = Mesh {
            positions: vec![[0.0, -1.0, 0.0], [10.0, -1.0, 0.0], [10.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
            normals: vec![[0.0, 0.0, 1.0]; 4],
            indices: vec![0, 1, 2, 0, 2, 3],
        };
        let down = |x: f32| (Vec3::new(x, 0.0, 5.0), Vec3::NEG_Z);
        assert_eq!(under_ray(&t, &square, Mat4::IDENTITY, down(2.0), |_| true), Some(1));
        assert_eq!(under_ray(&t, &square, Mat4::IDENTITY, down(8.0), |_| true), Some(4));
        assert_eq!(under_ray(&t, &square, Mat4::IDENTITY, down(12.0), |_| true), None, "a miss");
        assert_eq!(under_ray(&t, &square, Mat4::IDENTITY, down(8.0), |p| p.x < 5.0), None, "cut away");
        // Moved 6 mm right, the organ keeps its own territories: world x 8 is organ x 2.
        let moved = Mat4::from_translation(Vec3::new(6.0, 0.0, 0.0));
        assert_eq!(under_ray(&t, &square, moved, down(8.0), |_| true), Some(1));
    }

    #[test]
    fn a_mesh_mostly_outside_takes_no_territory() {
        let t = Territories::from_parts(vec![artery("aca")], [1, 1, 1], Mat4::IDENTITY, vec![2]);
        let mesh = |xs: &[f32]| Mesh {
            positions: xs.iter().map(|&x| [x, 0.0, 0.0]).collect(),
            normals: vec![[0.0, 0.0, 1.0]; xs.len()],
            indices: Vec::new(),
        };
        assert_eq!(t.of_mesh(&mesh(&[0.0, 0.2, 9.0])), Some(vec![2, 2, 0]));
        assert_eq!(t.of_mesh(&mesh(&[0.0, 9.0, 9.0])), None);
    }
}
