#!/usr/bin/env python3
"""White-matter tracts (JHU ICBM-DTI-81) and the brainstem split into midbrain, pons and medulla
(JHU "jhu189" parcellation), registered to the default set and meshed, into a staging folder.

    MRICRON_DEB=mricron-data_1.2.20211006+dfsg-4_all.deb \
    NILEARN_WHEEL=nilearn-0.14.1-py3-none-any.whl \
    VBRAIN=target/release/vbrain \
    python3 organs/brain/build_tracts.py [OUT]              # OUT defaults to /tmp/tracts-out

Writes OUT/meshes/<id>.vbo, OUT/entries.json (organ entries in organset.json's format), OUT/fit.json
and OUT/report.txt; nothing in the repository is changed. About 10 minutes on one core (two
registrations). Then

    python3 organs/brain/build_tracts.py --merge [OUT]

brings them into the set (merge()): the meshes into meshes/, the brainstem's entry replaced by its
three parts (in the solids too), the tracts' entries after the set's organs, the source recorded;
then `vbrain stand-ins` and `vbrain occluders` as README.md's rebuilding says.

Data: the Debian package mricron-data 1.2.20211006+dfsg-4 (apt-get download mricron-data), files
usr/share/mricron/templates/JHU-WhiteMatter-labels-1mm.nii.gz (+ .nii.txt, 48 labels) and
jhu189.nii.gz (189 labels, no names: the brainstem's labels are told by their positions, JHU189_*
below); the package is extracted into a temporary folder. The ICBM 2009a T1 and white-matter map
come from nilearn's wheel as in build_mri.py (NILEARN_WHEEL, or nilearn installed).

 1. The set's organs are voxelised on the grid of the set's MRI (mri/t1.nii.gz, 1 mm, RAS) by ray
    parity (build_mri.voxelise).
 2. JHU-WhiteMatter-labels-1mm is drawn on FSL's MNI152 1 mm grid. mricron-data's copy has a RAS
    header (x = i - 91) over FSL's radiological voxel order (x = 90 - i): with that header its "_R"
    labels lie at x < 0 and its tracts overlap the lateral ventricles of an MNI152 brain more; so
    its voxels are read with FSL's own affine (FSL_MNI152_1MM), which puts every label on the side
    its name says (checked after the warp).
 3. Registration of the tracts: the set's MRI is the ICBM 2009a T1 warped onto the set by
    build_mri.py, so the template T1 is registered back onto it (affine by mutual information,
    then SyN by cross-correlation of the two T1s, build_territories.py's settings), and the JHU
    labels follow by nearest neighbour, FSL's MNI152 world being taken as the 2009a template's.
    (Registering the MNI152NLin6Asym brain outline to the set's brain outline, as
    build_territories.py does, aligned the brains' surfaces but left the deep white matter several
    millimetres off: e.g. 34 % of the right posterior limb of the internal capsule fell in the
    white matter, 59 % in the thalamus; this way 91 %.)
 4. jhu189 (JHU-MNI space, its own grid, which stops at z = -50 mm) is registered like
    build_territories.py's atlas: its brain (labels > 0) to the set's brain above that plane.
 5. Fit: the share of each tract's voxels inside the set's cerebral white matter (white_matter_l/_r,
    corpus_callosum) or brainstem, and inside its allowed tissue: that, plus the cerebellar white
    matter for the cerebellar peduncles, the ventral diencephalon for the cerebral peduncle (it
    holds the crus's upper end in FreeSurfer's labels), and, for the fornix, brain voxels in no
    organ (the set has no organ under the callosum between the ventricles). Every tract is clipped
    to its allowed tissue (pieces under MIN_PIECE voxels cut off by the clip are dropped), meshed by
    `vbrain import --seamless` (neighbouring tracts share their boundaries), and the meshes are
    voxelised again to measure their own fit.
 6. Brainstem: the set's brainstem mesh is voxelised; each voxel takes the part (midbrain, pons,
    medulla) of the nearest registered jhu189 brainstem label of an unambiguous part (the
    cerebellar peduncles' and the fourth ventricle's labels, which span levels, are left out;
    labels more than 2 mm outside the brainstem too); the three part masks are smoothed (Gaussian,
    SMOOTH_PART_MM), each voxel takes the largest, stray pieces join the part they touch most, and
    below jhu189's field of view everything is medulla. The parts fill the brainstem's voxels
    exactly and are meshed together with --seamless. The junctions' levels in the median plane
    (pontomesencephalic and pontomedullary, at the ventral surface and at the back) are reported.

Needs: pip install nibabel numpy scipy dipy==1.12.1; pip download --no-deps nilearn==0.14.1;
dpkg-deb; vbrain (VBRAIN, default target/release/vbrain). TRACTS_CACHE=<folder> keeps the
registered labels between runs (development only).
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

from build_mri import CEREBRAL_WHITE_MATTER, NOT_CEREBRUM, dice_in_cerebrum, template, voxelise
from vbo import read_vbo

HERE = Path(__file__).resolve().parent
TEMPLATES = "usr/share/mricron/templates/"
JHU = TEMPLATES + "JHU-WhiteMatter-labels-1mm.nii.gz"
JHU189 = TEMPLATES + "jhu189.nii.gz"
# FSL's MNI152 1 mm grid (radiological voxel order: x = 90 - i), and the header mricron-data puts on
# the same voxels (x = i - 91), which mirrors them.
FSL_MNI152_1MM = np.array([[-1, 0, 0, 90], [0, 1, 0, -126], [0, 0, 1, -72], [0, 0, 0, 1]], float)
MRICRON_JHU_HEADER = np.array([[1, 0, 0, -91], [0, 1, 0, -126], [0, 0, 1, -72], [0, 0, 0, 1]], float)
SMOOTHING = 10          # Taubin iterations of vbrain import
TRACT_TRIANGLES = 11000  # budget of the whole tract set (vbrain import spreads it over the organs)
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


def register_t1(t1, grid, brain, outside, cerebral_wm):
    """The ICBM 2009a T1 template onto the set's MRI (build_mri.py's output, the same template
    warped onto the set): affine (mutual information) then SyN (cross-correlation) of the two T1s.
    Dice: the set's brain and the template's brain (T1 > 0), and build_mri's measure (the set's
    cerebral white matter and the template's white-matter map > 0.5, outside brainstem and cerebellum)."""
    from dipy.align import affine_registration
    from dipy.align.imaffine import AffineMap
    from dipy.align.imwarp import SymmetricDiffeomorphicRegistration
    from dipy.align.metrics import CCMetric

    shape, affine = grid.shape, grid.affine
    moving = t1.get_fdata() / 255.0
    static = grid.get_fdata() / 255.0
    wm_map = template("wm").get_fdata() / 255.0
    identity = AffineMap(np.eye(4), domain_grid_shape=shape, domain_grid2world=affine,
                         codomain_grid_shape=moving.shape, codomain_grid2world=t1.affine)
    d = {"brain_before": dice(brain, identity.transform(moving) > 0.05),
         "cerebral_white_matter_before": dice_in_cerebrum(cerebral_wm, identity.transform(wm_map), outside)}
    _, fit = affine_registration(moving, static, moving_affine=t1.affine, static_affine=affine, nbins=32,
                                 pipeline=["center_of_mass", "translation", "rigid", "affine"],
                                 level_iters=[1000, 100, 10], sigmas=[3.0, 1.0, 0.0], factors=[4, 2, 1])
    syn = SymmetricDiffeomorphicRegistration(CCMetric(3, sigma_diff=1.0, radius=3), level_iters=[60, 40, 20])
    mapping = syn.optimize(static, moving, static_grid2world=affine, moving_grid2world=t1.affine, prealign=fit)
    d["brain_after"] = dice(brain, mapping.transform(moving) > 0.05)
    d["cerebral_white_matter_after"] = dice_in_cerebrum(cerebral_wm, mapping.transform(wm_map), outside)
    print("ICBM 2009a T1 -> set MRI: Dice of the brains {brain_before:.3f} -> {brain_after:.3f}, of the cerebral "
          "white matter {cerebral_white_matter_before:.3f} -> {cerebral_white_matter_after:.3f}".format(**d))
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


# Teaching text: stem -> (name, Latin (Terminologia Anatomica where it has one), synonyms, colour, info).
# Colours follow the diffusion-imaging convention loosely: projection blue, commissural red,
# association green; limbic orange, brainstem and cerebellar peduncles violet and ochre.
TEXT = {
    "corticospinal_tract": (
        "corticospinal tract", "Tractus corticospinalis",
        ["pyramidal tract", "CST", "tractus pyramidalis", "fibrae corticospinales", "corticospinal fibres"],
        "#2f62d0",
        "The main descending pathway for voluntary movement, shown here in its brainstem segment. Its axons arise "
        "from the primary motor cortex of the precentral gyrus, the premotor and supplementary motor areas and the "
        "parietal cortex, descend through the corona radiata, the posterior limb of the internal capsule and the "
        "middle of the cerebral peduncle, are split into bundles among the pontine nuclei of the basis pontis and "
        "gather again as the pyramid of the medulla. At the cervicomedullary junction about 85-90 % of its fibres "
        "cross in the pyramidal decussation to form the lateral corticospinal tract of the opposite half of the "
        "spinal cord, the rest descending uncrossed as the anterior corticospinal tract; it drives spinal motor "
        "neurons and interneurons, above all for skilled, fractionated movements of the hand. A lesion above the "
        "decussation (cortex, internal capsule, brainstem) causes weakness of the contralateral body with upper motor "
        "neuron signs (spasticity, brisk reflexes, an extensor plantar response), usually after an initial flaccid "
        "phase, whereas a lesion of the lateral corticospinal tract in the spinal cord weakens the same side below "
        "it. In the JHU atlas this label covers the pons and medulla; the tract's course above is labelled as the "
        "cerebral peduncle and the internal capsule."),
    "cerebral_peduncle": (
        "cerebral peduncle (crus cerebri)", "Crus cerebri",
        ["crus cerebri", "cerebral crus", "basis pedunculi", "pes pedunculi", "cerebral peduncle"],
        "#4d7fe0",
        "The massive band of descending fibres on the front of the midbrain: the two crura diverge upwards from "
        "the pons, bounding the interpeduncular fossa, and the substantia nigra separates each from the tegmentum "
        "behind it (in Terminologia Anatomica the cerebral peduncle is the whole half of the midbrain in front of "
        "the tectum; this label is its crus). It carries the fibres that have come down through the internal "
        "capsule: corticospinal and corticonuclear (corticobulbar) fibres in its middle three-fifths, frontopontine "
        "fibres medially and parieto-temporo-occipitopontine fibres laterally. A ventral midbrain infarct "
        "(paramedian branches of the posterior cerebral or basilar artery) causes Weber syndrome: an ipsilateral "
        "oculomotor nerve palsy, because the third nerve's fascicles cross the medial crus to the interpeduncular "
        "fossa, with contralateral hemiparesis including the lower face. In transtentorial herniation the opposite "
        "crus can be pressed against the tentorial edge (Kernohan notch), giving a hemiparesis on the side of the "
        "mass, a false localising sign. In this set the label straddles the brainstem and the ventral diencephalon, "
        "which in FreeSurfer's labels holds the upper midbrain."),
    "anterior_limb_internal_capsule": (
        "anterior limb of the internal capsule", "Crus anterius capsulae internae",
        ["ALIC", "anterior limb", "internal capsule", "anterior thalamic radiation"],
        "#4aa3df",
        "The part of the internal capsule between the head of the caudate nucleus medially and the lentiform "
        "nucleus (putamen and globus pallidus) laterally, in front of the genu; grey bridges joining caudate and "
        "putamen cross it and give the corpus striatum its striped look. It carries the anterior thalamic "
        "radiation, reciprocal fibres between the anterior and mediodorsal thalamic nuclei and the prefrontal and "
        "cingulate cortex, and frontopontine fibres on their way to the cerebral peduncle. It is supplied by the "
        "medial and lateral lenticulostriate arteries and the recurrent artery of Heubner. Its lesions cause little "
        "weakness but, like those of the caudate head, can cause abulia and executive and behavioural change, and "
        "it is a target of capsulotomy and deep brain stimulation for refractory obsessive-compulsive disorder and "
        "depression."),
    "posterior_limb_internal_capsule": (
        "posterior limb of the internal capsule", "Crus posterius capsulae internae",
        ["PLIC", "posterior limb", "internal capsule"],
        "#2a4fb0",
        "The part of the internal capsule between the thalamus medially and the lentiform nucleus laterally, "
        "behind the genu. It carries the corticospinal fibres for the arm and leg (concentrated in its posterior "
        "half), corticopontine fibres and the somatosensory thalamic radiation from the ventral posterior nuclei "
        "to the postcentral gyrus; corticonuclear fibres for the face run near the genu, which has no label of its own "
        "in the JHU atlas. It is supplied by the lateral lenticulostriate branches of the "
        "middle cerebral artery and, in its lower part, by the anterior choroidal artery. Because its fibres are "
        "packed so closely, a small lacunar infarct here gives a pure motor stroke (equal weakness of the "
        "contralateral face, arm and leg without sensory, visual or cortical signs), larger lesions add "
        "contralateral hemisensory loss, and hypertensive putaminal or thalamic haemorrhages often damage it."),
    "posterior_thalamic_radiation": (
        "posterior thalamic radiation (with optic radiation)", "Radiatio posterior thalami",
        ["optic radiation", "radiatio optica", "geniculocalcarine tract", "geniculostriate pathway", "PTR",
         "Meyer's loop"],
        "#7566e0",
        "Thalamocortical and corticothalamic fibres that leave the back of the thalamus, chiefly the pulvinar and "
        "the lateral geniculate body, through the retrolenticular part of the internal capsule and sweep back "
        "beside the atrium and occipital horn of the lateral ventricle to the parietal and occipital lobes. Its "
        "largest component is the optic radiation (geniculocalcarine tract) from the lateral geniculate body to "
        "the primary visual cortex on the banks of the calcarine sulcus: fibres for the lower visual field run "
        "through the parietal white matter, while those for the upper field first loop forwards around the temporal "
        "horn (Meyer's loop). A lesion of the whole radiation causes a contralateral homonymous hemianopia; a "
        "temporal lesion, for example after anterior temporal lobectomy, damages Meyer's loop and gives a "
        "contralateral superior quadrantanopia ('pie in the sky'), and a parietal lesion an inferior "
        "quadrantanopia. In the JHU atlas this label is the radiation's part beside the occipital horn; Meyer's "
        "loop lies largely in its sagittal stratum label, which is not shown."),
    "corpus_callosum_genu": (
        "genu of the corpus callosum", "Genu corporis callosi",
        ["genu", "forceps minor", "forceps frontalis", "anterior corpus callosum", "CC genu"],
        "#d9463b",
        "The anterior bend of the corpus callosum in front of the septum pellucidum, continuous below with the "
        "thin rostrum and behind with the body. Its fibres connect the prefrontal and orbitofrontal cortex of the "
        "two hemispheres, fanning forwards on each side as the forceps minor (forceps frontalis), and it is "
        "supplied by branches of the anterior cerebral artery. Lesions of the genu alone are seldom noticed "
        "clinically, but it is a common site of multiple sclerosis plaques, of the 'butterfly' spread of "
        "glioblastoma and lymphoma across the midline, and of the necrosis of Marchiafava-Bignami disease. The JHU "
        "label overlaps the set's corpus callosum organ, which holds only the callosum's midline part; here the "
        "label reaches out into each hemisphere."),
    "corpus_callosum_body": (
        "body of the corpus callosum", "Truncus corporis callosi",
        ["trunk of the corpus callosum", "callosal body", "CC body"],
        "#e36a55",
        "The long arched middle part of the corpus callosum between genu and splenium, forming the roof of the "
        "lateral ventricles, with the septum pellucidum and the body of the fornix hanging beneath it and the "
        "pericallosal arteries (anterior cerebral artery) running above it. Its fibres connect the premotor, "
        "motor, supplementary motor and somatosensory cortex and the adjacent parietal cortex of the two "
        "hemispheres. Lesions or surgical section of its anterior part disconnect the right hemisphere from the "
        "left hemisphere's language and praxis areas, giving apraxia, agraphia and tactile anomia of the left hand "
        "and sometimes an alien-hand syndrome; anterior callosotomy for drop attacks divides it on purpose. Ovoid "
        "multiple sclerosis plaques on its undersurface, perpendicular to the ventricles ('Dawson's fingers'), are "
        "typical. The JHU label overlaps the set's corpus callosum organ (the callosum's midline part) and reaches "
        "out into each hemisphere."),
    "corpus_callosum_splenium": (
        "splenium of the corpus callosum", "Splenium corporis callosi",
        ["splenium", "forceps major", "forceps occipitalis", "posterior corpus callosum", "CC splenium"],
        "#b83232",
        "The thick rounded posterior end of the corpus callosum, overhanging the pineal gland and the tectum of "
        "the midbrain, with the great cerebral vein (of Galen) passing beneath it. Its fibres connect the "
        "occipital (visual) cortex and the posterior parietal and temporal cortex of the two hemispheres, curving "
        "back on each side as the forceps major (forceps occipitalis); it is supplied mainly by the posterior "
        "pericallosal branch of the posterior cerebral artery. A left posterior cerebral artery infarct that "
        "destroys the left visual cortex and the splenium causes alexia without agraphia (pure alexia) with a right "
        "homonymous hemianopia: words seen by the intact right occipital lobe can no longer reach the left "
        "hemisphere's language areas, yet the patient still writes. The splenium is also the typical site of "
        "transient cytotoxic lesions in seizures, antiepileptic drug withdrawal, infections and metabolic "
        "disorders. The JHU label overlaps the set's corpus callosum organ and reaches out into each hemisphere."),
    "cingulum": (
        "cingulum", "Cingulum",
        ["cingulum bundle", "cingulate fasciculus", "parahippocampal cingulum", "cingulum (cingulate gyrus)",
         "cingulum (hippocampus)"],
        "#3fae4a",
        "An association bundle in the white matter of the cingulate gyrus, arching around the corpus callosum from "
        "the subcallosal area, over the body and behind the splenium, then down into the parahippocampal gyrus "
        "towards the entorhinal cortex. It is made of many short and long fibres linking the cingulate gyrus with "
        "the medial frontal, parietal and medial temporal cortex, and carries the anterior thalamic projection to "
        "the cingulate cortex and the cingulate output to the parahippocampal and entorhinal cortex in Papez's "
        "circuit; it takes part in emotion, motivation, attention, pain and memory. Bilateral anterior "
        "cingulotomy, which interrupts its anterior part, has been used for intractable pain and "
        "obsessive-compulsive disorder, and reduced integrity of its parahippocampal part on diffusion imaging is an "
        "early finding in Alzheimer disease. The mesh joins the JHU atlas's two labels for it, the cingulate-gyrus "
        "part and the hippocampal (parahippocampal) part."),
    "uncinate_fasciculus": (
        "uncinate fasciculus", "Fasciculus uncinatus",
        ["UF", "uncinate fascicle", "fasciculus uncinatus cerebri"],
        "#8cc63f",
        "A hook-shaped association bundle linking the orbitofrontal cortex and frontal pole with the anterior "
        "temporal lobe (temporal pole, uncus, amygdala and entorhinal region): from the frontal lobe it runs back "
        "in the ventral extreme and external capsules, turns around the limen insulae and curves forwards and down "
        "into the temporal pole. It belongs to the limbic and paralimbic network for emotion, social behaviour and "
        "the valuation of memories, and on the left has been linked with naming, especially of people. It "
        "degenerates early in the behavioural and semantic variants of frontotemporal dementia, is at risk in "
        "anterior temporal lobectomy, and is often injured in contusions of the frontal and temporal poles. In the "
        "JHU atlas this label is only its compact part at the hook, near the limen insulae."),
    "superior_longitudinal_fasciculus": (
        "superior longitudinal fasciculus", "Fasciculus longitudinalis superior",
        ["SLF", "arcuate fasciculus", "fasciculus arcuatus", "SLF/AF"],
        "#2e9b6b",
        "The largest long association bundle of the lateral hemisphere, running front to back in the white matter "
        "above the insula and lateral to the corona radiata, linking the frontal lobe (premotor and prefrontal "
        "cortex and, on the left, Broca's area) with the parietal lobe; its arcuate part, the arcuate fasciculus, "
        "curves around the posterior end of the lateral sulcus into the temporal lobe. In the left hemisphere it "
        "supports language, above all repetition and phonological processing, and praxis; in the right, spatial "
        "attention. Damage to the left arcuate fasciculus is classically held to cause conduction aphasia (fluent "
        "speech with phonemic paraphasias, good comprehension, poor repetition), and damage to the right superior "
        "longitudinal fasciculus contributes to left hemispatial neglect. The JHU label is its compact central "
        "part in the frontoparietal white matter, where the SLF and the arcuate fasciculus cannot be told apart."),
    "fornix": (
        "fornix (body and columns)", "Fornix",
        ["body of fornix", "columns of fornix", "corpus fornicis", "columna fornicis", "fornices"],
        "#e3a33a",
        "The main output tract of the hippocampal formation, shown here in its midline part. Axons of the "
        "hippocampus and subiculum gather as the alveus and fimbria, rise behind the thalamus as the crura, "
        "converge under the splenium into the body, which runs forwards beneath the corpus callosum hung from it "
        "by the septum pellucidum, and part at its front into the two columns, which curve down in front of the "
        "interventricular foramina and divide around the anterior commissure. Precommissural fibres go to the "
        "septal nuclei and basal forebrain; postcommissural fibres go to the mammillary bodies (and from there by "
        "the mammillothalamic tract to the anterior thalamic nucleus and the cingulate gyrus: Papez's circuit) and "
        "to the anterior thalamic nucleus directly. Bilateral damage, as after removal of a colloid cyst of the "
        "third ventricle, trauma or tumour, causes anterograde amnesia; the fornix is also a target of deep brain "
        "stimulation trials in Alzheimer disease."),
    "fornix_crus_stria_terminalis": (
        "crus of the fornix and stria terminalis", "Crus fornicis et stria terminalis",
        ["crus of fornix", "posterior pillar of fornix", "fimbria of hippocampus", "stria terminalis",
         "fornix (crus)"],
        "#d08a2b",
        "The JHU atlas's label for two slender bundles it cannot separate at its resolution, which run side by "
        "side near the temporal horn and atrium of the lateral ventricle: the fimbria and crus of the fornix, "
        "carrying the hippocampal output, and the stria terminalis, the main output of the amygdala. The fimbria "
        "runs along the hippocampus and becomes the crus, which arches up behind the pulvinar of the thalamus to "
        "join the body of the fornix under the splenium; the two crura are joined by the hippocampal commissure. "
        "The stria terminalis leaves the amygdala, follows the curve of the caudate nucleus in the groove between "
        "caudate and thalamus with the thalamostriate vein, and ends in the bed nucleus of the stria terminalis, "
        "the septal area and the hypothalamus, carrying the amygdala's influence on stress, autonomic and endocrine "
        "responses. Damage to the fornix on both sides causes anterograde amnesia, while damage on one side has "
        "milder effects on memory."),
    "medial_lemniscus": (
        "medial lemniscus", "Lemniscus medialis",
        ["ML", "medial fillet", "dorsal column-medial lemniscus pathway", "posterior column-medial lemniscus pathway",
         "DCML"],
        "#a25bd0",
        "The second-order pathway for discriminative touch, vibration and conscious proprioception. Its axons arise "
        "in the gracile and cuneate nuclei of the lower medulla, cross the midline as the internal arcuate fibres "
        "(the sensory decussation) and ascend as a flat band beside the midline behind the pyramids, then turn to "
        "lie transversely in the ventral tegmentum of the pons, move laterally in the midbrain and end in the "
        "ventral posterolateral nucleus of the thalamus, which relays to the postcentral gyrus. Because its fibres "
        "have already crossed, a lesion anywhere above the lower medulla causes contralateral loss of vibration and "
        "joint-position sense with sensory ataxia; in the medulla the spinothalamic tract runs separately, "
        "laterally, so medial lesions there spare pain and temperature. In medial medullary (Dejerine) syndrome, "
        "from occlusion of the anterior spinal artery or paramedian branches of the vertebral artery, it is damaged "
        "with the pyramid and the hypoglossal fascicles: contralateral loss of vibration and position sense, "
        "contralateral hemiparesis and ipsilateral tongue weakness. In the JHU atlas the label spans the pons and "
        "upper medulla."),
    "superior_cerebellar_peduncle": (
        "superior cerebellar peduncle", "Pedunculus cerebellaris superior",
        ["SCP", "brachium conjunctivum", "dentatorubrothalamic tract", "dentatothalamic tract"],
        "#e0b43c",
        "The main output of the cerebellum: axons of the dentate and interposed (emboliform and globose) nuclei "
        "leave through it, run up in the lateral walls and roof of the upper fourth ventricle, enter the midbrain "
        "tegmentum and cross completely in the decussation of the superior cerebellar peduncles at the level of the "
        "inferior colliculi, ending in the contralateral red nucleus and, mostly, in the ventral lateral nucleus of "
        "the thalamus, which projects to the motor and premotor cortex (the dentato-rubro-thalamo-cortical "
        "pathway). It also brings some afferents into the cerebellum, notably the anterior (ventral) "
        "spinocerebellar tract. Because that cortex controls the opposite body through the crossed corticospinal "
        "tract, a lesion of the peduncle before its decussation (in the cerebellum or pons) causes ipsilateral "
        "ataxia and intention tremor, and a lesion beyond it (midbrain, as in Claude syndrome, or thalamus) "
        "contralateral ataxia. Atrophy of the superior cerebellar peduncles supports the diagnosis of progressive "
        "supranuclear palsy."),
    "middle_cerebellar_peduncle": (
        "middle cerebellar peduncles", "Pedunculus cerebellaris medius",
        ["MCP", "brachium pontis", "pontine crossing tract", "transverse pontine fibres", "pontocerebellar fibres"],
        "#c9773a",
        "The largest cerebellar peduncle, joining the pons to the cerebellum on each side; the JHU atlas labels both "
        "peduncles and the crossing fibres of the basis pontis between them as one structure (with its 'pontine "
        "crossing tract'), shown here as one mesh. It is made almost entirely of pontocerebellar fibres: the frontal, "
        "parietal, temporal and occipital cortex project through the cerebral peduncle to the pontine nuclei, "
        "whose axons cross the midline and enter the opposite cerebellar hemisphere as mossy fibres, the "
        "cortico-ponto-cerebellar route that tells the cerebellum of planned movements. A lesion of one peduncle "
        "(an anterior inferior cerebellar artery infarct, a tumour of the pons or cerebellopontine angle, "
        "demyelination) causes ataxia of the limbs on the same side. T2-hyperintensity of both peduncles (the 'MCP "
        "sign') is typical of the cerebellar type of multiple system atrophy, with the pontine 'hot cross bun' "
        "sign, and of fragile X-associated tremor/ataxia syndrome."),
    "inferior_cerebellar_peduncle": (
        "inferior cerebellar peduncle", "Pedunculus cerebellaris inferior",
        ["ICP", "restiform body", "corpus restiforme", "juxtarestiform body"],
        "#a8743a",
        "The peduncle joining the medulla to the cerebellum: it climbs the dorsolateral medulla and turns back into "
        "the cerebellum beside the lateral recess of the fourth ventricle. It is mainly afferent: its large lateral "
        "part, the restiform body, carries the posterior spinocerebellar and cuneocerebellar tracts (unconscious "
        "proprioception from the same side of the body), olivocerebellar climbing fibres from the opposite inferior "
        "olive, and reticulocerebellar and trigeminocerebellar fibres; its small medial part, the juxtarestiform "
        "body, carries fibres between the vestibular nuclei and the vestibulocerebellum in both directions. Its "
        "damage causes ataxia of the limbs and gait on the same side, as in the lateral medullary (Wallenberg) "
        "syndrome from vertebral or posterior inferior cerebellar artery occlusion, which adds vertigo and "
        "nystagmus, an ipsilateral Horner syndrome, loss of pain and temperature in the ipsilateral face and the "
        "contralateral body, dysphagia and hoarseness."),
    "midbrain": (
        "Midbrain", "Mesencephalon",
        ["mesencephalon", "mid-brain", "brainstem", "brain stem", "tectum", "tegmentum of midbrain"],
        "#d2a686",
        "The uppermost part of the brainstem, about 2 cm long, between the diencephalon and the pons, traversed by "
        "the cerebral aqueduct. Behind the aqueduct the tectum bears the superior colliculi (visual orienting, with "
        "the pretectal area for the pupillary light reflex) and the inferior colliculi (auditory relay); in front "
        "of it the tegmentum holds the periaqueductal grey, the oculomotor and trochlear nuclei, the red nuclei, the "
        "decussation of the superior cerebellar peduncles and the ascending lemnisci; ventrally lie the substantia "
        "nigra and the crura cerebri with the descending cortical fibres. The oculomotor nerve leaves it in the "
        "interpeduncular fossa and the trochlear nerve, alone among cranial nerves, from its dorsal surface below "
        "the inferior colliculi. Its lesions give classic syndromes: Weber (ipsilateral oculomotor palsy with "
        "contralateral hemiparesis), Benedikt and Claude (oculomotor palsy with contralateral involuntary "
        "movements or ataxia), and Parinaud's dorsal midbrain syndrome from pineal tumours or hydrocephalus "
        "(upgaze palsy, light-near dissociation of the pupils, convergence-retraction nystagmus); loss of its "
        "nigral dopaminergic neurons causes Parkinson disease. Here it is the set's brainstem above the "
        "pontomesencephalic junction; its upper part adjoins the set's ventral diencephalon, which in FreeSurfer's "
        "labels holds part of the substantia nigra, red nucleus and crura."),
    "pons": (
        "Pons", "Pons",
        ["pons Varolii", "basis pontis", "pontine tegmentum", "brainstem", "brain stem", "metencephalon"],
        "#c79a7a",
        "The middle part of the brainstem, between the midbrain and the medulla oblongata, in front of the "
        "cerebellum and the upper half of the fourth ventricle, resting on the clivus. Its ventral basis pontis "
        "holds the pontine nuclei, whose crossing fibres form the middle cerebellar peduncles, among the descending "
        "corticospinal and corticonuclear bundles; its dorsal tegmentum holds the nuclei of the trigeminal, "
        "abducens and facial nerves and part of the vestibular and cochlear nuclei, the paramedian pontine "
        "reticular formation and medial longitudinal fasciculus for horizontal gaze, the locus coeruleus, and the "
        "medial lemniscus and spinothalamic tract. The trigeminal nerve leaves its lateral surface, and the "
        "abducens, facial and vestibulocochlear nerves emerge at the pontomedullary junction. It is supplied by "
        "paramedian and circumferential branches of the basilar artery: a ventral pontine infarct from basilar "
        "occlusion causes the locked-in syndrome (quadriplegia and anarthria with preserved consciousness, vertical "
        "eye movements and blinking); smaller lesions give crossed syndromes such as Millard-Gubler (ipsilateral "
        "facial and abducens palsy with contralateral hemiparesis), and a dorsal lesion of the abducens nucleus and "
        "medial longitudinal fasciculus the one-and-a-half syndrome. Over-rapid correction of chronic hyponatraemia "
        "can cause osmotic demyelination (central pontine myelinolysis)."),
    "medulla_oblongata": (
        "Medulla oblongata", "Medulla oblongata",
        ["medulla", "myelencephalon", "bulb", "bulbus", "brainstem", "brain stem"],
        "#b98b6c",
        "The lowest part of the brainstem, from the pontomedullary junction to the foramen magnum, where it becomes "
        "the spinal cord at the level of the pyramidal decussation and the first cervical rootlets. On its front "
        "lie the pyramids (corticospinal tracts) and beside them the olives (inferior olivary nuclei); its upper "
        "dorsal part forms the lower floor of the fourth ventricle and its lower part bears the gracile and "
        "cuneate tubercles. It holds the nuclei of the glossopharyngeal, vagus, accessory and hypoglossal nerves "
        "(with the nucleus ambiguus and the dorsal vagal nucleus), the nucleus of the solitary tract, the spinal "
        "trigeminal nucleus, the vestibular nuclei and the reticular centres controlling breathing, heart rate and "
        "blood pressure; the hypoglossal nerve emerges between pyramid and olive, the glossopharyngeal, vagus and "
        "accessory nerves behind the olive. The lateral medullary (Wallenberg) syndrome, from vertebral or posterior "
        "inferior cerebellar artery occlusion, gives vertigo, nystagmus, ipsilateral ataxia and Horner syndrome, "
        "loss of pain and temperature in the ipsilateral face and contralateral body, dysphagia and hoarseness; the "
        "medial medullary (Dejerine) syndrome gives contralateral hemiparesis, contralateral loss of vibration and "
        "position sense and ipsilateral tongue weakness. Weakness of the muscles of the lower cranial nerves is "
        "bulbar palsy, and tonsillar herniation through the foramen magnum compresses the medulla and stops "
        "breathing. In this set its lower end is where FreeSurfer's brainstem label stops, near the foramen "
        "magnum."),
}


def entries(ids, meta, parts):
    """Organ entries in organset.json's format for the tracts (hidden) and the brainstem's parts."""
    made = []
    for oid in ids + parts:
        stem, group = (meta[oid][0], meta[oid][1]) if oid in meta else (oid, "Brainstem")
        name, latin, synonyms, colour, info = TEXT[stem]
        side = {"_l": "Left ", "_r": "Right "}.get(oid[-2:], "") if oid in meta else ""
        if oid in meta and not side:
            name = name[0].upper() + name[1:]
        made.append({"id": oid, "name": side + name, "mesh": f"meshes/{oid}.vbo", "colour": colour,
                     "opacity": 1.0, "visible": oid not in meta, "group": group, "latin": latin,
                     "synonyms": synonyms, "info": info})
    return made


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
    # Inside the brain's hull (closed by 3 mm) but in no organ: the spaces between organs.
    gap = ndimage.binary_closing(brain, iterations=3) & ~brain
    world = lambda ijk: nib.affines.apply_affine(affine, ijk)  # noqa: E731
    midline = world(np.argwhere(brain).mean(0))[0]

    with tempfile.TemporaryDirectory() as tmpdir:
        tmp = Path(tmpdir)
        jhu, names, j189, copyright_text = mricron(deb, tmp / "deb")

        # --- JHU white-matter labels ------------------------------------------------------------
        if jhu.shape != (182, 218, 182) or not np.allclose(jhu.affine, MRICRON_JHU_HEADER):
            sys.exit(f"unexpected grid of {JHU}: {jhu.shape}, {jhu.affine.tolist()}")
        labels = np.asarray(jhu.dataobj).astype(np.int32)  # voxels in FSL's order: FSL_MNI152_1MM
        l189 = np.asarray(j189.dataobj).astype(np.int32)
        bottom = j189.affine[2, 3]  # world z of jhu189's lowest slice
        above = world(np.indices(shape).reshape(3, -1).T)[:, 2].reshape(shape) >= bottom
        cache = os.environ.get("TRACTS_CACHE")  # a folder for the registered labels (development)
        if cache and (Path(cache) / "registered.npz").exists():
            c = np.load(Path(cache) / "registered.npz", allow_pickle=True)
            warped, w189, dice_fsl, dice_189 = c["warped"], c["w189"], c["dice_fsl"].item(), c["dice_189"].item()
        else:
            # The tracts: the ICBM 2009a T1 (MNI152) onto the set's MRI (the same template, warped
            # onto the set by build_mri.py), by intensity; the JHU labels (FSL's MNI152, taken as
            # the same world) follow. See the docstring for why not the brains' outlines.
            t1 = template("t1")
            mapping, dice_fsl = register_t1(t1, grid, brain, mask(NOT_CEREBRUM), mask(CEREBRAL_WHITE_MATTER))
            warped = mapping.transform(labels.astype(np.float64), interpolation="nearest",
                                       image_world2grid=np.linalg.inv(FSL_MNI152_1MM)).astype(np.int32)
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
        ids, meta, fit, allowed_of = [], {}, {}, {}
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
                if stem == "fornix":  # under the callosum, between the ventricles: no organ of the set there
                    allowed = allowed | gap
                n = int(vox.sum())
                strict = float((vox & (cerebral_wm | brainstem)).sum() / n)
                share = float((vox & allowed).sum() / n)
                kept = vox & allowed
                allowed_of[oid] = allowed
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
                            + (" + ventral diencephalon" if stem == "cerebral_peduncle" else "")
                            + (" + brain voxels in no organ of the set" if stem == "fornix" else ""),
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
        # One piece per part: a stray piece goes to the part it touches most.
        for i in (1, 2, 3):
            pieces, count = ndimage.label(part == i)
            if count > 1:
                largest = np.bincount(pieces.ravel())[1:].argmax() + 1
                for k in range(1, count + 1):
                    if k != largest:
                        piece = pieces == k
                        rim = part[ndimage.binary_dilation(piece) & ~piece]
                        rim = rim[(rim > 0) & (rim != i)]
                        if len(rim):
                            part[piece] = np.bincount(rim).argmax()
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

    # The meshes' own fit: each tract mesh voxelised, its share in the tissue it was clipped to.
    say("")
    say("Meshes' fit (the mesh voxelised; share in white matter + brainstem, and in its allowed tissue):")
    for oid in ids:
        v, f = read_vbo(out / "meshes" / f"{oid}.vbo")
        inside = voxelise(v, f, shape, affine)
        strict = float((inside & (cerebral_wm | brainstem)).sum() / max(inside.sum(), 1))
        share = float((inside & allowed_of[oid]).sum() / max(inside.sum(), 1))
        fit[oid]["mesh_voxels"] = int(inside.sum())
        fit[oid]["mesh_in_white_matter_or_brainstem"] = round(strict, 4)
        fit[oid]["mesh_in_allowed_tissue"] = round(share, 4)
        say(f"  {oid:40s} {int(inside.sum()):6d} voxels {100 * strict:6.1f}% {100 * share:6.1f}%")

    # --- Entries, fit, report --------------------------------------------------------------------
    made = entries(ids, meta, parts)
    (out / "entries.json").write_text(json.dumps(made, indent=2, ensure_ascii=False) + "\n")
    (out / "fit.json").write_text(json.dumps({
        "registration_dice": {"jhu_white_matter_via_icbm2009a_t1": dice_fsl,
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
    say(f"registration Dice: ICBM 2009a T1 (for the JHU tracts) {dice_fsl}, jhu189 {dice_189}")
    say(f"took {time.time() - t0:.0f} s")
    (out / "report.txt").write_text("\n".join(report) + "\n")


SOURCE = {
    "name": "JHU white-matter labels (ICBM-DTI-81, 48 labels) and the JHU-MNI parcellation jhu189, registered to this set (Debian mricron-data 1.2.20211006+dfsg-4, usr/share/mricron/templates/JHU-WhiteMatter-labels-1mm.nii.gz and jhu189.nii.gz)",
    "url": "https://packages.debian.org/bookworm/mricron-data",
    "licence": "BSD-3-Clause as Debian's copyright file declares for all of mricron-data's files (Copyright 2006-2010 Chris Rorden); the labels come from Johns Hopkins University's atlases, whose own terms the package does not state",
    "attribution": "Mori S, Oishi K, Jiang H, et al. (2008) Stereotaxic white matter atlas based on diffusion tensor imaging in an ICBM template. NeuroImage 40:570-582; Oishi K, et al. (2008) Human brain white matter atlas: identification and assignment of common anatomical structures in superficial white matter. NeuroImage 43:447-457; Rorden C, Brett M (2000) Stereotaxic display of brain lesions. Behav Neurol 12:191-200 (MRIcron)",
}


def flatten_spikes(path):
    """Moves each vertex far out of the mesh (farther from its median point than 2.5 times the 90th
    percentile of the vertices' distances: the import of the brainstem's parts left a few spiking
    to the grid's edge, x = 82 mm) to the mean of its neighbours that are not, with their mean
    normal, nearest the mesh first. Returns how many moved."""
    lines = Path(path).read_text().split("\n")
    v_at = [i for i, l in enumerate(lines) if l.startswith("v ")]
    n_at = [i for i, l in enumerate(lines) if l.startswith("vn ")]
    v, f = read_vbo(path)
    normals = np.array([[float(x) for x in lines[i].split()[1:4]] for i in n_at])
    d = np.linalg.norm(v - np.median(v, 0), axis=1)
    far = set(np.flatnonzero(d > 2.5 * np.percentile(d, 90)).tolist())
    moved = len(far)
    edges = np.vstack([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    while far:
        ring = {k: sorted({int(e) for e in edges[(edges == k).any(1)].ravel()} - far - {k}) for k in far}
        k = max(far, key=lambda k: len(ring[k]))
        if not ring[k]:
            sys.exit(f"{path}: a spike with no neighbour in the mesh")
        v[k] = v[ring[k]].mean(0)
        n = normals[ring[k]].mean(0)
        normals[k] = n / max(np.linalg.norm(n), 1e-9)
        lines[v_at[k]] = "v %.3f %.3f %.3f" % tuple(v[k])
        lines[n_at[k]] = "vn %.3f %.3f %.3f" % tuple(normals[k])
        far.discard(k)
    Path(path).write_text("\n".join(lines))
    return moved


def merge(out):
    """Brings OUT's meshes and entries into the set: the brainstem split, the tracts added."""
    manifest_path = HERE / "organset.json"
    manifest = json.loads(manifest_path.read_text())
    made = json.loads((out / "entries.json").read_text())
    parts = [e for e in made if e["group"] == "Brainstem"]
    tracts = [e for e in made if e["group"] != "Brainstem"]
    ids = [o["id"] for o in manifest["organs"]]
    if "brainstem" not in ids:
        sys.exit("organset.json has no organ \"brainstem\" to split (merged already?)")
    for e in made:
        shutil.copyfile(out / e["mesh"], HERE / e["mesh"])
        if e in parts and (moved := flatten_spikes(HERE / e["mesh"])):
            print(f"{e['id']}: {moved} spiking vertices moved to their neighbours' mean")
    at = ids.index("brainstem")
    old = manifest["organs"][at]
    manifest["organs"][at:at + 1] = parts
    manifest["organs"].extend(tracts)
    for solid in manifest.get("solids", []):
        if "brainstem" in solid["organs"]:
            k = solid["organs"].index("brainstem")
            solid["organs"][k:k + 1] = [p["id"] for p in parts]
    for key in ("mesh", "lod", "occluder"):
        if key in old and (HERE / old[key]).exists():
            (HERE / old[key]).unlink()
    manifest["sources"] = [s for s in manifest["sources"] if not s["name"].startswith("JHU white-matter")]
    manifest["sources"].append(SOURCE)
    manifest_path.write_text(json.dumps(manifest, indent=2, ensure_ascii=False) + "\n")
    print(f"merged {len(parts)} brainstem parts and {len(tracts)} tracts into {manifest_path}")


if __name__ == "__main__":
    if sys.argv[1:2] == ["--merge"]:
        merge(Path(sys.argv[2]) if len(sys.argv) > 2 else Path("/tmp/tracts-out"))
    else:
        main()
