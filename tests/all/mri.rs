//! The default set's MRI: it loads with the set, and it is registered to the organs (issue:
//! sectional anatomy). The fit is recomputed from the shipped files, as `build_mri.py` prints it.

use crate::common::{brain_dir, default_set};
use vbrain::mri::slice::{inside, Axis, Pane, SlicePlane};

#[test]
fn the_default_set_names_its_mri_and_it_loads() {
    let set = default_set();
    let mri = set.mri.as_ref().expect("organs/brain's manifest names mri/t1.nii.gz, and it loads");
    // It covers the brain: every organ but the scalp and skull lies inside its box.
    let m = mri.bounds();
    for o in set.organs.iter().filter(|o| !["scalp", "skull"].contains(&o.id.as_str())) {
        let b = o.mesh().bounds();
        let covered = (0..3).all(|a| m.min[a] <= b.min[a] && b.max[a] <= m.max[a]);
        assert!(covered, "{}: {b:?} is not inside the MRI's {m:?}", o.id);
    }
}

/// Dice overlap between the set's cerebral white matter (voxel centres inside its meshes) and the
/// registered template's white-matter map (probability > 0.5, stored as > 127 of 255) outside the
/// set's brainstem and cerebellum, whose white matter the map holds too.
#[test]
fn the_template_white_matter_fits_the_sets_at_dice_0_80_or_more() {
    let set = default_set();
    let map = vbrain::nifti_file::read(&brain_dir().join("mri/white_matter.nii.gz"), "MRI volume", 1 << 26).unwrap();
    let [nx, ny, nz] = map.dims;
    let a = map.affine;
    assert!(a.x_axis.x == 1.0 && a.y_axis.y == 1.0 && a.z_axis.z == 1.0, "a 1 mm axis-aligned grid: {a}");
    let origin = a.w_axis.truncate();
    let find = |ids: &[&str]| ids.iter().map(|id| set.find(id).unwrap()).collect::<Vec<_>>();
    let organs = find(&["white_matter_l", "white_matter_r"]);
    let outside = find(&[
        "midbrain",
        "pons",
        "medulla_oblongata",
        "cerebellum_l",
        "cerebellum_r",
        "cerebellum_white_matter_l",
        "cerebellum_white_matter_r",
    ]);
    let (mut both, mut ours, mut theirs) = (0usize, 0usize, 0usize);
    for k in 0..nz {
        // A neurological axial pane whose pixel centres are this slice's voxel centres (rows run
        // from +y down).
        let pane = Pane {
            plane: SlicePlane { axis: Axis::Axial, at: origin.z + k as f32 },
            centre: [origin.x + (nx as f32 - 1.0) / 2.0, origin.y + (ny as f32 - 1.0) / 2.0],
            mm_per_px: 1.0,
            width: nx as u32,
            height: ny as u32,
            radiological: false,
        };
        let masks: Vec<Vec<bool>> = organs.iter().map(|&o| inside(set.organs[o].mesh(), &pane)).collect();
        let not_cerebrum: Vec<Vec<bool>> = outside.iter().map(|&o| inside(set.organs[o].mesh(), &pane)).collect();
        for row in 0..ny {
            for i in 0..nx {
                let j = ny - 1 - row;
                let in_set = masks.iter().any(|m| m[row * nx + i]);
                let in_map = map.value(i + nx * (j + ny * k)) > 127.5 && !not_cerebrum.iter().any(|m| m[row * nx + i]);
                both += (in_set && in_map) as usize;
                ours += in_set as usize;
                theirs += in_map as usize;
            }
        }
    }
    let dice = 2.0 * both as f64 / (ours + theirs) as f64;
    assert!(ours > 300_000, "the set's white matter fills {ours} voxels");
    assert!(dice >= 0.80, "Dice {dice:.3} between the set's white matter and the registered template's");
    eprintln!("Dice {dice:.3} ({ours} set voxels, {theirs} template voxels)");
}

#[test]
fn a_plane_parses_and_its_bad_forms_are_refused() {
    assert_eq!(SlicePlane::parse("coronal=-10"), Ok(SlicePlane { axis: Axis::Coronal, at: -10.0 }));
    assert_eq!(SlicePlane::parse("Axial = 4.5"), Ok(SlicePlane { axis: Axis::Axial, at: 4.5 }));
    for bad in ["coronal", "oblique=3", "sagittal=x", "axial=1e39", "axial=NaN"] {
        assert!(SlicePlane::parse(bad).is_err(), "{bad}");
    }
}
