#!/usr/bin/env python3
"""White-matter tracts (JHU ICBM-DTI-81) and the brainstem split into midbrain, pons and medulla
(JHU "jhu189" parcellation), registered to the default set and meshed, into a staging folder.

    MRICRON_DEB=mricron-data_1.2.20211006+dfsg-4_all.deb \\
    PANPIPELINES_SDIST=panpipelines-1.1.10.tar.gz \\
    VBRAIN=target/release/vbrain \\
    python3 organs/brain/build_tracts.py [OUT]              # OUT defaults to /tmp/tracts-out

Writes OUT/meshes/<id>.vbo, OUT/entries.json (organ entries in organset.json's format, to be merged
by hand), OUT/fit.json and OUT/report.txt; nothing in the repository is changed.

Data: the Debian package mricron-data 1.2.20211006+dfsg-4 (apt-get download mricron-data), files
usr/share/mricron/templates/JHU-WhiteMatter-labels-1mm.nii.gz (+ .nii.txt, 48 labels) and
jhu189.nii.gz (189 labels, no names: the brainstem's labels are told by their positions, JHU189_*
below). The package is extracted into a temporary folder.

 1. The set's brain (every organ but the scalp and skull) is voxelised on the grid of the set's MRI
    (mri/t1.nii.gz, 1 mm, RAS) by ray parity (build_mri.voxelise).
 2. JHU-WhiteMatter-labels-1mm is drawn on FSL's MNI152 1 mm template (182 x 218 x 182), the grid
    of the arterial atlas that build_territories.py registers. mricron-data's copy has a RAS header
    (x = i - 91) over FSL's radiological voxel order (x = 90 - i): its "_R" labels sit at x < 0 and
    its tracts overlap the template's lateral ventricles more. So its x axis is flipped back, which
    puts every label on the side its name says (checked below). The arterial atlas's brain (labels
    > 0, MNI152NLin6Asym; build_territories.atlas(), needs PANPIPELINES_SDIST) is registered to the
    set's brain exactly as build_territories.py does (centre of mass, affine by mutual information,
    then SyN by cross-correlation), and the tract labels follow that transform by nearest neighbour.
 3. jhu189 (JHU-MNI space, its own 157 x 189 x 136 grid, which stops at z = -50 mm) is registered
    the same way, its brain (labels > 0) to the set's brain above that plane.
 4. Fit: the share of each tract's voxels inside the set's white matter (white_matter_l/_r,
    corpus_callosum), brainstem, and for the cerebellar peduncles the cerebellar white matter (for
    the cerebral peduncle also the ventral diencephalon, which holds the crus's upper end in
    FreeSurfer's labels). Every tract is then clipped to that tissue (the label is kept where the
    tissue is; pieces under MIN_PIECE voxels cut off by the clip are dropped) and meshed by
    `vbrain import --seamless` (neighbouring tracts share their boundaries).
 5. Brainstem: the set's brainstem mesh is voxelised; each voxel takes the part (midbrain, pons,
    medulla) of the nearest registered jhu189 brainstem label of an unambiguous part (the
    cerebellar peduncles' and the fourth ventricle's labels, which span levels, are left out), then
    the three part masks are smoothed (Gaussian, SMOOTH_PART_MM) and each voxel takes the largest:
    below jhu189's field of view everything is medulla. The three parts fill the brainstem's voxels
    exactly and are meshed together with --seamless. The junctions' levels (pontomesencephalic and
    pontomedullary, at the ventral surface and at the floor of the fourth ventricle) are measured
    and reported.

Needs: pip install nibabel numpy scipy dipy==1.12.1; dpkg-deb; vbrain (VBRAIN, default
target/release/vbrain).
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import nibabel as nib
import numpy as np
from scipy import ndimage

from build_mri import voxelise
from build_territories import atlas
from vbo import read_vbo

HERE = Path(__file__).resolve().parent
TEMPLATES = "usr/share/mricron/templates/"
JHU = TEMPLATES + "JHU-WhiteMatter-labels-1mm.nii.gz"
JHU189 = TEMPLATES + "jhu189.nii.gz"
SMOOTHING = 10          # Taubin iterations of vbrain import
TRACT_TRIANGLES = 10000  # budget of the whole tract set (vbrain import spreads it over the organs)
BRAINSTEM_TRIANGLES = 1500
MIN_PIECE = 20          # voxels: smaller pieces of a tract left by the clip are dropped
SMOOTH_PART_MM = 1.5
# jhu189's brainstem labels by part (left, right), told by their positions after registration:
JHU189_MIDBRAIN = [99, 100, 91, 92, 97, 98]          # midbrain, red nuclei, substantia nigra/crus
JHU189_PONS = [101, 102, 107, 108, 111, 112, 113, 114]  # basis and tegmentum of the pons, raphe
JHU189_MEDULLA = [115, 116]
JHU189_SPANNING = [103, 104, 105, 106, 109, 110, 181]  # superior, middle, inferior peduncles; 4th ventricle

# The tracts: id stem, JHU labels (the right one first; one label for midline tracts), group.
P, C, A, L, B = ("White matter tracts/" + g for g in
                 ("Projection", "Commissural", "Association", "Limbic", "Brainstem and cerebellar peduncles"))
TRACTS = [
    ("corticospinal_tract", (7, 8), P),
    ("cerebral_peduncle", (15, 16), P),
    ("anterior_limb_internal_capsule", (17, 18), P),
    ("posterior_limb_internal_capsule", (19, 20), P),
    ("posterior_thalamic_radiation", (29, 30), P),
    ("corpus_callosum_genu", (3,), C),
    ("corpus_callosum_body", (4,), C),
    ("corpus_callosum_splenium", (5,), C),
    ("cingulum", ((35, 37), (36, 38)), A),   # cingulate and hippocampal (parahippocampal) parts
    ("uncinate_fasciculus", (45, 46), A),
    ("superior_longitudinal_fasciculus", (41, 42), A),
    ("fornix", (6,), L),
    ("fornix_crus_stria_terminalis", (39, 40), L),
    ("medial_lemniscus", (9, 10), B),
    ("superior_cerebellar_peduncle", (13, 14), B),
    ("middle_cerebellar_peduncle", ((1, 2),), B),  # with the pontine crossing tract, "a part of MCP"
    ("inferior_cerebellar_peduncle", (11, 12), B),
]
PEDUNCLES = {"superior_cerebellar_peduncle", "middle_cerebellar_peduncle", "inferior_cerebellar_peduncle"}


def mricron(deb, tmp):
    """The two label volumes and the JHU names from the .deb, extracted into tmp."""
    subprocess.run(["dpkg-deb", "-x", str(deb), str(tmp)], check=True)
    names = {}
    for row in (tmp / (JHU[:-3] + ".txt")).read_text().splitlines():
        if row.strip():
            k, name = row.split("\t")
            names[int(k)] = name
    return nib.load(tmp / JHU), names, nib.load(tmp / JHU189), (tmp / "usr/share/doc/mricron-data/copyright").read_text()


def dice(a, b):
    return 2 * np.logical_and(a, b).sum() / (a.sum() + b.sum())


def register(moving, moving_affine, static_mask, shape, affine, label):
    """build_territories.py's registration of a binary brain to the set's brain; the mapping."""
    from dipy.align import affine_registration
    from dipy.align.imaffine import AffineMap
    from dipy.align.imwarp import SymmetricDiffeomorphicRegistration
    from dipy.align.metrics import CCMetric

    moving = moving.astype(np.float64)
    before = AffineMap(np.eye(4), domain_grid_shape=shape, domain_grid2world=affine,
                       codomain_grid_shape=moving.shape, codomain_grid2world=moving_affine)
    d = {"before": dice(static_mask, before.transform(moving) > 0.5)}
    static = ndimage.gaussian_filter(static_mask.astype(np.float64), 1.0)
    _, fit = affine_registration(ndimage.gaussian_filter(moving, 1.0), static, moving_affine=moving_affine,
                                 static_affine=affine, nbins=32,
                                 pipeline=["center_of_mass", "translation", "rigid", "affine"],
                                 level_iters=[1000, 100, 10], sigmas=[3.0, 1.0, 0.0], factors=[4, 2, 1])
    affine_map = AffineMap(fit, domain_grid_shape=shape, domain_grid2world=affine,
                           codomain_grid_shape=moving.shape, codomain_grid2world=moving_affine)
    d["affine"] = dice(static_mask, affine_map.transform(moving) > 0.5)
    syn = SymmetricDiffeomorphicRegistration(CCMetric(3, sigma_diff=1.0, radius=3), level_iters=[60, 40, 20])
    mapping = syn.optimize(static, ndimage.gaussian_filter(moving, 1.0), static_grid2world=affine,
                           moving_grid2world=moving_affine, prealign=fit)
    d["syn"] = dice(static_mask, mapping.transform(moving, interpolation="nearest") > 0.5)
    print(f"{label}: Dice of the brains before {d['before']:.3f}, after the affine fit {d['affine']:.3f}, "
          f"after the warp {d['syn']:.3f}")
    return mapping, {k: round(float(v), 4) for k, v in d.items()}


def run_import(vbrain, volume, table, out, triangles, title):
    env = dict(os.environ, XDG_RUNTIME_DIR=tempfile.mkdtemp())
    subprocess.run([str(vbrain), "import", str(volume), "--labels", str(table), "--out", str(out),
                    "--triangles", str(triangles), "--title", title, "--seamless",
                    "--smooth", str(SMOOTHING)], check=True, env=env, stdout=subprocess.DEVNULL)
    return json.loads((out / "organset.json").read_text())


def mesh_labels(vbrain, label_volume, ids, affine, triangles, title, tmp, dest):
    """Meshes label k (1-based) of label_volume as ids[k - 1] into dest; {id: (triangles, bytes)}."""
    work = tmp / title
    work.mkdir()
    img = nib.Nifti1Image(label_volume.astype(np.uint8), affine)
    img.set_qform(affine, 1)
    img.set_sform(affine, 1)
    nib.save(img, work / "labels.nii.gz")
    (work / "labels.csv").write_text("".join(f"{k},{oid}\n" for k, oid in enumerate(ids, 1)))
    made = run_import(vbrain, work / "labels.nii.gz", work / "labels.csv", work / "set", triangles, title)
    by_name = {o["name"]: o for o in made["organs"]}
    out = {}
    for oid in ids:
        o = by_name.get(oid) or next(o for o in made["organs"] if o["id"] == oid)
        src = work / "set" / o["mesh"]
        shutil.copyfile(src, dest / f"{oid}.vbo")
        # The organ's name line of the file is vbrain's; keep it, the id is the file name.
        _, f = read_vbo(dest / f"{oid}.vbo")
        out[oid] = (len(f), (dest / f"{oid}.vbo").stat().st_size)
    return out


def entries(ids, meta, parts):
    return []


def main():
    t0 = time.time()
    deb = os.environ.get("MRICRON_DEB")
    if not deb:
        sys.exit("set MRICRON_DEB to mricron-data_1.2.20211006+dfsg-4_all.deb (apt-get download mricron-data)")
    vbrain = Path(os.environ.get("VBRAIN", HERE.parent.parent / "target" / "release" / "vbrain"))
    out = Path(sys.argv[1] if len(sys.argv) > 1 else "/tmp/tracts-out")
    if out.exists():
        shutil.rmtree(out)
    (out / "meshes").mkdir(parents=True)
    report = []

    def say(line=""):
        print(line)
        report.append(line)

    grid = nib.load(HERE / "mri" / "t1.nii.gz")
    shape, affine = grid.shape, grid.affine
    manifest = json.loads((HERE / "organset.json").read_text())
    organ = {o["id"]: o for o in manifest["organs"]}

    def mask(ids):
        m = np.zeros(shape, bool)
        for oid in ids:
            v, f = read_vbo(HERE / organ[oid]["mesh"])
            m |= voxelise(v, f, shape, affine)
        return m

    brain = mask([o["id"] for o in manifest["organs"] if o["group"] != "Head"])
    cerebral_wm = mask(["white_matter_l", "white_matter_r", "corpus_callosum"])
    brainstem = mask(["brainstem"])
    cerebellar_wm = mask(["cerebellum_white_matter_l", "cerebellum_white_matter_r"])
    ventral_dc = mask(["ventral_dc_l", "ventral_dc_r"])
    world = lambda ijk: nib.affines.apply_affine(affine, ijk)  # noqa: E731
    midline = world(np.argwhere(brain).mean(0))[0]

    with tempfile.TemporaryDirectory() as tmpdir:
        tmp = Path(tmpdir)
        jhu, names, j189, copyright_text = mricron(deb, tmp / "deb")

        # --- JHU white-matter labels, through the FSL MNI152 brain (arterial atlas) ---------------
        art, _ = atlas()
        if jhu.shape != art.shape or not np.allclose(jhu.affine, art.affine):
            sys.exit("JHU labels and the arterial atlas are not on the same grid")
        labels = np.asarray(jhu.dataobj).astype(np.int32)[::-1]  # back to FSL's x = 90 - i order
        l189 = np.asarray(j189.dataobj).astype(np.int32)
        bottom = j189.affine[2, 3]  # world z of jhu189's lowest slice
        above = world(np.indices(shape).reshape(3, -1).T)[:, 2].reshape(shape) >= bottom
        cache = os.environ.get("TRACTS_CACHE")  # a folder for the registered labels (development)
        if cache and (Path(cache) / "registered.npz").exists():
            c = np.load(Path(cache) / "registered.npz", allow_pickle=True)
            warped, w189, dice_fsl, dice_189 = c["warped"], c["w189"], c["dice_fsl"].item(), c["dice_189"].item()
        else:
            mapping, dice_fsl = register(np.asarray(art.dataobj) > 0, art.affine, brain, shape, affine,
                                         "FSL MNI152 (arterial atlas brain) -> set")
            warped = mapping.transform(labels.astype(np.float64), interpolation="nearest").astype(np.int32)
            # jhu189, for the brainstem: its brain to the set's brain above its lowest slice.
            mapping189, dice_189 = register(l189 > 0, j189.affine, brain & above, shape, affine,
                                            f"jhu189 brain -> set brain above z = {bottom:.0f} mm")
            w189 = mapping189.transform(l189.astype(np.float64), interpolation="nearest").astype(np.int32)
            if cache:
                Path(cache).mkdir(parents=True, exist_ok=True)
                np.savez_compressed(Path(cache) / "registered.npz", warped=warped, w189=w189,
                                    dice_fsl=np.array(dice_fsl, dtype=object), dice_189=np.array(dice_189, dtype=object))

        # Sides: every "_R" label must lie right of the midline after the flip.
        for k, name in names.items():
            if name.endswith(("_R", "_L")):
                x = world(np.argwhere(warped == k).mean(0))[0]
                if (x > midline) != name.endswith("_R"):
                    sys.exit(f"label {k} {name} at x = {x:.1f} mm: wrong side")

        # --- Tracts: fit, clip ------------------------------------------------------------------
        say("")
        say("Tract fit (share of the registered label's voxels in the tissue it belongs to):")
        say(f"{'id':40s} {'voxels':>7s} {'WM+BS':>7s} {'allowed':>8s}  {'kept':>6s}")
        volume = np.zeros(shape, np.uint8)
        ids, meta, fit = [], {}, {}
        for stem, labs, group in TRACTS:
            sides = [("_r", labs[0]), ("_l", labs[1])] if len(labs) == 2 else [("", labs[0])]
            for suffix, lab in sides:
                oid = stem + suffix
                lab = lab if isinstance(lab, tuple) else (lab,)
                vox = np.isin(warped, lab)
                allowed = cerebral_wm | brainstem
                if stem in PEDUNCLES:
                    allowed = allowed | cerebellar_wm
                if stem == "cerebral_peduncle":
                    allowed = allowed | ventral_dc
                n = int(vox.sum())
                strict = float((vox & (cerebral_wm | brainstem)).sum() / n)
                share = float((vox & allowed).sum() / n)
                kept = vox & allowed
                pieces, count = ndimage.label(kept)
                sizes = np.bincount(pieces.ravel())
                kept &= (sizes >= MIN_PIECE)[pieces] & (pieces > 0)
                if (volume[kept] > 0).any():
                    sys.exit(f"{oid} overlaps another tract")
                ids.append(oid)
                volume[kept] = len(ids)
                meta[oid] = (stem, group, [names[k] for k in lab])
                fit[oid] = {"jhu_labels": [f"{k} {names[k]}" for k in lab], "voxels": n,
                            "in_white_matter_or_brainstem": round(strict, 4),
                            "in_allowed_tissue": round(share, 4),
                            "allowed_tissue": "cerebral white matter + corpus callosum + brainstem"
                            + (" + cerebellar white matter" if stem in PEDUNCLES else "")
                            + (" + ventral diencephalon" if stem == "cerebral_peduncle" else ""),
                            "voxels_meshed_after_clip": int(kept.sum())}
                say(f"{oid:40s} {n:7d} {100 * strict:6.1f}% {100 * share:7.1f}%  {int(kept.sum()):6d}")

        # --- Brainstem parts --------------------------------------------------------------------
        parts = ["midbrain", "pons", "medulla_oblongata"]
        seeds = np.zeros(shape, np.int8)
        for i, group in enumerate((JHU189_MIDBRAIN, JHU189_PONS, JHU189_MEDULLA), 1):
            seeds[np.isin(w189, group)] = i
        # Seeds inside (or within 2 mm of) the brainstem only: the atlas's labels past its surface
        # would otherwise pull the nearest-label split.
        seeds[~ndimage.binary_dilation(brainstem, iterations=2)] = 0
        _, nearest = ndimage.distance_transform_edt(seeds == 0, return_indices=True)
        part = seeds[tuple(nearest)]
        # Below jhu189's field of view: medulla.
        part[~above] = 3
        onehot = np.stack([ndimage.gaussian_filter((part == i).astype(np.float32), SMOOTH_PART_MM)
                           for i in (1, 2, 3)])
        part = np.where(brainstem, onehot.argmax(0) + 1, 0).astype(np.uint8)
        say("")
        say("Brainstem split (voxels of the set's brainstem: " + str(int(brainstem.sum())) + "):")
        seeded = {}
        for i, name in enumerate(parts, 1):
            zs = world(np.argwhere(part == i))[:, 2]
            seeded[name] = int(((seeds == i) & brainstem).sum())
            say(f"  {name:18s} {int((part == i).sum()):6d} voxels, z {zs.min():6.1f} .. {zs.max():6.1f} mm, "
                f"{seeded[name]} voxels labelled by jhu189")
        # Junction levels: the z of the boundary at the ventral surface and at the back (median plane).
        ix = int(round(np.linalg.inv(affine)[0] @ np.array([midline, 0, 0, 1])))
        sl = part[ix]
        junctions = {}
        for a, b, name in ((1, 2, "pontomesencephalic"), (2, 3, "pontomedullary")):
            ys = []
            for j in range(shape[1]):
                col = sl[j]
                ka, kb = np.nonzero(col == a)[0], np.nonzero(col == b)[0]
                if len(ka) and len(kb):
                    ys.append((world([ix, j, (ka.min() + kb.max()) / 2])[1:]))
            ys = np.array(ys)
            junctions[name] = {"ventral_y_z_mm": ys[ys[:, 0].argmax()].round(1).tolist(),
                               "dorsal_y_z_mm": ys[ys[:, 0].argmin()].round(1).tolist()}
            say(f"  {name} junction in the median plane: ventral (y, z) = {junctions[name]['ventral_y_z_mm']}, "
                f"dorsal (y, z) = {junctions[name]['dorsal_y_z_mm']} mm")
        # jhu189's labels per part, for the record: each label's centre and part.
        for i, group in enumerate((JHU189_MIDBRAIN, JHU189_PONS, JHU189_MEDULLA, JHU189_SPANNING)):
            for k in group:
                v = np.argwhere(w189 == k)
                if len(v):
                    c = world(v.mean(0))
                    say(f"    jhu189 label {k:3d} -> {(parts + ['left out (spans levels)'])[i]:24s} "
                        f"centre ({c[0]:5.1f}, {c[1]:5.1f}, {c[2]:5.1f}), {len(v)} voxels, "
                        f"{100 * (brainstem[tuple(v.T)]).mean():.0f} % in the brainstem")

        # --- Meshes -----------------------------------------------------------------------------
        sizes = mesh_labels(vbrain, volume, ids, affine, TRACT_TRIANGLES, "tracts", tmp, out / "meshes")
        sizes.update(mesh_labels(vbrain, part, parts, affine, BRAINSTEM_TRIANGLES, "brainstem", tmp, out / "meshes"))

    # --- Entries, fit, report --------------------------------------------------------------------
    made = entries(ids, meta, parts)
    (out / "entries.json").write_text(json.dumps(made, indent=2, ensure_ascii=False) + "\n")
    (out / "fit.json").write_text(json.dumps({
        "registration_dice": {"jhu_white_matter_via_fsl_mni152": dice_fsl,
                              "jhu189_above_its_lowest_slice": dice_189},
        "tracts": fit, "brainstem": {"voxels": int(brainstem.sum()), "labelled_by_jhu189": seeded,
                                      "parts": {p: int((part == i).sum()) for i, p in enumerate(parts, 1)},
                                      "junctions_median_plane": junctions}},
        indent=2) + "\n")
    say("")
    say(f"{'mesh':40s} {'triangles':>9s} {'bytes':>8s}")
    for oid, (tris, size) in sizes.items():
        say(f"{oid:40s} {tris:9d} {size:8d}")
    total = sum(s for _, s in sizes.values())
    old = (HERE / "meshes" / "brainstem.vbo").stat().st_size
    say(f"{'total':40s} {sum(t for t, _ in sizes.values()):9d} {total:8d}  "
        f"(tracts {sum(s for k, (_, s) in sizes.items() if k not in parts)}, brainstem parts "
        f"{sum(s for k, (_, s) in sizes.items() if k in parts)}; less the old brainstem.vbo {old}: "
        f"{total - old} bytes added)")
    say(f"registration Dice: FSL MNI152 {dice_fsl}, jhu189 {dice_189}")
    say(f"took {time.time() - t0:.0f} s")
    (out / "report.txt").write_text("\n".join(report) + "\n")


if __name__ == "__main__":
    main()
