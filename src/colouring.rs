//! What colours the organs: each its own colour, its lobe's, or the arterial territory at each
//! point (issue: blood supply and pathways).
//!
//! - Colours are sRGB components in 0..=1, as in the layout.
//! - A lobe is an organ's group path without its side ("Cerebrum/Left hemisphere/Frontal lobe" and
//!   "Cerebrum/Right hemisphere/Frontal lobe" are "Cerebrum/Frontal lobe"), so both hemispheres'
//!   lobes match.
//! - Territories colour per vertex (see [`crate::organ_set::territory`]); an organ or a vertex
//!   without one shows [`UNSUPPLIED`], so what the atlas colours stands out.

use crate::layout::{ColourBy, Layout};
use crate::organ_set::OrganSet;

/// The colour of what no territory covers, in territory colouring: a light neutral grey.
pub const UNSUPPLIED: [f32; 3] = [0.72, 0.72, 0.70];

/// Colours of the lobes of the cerebrum as textbooks draw them (frontal blue, parietal yellow,
/// temporal green, occipital red), and of the parts around them in hues those leave free; other
/// groups take [`crate::organ_set::distinct_colour`]s.
const LOBES: [(&str, [f32; 3]); 8] = [
    ("Frontal lobe", [0.30, 0.52, 0.86]),
    ("Parietal lobe", [0.93, 0.80, 0.30]),
    ("Temporal lobe", [0.38, 0.72, 0.38]),
    ("Occipital lobe", [0.86, 0.36, 0.36]),
    ("Insula", [0.95, 0.58, 0.22]),
    ("Cingulate gyrus", [0.64, 0.46, 0.82]),
    ("Cerebellum", [0.80, 0.58, 0.50]),
    ("Brainstem", [0.62, 0.62, 0.76]),
];

/// An organ's lobe: its group path without the parts that name a side.
pub fn lobe(group: &str) -> String {
    let sided = |p: &str| {
        let first = p.split(' ').next().unwrap_or("");
        first == "Left" || first == "Right"
    };
    group.split('/').filter(|p| !p.is_empty() && !sided(p)).collect::<Vec<_>>().join("/")
}

/// The set's lobes in the order their first organ comes, each with its colour.
pub fn lobes(set: &OrganSet) -> Vec<(String, [f32; 3])> {
    let mut out: Vec<(String, [f32; 3])> = Vec::new();
    let mut others = 0;
    for organ in &set.organs {
        let key = lobe(&organ.group);
        if out.iter().any(|(k, _)| *k == key) {
            continue;
        }
        let last = key.rsplit('/').next().unwrap_or("");
        let colour = match LOBES.iter().find(|(name, _)| *name == last) {
            Some((_, c)) => *c,
            None => {
                others += 1;
                crate::organ_set::distinct_colour(others + 3)
            }
        };
        out.push((key, colour));
    }
    out
}

/// The colour each organ is drawn in, index-aligned with the set: the layout's in organ
/// colouring, the lobe's in lobe colouring, [`UNSUPPLIED`] in territory colouring (where vertices
/// with a territory take its colour instead).
pub fn organ_colours(set: &OrganSet, layout: &Layout) -> Vec<[f32; 3]> {
    match layout.colour_by {
        ColourBy::Organ => layout.organs.iter().map(|s| s.colour).collect(),
        ColourBy::Lobe => {
            let lobes = lobes(set);
            let of = |group: &str| {
                let key = lobe(group);
                lobes.iter().find(|(k, _)| *k == key).map_or(UNSUPPLIED, |(_, c)| *c)
            };
            (0..layout.organs.len()).map(|i| set.organs.get(i).map_or(UNSUPPLIED, |o| of(&o.group))).collect()
        }
        ColourBy::Territory => vec![UNSUPPLIED; layout.organs.len()],
    }
}

/// What the legend lists: (name, colour) of each lobe of the drawn organs, or each artery of the
/// set's territories by its short name ("MCA frontal"); empty in organ colouring.
pub fn legend(set: &OrganSet, layout: &Layout) -> Vec<(String, [f32; 3])> {
    match layout.colour_by {
        ColourBy::Organ => Vec::new(),
        ColourBy::Lobe => {
            let drawn: Vec<String> = set
                .organs
                .iter()
                .zip(&layout.organs)
                .filter(|(_, s)| s.is_drawn())
                .map(|(o, _)| lobe(&o.group))
                .collect();
            lobes(set)
                .into_iter()
                .filter(|(k, _)| drawn.contains(k))
                .map(|(k, c)| (k.rsplit('/').next().unwrap_or(&k).to_string(), c))
                .collect()
        }
        ColourBy::Territory => {
            let Some(t) = &set.territories else { return Vec::new() };
            let name = |a: &crate::organ_set::territory::Artery| match a.is_artery {
                true => a.short.clone(),
                false => format!("{} (no artery)", a.short),
            };
            t.arteries.iter().map(|a| (name(a), a.colour)).collect()
        }
    }
}

/// The colour of each vertex of a mesh in territory colouring: its territory's, or `None` where no
/// territory covers it; `None` for the whole mesh where the organ takes no territories
/// ([`crate::organ_set::territory::Territories::of_mesh`]).
pub fn territory_colours(
    territories: &crate::organ_set::territory::Territories,
    mesh: &crate::mesh::Mesh,
) -> Option<Vec<Option<[f32; 3]>>> {
    let ids = territories.of_mesh(mesh)?;
    let table: Vec<Option<[f32; 3]>> = (0..=u8::MAX).map(|id| territories.artery(id).map(|(a, _)| a.colour)).collect();
    Some(ids.iter().map(|&id| table[id as usize]).collect())
}

/// [`territory_colours`] packed for the GPU: sRGB bytes r, g, b, 255 from the low byte up, 0 where
/// a vertex has no territory.
pub fn packed_territory_colours(
    territories: &crate::organ_set::territory::Territories,
    mesh: &crate::mesh::Mesh,
) -> Option<Vec<u32>> {
    let pack = |c: [f32; 3]| {
        let b = c.map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u32);
        b[0] | b[1] << 8 | b[2] << 16 | 255 << 24
    };
    Some(territory_colours(territories, mesh)?.into_iter().map(|c| c.map_or(0, pack)).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lobes_match_across_sides_and_keep_their_textbook_colours() {
        assert_eq!(lobe("Cerebrum/Left hemisphere/Frontal lobe"), "Cerebrum/Frontal lobe");
        assert_eq!(lobe("Basal ganglia/Right"), "Basal ganglia");
        assert_eq!(lobe("Brainstem"), "Brainstem");
        assert_eq!(lobe(""), "");
        for c in ColourBy::ALL {
            assert_eq!(ColourBy::parse(c.name()), Some(c));
            let json = serde_json::to_string(&c).unwrap_or_default();
            assert_eq!(json, format!("\"{}\"", c.name()));
        }
        assert_eq!(ColourBy::parse("lobes"), None);
    }

    #[test]
    fn organ_colours_follow_the_colouring() {
        use crate::mesh::Mesh;
        use crate::organ_set::Organ;
        let mut organs: Vec<Organ> = ["a", "b", "c"]
            .iter()
            .map(|id| Organ::new(id.to_string(), id.to_string(), [0.1, 0.2, 0.3], Mesh::octahedron()))
            .collect();
        organs[0].group = "Cerebrum/Left hemisphere/Frontal lobe".into();
        organs[1].group = "Cerebrum/Right hemisphere/Frontal lobe".into();
        organs[2].group = "Cerebellum/Left".into();
        let set = OrganSet { organs, ..Default::default() };
        let mut layout = Layout::new(&set);
        assert_eq!(organ_colours(&set, &layout), vec![[0.1, 0.2, 0.3]; 3]);
        layout.colour_by = ColourBy::Lobe;
        let c = organ_colours(&set, &layout);
        assert_eq!(c[0], LOBES[0].1);
        assert_eq!(c[0], c[1], "both frontal lobes match");
        assert_ne!(c[2], c[0]);
        let names: Vec<String> = legend(&set, &layout).into_iter().map(|(n, _)| n).collect();
        assert_eq!(names, ["Frontal lobe", "Cerebellum"]);
        layout.colour_by = ColourBy::Territory;
        assert_eq!(organ_colours(&set, &layout), vec![UNSUPPLIED; 3]);
        assert!(legend(&set, &layout).is_empty(), "the set has no territories");
    }
}
