//! The default set's white-matter tracts and brainstem parts (issue: blood supply and pathways):
//! every structure teaches (a name, synonyms, two sentences or more; Latin names for the new
//! ones), the tracts lie in the tissue they run in, and the brainstem's three parts fill it.

use crate::common::default_set;
use vbrain::mesh::Bounds;
use vbrain::mri::slice::{inside, Axis, Pane, SlicePlane};

fn sentences(text: &str) -> usize {
    text.split(". ").filter(|s| s.trim().len() > 10).count()
}

#[test]
fn at_least_130_structures_teach_and_the_new_ones_have_latin_names() {
    let set = default_set();
    let organs = set.organs.iter().filter(|o| !o.synonyms.is_empty() && sentences(&o.info) >= 2).count();
    let t = set.territories.as_ref().unwrap();
    let arteries = t.arteries.iter().filter(|a| !a.synonyms.is_empty() && sentences(&a.info) >= 2).count();
    assert!(organs + arteries >= 130, "{organs} organs and {arteries} arteries teach");
    let tracts: Vec<_> = set.organs.iter().filter(|o| o.group.starts_with("White matter tracts")).collect();
    assert!(tracts.len() >= 25, "{} tracts", tracts.len());
    assert!(tracts.iter().all(|o| !o.visible), "the tracts are hidden by default");
    for o in tracts.iter().copied().chain(set.select("Brainstem").into_iter().map(|i| &set.organs[i])) {
        assert!(o.latin.as_deref().is_some_and(|l| !l.is_empty()), "{}: no Latin name", o.id);
        assert!(sentences(&o.info) >= 3 && !o.synonyms.is_empty(), "{}: too little text", o.id);
    }
    let pyramidal = set.organs.iter().filter(|o| o.synonyms.iter().any(|s| s == "pyramidal tract")).count();
    assert_eq!(pyramidal, 2, "both corticospinal tracts are the pyramidal tract");
    let stem: Vec<&str> = set.select("Brainstem").into_iter().map(|i| set.organs[i].id.as_str()).collect();
    assert_eq!(stem, ["midbrain", "pons", "medulla_oblongata"]);
}

/// Voxel centres (1 mm, axial slices) inside the union of `organs` over `b`, x fastest.
fn voxels(organs: &[usize], b: &Bounds) -> Vec<bool> {
    let set = default_set();
    let (nx, ny) = ((b.max[0] - b.min[0]).ceil() as u32 + 1, (b.max[1] - b.min[1]).ceil() as u32 + 1);
    let mut out = Vec::new();
    for k in 0..=(b.max[2] - b.min[2]).ceil() as u32 {
        let pane = Pane {
            plane: SlicePlane { axis: Axis::Axial, at: b.min[2] + k as f32 },
            centre: [b.min[0] + (nx as f32 - 1.0) / 2.0, b.min[1] + (ny as f32 - 1.0) / 2.0],
            mm_per_px: 1.0,
            width: nx,
            height: ny,
            radiological: false,
        };
        let masks: Vec<Vec<bool>> = organs.iter().map(|&o| inside(set.organs[o].mesh(), &pane)).collect();
        out.extend((0..(nx * ny) as usize).map(|i| masks.iter().any(|m| m[i])));
    }
    out
}

#[test]
fn at_least_90_percent_of_each_tract_lies_in_white_matter_or_brainstem() {
    let set = default_set();
    let ids = |keys: &[&str]| keys.iter().flat_map(|k| set.select(k)).collect::<Vec<_>>();
    // The tissue tracts run in: the cerebral white matter with the corpus callosum, the brainstem,
    // the cerebellar white matter (the peduncles enter it) and the ventral diencephalon, FreeSurfer's
    // label that holds the upper crus of the cerebral peduncle.
    let tissue = ids(&[
        "white_matter_l",
        "white_matter_r",
        "corpus_callosum",
        "Brainstem",
        "cerebellum_white_matter_l",
        "cerebellum_white_matter_r",
        "ventral_dc_l",
        "ventral_dc_r",
    ]);
    // The fornix runs under the corpus callosum between the lateral ventricles, where the set has
    // no organ (FreeSurfer's labels have no septal region): there it counts what no organ of the
    // brain holds.
    let brain = |o: &usize| !set.organs[*o].group.starts_with("White matter") && set.organs[*o].group != "Head";
    let organs: Vec<usize> = (0..set.organs.len()).filter(brain).collect();
    let solid: Vec<usize> = organs.iter().copied().filter(|o| !tissue.contains(o)).collect();
    let mut report = Vec::new();
    for t in set.organs.iter().enumerate().filter(|(_, o)| o.group.starts_with("White matter tracts")) {
        let (i, o) = t;
        let b = o.mesh().bounds();
        let tract = voxels(&[i], &b);
        let mut within = voxels(&tissue, &b);
        if o.id == "fornix" {
            let other = voxels(&solid, &b);
            within.iter_mut().zip(other).for_each(|(w, taken)| *w |= !taken);
        }
        let n = tract.iter().filter(|&&v| v).count();
        let both = tract.iter().zip(&within).filter(|(&a, &w)| a && w).count();
        report.push((o.id.clone(), n, both as f64 / n.max(1) as f64));
    }
    let short: Vec<_> = report.iter().filter(|(_, n, share)| *n < 20 || *share < 0.9).collect();
    assert!(short.is_empty(), "tracts under 90 % in white matter or brainstem: {short:?} (all: {report:?})");
}
