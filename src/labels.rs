//! Labels for figures, as pure functions: an anchor per organ on its visible surface, and a
//! placement of the label texts in two columns beside the brain's silhouette.
//!
//! - Screen pixels, origin top left, y down.
//! - An anchor is chosen from the organ-ID buffer as the pixel farthest from any other organ or
//!   the background, so it sits well inside what is seen and moves little when the camera does.
//! - Labels go left of the silhouette for anchors in its left half and right of it for the
//!   others, each column in the order of its anchors from top to bottom, then reordered where
//!   leader lines would cross.
//! - Placed labels never overlap each other, stay within the image and, where the image leaves
//!   room beside the silhouette, never cover it or an anchor.
//! - Labels that do not fit (too many for a column, or columns that meet in a narrow image) are
//!   left out, the smallest organs first.
//! - While the camera moves, each organ keeps its last anchor as long as that stays deep inside
//!   the organ ([`anchors_near`]), so labels do not jump.
//! - [`Which`] names the organs a figure labels, as scene files, lessons and `render --labels` do.

/// Which organs a figure labels: the `labels` key of scene files and lesson steps and the value
/// of `render --labels` (`none`, `selected`, `all` or ids and groups separated by commas).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum Which {
    #[default]
    None,
    /// The selected organ.
    Selected,
    /// Every organ seen.
    All,
    /// These ids or groups.
    Chosen(Vec<String>),
}

impl Which {
    pub fn parse(text: &str) -> Which {
        match text.trim() {
            "" | "none" => Which::None,
            "selected" => Which::Selected,
            "all" => Which::All,
            list => Which::Chosen(list.split(',').map(str::trim).filter(|k| !k.is_empty()).map(String::from).collect()),
        }
    }

    /// The text [`Which::parse`] reads back; `None` for no labels.
    pub fn key(&self) -> Option<String> {
        match self {
            Which::None => None,
            Which::Selected => Some("selected".into()),
            Which::All => Some("all".into()),
            Which::Chosen(list) if list.is_empty() => None,
            Which::Chosen(list) => Some(list.join(",")),
        }
    }

    /// The chosen organs of `set` (indices, in the set's order) for ids and groups; the names the
    /// set lacks come back apart.
    pub fn chosen(names: &[String], set: &crate::organ_set::OrganSet) -> (Vec<usize>, Vec<String>) {
        let mut organs = Vec::new();
        let mut unknown = Vec::new();
        for n in names {
            let found = set.select(n);
            if found.is_empty() {
                unknown.push(n.clone());
            }
            organs.extend(found);
        }
        organs.sort_unstable();
        organs.dedup();
        (organs, unknown)
    }
}

/// An organ's anchor: where its label points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Anchor {
    pub organ: usize,
    /// Pixel centre.
    pub at: [f32; 2],
    /// How many pixels of the organ are visible.
    pub pixels: usize,
}

/// A placed label: its organ, anchor and text rectangle (min x, min y, max x, max y).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placed {
    pub organ: usize,
    pub anchor: [f32; 2],
    pub rect: [f32; 4],
}

/// Per visible organ of an ID buffer (organ index + 1 per pixel, 0 background), the pixel farthest
/// (in chessboard steps) from a pixel of another organ, the background or the image's edge;
/// ties go to the first in reading order. Organs in the set's order.
pub fn anchors(ids: &[u32], width: usize, height: usize) -> Vec<Anchor> {
    anchors_near(ids, width, height, &[])
}

/// How deep (against the deepest pixel of its organ) a previous anchor must still lie to be kept.
pub const KEEP_DEPTH: f32 = 0.7;

/// As [`anchors`], but an organ's `previous` anchor (the last frame's) is kept where it still lies
/// on the organ at least [`KEEP_DEPTH`] as deep as its deepest pixel: a label does not jump
/// between two nearly equally deep places while the camera moves a little.
pub fn anchors_near(ids: &[u32], width: usize, height: usize, previous: &[Anchor]) -> Vec<Anchor> {
    if ids.len() != width * height || ids.is_empty() {
        return Vec::new();
    }
    let d = depth(ids, width, height);
    let organs = ids.iter().copied().max().unwrap_or(0) as usize;
    let mut best: Vec<Option<(u32, usize)>> = vec![None; organs];
    let mut count = vec![0usize; organs];
    for (i, &id) in ids.iter().enumerate() {
        if id == 0 {
            continue;
        }
        let o = id as usize - 1;
        count[o] += 1;
        if best[o].is_none_or(|(bd, _)| d[i] > bd) {
            best[o] = Some((d[i], i));
        }
    }
    let kept = |o: usize, deepest: u32| {
        let p = previous.iter().find(|a| a.organ == o)?;
        let (x, y) = (p.at[0].floor(), p.at[1].floor());
        if x < 0.0 || y < 0.0 || x >= width as f32 || y >= height as f32 {
            return None;
        }
        let i = y as usize * width + x as usize;
        (ids[i] as usize == o + 1 && d[i] as f32 >= KEEP_DEPTH * deepest as f32).then_some(i)
    };
    best.iter()
        .enumerate()
        .filter_map(|(o, b)| {
            b.map(|(deepest, i)| {
                let i = kept(o, deepest).unwrap_or(i);
                Anchor { organ: o, at: [(i % width) as f32 + 0.5, (i / width) as f32 + 0.5], pixels: count[o] }
            })
        })
        .collect()
}

/// Two-pass chamfer distance per pixel to the nearest pixel with another id (the image's outside
/// counts as other); 0 on the background.
fn depth(ids: &[u32], width: usize, height: usize) -> Vec<u32> {
    let mut d = vec![u32::MAX / 2; ids.len()];
    let at = |x: usize, y: usize| y * width + x;
    for pass in 0..2 {
        let ys: Vec<usize> = if pass == 0 { (0..height).collect() } else { (0..height).rev().collect() };
        let xs: Vec<usize> = if pass == 0 { (0..width).collect() } else { (0..width).rev().collect() };
        for &y in &ys {
            for &x in &xs {
                let i = at(x, y);
                if ids[i] == 0 {
                    d[i] = 0;
                    continue;
                }
                let edge = x == 0 || y == 0 || x + 1 == width || y + 1 == height;
                let mut best = if edge { 1 } else { d[i] };
                let (dx, dy): (isize, isize) = if pass == 0 { (-1, -1) } else { (1, 1) };
                for (ox, oy) in [(dx, 0), (0, dy), (dx, dy), (-dx, dy)] {
                    let (nx, ny) = (x as isize + ox, y as isize + oy);
                    if nx < 0 || ny < 0 || nx >= width as isize || ny >= height as isize {
                        continue;
                    }
                    let n = at(nx as usize, ny as usize);
                    let step = if ids[n] == ids[i] { d[n] + 1 } else { 1 };
                    best = best.min(step);
                }
                d[i] = best;
            }
        }
    }
    d
}

/// Places labels of text sizes `sizes[k]` (width, height in pixels) for `anchors[k]` beside
/// `silhouette` (min x, min y, max x, max y) in an image of `image` pixels, `gap` pixels from the
/// silhouette and apart from each other.
pub fn place(anchors: &[Anchor], sizes: &[[f32; 2]], silhouette: [f32; 4], image: [f32; 2], gap: f32) -> Vec<Placed> {
    let centre = (silhouette[0] + silhouette[2]) / 2.0;
    let mut out = Vec::new();
    for left in [true, false] {
        let mut column: Vec<(Anchor, [f32; 2])> = anchors
            .iter()
            .zip(sizes)
            .filter(|(a, s)| (a.at[0] < centre) == left && s[0] > 0.0 && s[1] > 0.0 && s[0] <= image[0])
            .map(|(a, s)| (*a, *s))
            .collect();
        // Too many for the column's height: the smallest organs go first.
        let fits = |c: &[(Anchor, [f32; 2])]| c.iter().map(|(_, s)| s[1] + gap).sum::<f32>() <= image[1];
        while !fits(&column) {
            let smallest = column.iter().enumerate().min_by_key(|(_, (a, _))| a.pixels).map(|(k, _)| k);
            column.remove(smallest.unwrap_or(0));
        }
        column.sort_by(|a, b| a.0.at[1].total_cmp(&b.0.at[1]).then(a.0.organ.cmp(&b.0.organ)));
        // Top to bottom at the anchors' heights, pushed down to clear the one above, then up from
        // the image's bottom edge.
        let mut tops: Vec<f32> = Vec::with_capacity(column.len());
        for (k, (a, s)) in column.iter().enumerate() {
            let wanted = (a.at[1] - s[1] / 2.0).max(gap / 2.0);
            let below = if k == 0 { wanted } else { wanted.max(tops[k - 1] + column[k - 1].1[1] + gap) };
            tops.push(below);
        }
        let mut limit = image[1] - gap / 2.0;
        for k in (0..column.len()).rev() {
            let h = column[k].1[1];
            tops[k] = tops[k].min(limit - h).max(0.0);
            limit = tops[k] - gap;
        }
        let x = |s: &[f32; 2]| {
            if left {
                (silhouette[0] - gap - s[0]).max(0.0)
            } else {
                (silhouette[2] + gap).min(image[0] - s[0])
            }
        };
        // Leader lines that cross swap their labels' places (of labels one height whose lines end
        // on one vertical, not pushed in by the image's edge): each swap shortens the lines in
        // all, so this ends.
        let end = |k: usize, top: f32| {
            let s = column[k].1;
            [if left { x(&s) + s[0] } else { x(&s) }, top + s[1] / 2.0]
        };
        for _ in 0..column.len() * column.len() {
            let mut swapped = false;
            for i in 0..column.len() {
                for j in i + 1..column.len() {
                    let (a, b) = (column[i].0.at, column[j].0.at);
                    let (ei, ej) = (end(i, tops[i]), end(j, tops[j]));
                    if column[i].1[1] == column[j].1[1] && ei[0] == ej[0] && crosses([a, ei], [b, ej]) {
                        tops.swap(i, j);
                        swapped = true;
                    }
                }
            }
            if !swapped {
                break;
            }
        }
        for ((a, s), top) in column.iter().zip(tops) {
            let x = x(s);
            out.push(Placed { organ: a.organ, anchor: a.at, rect: [x, top, x + s[0], top + s[1]] });
        }
    }
    // Where the image is too narrow for both columns beside the silhouette they may meet: of two
    // labels that overlap, the smaller organ's goes.
    let pixels = |organ: usize| anchors.iter().find(|a| a.organ == organ).map_or(0, |a| a.pixels);
    let mut keep = vec![true; out.len()];
    for i in 0..out.len() {
        for j in i + 1..out.len() {
            if keep[i] && keep[j] && overlap(&out[i].rect, &out[j].rect) {
                let drop = if pixels(out[i].organ) < pixels(out[j].organ) { i } else { j };
                keep[drop] = false;
            }
        }
    }
    out.into_iter().zip(keep).filter_map(|(p, k)| k.then_some(p)).collect()
}

/// The bounds (min x, min y, max x, max y) of the pixels an ID buffer `width` wide shows organs
/// in; `None` if it shows none.
pub fn silhouette(ids: &[u32], width: usize) -> Option<[f32; 4]> {
    let mut b: Option<[f32; 4]> = None;
    for (i, _) in ids.iter().enumerate().filter(|(_, &id)| id != 0) {
        let (x, y) = ((i % width.max(1)) as f32, (i / width.max(1)) as f32);
        let r = b.get_or_insert([x, y, x + 1.0, y + 1.0]);
        *r = [r[0].min(x), r[1].min(y), r[2].max(x + 1.0), r[3].max(y + 1.0)];
    }
    b
}

/// Do two segments cross (touching at an end does not count)?
pub fn crosses(p: [[f32; 2]; 2], q: [[f32; 2]; 2]) -> bool {
    let side = |a: [f32; 2], b: [f32; 2], c: [f32; 2]| (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    let (d1, d2) = (side(p[0], p[1], q[0]), side(p[0], p[1], q[1]));
    let (d3, d4) = (side(q[0], q[1], p[0]), side(q[0], q[1], p[1]));
    d1 * d2 < 0.0 && d3 * d4 < 0.0
}

/// Do two rectangles overlap (touching edges do not)?
pub fn overlap(a: &[f32; 4], b: &[f32; 4]) -> bool {
    a[0] < b[2] && b[0] < a[2] && a[1] < b[3] && b[1] < a[3]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::XorShift;

    #[test]
    fn label_choices_read_back() {
        for text in ["selected", "all", "caudate_l,Basal ganglia"] {
            assert_eq!(Which::parse(text).key().as_deref(), Some(text));
        }
        assert_eq!(Which::parse(" none "), Which::None);
        assert_eq!(Which::parse("a, b,,"), Which::Chosen(vec!["a".into(), "b".into()]));
        assert_eq!(Which::None.key(), None);
    }

    #[test]
    fn anchors_sit_deep_inside_what_is_seen() {
        // A 9x5 organ 1 with a 3x3 organ 2 inside at its right.
        let (w, h) = (11, 7);
        let mut ids = vec![0u32; w * h];
        for y in 1..6 {
            for x in 1..10 {
                ids[y * w + x] = 1;
            }
        }
        for y in 2..5 {
            for x in 6..9 {
                ids[y * w + x] = 2;
            }
        }
        let a = anchors(&ids, w, h);
        assert_eq!(a.len(), 2);
        assert_eq!(a[1].at, [7.5, 3.5], "the middle of organ 2");
        assert_eq!(a[0].pixels, 45 - 9);
        assert!(a[0].at[0] < 6.0, "organ 1's anchor is away from organ 2: {:?}", a[0].at);
    }

    #[test]
    fn anchors_stay_put_between_two_nearly_equal_places() {
        // One organ in two blobs, 9x9 and 8x8 pixels; each frame they swap sizes, so the deepest
        // pixel swaps blobs. With the last frame's anchor kept, the anchor does not jump.
        let (w, h) = (30, 11);
        let frame = |right_big: bool| {
            let mut ids = vec![0u32; w * h];
            let (left, right) = if right_big { (8, 9) } else { (9, 8) };
            for y in 1..=left {
                ids[y * w + 1..y * w + 1 + left].fill(1);
            }
            for y in 1..=right {
                ids[y * w + 15..y * w + 15 + right].fill(1);
            }
            ids
        };
        let mut last = anchors(&frame(false), w, h);
        let first = last[0].at;
        assert_eq!(first, [5.5, 5.5]);
        for k in 0..6 {
            let ids = frame(k % 2 == 0);
            assert_eq!(anchors(&ids, w, h)[0].at[0] > 10.0, k % 2 == 0, "alone, the anchor would jump");
            last = anchors_near(&ids, w, h, &last);
            assert_eq!(last[0].at, first, "frame {k}");
        }
        // Where the old place is no longer on the organ, the deepest pixel is taken.
        let mut gone = frame(true);
        gone.iter_mut().take(w * h).enumerate().filter(|(i, _)| i % w < 10).for_each(|(_, v)| *v = 0);
        assert!(anchors_near(&gone, w, h, &last)[0].at[0] > 15.0);
    }

    #[test]
    fn placed_labels_never_overlap_and_stay_in_the_image() {
        let mut rng = XorShift(7);
        let mut r = |a: f32, b: f32| a + (b - a) * (rng.next_u64() % 10_000) as f32 / 10_000.0;
        for _ in 0..200 {
            let image = [r(300.0, 2400.0), r(200.0, 1800.0)];
            let sil =
                [image[0] * r(0.2, 0.4), image[1] * r(0.05, 0.3), image[0] * r(0.6, 0.8), image[1] * r(0.7, 0.95)];
            let n = r(1.0, 60.0) as usize;
            let anchors: Vec<Anchor> = (0..n)
                .map(|organ| Anchor {
                    organ,
                    at: [r(sil[0], sil[2]), r(sil[1], sil[3])],
                    pixels: r(1.0, 5000.0) as usize,
                })
                .collect();
            let text = image[1] * 0.022;
            let sizes: Vec<[f32; 2]> = (0..n).map(|_| [text * r(3.0, 14.0), text * 1.3]).collect();
            let placed = place(&anchors, &sizes, sil, image, text * 0.4);
            assert!(!placed.is_empty());
            for (i, a) in placed.iter().enumerate() {
                let [x0, y0, x1, y1] = a.rect;
                assert!(x0 >= 0.0 && y0 >= 0.0 && x1 <= image[0] + 1e-3 && y1 <= image[1] + 1e-3, "{a:?} in {image:?}");
                for b in &placed[i + 1..] {
                    assert!(!overlap(&a.rect, &b.rect), "{a:?} overlaps {b:?}");
                    let end = |p: &Placed| {
                        let left = p.rect[2] <= p.anchor[0];
                        [if left { p.rect[2] } else { p.rect[0] }, (p.rect[1] + p.rect[3]) / 2.0]
                    };
                    // Beside the silhouette (not pushed in by the image's edge), lines never cross.
                    let clear = |p: &Placed| p.rect[2] <= p.anchor[0] || p.rect[0] >= p.anchor[0];
                    let beside = clear(a) && clear(b) && end(a)[0] == end(b)[0];
                    assert!(!beside || !crosses([a.anchor, end(a)], [b.anchor, end(b)]), "{a:?} crosses {b:?}");
                }
                for c in &placed {
                    let [ax, ay] = c.anchor;
                    assert!(
                        !(ax > x0 && ax < x1 && ay > y0 && ay < y1) || x0 <= 0.0 || x1 >= image[0] - 1e-3,
                        "a label covers an anchor"
                    );
                }
            }
        }
    }
}
