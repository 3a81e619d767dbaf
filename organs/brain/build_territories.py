#!/usr/bin/env python3
"""Brings the Liu et al. 2023 arterial territory atlas into the default set's space (territories/).

    python3 organs/brain/build_territories.py     # from the repository root, after build_mri.py

The atlas is drawn on FSL's MNI152 (NLin6Asym) template, a few millimetres from the set's fsaverage
surfaces and aparc+aseg labels. So it is registered to the set itself, on the grid of the set's MRI
(mri/t1.nii.gz: 1 mm, RAS, already in the set's space):
 1. The set's brain (every organ but the scalp and skull) is voxelised by ray parity.
 2. The atlas's brain (its labels > 0) is registered to that mask with dipy: a centre-of-mass start,
    an affine fit (mutual information), then a symmetric diffeomorphic warp (SyN,
    cross-correlation). The labels follow the same transform by nearest neighbour.
 3. Where the set's brain (grown by GROW_MM) has no label after the warp, the nearest label fills
    it, so every vertex of every brain organ lies in a territory. The share of cortex vertices that
    had a label before this fill is printed, with the Dice overlap of the two brains.
 4. Sides come from each label's position (x < midline: left), not from the atlas's tables: one of
    them swaps the posterior cerebral arteries.
 5. Written as territories/arterial.nii.gz (uint8, this set's territory ids, 0 = none), which
    `territories.json` names and describes (artery k from 0: id 2k + 1 left, 2k + 2 right); cropped like the MRI.

Needs: pip download --no-deps --no-binary :all: panpipelines==1.1.10 (set PANPIPELINES_SDIST to
the .tar.gz; only its deployment/atlas/Arterial/ files are read, nothing else is copied); pip
install nibabel numpy scipy dipy==1.12.1.
"""
import gzip
import os
import sys
import tarfile
from pathlib import Path

import nibabel as nib
import numpy as np

from build_mri import voxelise
from vbo import read_vbo

HERE = Path(__file__).resolve().parent
ATLAS = "panpipelines-1.1.10/deployment/atlas/Arterial/"
VOLUME = ATLAS + "MNI152NLin6Asym/tpl-MNI152NLin6Asym_res-01_atlas-Arterial_dseg.nii.gz"
TABLE = ATLAS + "res-01_atlas-Arterial_dseg.tsv"
GROW_MM = 6
# The atlas's label names without their side letter -> this set's territory keys (territories.json).
KEYS = {
    "ACA": "aca", "MLS": "medial_lenticulostriate", "LLS": "lateral_lenticulostriate",
    "MCAF": "mca_frontal", "MCAP": "mca_parietal", "MCAT": "mca_temporal", "MCAO": "mca_occipital",
    "MCAI": "mca_insular", "PCAT": "pca_temporal", "PCAO": "pca_occipital",
    "PCTP": "posterior_choroidal_thalamoperforating", "ACTP": "anterior_choroidal_thalamoperforating",
    "B": "basilar", "SC": "sca", "IC": "pica", "LV": "lateral_ventricle",
}


def atlas():
    """The atlas's label volume and its label names (index -> name) from the panpipelines sdist."""
    sdist = os.environ.get("PANPIPELINES_SDIST")
    if not sdist:
        sys.exit("set PANPIPELINES_SDIST to panpipelines-1.1.10.tar.gz "
                 "(pip download --no-deps --no-binary :all: panpipelines==1.1.10)")
    with tarfile.open(sdist) as tar:
        volume = nib.Nifti1Image.from_bytes(gzip.decompress(tar.extractfile(VOLUME).read()))
        rows = tar.extractfile(TABLE).read().decode().split("\n")[1:]
    names = {int(r.split()[0]): r.split()[1] for r in rows if r.strip()}
    return volume, names


def main():
    import json
    from dipy.align import affine_registration
    from dipy.align.imaffine import AffineMap
    from dipy.align.imwarp import SymmetricDiffeomorphicRegistration
    from dipy.align.metrics import CCMetric
    from scipy import ndimage

    grid = nib.load(HERE / "mri" / "t1.nii.gz")
    shape, affine = grid.shape, grid.affine
    manifest = json.loads((HERE / "organset.json").read_text())
    brain_organs = [o for o in manifest["organs"] if o["group"] != "Head"]
    brain = np.zeros(shape, bool)
    for o in brain_organs:
        v, f = read_vbo(HERE / o["mesh"])
        brain |= voxelise(v, f, shape, affine)
    src, names = atlas()
    labels = np.asarray(src.dataobj).astype(np.int32)
    moving = (labels > 0).astype(np.float64)

    def dice(a, b):
        return 2 * np.logical_and(a, b).sum() / (a.sum() + b.sum())

    before = AffineMap(np.eye(4), domain_grid_shape=shape, domain_grid2world=affine,
                       codomain_grid_shape=labels.shape, codomain_grid2world=src.affine)
    print(f"Dice of the two brains before registration: {dice(brain, before.transform(moving) > 0.5):.3f}")
    static = ndimage.gaussian_filter(brain.astype(np.float64), 1.0)
    _, fit = affine_registration(ndimage.gaussian_filter(moving, 1.0), static, moving_affine=src.affine,
                                 static_affine=affine, nbins=32,
                                 pipeline=["center_of_mass", "translation", "rigid", "affine"],
                                 level_iters=[1000, 100, 10], sigmas=[3.0, 1.0, 0.0], factors=[4, 2, 1])
    affine_map = AffineMap(fit, domain_grid_shape=shape, domain_grid2world=affine,
                           codomain_grid_shape=labels.shape, codomain_grid2world=src.affine)
    print(f"Dice after the affine fit: {dice(brain, affine_map.transform(moving) > 0.5):.3f}")
    syn = SymmetricDiffeomorphicRegistration(CCMetric(3, sigma_diff=1.0, radius=3), level_iters=[60, 40, 20])
    mapping = syn.optimize(static, ndimage.gaussian_filter(moving, 1.0), static_grid2world=affine,
                           moving_grid2world=src.affine, prealign=fit)
    warped = mapping.transform(labels.astype(np.float64), interpolation="nearest").astype(np.int32)
    print(f"Dice after the nonlinear warp: {dice(brain, warped > 0):.3f}")

    # Territory ids of this set: artery k of territories.json (from 0) is 2k + 1 on the left and
    # 2k + 2 on the right.
    arteries = [a["key"] for a in json.loads((HERE / "territories.json").read_text())["arteries"]]
    ids = {(key, side): 2 * k + 1 + (side == "right") for k, key in enumerate(arteries) for side in ("left", "right")}
    midline = nib.affines.apply_affine(affine, np.argwhere(brain).mean(0))[0]
    out = np.zeros(shape, np.uint8)
    for index, name in names.items():
        voxels = warped == index
        if not voxels.any():
            sys.exit(f"atlas label {index} ({name}) is lost in the warp")
        x = nib.affines.apply_affine(affine, np.argwhere(voxels).mean(0))[0]
        side = "left" if x < midline else "right"
        if name[-1] != ("L" if side == "left" else "R"):
            print(f"  label {index} {name}: its position (x = {x:.1f} mm) says {side}")
        out[voxels] = ids[(KEYS[name[:-1]], side)]

    # Cortex vertices with a label before the fill.
    cortex = [o for o in brain_organs if o["group"].startswith("Cerebrum/") and "white_matter" not in o["id"]
              and "Cerebrum/Deep" not in o["group"]]
    inv = np.linalg.inv(affine)
    hit = total = 0
    for o in cortex:
        v, _ = read_vbo(HERE / o["mesh"])
        ijk = np.rint(v @ inv[:3, :3].T + inv[:3, 3]).astype(int).clip(0, np.array(shape) - 1)
        hit += (out[tuple(ijk.T)] > 0).sum()
        total += len(v)
    print(f"cortex vertices in a territory before the fill: {100 * hit / total:.1f} % of {total}")

    reach = ndimage.binary_dilation(brain, iterations=GROW_MM)
    _, nearest = ndimage.distance_transform_edt(out == 0, return_indices=True)
    filled = out[tuple(nearest)]
    out = np.where(reach, np.where(out > 0, out, filled), 0).astype(np.uint8)

    img = nib.Nifti1Image(out, affine)
    img.header.set_xyzt_units("mm")
    img.header["descrip"] = b"Liu 2023 arterial atlas, registered to vbrain's set"
    img.set_qform(affine, 1)
    img.set_sform(affine, 1)
    (HERE / "territories").mkdir(exist_ok=True)
    nib.save(img, HERE / "territories" / "arterial.nii.gz")
    print(f"wrote territories/arterial.nii.gz: {out.shape}, "
          f"{(HERE / 'territories' / 'arterial.nii.gz').stat().st_size} bytes")


if __name__ == "__main__":
    main()
