//! The occluder database and its use at run time (CPU only): pre-processing writes a database that
//! loads back beside the set, is ignored once the set changes, is used while the layout is the
//! pre-processed one or has organs faded since (not after an organ moves or one hidden is shown),
//! and never lets a faded organ occlude.

use crate::common::cube;
use glam::Vec3;
use vbrain::camera::Camera;
use vbrain::cull::database::{self, Database, DbProblem};
use vbrain::cull::{choose_occluders, CullSettings, Culler, OccluderSource, OrganRecord, Selection};
use vbrain::layout::Layout;
use vbrain::mos::{self, Params};
use vbrain::organ_set::{self, Organ, OrganSet};

/// A wall in front of a row of boxes, seen from the front: the wall hides the boxes.
fn wall_and_boxes() -> OrganSet {
    let mut set = OrganSet { title: "wall".into(), ..Default::default() };
    set.organs.push(Organ::new(
        "wall".into(),
        "Wall".into(),
        [0.8; 3],
        cube(Vec3::new(0.0, 40.0, 0.0), Vec3::new(60.0, 2.0, 30.0), 12),
    ));
    for i in 0..5 {
        let c = Vec3::new(-40.0 + 20.0 * i as f32, 0.0, 0.0);
        set.organs.push(Organ::new(format!("box{i}"), format!("Box {i}"), [0.5; 3], cube(c, Vec3::splat(6.0), 6)));
    }
    set
}

#[test]
fn the_database_round_trips_and_goes_stale() {
    let dir = std::env::temp_dir().join(format!("vbrain-occluders-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    wall_and_boxes().save(&dir).unwrap();
    // As `vbrain occluders` does: pre-process the set as loaded from its folder.
    let set = organ_set::open(&dir).unwrap().set;
    let layout = Layout::new(&set);
    let db = mos::preprocess(&set, &layout, 6, &Params::default(), &|_, _| {});
    assert_eq!(db.viewpoints.len(), 6 * mos::DISTANCES.len());
    assert!(db.viewpoints.iter().any(|v| !v.occluders.is_empty()), "no viewpoint found an occluder");
    db.save(&dir).unwrap();
    let loaded = organ_set::open(&dir).unwrap();
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    assert_eq!(Database::load_for(&dir, &loaded.set).unwrap().as_ref(), Some(&db));
    // Also when the set is opened from its manifest; a set of mesh files has none.
    let manifest = dir.join(organ_set::MANIFEST_FILE);
    assert_eq!(Database::load_for(&manifest, &loaded.set).unwrap().as_ref(), Some(&db));
    // The set changes: the database is stale, says so, and is not used.
    let mut changed = loaded.set.clone();
    changed.organs[1].set_mesh(cube(Vec3::ZERO, Vec3::splat(7.0), 6));
    changed.save(&dir).unwrap();
    // Saving a set replaces its folder whole; the database made for the old set is put back.
    assert!(!dir.join(database::FILE).exists(), "a saved set keeps no file of the folder it replaced");
    db.save(&dir).unwrap();
    let reloaded = organ_set::open(&dir).unwrap();
    match Database::load_for(&dir, &reloaded.set) {
        Err(e @ vbrain::Error::OccluderDb { problem: DbProblem::Stale, .. }) => {
            assert!(e.to_string().contains(database::FILE), "{e}")
        }
        other => panic!("a stale database: {other:?}"),
    }
    // A broken file names itself and its line.
    std::fs::write(dir.join(database::FILE), "{\n  \"version\": oops\n}").unwrap();
    let broken = Database::load_for(&dir, &reloaded.set).unwrap_err().to_string();
    assert!(broken.contains(&format!("{}:2", database::FILE)), "{broken}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_culler_uses_the_database_only_for_the_layout_it_was_made_for() {
    let set = wall_and_boxes();
    let layout = Layout::new(&set);
    let db = mos::preprocess(&set, &layout, 32, &Params::default(), &|_, _| {});
    let home = layout.bounds(&set);
    // From the front (anterior, +y), looking through the wall at the boxes.
    let camera = Camera::orbit(&home, 0.0, 0.0);
    let vp = camera.view_projection(1.0);
    let auto = CullSettings::default();
    let (list, source) =
        choose_occluders(&set, &layout, &camera, &vp, &auto, Some(&db), &OrganRecord::unclipped(&layout));
    assert_eq!(source, OccluderSource::Mos);
    assert!(list.iter().any(|r| r.organ == 0), "the wall is not among the pre-computed occluders: {list:?}");
    let (_, stats) = Culler::new(Some(db.clone())).cull(&set, &layout, &camera, 1.0, &auto);
    assert_eq!(stats.source, Some(OccluderSource::Mos));
    assert!(stats.occlusion_culled > 0, "the wall culled nothing");
    // An organ moves: projected size again, unless the database is forced.
    let mut moved = layout.clone();
    moved.organs[3].transform.translation = Vec3::new(0.0, 0.0, 5.0);
    assert_eq!(
        choose_occluders(&set, &moved, &camera, &vp, &auto, Some(&db), &OrganRecord::unclipped(&moved)).1,
        OccluderSource::ProjectedSize
    );
    let forced = CullSettings { selection: Selection::Mos, ..auto };
    assert_eq!(
        choose_occluders(&set, &moved, &camera, &vp, &forced, Some(&db), &OrganRecord::unclipped(&moved)).1,
        OccluderSource::Mos
    );
    // Far from every viewpoint (inside the set, looking sideways): projected size.
    let inside = Camera { eye: home.center(), target: home.center() + Vec3::X, ..camera };
    assert_eq!(
        choose_occluders(&set, &layout, &inside, &vp, &auto, Some(&db), &OrganRecord::unclipped(&layout)).1,
        OccluderSource::ProjectedSize
    );
    let ps = CullSettings { selection: Selection::ProjectedSize, ..auto };
    assert_eq!(
        choose_occluders(&set, &layout, &camera, &vp, &ps, Some(&db), &OrganRecord::unclipped(&layout)).1,
        OccluderSource::ProjectedSize
    );
    // A faded wall never occludes, even when the database is forced.
    let mut faded = layout.clone();
    faded.organs[0].opacity = 0.5;
    let (list, _) = choose_occluders(&set, &faded, &camera, &vp, &forced, Some(&db), &OrganRecord::unclipped(&faded));
    assert!(list.iter().all(|r| r.organ != 0));
    // Automatic: with the wall faded, what is left of the set is joined by the occluders by
    // projected size (the organs under the wall now hide each other), on the settings' budget
    // and that of the wall's triangles left out (those facing the eye); a faded box leaves the
    // wall.
    let pick = |l: &Layout| choose_occluders(&set, l, &camera, &vp, &auto, Some(&db), &OrganRecord::unclipped(l));
    // On a budget too small for a box's leaf, by projected size alone takes none.
    let tight = CullSettings { occluder_triangles: 8, ..auto };
    let (list, source) =
        choose_occluders(&set, &faded, &camera, &vp, &tight, Some(&db), &OrganRecord::unclipped(&faded));
    assert_eq!(source, OccluderSource::Mos);
    let wall = &set.organs[0];
    let facing = |r: &vbrain::cull::LeafRef| {
        let mesh = wall.mesh();
        let p = |i: u32| Vec3::from(mesh.positions[mesh.indices[i as usize] as usize]);
        let faces = |i: u32| (p(i + 1) - p(i)).cross(p(i + 2) - p(i)).dot(camera.eye - p(i)) > 0.0;
        wall.bvh().leaf_range(r.leaf).step_by(3).filter(|&i| faces(i)).count()
    };
    let wall_leaves: Vec<_> = list_of(&db, &camera).into_iter().filter(|r| r.organ == 0).collect();
    assert!(wall_leaves.iter().all(|r| !r.stand_in));
    let left_out: usize = wall_leaves.iter().map(facing).sum();
    assert!(left_out > 0, "the set has none of the wall's triangles");
    let budget = CullSettings { occluder_triangles: tight.occluder_triangles + left_out, ..auto };
    let by_size = vbrain::cull::by_projected_size(&set, &faded, &camera, &vp, &budget, &OrganRecord::unclipped(&faded));
    let small = vbrain::cull::by_projected_size(&set, &faded, &camera, &vp, &tight, &OrganRecord::unclipped(&faded));
    assert!(by_size.len() > small.len(), "the wall's budget takes no more occluders");
    assert!(by_size.iter().all(|r| list.contains(r)), "every occluder by projected size joins");
    let left: Vec<_> = list_of(&db, &camera).into_iter().filter(|r| r.organ != 0).collect();
    assert!(left.iter().all(|r| list.contains(r)), "what is left of the set stays");
    let joined = by_size.iter().filter(|r| !left.contains(r)).count();
    assert_eq!(list.len(), left.len() + joined, "no occluder twice, and no other");
    assert!(list.iter().all(|r| faded.organs[r.organ as usize].is_opaque()));
    let box_faded = {
        let mut l = layout.clone();
        let used = |o: usize| list_of(&db, &camera).iter().filter(|r| r.organ as usize == o).count();
        let (o, _) = (1..6).map(|o| (o, used(o))).min_by_key(|&(_, n)| n).unwrap();
        l.organs[o].opacity = 0.5;
        l
    };
    let (list, source) = pick(&box_faded);
    assert_eq!(source, OccluderSource::Mos, "a faded box leaves most of the set");
    assert!(list.iter().all(|r| box_faded.organs[r.organ as usize].is_opaque()));
    // An organ shown that was hidden when the set was chosen: projected size.
    let mut hidden = layout.clone();
    hidden.organs[3].visible = false;
    let db_hidden = mos::preprocess(&set, &hidden, 32, &Params::default(), &|_, _| {});
    let (_, source) =
        choose_occluders(&set, &layout, &camera, &vp, &auto, Some(&db_hidden), &OrganRecord::unclipped(&layout));
    assert_eq!(source, OccluderSource::ProjectedSize);
}

/// The pre-computed occluders of the viewpoint nearest `camera`.
fn list_of(db: &Database, camera: &Camera) -> Vec<vbrain::cull::LeafRef> {
    db.nearest(camera).map(|v| v.occluders.clone()).unwrap_or_default()
}
