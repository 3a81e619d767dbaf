//! Import of a label volume (NIfTI) and its label table into an organ set.
//!
//! - Surfaces are extracted in voxel index space, then mapped by the volume's affine (sform, else
//!   qform, else pixel sizes) into world space, which for atlases and scanner segmentations is
//!   millimetres, RAS.
//! - Several labels of one name form one organ.
//! - Pipeline per organ: the voxels of its labels -> a lightly blurred mask -> surface nets ->
//!   stray specks removed -> Taubin smoothing -> meshoptimizer simplification to the organ's share
//!   of the triangle budget -> smooth normals.

use super::{distinct_colour, slug, Organ, OrganSet};
use crate::error::{Error, Result};
use crate::mesh::Mesh;
use crate::multi_surface;
use crate::surface;
use glam::{Mat4, Vec3};
use std::collections::{BTreeMap, HashMap};
use std::path::Path;

pub use super::label_table::{parse_label_table, read_label_table, Label, LabelTable};

/// A label volume: labels on a grid (x fastest) and the voxel-to-world affine.
pub struct LabelVolume {
    pub dims: [usize; 3],
    pub labels: Vec<i64>,
    pub affine: Mat4,
}

/// The most voxels a label volume may have (2^28, e.g. 640^3): each becomes an 8-byte label and
/// passes through several masks while surfaces are extracted.
pub const MAX_VOXELS: usize = 1 << 28;

/// Reads a NIfTI-1 label volume (`.nii` or `.nii.gz`) through [`crate::nifti_file`]: the header
/// is checked before any voxel is read. Stored values are scaled by the header's slope; a
/// label must then be a whole number.
pub fn read_volume(path: &Path) -> Result<LabelVolume> {
    let raw = crate::nifti_file::read(path, "label volume", MAX_VOXELS)?;
    // The surfaces lie inside the voxel grid's corners: where the affine puts one beyond what a
    // mesh may hold, the set would be written and then refused by every command.
    let limit = super::obj::MAX_COORDINATE;
    let grid = crate::mesh::Bounds { min: [-0.5; 3], max: raw.dims.map(|d| d as f32 - 0.5) };
    for corner in grid.corners() {
        let p = raw.affine.transform_point3(corner);
        if !p.is_finite() || p.abs().max_element() > limit {
            return Err(Error::parse(
                path,
                None,
                format!(
                    "header fields srow/qform: the volume's corner lies at ({:.0}, {:.0}, {:.0}) mm, beyond +-{limit} mm \
                     (1 km) where vbrain's meshes lie; is its affine in millimetres?",
                    p.x, p.y, p.z
                ),
            ));
        }
    }
    let labels = decode_labels(&raw).map_err(|m| Error::parse(path, None, m))?;
    Ok(LabelVolume { dims: raw.dims, labels, affine: raw.affine })
}

/// The voxels as integer labels. A float volume (or a scaled one) must hold whole numbers (a
/// probability or intensity map is not a label volume); non-finite voxels are refused.
fn decode_labels(raw: &crate::nifti_file::RawVolume) -> std::result::Result<Vec<i64>, String> {
    let mut labels = Vec::new();
    labels.try_reserve_exact(raw.len()).map_err(|_| format!("{} labels do not fit in memory", raw.len()))?;
    for i in 0..raw.len() {
        let v = raw.value(i);
        if !(v.is_finite() && (v - v.round()).abs() <= 1e-3 && v.abs() < 9e15) {
            let hint = if raw.is_float() { " (is this a probability or intensity map?)" } else { "" };
            return Err(format!("voxel {i} holds {}: a label volume must hold whole-number labels{hint}", v as f32));
        }
        labels.push(v.round() as i64);
    }
    Ok(labels)
}

/// Options of [`import`].
#[derive(Clone, Debug)]
pub struct ImportOptions {
    /// Total triangle budget of the set, shared among organs by their surface size.
    pub triangles: usize,
    /// Taubin smoothing iterations.
    pub smoothing: usize,
    pub title: String,
}

impl Default for ImportOptions {
    fn default() -> Self {
        ImportOptions { triangles: 200_000, smoothing: 10, title: "Imported organs".into() }
    }
}

/// Progress of a long job: `(done, total, what)`.
pub type Progress<'a> = &'a mut dyn FnMut(usize, usize, &str);

/// Builds an organ set from a label volume and its table. Labels present in the volume but not in
/// the table are reported in the returned warnings.
pub fn import(
    volume: &LabelVolume,
    table: &[Label],
    opts: &ImportOptions,
    progress: Progress,
) -> Result<(OrganSet, Vec<String>)> {
    let mut warnings = Vec::new();
    let (organs, boxes) = present_organs(volume, table, &mut warnings)?;
    // Extract every surface first; the budget is then shared by surface size.
    let total_steps = organs.len() * 2;
    let mut raw: Vec<Mesh> = Vec::new();
    for (i, (name, labels, _)) in organs.iter().enumerate() {
        progress(i, total_steps, name);
        raw.push(extract(volume, labels, &boxes, opts.smoothing));
    }
    let total_raw: usize = raw.iter().map(Mesh::triangle_count).sum::<usize>().max(1);
    for (i, ((name, _, _), mesh)) in organs.iter().zip(&mut raw).enumerate() {
        progress(total_steps / 2 + i, total_steps, name);
        let share = (opts.triangles as f64 * mesh.triangle_count() as f64 / total_raw as f64) as usize;
        surface::simplify(mesh, share.max(64));
        mesh.compute_normals();
    }
    let set = assemble(&opts.title, organs, raw, &mut warnings);
    progress(total_steps, total_steps, "done");
    Ok((set, warnings))
}

/// An organ of a label table: its name, its labels, the table's colour.
type OrganLabels = (String, Vec<i64>, Option<[f32; 3]>);

/// Each present label's voxel bounding box, `(min, max)` inclusive.
type LabelBoxes = BTreeMap<i64, ([usize; 3], [usize; 3])>;

/// The table's organs (by name, in table order) that have voxels, and each present label's box.
/// Warns of labels missing from the table and of organs without voxels; `NoLabels` if none has any.
fn present_organs(
    volume: &LabelVolume,
    table: &[Label],
    warnings: &mut Vec<String>,
) -> Result<(Vec<OrganLabels>, LabelBoxes)> {
    // Organs by name, in table order; each with its labels.
    let mut organs: Vec<OrganLabels> = Vec::new();
    for l in table.iter().filter(|l| l.index != 0) {
        match organs.iter_mut().find(|o| o.0 == l.name) {
            Some(o) => o.1.push(l.index),
            None => organs.push((l.name.clone(), vec![l.index], l.colour)),
        }
    }
    // Bounding boxes of each label present, in one pass over the volume.
    let [nx, ny, _] = volume.dims;
    let mut boxes: BTreeMap<i64, ([usize; 3], [usize; 3])> = BTreeMap::new();
    for (i, &label) in volume.labels.iter().enumerate() {
        if label == 0 {
            continue;
        }
        let p = [i % nx, (i / nx) % ny, i / (nx * ny)];
        let b = boxes.entry(label).or_insert((p, p));
        for k in 0..3 {
            b.0[k] = b.0[k].min(p[k]);
            b.1[k] = b.1[k].max(p[k]);
        }
    }
    for label in boxes.keys() {
        if !table.iter().any(|l| l.index == *label) {
            warnings.push(format!("label {label} is in the volume but not in the table: skipped"));
        }
    }
    organs.retain(|o| {
        let present = o.1.iter().any(|l| boxes.contains_key(l));
        if !present {
            warnings.push(format!("\"{}\" (label {:?}) has no voxels: skipped", o.0, o.1));
        }
        present
    });
    if organs.is_empty() {
        return Err(Error::NoLabels);
    }
    Ok((organs, boxes))
}

/// The set of `organs` with their `meshes`: each under its name's slug made unique, in the table's
/// colour or a distinct one; an organ whose mesh is empty is left out with a warning.
fn assemble(title: &str, organs: Vec<OrganLabels>, meshes: Vec<Mesh>, warnings: &mut Vec<String>) -> OrganSet {
    let mut set = OrganSet { title: title.to_string(), ..Default::default() };
    let mut ids = std::collections::HashSet::new();
    for ((name, _, colour), mesh) in organs.into_iter().zip(meshes) {
        if mesh.triangle_count() == 0 {
            warnings.push(format!("\"{name}\": no surface left after clean-up: skipped"));
            continue;
        }
        let id = super::unique_id(&slug(&name), &mut ids);
        let colour = colour.unwrap_or_else(|| distinct_colour(set.organs.len()));
        set.organs.push(Organ::new(id, name, colour, mesh));
    }
    set
}

/// Like [`import`], but all organs from one multi-label surface net
/// ([`crate::multi_surface`]): neighbouring organs share their interfaces' vertices and
/// triangles, with no slivers or gaps between them. The budget counts a shared interface once per
/// organ that draws it. It is a ceiling that thin parts and junctions (where three organs meet)
/// may keep decimation above: on whole-brain atlases, from about 130 000 triangles.
pub fn import_seamless(
    volume: &LabelVolume,
    table: &[Label],
    opts: &ImportOptions,
    progress: Progress,
) -> Result<(OrganSet, Vec<String>)> {
    let mut warnings = Vec::new();
    let (organs, _) = present_organs(volume, table, &mut warnings)?;
    const STEPS: usize = 4;
    progress(0, STEPS, "labels");
    let number: HashMap<i64, u32> =
        organs.iter().enumerate().flat_map(|(k, o)| o.1.iter().map(move |&l| (l, k as u32 + 1))).collect();
    let grid: Vec<u32> =
        volume.labels.iter().map(|l| if *l == 0 { 0 } else { number.get(l).copied().unwrap_or(0) }).collect();
    progress(1, STEPS, "surfaces");
    let ms_opts = multi_surface::Options { smoothing: opts.smoothing, triangles: opts.triangles, ..Default::default() };
    let mut shared =
        multi_surface::interfaces(&multi_surface::OrganGrid { dims: volume.dims, organs: &grid }, &ms_opts);
    progress(2, STEPS, "simplifying");
    shared.decimate(opts.triangles);
    shared.transform(volume.affine);
    progress(3, STEPS, "organs");
    let meshes = shared.organ_meshes(organs.len());
    let set = assemble(&opts.title, organs, meshes, &mut warnings);
    progress(STEPS, STEPS, "done");
    Ok((set, warnings))
}

/// The smoothed surface of the union of `labels`, in world space.
fn extract(
    volume: &LabelVolume,
    labels: &[i64],
    boxes: &BTreeMap<i64, ([usize; 3], [usize; 3])>,
    smoothing: usize,
) -> Mesh {
    const MARGIN: usize = 2;
    let mut lo = [usize::MAX; 3];
    let mut hi = [0usize; 3];
    for b in labels.iter().filter_map(|l| boxes.get(l)) {
        for k in 0..3 {
            lo[k] = lo[k].min(b.0[k]);
            hi[k] = hi[k].max(b.1[k]);
        }
    }
    // The cropped grid has a margin of empty voxels on every side, so the surface closes.
    let origin: [i64; 3] = std::array::from_fn(|k| lo[k] as i64 - MARGIN as i64);
    let dims: [usize; 3] = std::array::from_fn(|k| hi[k] - lo[k] + 1 + 2 * MARGIN);
    let [nx, ny, nz] = volume.dims;
    let mut mask = vec![0f32; dims[0] * dims[1] * dims[2]];
    for z in 0..dims[2] {
        for y in 0..dims[1] {
            for x in 0..dims[0] {
                let g = [origin[0] + x as i64, origin[1] + y as i64, origin[2] + z as i64];
                if g.iter().any(|&c| c < 0) || g[0] >= nx as i64 || g[1] >= ny as i64 || g[2] >= nz as i64 {
                    continue;
                }
                let label = volume.labels[g[0] as usize + nx * (g[1] as usize + ny * g[2] as usize)];
                if labels.contains(&label) {
                    mask[x + dims[0] * (y + dims[1] * z)] = 1.0;
                }
            }
        }
    }
    blur121(&mut mask, dims);
    let mut mesh = surface::surface_nets(&surface::Grid { dims, values: &mask }, 0.5);
    surface::remove_small_components(&mut mesh, 40);
    surface::taubin_smooth(&mut mesh, smoothing);
    let to_world =
        volume.affine * Mat4::from_translation(Vec3::new(origin[0] as f32, origin[1] as f32, origin[2] as f32));
    for p in &mut mesh.positions {
        *p = to_world.transform_point3(Vec3::from(*p)).to_array();
    }
    // A mirroring affine turns the winding inside out.
    if volume.affine.determinant() < 0.0 {
        for t in mesh.indices.chunks_exact_mut(3) {
            t.swap(1, 2);
        }
    }
    mesh
}

/// A separable [1 2 1]/4 blur along each axis: sub-voxel surface positions instead of stair steps.
fn blur121(values: &mut [f32], dims: [usize; 3]) {
    let strides = [1, dims[0], dims[0] * dims[1]];
    let mut tmp = values.to_vec();
    for axis in 0..3 {
        let (s, n) = (strides[axis], dims[axis]);
        for (i, out) in tmp.iter_mut().enumerate() {
            let c = (i / s) % n;
            let prev = if c > 0 { values[i - s] } else { 0.0 };
            let next = if c + 1 < n { values[i + s] } else { 0.0 };
            *out = 0.25 * prev + 0.5 * values[i] + 0.25 * next;
        }
        values.copy_from_slice(&tmp);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_float_volume_must_hold_whole_numbers() {
        use crate::nifti_file::TestFile;
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("v.nii");
        std::fs::write(&path, TestFile::float32([3, 1, 1], &[2.0, 17.0, 0.0])).unwrap();
        assert_eq!(read_volume(&path).unwrap().labels, vec![2, 17, 0]);
        std::fs::write(&path, TestFile::float32([3, 1, 1], &[2.0, 0.37, f32::NAN])).unwrap();
        let e = read_volume(&path).err().unwrap().to_string();
        assert!(e.contains("voxel 1 holds 0.37") && e.contains("whole-number"), "{e}");
    }

    #[test]
    fn two_cubes_two_organs_in_world_space() {
        let dims = [20, 12, 12];
        let mut labels = vec![0i64; 20 * 12 * 12];
        for z in 3..9 {
            for y in 3..9 {
                for x in 2..8 {
                    labels[x + 20 * (y + 12 * z)] = 5;
                    labels[x + 10 + 20 * (y + 12 * z)] = 9;
                }
            }
        }
        // 2 mm voxels, mirrored x (as radiological volumes are), shifted.
        let affine = Mat4::from_translation(Vec3::new(100.0, 0.0, 0.0)) * Mat4::from_scale(Vec3::new(-2.0, 2.0, 2.0));
        let vol = LabelVolume { dims, labels, affine };
        let table = vec![
            Label { index: 5, name: "Left".into(), colour: None },
            Label { index: 9, name: "Right".into(), colour: Some([1.0, 0.0, 0.0]) },
            Label { index: 7, name: "Absent".into(), colour: None },
        ];
        let (set, warnings) =
            import(&vol, &table, &ImportOptions { triangles: 2000, ..Default::default() }, &mut |_, _, _| {}).unwrap();
        assert_eq!(set.organs.len(), 2);
        assert_eq!(warnings.len(), 1, "{warnings:?}");
        let left = set.organs[0].mesh.bounds();
        // Voxels 2..8 map to x = 100 - 2*[2..8) -> about 84..96.
        assert!(left.min[0] > 82.0 && left.max[0] < 98.0, "{left:?}");
        assert_eq!(set.organs[1].colour, [1.0, 0.0, 0.0]);
        // Outward winding survives the mirroring affine: positive signed volume.
        for o in &set.organs {
            let m = &o.mesh;
            let vol = m.signed_volume();
            assert!(vol > 500.0, "{}: signed volume {vol}", o.name);
            assert!(m.validate().is_ok());
        }
    }

    #[test]
    fn seamless_import_shares_the_interface_in_world_space() {
        let dims = [20, 12, 12];
        let mut labels = vec![0i64; 20 * 12 * 12];
        for z in 3..9 {
            for y in 3..9 {
                for x in 2..14 {
                    // Labels 5 and 6 are both "Left"; 11 is not in the table.
                    labels[x + 20 * (y + 12 * z)] = [5, 6, 9, 9, 11][x / 3];
                }
            }
        }
        let affine = Mat4::from_translation(Vec3::new(100.0, 0.0, 0.0)) * Mat4::from_scale(Vec3::new(-2.0, 2.0, 2.0));
        let vol = LabelVolume { dims, labels, affine };
        let table = vec![
            Label { index: 5, name: "Left".into(), colour: None },
            Label { index: 6, name: "Left".into(), colour: None },
            Label { index: 9, name: "Right".into(), colour: Some([1.0, 0.0, 0.0]) },
            Label { index: 7, name: "Absent".into(), colour: None },
        ];
        let opts = ImportOptions { triangles: 2000, ..Default::default() };
        let (set, warnings) = import_seamless(&vol, &table, &opts, &mut |_, _, _| {}).unwrap();
        assert_eq!(set.organs.iter().map(|o| o.id.as_str()).collect::<Vec<_>>(), ["left", "right"]);
        assert_eq!(warnings.len(), 2, "{warnings:?}");
        for o in &set.organs {
            assert!(o.mesh.signed_volume() > 0.0, "{}: inside out", o.name);
            assert!(o.mesh.validate().is_ok());
        }
        // Voxels x 2..=5 ("Left") and 6..=11 ("Right") meet at x = 5.5 -> 100 - 11 = 89 mm.
        let key = |p: &[f32; 3]| p.map(f32::to_bits);
        let left: std::collections::HashSet<_> = set.organs[0].mesh.positions.iter().map(key).collect();
        let common: Vec<_> = set.organs[1].mesh.positions.iter().filter(|p| left.contains(&key(p))).collect();
        assert!(common.len() >= 25 && common.iter().filter(|p| p[0] == 89.0).count() >= 25, "{common:?}");
        assert!(matches!(import_seamless(&vol, &table[3..], &opts, &mut |_, _, _| {}), Err(Error::NoLabels)));
    }
}
