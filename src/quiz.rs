//! Quizzes (the thesis's future work: a question module): questions that ask a student to locate
//! a structure (click it), to name one (type its name or pick among four), or which artery
//! supplies one (pick among four arteries; issue: blood supply and pathways).
//!
//! - Questions are drawn from a scope of organs with a seed, so a seed gives the same quiz.
//! - Pure functions over the organ set; the camera and the fading that make a deep target visible
//!   take the organ-ID buffer (organ index + 1 per pixel) from the caller, who renders it.
//! - Choices are the answer and three distractors near it: organs of its own group first, then the
//!   others, each by the distance between bounding-box centres (millimetres, world RAS), never
//!   random far-away ones.
//! - Typed names are accepted as the organ set's search finds them (name, id, Latin name,
//!   synonyms; case- and accent-insensitive, [`crate::organ_set::names::fold`]), with a small
//!   misspelling allowed, and a side word ("left", "right") checked only where one is typed.

use crate::layout::Layout;
use crate::mri::slice::SlicePlane;
use crate::navigation::Navigator;
use crate::organ_set::{names, OrganSet};
use crate::rng::XorShift;
use serde::{Deserialize, Serialize};

/// What a question asks.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Kind {
    /// Click the named structure.
    Locate,
    /// Name the highlighted structure.
    Name,
    /// Which artery supplies the highlighted structure: `choices` are indices into the set's
    /// territories' arteries, the answer [`supplier`]'s.
    Supply,
}

/// Which kinds a quiz asks.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Mode {
    Locate,
    Name,
    #[default]
    Mixed,
    /// Name and locate by turns, each on an axial, coronal or sagittal slice through the structure
    /// (the set's MRI with outlines) instead of the 3-D view.
    Mri,
    /// Which artery supplies the highlighted structure (structures that one artery supplies for
    /// the most part, [`SUPPLY_SHARE`]).
    Supply,
}

/// The least share of a structure's surface its artery must supply for a supply question on it.
pub const SUPPLY_SHARE: f32 = 0.8;

/// The artery that supplies most of `organ` (index into the set's territories' arteries), where
/// it supplies at least [`SUPPLY_SHARE`] of its surface and the territories do not leave the
/// organ unasked.
pub fn supplier(set: &OrganSet, organ: usize) -> Option<usize> {
    let (t, o) = (set.territories.as_ref()?, set.organs.get(organ)?);
    let (artery, share) = t.supplier(o.mesh())?;
    (share >= SUPPLY_SHARE && !t.unasked.contains(&o.id)).then_some(artery)
}

/// A supply question's prompt, in two phrasings by turns (`k` the question's number from 0).
pub fn supply_prompt(k: usize) -> &'static str {
    if k.is_multiple_of(2) {
        "Which artery supplies the outlined region?"
    } else {
        "A stroke destroys the outlined region: which artery's territory is it?"
    }
}

impl Mode {
    pub const ALL: [Mode; 5] = [Mode::Locate, Mode::Name, Mode::Mixed, Mode::Mri, Mode::Supply];

    pub fn parse(s: &str) -> Option<Mode> {
        Mode::ALL.into_iter().find(|m| m.name() == s.trim().to_ascii_lowercase())
    }

    pub fn name(self) -> &'static str {
        match self {
            Mode::Locate => "locate",
            Mode::Name => "name",
            Mode::Mixed => "mixed",
            Mode::Mri => "mri",
            Mode::Supply => "supply",
        }
    }
}

/// One question: its kind, the organ it is about (index) and four choices (indices, distinct, the
/// organ among them) for picking a name, or for a worksheet's letters; asked on a slice through
/// the organ where `slice` is set ([`Mode::Mri`]), else in the 3-D view.
#[derive(Clone, Debug, PartialEq)]
pub struct Question {
    pub kind: Kind,
    pub organ: usize,
    pub choices: Vec<usize>,
    pub slice: Option<SlicePlane>,
}

/// The least pixels of its own a structure shows on a question's slice, in a 160 x 160 pane over
/// the organs shown by default (so it is outlined and can be clicked).
pub const SLICE_PIXELS: usize = 24;

/// A plane through `organ` on which it shows at least [`SLICE_PIXELS`] pixels of its own among the
/// organs the set shows by default: through its middle along an axis (in an order drawn from
/// `rng`), else a quarter of the way in either side. `None` where no such plane shows it.
pub fn slice_through(set: &OrganSet, organ: usize, rng: &mut XorShift) -> Option<SlicePlane> {
    use crate::mri::slice::{organ_ids, Axis, Pane};
    let shown: Vec<usize> = (0..set.organs.len()).filter(|&o| set.organs[o].visible || o == organ).collect();
    let home = shown.iter().fold(crate::mesh::Bounds::EMPTY, |b, &o| b.union(set.organs[o].mesh().bounds()));
    let b = set.organs.get(organ)?.mesh().bounds();
    let mut axes = Axis::ALL.to_vec();
    rng.shuffle(&mut axes);
    for share in [0.5, 0.25, 0.75] {
        for &axis in &axes {
            let n = axis.normal();
            let at = (b.min[n] + (b.max[n] - b.min[n]) * share).round();
            let plane = SlicePlane { axis, at };
            let pane = Pane::fit(plane, &home, 160, 160, true);
            let own = organ_ids(set, &shown, &pane).iter().filter(|&&id| id as usize == organ + 1).count();
            if own >= SLICE_PIXELS {
                return Some(plane);
            }
        }
    }
    None
}

/// What to ask: the organs in scope (indices), how many questions, which kinds, the seed.
#[derive(Clone, Debug, PartialEq)]
pub struct Spec {
    pub scope: Vec<usize>,
    pub questions: usize,
    pub mode: Mode,
    pub seed: u64,
}

/// A generated quiz, and a note where fewer questions were made than asked.
#[derive(Clone, Debug, PartialEq)]
pub struct Quiz {
    pub questions: Vec<Question>,
    pub note: Option<String>,
}

/// How many choices a question offers.
pub const CHOICES: usize = 4;

/// The organs a quiz may ask about: those of `group` (an id or a group path), else every organ
/// the set shows by default (not the scalp and skull it hides). At least two are needed.
pub fn scope(set: &OrganSet, group: Option<&str>) -> Result<Vec<usize>, String> {
    let organs: Vec<usize> = match group.map(str::trim).filter(|g| !g.is_empty()) {
        Some(g) => set.select(g),
        None => (0..set.organs.len()).filter(|&i| set.organs[i].visible).collect(),
    };
    match (organs.len(), group) {
        (0, Some(g)) => Err(format!("no organ or group \"{g}\" in the set (see `vbrain info`)")),
        (n, Some(g)) if n < 2 => Err(format!("\"{g}\" has {n} organ: a quiz needs at least two")),
        (n, None) if n < 2 => Err(format!("the set shows {n} organ: a quiz needs at least two")),
        _ => Ok(organs),
    }
}

/// A quiz over `spec.scope`: each organ asked about at most once, in an order drawn from the
/// seed. Asking for more questions than the scope has organs stops at the organs (and says so).
pub fn generate(set: &OrganSet, spec: &Spec) -> Result<Quiz, String> {
    let scope: Vec<usize> = spec.scope.iter().copied().filter(|&o| o < set.organs.len()).collect();
    if scope.len() < 2 {
        return Err(format!("a quiz needs at least two structures in scope, not {}", scope.len()));
    }
    if spec.questions == 0 {
        return Err("a quiz needs at least one question".into());
    }
    let mut rng = XorShift::seeded(spec.seed);
    // Per organ of the set, its supplier, found once (over every vertex) for those in scope of a
    // supply quiz.
    let mut artery_of: Vec<Option<usize>> = vec![None; set.organs.len()];
    let scope = match spec.mode {
        Mode::Supply => {
            if set.territories.is_none() {
                return Err("the set has no arterial territories: a supply quiz needs them".into());
            }
            for &o in &scope {
                artery_of[o] = supplier(set, o);
            }
            let supplied: Vec<usize> = scope.iter().copied().filter(|&o| artery_of[o].is_some()).collect();
            if supplied.is_empty() {
                return Err("no structure in scope lies mostly in one artery's territory".into());
            }
            supplied
        }
        _ => scope,
    };
    let mut order = scope.clone();
    rng.shuffle(&mut order);
    let n = spec.questions.min(order.len());
    let note = (spec.questions > n)
        .then(|| format!("{} questions asked but only {n} structures in scope: the quiz stops at {n}", spec.questions));
    let mut questions = Vec::with_capacity(n);
    let mut unsliced = 0;
    for &organ in &order {
        if questions.len() == n {
            break;
        }
        let k = questions.len();
        let kind = match spec.mode {
            Mode::Locate => Kind::Locate,
            Mode::Name => Kind::Name,
            Mode::Mixed | Mode::Mri if k % 2 == 0 => Kind::Locate,
            Mode::Mixed | Mode::Mri => Kind::Name,
            Mode::Supply => Kind::Supply,
        };
        let slice = match spec.mode {
            Mode::Mri => match slice_through(set, organ, &mut rng) {
                Some(plane) => Some(plane),
                None => {
                    unsliced += 1;
                    continue;
                }
            },
            _ => None,
        };
        let choices = match (kind, &set.territories, artery_of[organ]) {
            (Kind::Supply, Some(t), Some(artery)) => t.choices(set.organs[organ].mesh(), artery, CHOICES, &mut rng),
            _ => choices(set, organ, &scope, &mut rng),
        };
        questions.push(Question { kind, organ, choices, slice });
    }
    if questions.is_empty() {
        return Err("no structure in scope shows on a slice: an MRI quiz needs organs with volume".into());
    }
    let note = note.or_else(|| {
        (questions.len() < n).then(|| {
            format!("{unsliced} structures show too little on any slice: the quiz stops at {}", questions.len())
        })
    });
    Ok(Quiz { questions, note })
}

/// The answer `organ` and up to three distractors, shuffled: organs of its group first, then the
/// rest of `candidates`, then of the set, each nearest first.
pub fn choices(set: &OrganSet, organ: usize, candidates: &[usize], rng: &mut XorShift) -> Vec<usize> {
    let centre = |o: usize| set.organs[o].mesh().bounds().center();
    let at = centre(organ);
    let group = &set.organs[organ].group;
    let by_distance = |pool: Vec<usize>| {
        let mut pool = pool;
        pool.sort_by(|&a, &b| centre(a).distance(at).total_cmp(&centre(b).distance(at)).then(a.cmp(&b)));
        pool
    };
    let others = |pool: &mut dyn Iterator<Item = usize>| pool.filter(|&o| o != organ).collect::<Vec<_>>();
    let same: Vec<usize> = others(&mut candidates.iter().copied().filter(|&o| &set.organs[o].group == group));
    let rest: Vec<usize> = others(&mut candidates.iter().copied().filter(|&o| &set.organs[o].group != group));
    let all: Vec<usize> = others(&mut (0..set.organs.len()).filter(|&o| set.organs[o].visible));
    let mut out = vec![organ];
    for o in by_distance(same).into_iter().chain(by_distance(rest)).chain(by_distance(all)) {
        if out.len() == CHOICES {
            break;
        }
        if !out.contains(&o) && set.organs[o].name != set.organs[organ].name {
            out.push(o);
        }
    }
    rng.shuffle(&mut out);
    out
}

/// Side words: a typed side must match the organ's.
const LEFT: [&str; 4] = ["left", "l", "sinister", "sinistra"];
const RIGHT: [&str; 4] = ["right", "r", "dexter", "dextra"];

/// The words of a folded name without side words, and the side named (-1 left, 1 right, 0 none).
fn sided(folded: &str) -> (String, i32) {
    let mut side = 0;
    let mut words = Vec::new();
    for w in folded.split(|c: char| !c.is_alphanumeric()).filter(|w| !w.is_empty()) {
        if LEFT.contains(&w) {
            side = -1;
        } else if RIGHT.contains(&w) {
            side = 1;
        } else {
            words.push(w);
        }
    }
    (words.join(" "), side)
}

/// Does a typed `answer` name organ `organ` of `set`? Any of its names, case and accents aside,
/// one misspelt letter in five allowed (none below five letters); a side word, where typed, must
/// be the organ's side. Ids and groups of other organs are never accepted.
pub fn accepts(set: &OrganSet, organ: usize, answer: &str) -> bool {
    let Some(o) = set.organs.get(organ) else { return false };
    let (typed, typed_side) = sided(&names::fold(answer));
    if typed.is_empty() {
        return false;
    }
    let own_side = sided(&names::fold(&o.name)).1;
    if typed_side != 0 && own_side != 0 && typed_side != own_side {
        return false;
    }
    names::names(o).any(|n| {
        let (name, _) = sided(&names::fold(n));
        let allowed = name.chars().count() / 5;
        !name.is_empty() && levenshtein(&name, &typed) <= allowed
    })
}

/// Edit distance (insertions, deletions, substitutions) between two strings, by characters.
pub fn levenshtein(a: &str, b: &str) -> usize {
    let (a, b): (Vec<char>, Vec<char>) = (a.chars().collect(), b.chars().collect());
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.iter().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let above = row[j + 1];
            row[j + 1] = (above + 1).min(row[j] + 1).min(diagonal + usize::from(ca != cb));
            diagonal = above;
        }
    }
    row[b.len()]
}

/// A name as it reads inside a sentence: "Left caudate nucleus" becomes "left caudate nucleus".
pub fn lower_first(s: &str) -> String {
    let mut c = s.chars();
    match c.next() {
        Some(f) => f.to_lowercase().chain(c).collect(),
        None => String::new(),
    }
}

/// Where a question about `organ` starts when no lesson step gives its view: the set as it is
/// laid out at first, seen from [`camera`].
pub fn side_view(set: &OrganSet, organ: usize) -> (Layout, Navigator) {
    let layout = Layout::new(set);
    let nav = camera(set, &layout, organ);
    (layout, nav)
}

/// The camera for a question about `organ`: from the subject's left for a left-sided structure,
/// from the right for a right-sided one, from the front left for one on the midline; at a distance
/// that frames the organ with room around it (three times the framed distance, between 0.55 and 1
/// times the distance that frames the whole set, so a small structure is seen in its place).
pub fn camera(set: &OrganSet, layout: &Layout, organ: usize) -> Navigator {
    let b = set.organs[organ].mesh().bounds().transformed(&layout.organs[organ].transform.matrix());
    let x = (b.min[0] + b.max[0]) / 2.0;
    let (az, el) = if x < -8.0 {
        (-90.0, 10.0)
    } else if x > 8.0 {
        (90.0, 10.0)
    } else {
        (-60.0, 20.0)
    };
    let whole = Navigator::framing(&layout.bounds(set), az, el);
    let mut nav = Navigator::framing(&b, az, el);
    nav.distance = (nav.distance * 3.0).clamp(whole.distance * 0.55, whole.distance);
    nav
}

/// How faint the organs that hide a target are made.
pub const FADED: f32 = 0.15;

/// The share of a target's own pixels that must be seen for it to count as revealed.
pub const SEEN_SHARE: f32 = 0.5;

/// How many times [`reveal`] fades what still hides a target (one layer of organs each).
pub const ROUNDS: usize = 8;

/// `layout` with the organs that hide `organ` faded to [`FADED`], found from organ-ID buffers:
/// `ids(layout)` renders one from the question's camera, treating organs fainter than a half as
/// see-through (as picking does). The organ is shown opaque; the organs drawn over its own pixels
/// (those it covers when drawn alone) are faded, again until at least [`SEEN_SHARE`] of them show
/// it, at most [`ROUNDS`] times. Returns the layout and the share of its pixels seen.
pub fn reveal(organ: usize, layout: &Layout, mut ids: impl FnMut(&Layout) -> Vec<u32>) -> (Layout, f32) {
    let mut out = layout.clone();
    out.organs[organ].visible = true;
    out.organs[organ].opacity = 1.0;
    let mut alone = out.clone();
    for (k, s) in alone.organs.iter_mut().enumerate() {
        s.visible = k == organ;
    }
    let own: Vec<usize> =
        ids(&alone).iter().enumerate().filter(|(_, &id)| id as usize == organ + 1).map(|(i, _)| i).collect();
    if own.is_empty() {
        return (out, 0.0);
    }
    let mut share = 0.0;
    for _ in 0..ROUNDS {
        let seen = ids(&out);
        let shown = own.iter().filter(|&&i| seen.get(i) == Some(&(organ as u32 + 1))).count();
        share = shown as f32 / own.len() as f32;
        if share >= SEEN_SHARE {
            break;
        }
        for &i in &own {
            match seen.get(i).map(|&id| id as usize) {
                Some(id) if id > 0 && id != organ + 1 => out.organs[id - 1].opacity = FADED,
                _ => {}
            }
        }
    }
    (out, share)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Mesh;
    use crate::organ_set::Organ;

    fn set() -> OrganSet {
        let organ = |id: &str, name: &str, group: &str, at: [f32; 3]| {
            let mut mesh = Mesh::octahedron();
            mesh.positions.iter_mut().for_each(|p| *p = [p[0] + at[0], p[1] + at[1], p[2] + at[2]]);
            let mut o = Organ::new(id.into(), name.into(), [0.5; 3], mesh);
            o.group = group.into();
            o
        };
        let mut caudate = organ("caudate_l", "Left caudate nucleus", "Basal ganglia/Left", [-12.0, 10.0, 10.0]);
        caudate.latin = Some("Nucleus caudatus".into());
        caudate.synonyms = vec!["caudate".into()];
        OrganSet {
            organs: vec![
                caudate,
                organ("putamen_l", "Left putamen", "Basal ganglia/Left", [-25.0, 2.0, 0.0]),
                organ("pallidum_l", "Left globus pallidus", "Basal ganglia/Left", [-19.0, -2.0, 0.0]),
                organ("caudate_r", "Right caudate nucleus", "Basal ganglia/Right", [12.0, 10.0, 10.0]),
                organ("cuneus_l", "Left cuneus", "Occipital lobe", [-8.0, -80.0, 20.0]),
                organ("precuneus_l", "Left precuneus", "Parietal lobe", [-8.0, -60.0, 40.0]),
                organ("thalamus_l", "Left thalamus", "Diencephalon", [-10.0, -15.0, 5.0]),
            ],
            ..Default::default()
        }
    }

    #[test]
    fn supply_questions_offer_four_arteries_with_the_supplier_among_them() {
        use crate::organ_set::territory::{Artery, Territories};
        let mut set = set();
        assert!(generate(&set, &Spec { scope: vec![0, 1, 2], questions: 2, mode: Mode::Supply, seed: 1 }).is_err());
        let artery = |key: &str| Artery {
            key: key.into(),
            name: key.into(),
            short: key.into(),
            latin: String::new(),
            colour: [0.5; 3],
            synonyms: Vec::new(),
            info: "A. B.".into(),
            is_artery: key != "none",
        };
        let arteries = ["aca", "mca", "pca", "sca", "none"].map(artery).to_vec();
        // x < 0: the left MCA (id 3); x >= 0: the right PCA (id 6); 100 mm voxels.
        let to_world = glam::Mat4::from_translation(glam::Vec3::new(-50.0, 0.0, 0.0))
            * glam::Mat4::from_scale(glam::Vec3::new(100.0, 1000.0, 1000.0));
        set.territories = Some(std::sync::Arc::new(Territories::from_parts(arteries, [2, 1, 1], to_world, vec![3, 6])));
        assert_eq!((supplier(&set, 0), supplier(&set, 3)), (Some(1), Some(2)), "left caudate MCA, right PCA");
        for seed in 0..20 {
            let spec = Spec { scope: (0..set.organs.len()).collect(), questions: 5, mode: Mode::Supply, seed };
            let quiz = generate(&set, &spec).unwrap();
            assert_eq!(quiz.questions.len(), 5);
            for q in &quiz.questions {
                assert_eq!(q.kind, Kind::Supply);
                let answer = supplier(&set, q.organ).unwrap();
                let mut choices = q.choices.clone();
                assert!(choices.contains(&answer), "{choices:?} lacks {answer}");
                choices.sort_unstable();
                assert_eq!(choices, [0, 1, 2, 3], "four distinct true arteries, never \"none\"");
            }
        }
    }

    #[test]
    fn every_question_has_one_right_answer_among_distinct_near_choices() {
        let set = set();
        for seed in 0..200 {
            let scope: Vec<usize> = (0..set.organs.len()).filter(|&o| seed % 3 != 0 || o < 3).collect();
            // Supply questions need territories: tested below.
            let modes = [Mode::Locate, Mode::Name, Mode::Mixed, Mode::Mri];
            let mode = modes[seed as usize % modes.len()];
            let spec = Spec { scope: scope.clone(), questions: 1 + seed as usize % 9, mode, seed };
            let quiz = generate(&set, &spec).unwrap();
            assert_eq!(generate(&set, &spec).unwrap(), quiz, "a seed gives the same quiz");
            assert_eq!(quiz.questions.len(), spec.questions.min(scope.len()));
            assert_eq!(quiz.note.is_some(), spec.questions > scope.len());
            let mut asked: Vec<usize> = quiz.questions.iter().map(|q| q.organ).collect();
            asked.sort_unstable();
            asked.dedup();
            assert_eq!(asked.len(), quiz.questions.len(), "each organ asked once");
            for q in &quiz.questions {
                assert!(scope.contains(&q.organ));
                assert_eq!(q.choices.len(), CHOICES);
                assert_eq!(q.choices.iter().filter(|&&c| c == q.organ).count(), 1, "one right answer");
                let names: Vec<&str> = q.choices.iter().map(|&c| set.organs[c].name.as_str()).collect();
                for (i, n) in names.iter().enumerate() {
                    assert!(!names[i + 1..].contains(n), "distinct choices {names:?}");
                    let accepted = q.choices.iter().filter(|&&c| accepts(&set, q.organ, &set.organs[c].name));
                    assert_eq!(accepted.count(), 1, "only the answer's name is accepted: {n}");
                }
                if q.organ == 0 {
                    let near = &q.choices;
                    assert!(near.contains(&1) && near.contains(&2), "the caudate's own group first: {near:?}");
                    assert!(!near.contains(&4), "not the far-away cuneus: {near:?}");
                }
            }
            match spec.mode {
                Mode::Locate => assert!(quiz.questions.iter().all(|q| q.kind == Kind::Locate)),
                Mode::Name => assert!(quiz.questions.iter().all(|q| q.kind == Kind::Name)),
                Mode::Mixed | Mode::Mri => {
                    assert!(quiz.questions.len() < 2 || quiz.questions[1].kind == Kind::Name)
                }
                Mode::Supply => unreachable!(),
            }
            let sliced = quiz.questions.iter().all(|q| q.slice.is_some());
            assert_eq!(sliced, spec.mode == Mode::Mri, "questions on slices only in the MRI mode");
        }
    }

    #[test]
    fn typed_names_are_forgiven_small_slips_but_not_the_wrong_side() {
        let set = set();
        for ok in [
            "Left caudate nucleus",
            "left  CAUDATE nucleus",
            "caudate",
            "Nucleus caudatus",
            "caudate nucleus",
            "Left caudate nucleos",
            "caudate_l",
            "Caudaté",
        ] {
            assert!(accepts(&set, 0, ok), "{ok}");
        }
        for bad in ["Right caudate nucleus", "putamen", "", "  ", "nucleus", "cuneus", "left"] {
            assert!(!accepts(&set, 0, bad), "{bad}");
        }
        assert!(!accepts(&set, 4, "precuneus") && accepts(&set, 5, "precuneus"));
        assert_eq!(levenshtein("kitten", "sitting"), 3);
        assert_eq!(levenshtein("", "abc"), 3);
    }

    #[test]
    fn bad_scopes_say_why() {
        let set = set();
        assert!(scope(&set, Some("nonesuch")).unwrap_err().contains("no organ or group"));
        assert!(scope(&set, Some("Diencephalon")).unwrap_err().contains("at least two"));
        assert_eq!(scope(&set, Some("Basal ganglia")).unwrap(), vec![0, 1, 2, 3]);
        assert!(generate(&set, &Spec { scope: vec![1], questions: 3, mode: Mode::Name, seed: 1 }).is_err());
    }

    #[test]
    fn reveal_fades_exactly_what_covers_the_target() {
        // A 1-D "screen" of 10 pixels: organ 0 on pixels 3..6, organ 1 covering 2..5, organ 2 on
        // 7..9 apart. Faded organs are see-through.
        let set = set();
        let layout = Layout::new(&set);
        let ids = |l: &Layout| {
            let mut px = vec![0u32; 10];
            let solid = |o: usize| l.organs[o].visible && l.organs[o].opacity >= 0.5;
            for (o, range) in [(0usize, 3..6), (2, 7..9), (1, 2..5)] {
                if solid(o) {
                    range.for_each(|i| px[i] = o as u32 + 1);
                }
            }
            px
        };
        let (out, share) = reveal(0, &layout, ids);
        assert_eq!(share, 1.0);
        assert_eq!(out.organs[1].opacity, FADED, "the organ in front is faded");
        assert_eq!(out.organs[2].opacity, 1.0, "the one beside it is not");
    }
}
