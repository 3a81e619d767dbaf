//! Finding organs by any of their names, and groups by a run of their path.
//!
//! - An organ's names are the English name, the id, Terminologia Anatomica's Latin name and the
//!   synonyms, compared case- and accent-insensitively ("Broca", "gyrus precentralis", "Heschl"
//!   all find their organs).
//! - A group is found by a run of its path ("Frontal lobe", "Left hemisphere/Frontal lobe").

use super::Organ;
use unicode_normalization::UnicodeNormalization;

/// `s` in the form names are compared in: decomposed, without combining marks, lower case, runs of
/// whitespace, `-` and `_` as one space, an apostrophe dropped ("Broca's" and "brocas" alike).
pub fn fold(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.nfd().filter(|c| !unicode_normalization::char::is_combining_mark(*c)) {
        match c {
            '\'' | '\u{2019}' => {}
            c if c.is_whitespace() || c == '-' || c == '_' => {
                if !out.is_empty() && !out.ends_with(' ') {
                    out.push(' ');
                }
            }
            c => out.extend(c.to_lowercase()),
        }
    }
    let trimmed = out.trim_end().len();
    out.truncate(trimmed);
    out
}

/// Every name of an organ: its name, id, Latin name and synonyms.
pub fn names(organ: &Organ) -> impl Iterator<Item = &str> {
    [organ.name.as_str(), organ.id.as_str()]
        .into_iter()
        .chain(organ.latin.as_deref())
        .chain(organ.synonyms.iter().map(String::as_str))
}

/// Does any name of `organ` contain `query` (folded)? An empty query matches every organ.
pub fn matches(organ: &Organ, query: &str) -> bool {
    matches_folded(organ, &fold(query))
}

/// [`matches()`] with the query already [`fold`]ed, for searching many organs with one query.
pub fn matches_folded(organ: &Organ, folded: &str) -> bool {
    folded.is_empty() || names(organ).any(|n| fold(n).contains(folded))
}

/// Is the organ in the group `path`: do `path`'s `/`-separated parts (folded) appear as a run of
/// consecutive parts of the organ's group? "Frontal lobe" names both hemispheres' frontal lobes,
/// "Left hemisphere" everything under it, "Cerebrum/Left hemisphere/Frontal lobe" one lobe.
pub fn in_group(organ: &Organ, path: &str) -> bool {
    let parts = |s: &str| s.split('/').map(fold).filter(|p| !p.is_empty()).collect::<Vec<_>>();
    let (group, run) = (parts(&organ.group), parts(path));
    !run.is_empty() && group.windows(run.len()).any(|w| w == run.as_slice())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Mesh;

    fn organ() -> Organ {
        let mut o = Organ::new("precentral_l".into(), "Left precentral gyrus".into(), [1.0; 3], Mesh::octahedron());
        o.latin = Some("Gyrus precentralis".into());
        o.synonyms = vec!["M1".into(), "primary motor cortex".into(), "Broca's area".into()];
        o
    }

    #[test]
    fn any_name_matches_whatever_its_case_and_accents() {
        let o = organ();
        for q in ["precentral", "PRECENTRAL", "gyrus précentralis", "m1", "Brocas", "broca’s area", "precentral_l", ""]
        {
            assert!(matches(&o, q), "{q}");
        }
        for q in ["postcentral", "M2", "gyrus postcentralis"] {
            assert!(!matches(&o, q), "{q}");
        }
        assert_eq!(fold("  Heschl's  gyrus-Ü "), "heschls gyrus u");
    }

    #[test]
    fn a_group_is_found_by_any_run_of_its_path() {
        let mut o = organ();
        o.group = "Cerebrum/Left hemisphere/Frontal lobe".into();
        for path in
            ["Frontal lobe", "frontal LOBE", "Left hemisphere", "left hemisphere/frontal lobe", o.group.as_str()]
        {
            assert!(in_group(&o, path), "{path}");
        }
        for path in ["Frontal", "Right hemisphere", "Cerebrum/Frontal lobe", "", "/"] {
            assert!(!in_group(&o, path), "{path}");
        }
    }
}
