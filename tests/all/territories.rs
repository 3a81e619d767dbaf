//! The default set's arterial territories (issue: blood supply and pathways): they load with the
//! set, cover the cortex, lie where anatomy puts them, carry teaching text, colour renders, and a
//! broken territories file names itself while the organs still load.

use crate::common::{default_set, gpu};
use glam::Vec3;
use vbrain::camera::{Camera, View};
use vbrain::layout::ColourBy;
use vbrain::layout::Layout;
use vbrain::organ_set;
use vbrain::render::{FrameInput, Renderer, Target};

/// The cortex: every organ in a lobe, the cingulate gyrus or the insula of a hemisphere.
fn cortex() -> Vec<usize> {
    let set = default_set();
    (0..set.organs.len()).filter(|&i| set.organs[i].group.contains("hemisphere/")).collect()
}

#[test]
fn at_least_95_percent_of_the_cortex_carries_a_territory() {
    let set = default_set();
    let t = set.territories.as_ref().expect("organs/brain's manifest names territories.json, and it loads");
    let (mut inside, mut all) = (0usize, 0usize);
    let organs = cortex();
    assert!(organs.len() >= 60, "{} cortical organs", organs.len());
    for &i in &organs {
        let mesh = set.organs[i].mesh();
        all += mesh.positions.len();
        inside += mesh.positions.iter().filter(|&&p| t.at(Vec3::from(p)) != 0).count();
    }
    let share = inside as f64 / all as f64;
    assert!(share >= 0.95, "{inside} of {all} cortex vertices ({:.1} %) carry a territory", share * 100.0);
}

#[test]
fn territories_lie_where_anatomy_puts_them_and_teach() {
    let set = default_set();
    let t = set.territories.as_ref().unwrap();
    // Mean position of the cortex vertices in each territory.
    let mut sums = vec![(Vec3::ZERO, 0usize); 256];
    for i in cortex() {
        for &p in &set.organs[i].mesh().positions {
            let id = t.at(Vec3::from(p)) as usize;
            sums[id].0 += Vec3::from(p);
            sums[id].1 += 1;
        }
    }
    let centre = |key: &str, left: bool| {
        let k = t.arteries.iter().position(|a| a.key == key).unwrap_or_else(|| panic!("no artery {key}"));
        let (sum, n) = sums[2 * k + if left { 1 } else { 2 }];
        assert!(n > 50, "{key}: only {n} cortex vertices");
        sum / n as f32
    };
    for left in [true, false] {
        let side = if left { -1.0 } else { 1.0 };
        let (aca, mca, pca) = (centre("aca", left), centre("mca_frontal", left), centre("pca_occipital", left));
        for (name, c) in [("ACA", aca), ("MCA frontal", mca), ("PCA", pca)] {
            assert!(c.x * side > 0.0, "{name} left={left} is on the wrong side: {c}");
        }
        assert!(mca.x.abs() > aca.x.abs() + 15.0, "the MCA is lateral to the ACA: {mca} vs {aca}");
        assert!(pca.y < mca.y - 30.0, "the PCA is posterior to the MCA's frontal branches: {pca} vs {mca}");
        assert!(aca.z > pca.z, "the ACA's territory climbs higher than the PCA's: {aca} vs {pca}");
    }
    for a in &t.arteries {
        let sentences = a.info.matches(". ").count() + 1;
        assert!(sentences >= 2 && !a.short.is_empty() && !a.synonyms.is_empty(), "{}: too little text", a.key);
    }
    assert!(t.arteries.iter().any(|a| a.synonyms.iter().any(|s| s == "middle cerebral artery territory")));
}

#[test]
fn colouring_by_territory_or_lobe_changes_the_picture() {
    let gpu = gpu();
    let set = default_set();
    let renderer = Renderer::new(&gpu.device, set).unwrap();
    let camera = Camera::view(&Layout::new(set).bounds(set), View::Left);
    let shot = |by: ColourBy| {
        let layout = Layout { colour_by: by, ..Layout::new(set) };
        let mut target = Target::new(&gpu.device, 160, 128).unwrap();
        let frame = FrameInput { background: [0.0, 0.0, 0.0, 1.0], ..FrameInput::new(set, &camera, &layout) };
        renderer.render(&gpu.device, &gpu.queue, &mut target, &frame).unwrap();
        target.read_color(&gpu.device, &gpu.queue).unwrap()
    };
    let (organ, lobe, territory) = (shot(ColourBy::Organ), shot(ColourBy::Lobe), shot(ColourBy::Territory));
    let lit = organ.pixels().filter(|p| p[0] > 10 || p[1] > 10 || p[2] > 10).count();
    let differ = |a: &image::RgbaImage, b: &image::RgbaImage| {
        a.pixels().zip(b.pixels()).filter(|(x, y)| x.0.iter().zip(y.0).any(|(u, v)| u.abs_diff(v) > 24)).count()
    };
    for (name, image) in [("lobe", &lobe), ("territory", &territory)] {
        let d = differ(&organ, image);
        assert!(d > lit / 3, "{name} colouring changes only {d} of {lit} brain pixels");
    }
    assert!(differ(&lobe, &territory) > lit / 4, "lobes and territories look alike");
    // The territory colours are the atlas's: the left MCA's frontal branches' colour shows (lit
    // between 18 % and 100 % of itself).
    let t = set.territories.as_ref().unwrap();
    let mca = t.arteries.iter().find(|a| a.key == "mca_frontal").unwrap().colour;
    let hue = |c: [f32; 3]| {
        let sum: f32 = c.iter().sum::<f32>().max(1e-3);
        [c[0] / sum, c[1] / sum, c[2] / sum]
    };
    let want = hue(mca.map(|v| v.powf(2.2)));
    let near = territory
        .pixels()
        .filter(|p| {
            let lin = [p[0], p[1], p[2]].map(|v| (v as f32 / 255.0).powf(2.2));
            lin.iter().sum::<f32>() > 0.05 && hue(lin).iter().zip(want).all(|(a, b)| (a - b).abs() < 0.06)
        })
        .count();
    assert!(near > lit / 20, "only {near} of {lit} pixels show the MCA's colour");
}

#[test]
fn a_broken_territories_file_names_itself_and_the_organs_still_load() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("a.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let manifest = |territories: &str| {
        format!(
            r##"{{"format": "vbrain-organ-set/1", "title": "t", "units": "mm", "coordinates": "RAS",
            "organs": [{{"id": "a", "name": "a", "mesh": "a.obj", "colour": "#ff0000"}}],
            "territories": "{territories}"}}"##
        )
    };
    let cases = [
        ("t.json", "{\n  \"format\": \"vbrain-territories/1\",\n  \"volume\": 3\n}", "t.json:3"),
        ("t.json", "{\"format\": \"vbrain-territories/1\", \"volume\": \"v.nii.gz\", \"arteries\": []}", "0 arteries"),
        (
            "t.json",
            r##"{"format": "vbrain-territories/1", "volume": "v.nii.gz", "arteries": [{"key": "aca",
            "name": "ACA", "short": "ACA", "colour": "#0000ff", "info": "x. y."}]}"##,
            "v.nii.gz",
        ),
        ("../t.json", "", "escapes"),
    ];
    for (file, text, says) in cases {
        if !text.is_empty() {
            std::fs::write(dir.path().join(file), text).unwrap();
        }
        std::fs::write(dir.path().join("organset.json"), manifest(file)).unwrap();
        let loaded = organ_set::open(dir.path()).unwrap();
        assert_eq!(loaded.set.organs.len(), 1, "the organs load");
        assert!(loaded.set.territories.is_none());
        let errors: Vec<String> = loaded.errors.iter().map(|e| e.to_string()).collect();
        assert!(errors.len() == 1 && errors[0].contains(says), "{errors:?} should say {says:?}");
    }
}
