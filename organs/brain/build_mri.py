#!/usr/bin/env python3
"""Brings the ICBM 2009a MNI152 T1 template into the default set's space (organs/brain/mri/).

    python3 organs/brain/build_mri.py            # from the repository root, after build_brain.py

The set's meshes come from FreeSurfer's fsaverage and aparc+aseg; the template is a different
average a few millimetres away. So the template is registered to the set itself (all millimetres,
RAS, on the template's own 1 mm grid):
 1. The set's white matter (cerebral: meshes/white_matter_{l,r}.vbo; and the brainstem and the
    cerebellar white matter, which the template's map also holds) is voxelised by ray parity
    along x through every voxel centre (closed solids).
 2. The template's white-matter probability map is registered to that mask with dipy: a
    centre-of-mass start, an affine fit (mutual information), then a symmetric diffeomorphic
    warp (SyN, cross-correlation). The same transform carries the T1 and the map.
 3. Written, cropped to the brain's bounds plus a margin: mri/t1.nii.gz (uint8) and
    mri/white_matter.nii.gz (its mask, probability > 0.5, as 0 or 255, uint8). The Dice overlap between the set's
    cerebral white matter and the map (> 0.5) outside the set's brainstem and cerebellum is
    printed; vbrain's tests recompute it from these files.

Needs: pip download --no-deps nilearn==0.14.1 (its wheel is only read for the template files:
set NILEARN_WHEEL to the .whl, or have nilearn installed); pip install nibabel numpy scipy
dipy==1.12.1.
"""
import gzip
import os
import sys
import zipfile
from pathlib import Path

import nibabel as nib
import numpy as np

from vbo import read_vbo

HERE = Path(__file__).resolve().parent
TEMPLATE = "nilearn/datasets/data/mni_icbm152_{}_tal_nlin_sym_09a_converted.nii.gz"
MARGIN_MM = 12


def template(kind):
    """A template volume from the nilearn wheel (NILEARN_WHEEL) or an installed nilearn."""
    wheel = os.environ.get("NILEARN_WHEEL")
    if wheel:
        with zipfile.ZipFile(wheel) as z:
            data = z.read(TEMPLATE.format(kind))
        return nib.Nifti1Image.from_bytes(gzip.decompress(data))
    import importlib.util
    spec = importlib.util.find_spec("nilearn")
    if spec is None:
        sys.exit("set NILEARN_WHEEL to nilearn-0.14.1-py3-none-any.whl (pip download --no-deps nilearn==0.14.1)")
    return nib.load(Path(spec.origin).parent.parent / TEMPLATE.format(kind))


def voxelise(v, f, shape, affine):
    """Voxels whose centres lie inside a closed mesh: the parity of crossings along +x of each
    row of centres (axis-aligned grid). A centre counts as inside when an odd number of
    triangles cross its row at a smaller x. Same rule as vbrain's `mri::organ_mask`."""
    inv = np.linalg.inv(affine)
    p = v @ inv[:3, :3].T + inv[:3, 3]  # voxel coordinates
    tri = p[f]  # (n, 3, 3)
    ymin = np.ceil(tri[:, :, 1].min(1)).astype(int)
    ymax = np.floor(tri[:, :, 1].max(1)).astype(int)
    zmin = np.ceil(tri[:, :, 2].min(1)).astype(int)
    zmax = np.floor(tri[:, :, 2].max(1)).astype(int)
    toggles = np.zeros((shape[0] + 1, shape[1], shape[2]), np.int32)
    span = max(int((ymax - ymin).max()), int((zmax - zmin).max())) + 1
    for dy in range(span):
        for dz in range(span):
            y = ymin + dy
            z = zmin + dz
            keep = (y <= ymax) & (z <= zmax)
            t, y, z = tri[keep], y[keep], z[keep]
            a, b, c = t[:, 0], t[:, 1], t[:, 2]
            # Barycentric coordinates of (y, z) in the triangle's (y, z) projection.
            d = (b[:, 1] - a[:, 1]) * (c[:, 2] - a[:, 2]) - (c[:, 1] - a[:, 1]) * (b[:, 2] - a[:, 2])
            ok = np.abs(d) > 1e-12
            t, y, z, a, b, c, d = t[ok], y[ok], z[ok], a[ok], b[ok], c[ok], d[ok]
            w1 = ((y - a[:, 1]) * (c[:, 2] - a[:, 2]) - (c[:, 1] - a[:, 1]) * (z - a[:, 2])) / d
            w2 = ((b[:, 1] - a[:, 1]) * (z - a[:, 2]) - (y - a[:, 1]) * (b[:, 2] - a[:, 2])) / d
            w0 = 1 - w1 - w2
            hit = (w0 >= 0) & (w1 >= 0) & (w2 > 0) | (w0 > 0) & (w1 > 0) & (w2 >= 0)
            x = (w0 * a[:, 0] + w1 * b[:, 0] + w2 * c[:, 0])[hit]
            y, z = y[hit], z[hit]
            inside = (y >= 0) & (y < shape[1]) & (z >= 0) & (z < shape[2])
            i = np.clip(np.ceil(x[inside]).astype(int), 0, shape[0])
            np.add.at(toggles, (i, y[inside], z[inside]), 1)
    return (np.cumsum(toggles, 0)[:-1] % 2).astype(bool)


SOURCE = {
    "name": "ICBM 2009a nonlinear symmetric MNI152 T1 template and white-matter map, registered to this set "
            "(nilearn 0.14.1, nilearn/datasets/data/mni_icbm152_{t1,wm}_tal_nlin_sym_09a_converted.nii.gz)",
    "url": "https://www.bic.mni.mcgill.ca/ServicesAtlases/ICBM152NLin2009",
    "licence": "Copyright (C) 1993-2009 Louis Collins, McConnell Brain Imaging Centre, Montreal Neurological "
               "Institute, McGill University: use, copy, modify and distribute freely with this notice "
               "(mri/LICENSE.txt)",
    "attribution": "Fonov VS, Evans AC, McKinstry RC, Almli CR, Collins DL (2009) NeuroImage 47:S102; "
                   "Fonov V et al. (2011) NeuroImage 54:313-327; Collins DL et al. (1999) "
                   "Animal+Insect: improved cortical structure segmentation. IPMI 1613:210-223",
}


def record_in_manifest():
    """Names the MRI in organset.json and lists its source (the other fields kept as they are)."""
    import json
    path = HERE / "organset.json"
    manifest = json.loads(path.read_text())
    manifest["sources"] = [s for s in manifest["sources"] if not s["name"].startswith("ICBM 2009a")] + [SOURCE]
    manifest["mri"] = "mri/t1.nii.gz"
    path.write_text(json.dumps(manifest, indent=2, ensure_ascii=False) + "\n")


CEREBRAL_WHITE_MATTER = ["white_matter_l", "white_matter_r"]
OTHER_WHITE_MATTER = ["brainstem", "cerebellum_white_matter_l", "cerebellum_white_matter_r"]
# Not the cerebrum: the map's white matter there is not the cerebral white matter's.
NOT_CEREBRUM = ["brainstem", "cerebellum_l", "cerebellum_r", "cerebellum_white_matter_l", "cerebellum_white_matter_r"]


def dice_in_cerebrum(cerebral, wm_map, outside):
    """Dice overlap of the set's cerebral white matter and the map (> 0.5) outside the set's
    brainstem and cerebellum (the same as vbrain's test)."""
    theirs = (wm_map > 0.5) & ~outside
    return 2 * np.logical_and(cerebral, theirs).sum() / (cerebral.sum() + theirs.sum())


def main():
    from dipy.align import affine_registration
    from dipy.align.imaffine import AffineMap
    from dipy.align.imwarp import SymmetricDiffeomorphicRegistration
    from dipy.align.metrics import CCMetric
    from scipy import ndimage

    t1, wm = template("t1"), template("wm")
    shape, affine = t1.shape, t1.affine

    def organs(ids):
        mask = np.zeros(shape, bool)
        for oid in ids:
            v, f = read_vbo(HERE / "meshes" / f"{oid}.vbo")
            mask |= voxelise(v, f, shape, affine)
        return mask

    cerebral = organs(CEREBRAL_WHITE_MATTER)
    outside = organs(NOT_CEREBRUM)
    wm_map = wm.get_fdata() / 255.0
    print(f"set cerebral white matter: {cerebral.sum()} voxels; Dice before registration: "
          f"{dice_in_cerebrum(cerebral, wm_map, outside):.3f}")

    # The template's white-matter map holds the brainstem's and cerebellum's white matter too: the
    # target holds them as well, so the warp has something to match there.
    static = ndimage.gaussian_filter((cerebral | organs(OTHER_WHITE_MATTER)).astype(np.float64), 1.0)
    _, fit = affine_registration(wm_map, static, moving_affine=affine, static_affine=affine, nbins=32,
                                 pipeline=["center_of_mass", "translation", "rigid", "affine"],
                                 level_iters=[1000, 100, 10], sigmas=[3.0, 1.0, 0.0], factors=[4, 2, 1])
    affine_map = AffineMap(fit, domain_grid_shape=shape, domain_grid2world=affine,
                           codomain_grid_shape=shape, codomain_grid2world=affine)
    print(f"Dice after the affine fit: {dice_in_cerebrum(cerebral, affine_map.transform(wm_map), outside):.3f}")
    syn = SymmetricDiffeomorphicRegistration(CCMetric(3, sigma_diff=1.0, radius=3), level_iters=[60, 40, 20])
    mapping = syn.optimize(static, wm_map, static_grid2world=affine, moving_grid2world=affine, prealign=fit)
    wm_reg = mapping.transform(wm_map)
    t1_reg = mapping.transform(t1.get_fdata().astype(np.float64))
    print(f"Dice after the nonlinear warp: {dice_in_cerebrum(cerebral, wm_reg, outside):.3f} (target >= 0.80)")

    # Crop to the brain's meshes' bounds plus a margin (the template has no skull or scalp).
    lo, hi = np.full(3, np.inf), np.full(3, -np.inf)
    for path in (HERE / "meshes").glob("*.vbo"):
        if any(part in path.name for part in ("solid", "occluder", "scalp", "skull")):
            continue
        v, _ = read_vbo(path)
        lo, hi = np.minimum(lo, v.min(0)), np.maximum(hi, v.max(0))
    inv = np.linalg.inv(affine)
    a = np.floor(inv[:3, :3] @ (lo - MARGIN_MM) + inv[:3, 3]).astype(int).clip(0, np.array(shape) - 1)
    b = np.ceil(inv[:3, :3] @ (hi + MARGIN_MM) + inv[:3, 3]).astype(int).clip(0, np.array(shape) - 1) + 1
    crop = tuple(slice(a[i], b[i]) for i in range(3))
    out_affine = affine.copy()
    out_affine[:3, 3] = affine[:3, :3] @ a + affine[:3, 3]
    out = HERE / "mri"
    out.mkdir(exist_ok=True)
    # The white-matter map is kept as its mask (> 0.5): all the tests read of it, in a tenth of the bytes.
    for name, data in (("t1", t1_reg), ("white_matter", (wm_reg > 0.5) * 255)):
        img = nib.Nifti1Image(np.clip(np.rint(data[crop]), 0, 255).astype(np.uint8), out_affine)
        img.header.set_xyzt_units("mm")
        img.header["descrip"] = b"ICBM 2009a sym, registered to vbrain's set"
        img.set_qform(out_affine, 1)
        img.set_sform(out_affine, 1)
        nib.save(img, out / f"{name}.nii.gz")
        print(f"wrote mri/{name}.nii.gz: {img.shape}, {(out / f'{name}.nii.gz').stat().st_size} bytes")
    record_in_manifest()


if __name__ == "__main__":
    main()
