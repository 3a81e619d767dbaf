//! Masks regenerated every frame per screen region (thesis §4.3.4), as plain data for the
//! renderer: a configuration per region and, per configuration, one GPU mask per organ.
//!
//! - Organ meshes in organ space, moved into world space by the layout and projected by the
//!   camera; regions are squares of `region_px` screen pixels (x right, y down); depth is NDC z
//!   (larger is farther).
//! - A GPU mask's bit b is MSAA sample b % 4 of pass b / 4.
//! - Per frame:
//! 1. (`region_keys`) The leaves of each drawn transparent organ's hierarchy (at most 256
//!    triangles each) are projected; every region a leaf's screen rectangle (grown by a pixel, for
//!    MSAA samples and rounding, and by how far a pixel's region lookup moves) touches records the
//!    organ as present, with the nearest depth of the leaf's box (a row of regions at a time).
//!    Rectangles over-cover, so no organ drawn in a region is missed; box depths are a little
//!    near, which only matters for which organs count as the K nearest (the thesis notes that the
//!    compensation tolerates small depth changes within a region).
//! 2. A region's configuration is the set of organs present and its K nearest, nearest first (K at
//!    most what the masks' sub-samples resolve, [`followed_nearest`]).
//! 3. Each distinct configuration gets one generation: masks in the order K nearest (nearest
//!    first) then the rest by organ index, each compensating for the nearest generated before it.
//!    Configurations that begin alike share the masks they begin with ([`configuration_masks`]).
//!    The result depends on the configuration only, never on the order organs are drawn in.
//! 4. A [`MaskCache`] keeps the last frame's configurations and their masks: a configuration seen
//!    again with the same sub-samples, K, method and opacities of its organs is not generated
//!    again (most survive a small camera move or a slider dragged). It also keeps, per list of K
//!    nearest, what configurations with those K nearest share ([`AfterNearest`]). Masks depend on
//!    the configuration only, so the images do not change.

use super::layout::{self, GpuBits};
use super::region_keys::{covered_pixels, leaf_rects, region_keys, region_of, Grid};
use super::{generate, MaskMethod, MaskTable, SplitOrder};
use crate::camera::Camera;
use crate::layout::Layout;
use crate::organ_set::OrganSet;
use rayon::prelude::*;
use rustc_hash::FxHashMap;

#[derive(Clone, Copy, Debug)]
pub struct RegionParams {
    pub width: u32,
    pub height: u32,
    pub region_px: u32,
    /// Sub-samples per mask: 4 per pass, up to 64.
    pub subsamples: usize,
    pub k: usize,
    pub method: MaskMethod,
}

/// Per-region masks for one frame.
#[derive(Clone, Debug, Default)]
pub struct RegionMasks {
    pub region_px: u32,
    pub cols: u32,
    pub rows: u32,
    pub subsamples: usize,
    pub organ_count: usize,
    /// Configuration of each region, row-major.
    pub config_of_region: Vec<u32>,
    /// `masks[config * organ_count + organ]`: GPU mask bits of the organ in that configuration.
    pub masks: Vec<u64>,
    /// Distinct configurations (masks generated once each, or kept from the last frame).
    pub configs: usize,
    /// Of those, configurations whose masks were kept from the last frame.
    pub kept: usize,
    /// The pixels of the regions where a transparent organ is present, `[x, y, width, height]`
    /// (clamped to the image; zero width where none is): all that transparent organs can touch.
    pub covered: [u32; 4],
    /// Time to compute all of it, milliseconds.
    pub ms: f64,
}

impl RegionMasks {
    /// The mask of `organ` at pixel (x, y), for tests and inspection.
    pub fn mask_at(&self, x: u32, y: u32, organ: usize) -> u64 {
        let (c, r) = region_of(x, y, self.region_px, self.cols, self.rows);
        let config = self.config_of_region[(r * self.cols + c) as usize] as usize;
        self.masks[config * self.organ_count + organ]
    }
}

/// The masks of a configuration's organs: (organ, GPU mask) pairs.
pub type OrganMasks = Vec<(usize, u64)>;

/// Masks for one configuration: `present` organs (by index) of which `nearest` are the K nearest,
/// nearest first. Returns (organ, GPU mask) pairs.
pub fn config_masks(
    present: &[usize],
    nearest: &[usize],
    opacity: impl Fn(usize) -> f32 + Sync,
    p: &RegionParams,
    bits: &GpuBits,
) -> Vec<(usize, u64)> {
    configuration_masks(&[(present, nearest)], opacity, p, bits, &mut KnownMasks::default()).pop().unwrap_or_default()
}

/// Masks for configurations `(present, nearest)`, one list of (organ, GPU mask) per configuration.
/// Masks are generated in the order K nearest (nearest first), then the others by index.
///
/// For the tabular methods a mask depends only on the table the masks before it left, so
/// configurations are visited in the order of their K nearest and then of their others, and each
/// continues the tables of the longest runs it shares with the one before. Once every row of a
/// table holds one sub-sample, a mask no longer depends on the others before it, only on the K
/// nearest, so it is made once per K nearest. Configurations whose two nearest organs differ share
/// at most one mask; such runs are generated in parallel.
pub fn configuration_masks(
    configs: &[(&[usize], &[usize])],
    opacity: impl Fn(usize) -> f32 + Sync,
    p: &RegionParams,
    bits: &GpuBits,
    known: &mut KnownMasks,
) -> Vec<Vec<(usize, u64)>> {
    let others: Vec<Vec<usize>> = configs
        .iter()
        .map(|(present, nearest)| present.iter().copied().filter(|o| !nearest.contains(o)).collect())
        .collect();
    if !matches!(p.method, MaskMethod::Tabular | MaskMethod::TabularNec) {
        return configs
            .par_iter()
            .zip(&others)
            .map(|((_, nearest), others)| {
                let order: Vec<usize> = nearest.iter().chain(others).copied().collect();
                let alphas: Vec<f32> = order.iter().map(|&o| opacity(o)).collect();
                let seed = order.iter().fold(0x5eed_u64, |h, &o| h.wrapping_mul(0x100_0000_01b3) ^ o as u64);
                let (masks, _) = generate(p.method, p.subsamples, &alphas, |_| Default::default(), seed);
                order.iter().zip(&masks).map(|(&o, m)| (o, bits.of(m))).collect()
            })
            .collect();
    }
    let mut visit: Vec<usize> = (0..configs.len()).collect();
    visit.sort_by(|&a, &b| configs[a].1.cmp(configs[b].1).then_with(|| others[a].cmp(&others[b])));
    let runs: Vec<&[usize]> = visit.chunk_by(|&a, &b| configs[a].1.get(..2) == configs[b].1.get(..2)).collect();
    let was_known = &*known;
    let walk = |run: &&[usize]| -> (Vec<(usize, OrganMasks)>, KnownMasks, Vec<AfterFull>) {
        let k_most = run.iter().map(|&i| configs[i].1.len()).max().unwrap_or(0);
        let priorities: Vec<usize> = (0..k_most).collect();
        let nec = p.method == MaskMethod::TabularNec;
        let near_split = |j: usize| if nec { SplitOrder::Priorities(&priorities[..j]) } else { SplitOrder::Table };
        let other_split = |k: usize, o: usize| match nec {
            true => SplitOrder::Shuffled { priorities: &priorities[..k], seed: o as u64 + 1 },
            false => SplitOrder::Table,
        };
        let mut walked = Vec::with_capacity(run.len());
        // near[j]: the table after the first j nearest of the configuration visited last, and
        // others[d] after its first d others, up to the first saturated one, after which an
        // organ's mask depends on the organ alone (`after_full`). Both keep their tables'
        // allocations beyond their depths for reuse.
        let (mut near, mut near_depth) = (vec![MaskTable::new(p.subsamples)], 0);
        let (mut tables, mut depth) = (vec![MaskTable::new(p.subsamples)], 0);
        // What this run learns: each new list of K nearest, and the saturated-table masks made
        // after each list.
        let (mut after_full, mut learned, mut made) = (FxHashMap::default(), KnownMasks::default(), Vec::new());
        let mut known_here: Option<&AfterNearest> = None;
        let mut masks: Vec<(usize, u64)> = Vec::new();
        let (mut last_near, mut last_others): (Option<&[usize]>, &[usize]) = (None, &[]);
        for &i in run.iter() {
            let (nearest, mine) = (configs[i].1, others[i].as_slice());
            let k = nearest.len();
            if last_near != Some(nearest) {
                if let Some(last) = last_near.filter(|_| !after_full.is_empty()) {
                    made.push((last, std::mem::take(&mut after_full)));
                }
                known_here = was_known.get(nearest);
                if let Some(kept) = known_here {
                    // The near stack no longer holds the nearest visited last.
                    near_depth = 0;
                    masks.clone_from(&kept.masks);
                    tables[0].clone_from(&kept.table);
                } else {
                    near_depth = common_run(last_near.unwrap_or_default(), nearest).min(near_depth);
                    masks.truncate(near_depth);
                    for (j, &o) in nearest.iter().enumerate().skip(near_depth) {
                        let table = next_table(&mut near, j);
                        masks.push((o, bits.of(&table.add(opacity(o), near_split(j)))));
                    }
                    near_depth = k;
                    tables[0].clone_from(&near[k]);
                    let saturated = FxHashMap::default();
                    let after = AfterNearest { table: near[k].clone(), masks: masks.clone(), saturated };
                    learned.insert(nearest.to_vec(), after);
                }
                depth = 0;
                (last_near, last_others) = (Some(nearest), &[]);
            }
            depth = common_run(last_others, mine).min(depth);
            masks.truncate(k + depth);
            for &o in &mine[depth..] {
                if tables[depth].is_saturated() {
                    if let Some(&mask) = known_here.and_then(|m| m.saturated.get(&o)) {
                        masks.push((o, mask));
                        continue;
                    }
                    let table = &mut tables[depth];
                    let mut add = || bits.of(&table.saturated_mask(opacity(o), other_split(k, o)));
                    masks.push((o, *after_full.entry(o).or_insert_with(&mut add)));
                    continue;
                }
                let table = next_table(&mut tables, depth);
                masks.push((o, bits.of(&table.add(opacity(o), other_split(k, o)))));
                depth += 1;
            }
            walked.push((i, masks.clone()));
            last_others = mine;
        }
        if let Some(last) = last_near.filter(|_| !after_full.is_empty()) {
            made.push((last, after_full));
        }
        (walked, learned, made)
    };
    let mut out = vec![Vec::new(); configs.len()];
    for (walked, learned, made) in runs.par_iter().map(walk).collect::<Vec<_>>() {
        for (i, masks) in walked {
            out[i] = masks;
        }
        // Every list made after is known from an earlier frame or learned in this run.
        known.extend(learned);
        for (nearest, masks) in made {
            if let Some(after) = known.get_mut(nearest) {
                after.saturated.extend(masks);
            }
        }
    }
    out
}

/// What configurations with the same K nearest (nearest first) share, for the same opacities,
/// sub-samples and method: the table after the K nearest and their masks, and the masks of organs
/// made after a saturated table, where a mask depends on the K nearest and the organ alone.
#[derive(Debug)]
pub struct AfterNearest {
    table: MaskTable,
    masks: OrganMasks,
    saturated: FxHashMap<usize, u64>,
}

/// [`AfterNearest`] by K nearest.
pub type KnownMasks = FxHashMap<Vec<usize>, AfterNearest>;

/// Saturated-table masks made after one list of K nearest, by organ.
type AfterFull<'a> = (&'a [usize], FxHashMap<usize, u64>);

/// `stack[depth + 1]` made a copy of `stack[depth]`, reusing its allocation where it has one.
fn next_table(stack: &mut Vec<MaskTable>, depth: usize) -> &mut MaskTable {
    if stack.len() == depth + 1 {
        stack.push(stack[depth].clone());
    } else {
        let (below, above) = stack.split_at_mut(depth + 1);
        above[0].clone_from(&below[depth]);
    }
    &mut stack[depth + 1]
}

/// Length of the longest run `a` and `b` begin with.
fn common_run(a: &[usize], b: &[usize]) -> usize {
    a.iter().zip(b).take_while(|(x, y)| x == y).count()
}

/// How many of a region's nearest organs its masks follow in depth order: at most `k`, and no
/// more than the stacking levels a mask of `n` sub-samples resolves with two sub-samples or more
/// at 50 % opacity (log2(n) - 1: 2 for 8, 3 for 16, 5 for 64). Following deeper levels only makes
/// their rounding err the same way in every mask: with every organ at 50 % and 16 sub-samples the
/// image's mean error is 2.77 following 8 and 1.51 following 3.
pub fn followed_nearest(k: usize, n: usize) -> usize {
    let levels = n.max(4).ilog2() as usize - 1;
    k.clamp(1, levels)
}

/// The last frame's configurations (key: present organs as bits, then the K nearest) and their
/// masks, valid while `settings` (sub-samples, K, method) stay the same and, for each
/// configuration, the opacities of its organs: when an organ's opacity changes (a slider dragged),
/// only what involves that organ is dropped.
#[derive(Debug, Default)]
pub struct MaskCache {
    settings: [u64; 3],
    /// Every organ's opacity (as bits) the masks were made with.
    opacities: Vec<u32>,
    /// Masks by configuration key, with the frame that last had the configuration.
    masks: FxHashMap<Vec<u64>, (u64, OrganMasks)>,
    frame: u64,
    /// What every K nearest seen under these settings share (up to [`NEAREST_KEPT`] of them).
    known: KnownMasks,
}

/// Most lists of K nearest a [`MaskCache`] keeps (a few kB each); beyond it, it starts again.
const NEAREST_KEPT: usize = 1 << 13;

impl MaskCache {
    /// Drops what depends on the opacity of the `changed` organs: the configurations they are in
    /// (their key's first `words` u64 hold the organs as bits), the lists of K nearest they are
    /// in, and their masks after saturated tables.
    fn forget(&mut self, changed: &[usize], words: usize) {
        let mut bits = vec![0u64; words];
        for &o in changed {
            bits[o / 64] |= 1 << (o % 64);
        }
        let has = |o: usize| bits[o / 64] >> (o % 64) & 1 == 1;
        self.masks.retain(|key, _| key.iter().zip(&bits).all(|(k, b)| k & b == 0));
        self.known.retain(|nearest, _| !nearest.iter().any(|&o| has(o)));
        for after in self.known.values_mut() {
            after.saturated.retain(|&o, _| !has(o));
        }
    }
}

/// The masks of every region for this frame, all generated anew.
pub fn region_masks(set: &OrganSet, layout: &Layout, camera: &Camera, p: &RegionParams) -> RegionMasks {
    region_masks_kept(set, layout, camera, p, &mut MaskCache::default())
}

/// The masks of every region for this frame, keeping from `cache` the masks of configurations the
/// last frame had (with the same settings); `cache` then holds this frame's.
pub fn region_masks_kept(
    set: &OrganSet,
    layout: &Layout,
    camera: &Camera,
    p: &RegionParams,
    cache: &mut MaskCache,
) -> RegionMasks {
    let started = std::time::Instant::now();
    let region_px = p.region_px.max(1);
    let subsamples = p.subsamples.clamp(4, 64);
    let p = RegionParams { region_px, subsamples, k: followed_nearest(p.k, subsamples), ..*p };
    let cols = p.width.div_ceil(region_px).max(1);
    let rows = p.height.div_ceil(region_px).max(1);
    let organs = set.organs.len().min(layout.organs.len());
    let bits = GpuBits::new(&layout::logical_to_bit(p.subsamples));
    let opacity = |o: usize| layout.organs[o].opacity.clamp(0.0, 1.0);
    // Outside any configuration an organ gets its mask on its own: right in coverage, stacked by chance.
    let defaults: Vec<u64> = (0..organs)
        .map(|o| {
            let mut t = MaskTable::new(p.subsamples);
            bits.of(&t.add(opacity(o), SplitOrder::Table))
        })
        .collect();
    let words = organs.div_ceil(64);
    let grid = Grid { width: p.width, height: p.height, region_px, cols, rows };
    let rects = leaf_rects((set, layout, organs), camera, &grid);
    let covered = covered_pixels(&rects, &grid);
    let stride = words + p.k;
    let region_keys = region_keys(&rects, organs, p.k, &grid);
    // Configurations numbered in region order, by key.
    let mut configs: FxHashMap<&[u64], u32> = FxHashMap::default();
    let mut keys: Vec<&[u64]> = Vec::new();
    let mut config_of_region = Vec::with_capacity((cols * rows) as usize);
    // A region's key is most often its left or upper neighbour's.
    let (row_len, width) = (stride * cols as usize, cols as usize);
    for (i, key) in region_keys.chunks_exact(stride).enumerate() {
        let at = i * stride;
        let same_as = |j: usize| region_keys[j..j + stride] == *key;
        let id = if i % width > 0 && same_as(at - stride) {
            config_of_region[i - 1]
        } else if i >= width && same_as(at - row_len) {
            config_of_region[i - width]
        } else {
            *configs.entry(key).or_insert_with(|| {
                keys.push(key);
                keys.len() as u32 - 1
            })
        };
        config_of_region.push(id);
    }
    // The last frame's masks where its configuration and settings come again.
    let settings = [p.subsamples as u64, p.k as u64, p.method as u64];
    let opacities: Vec<u32> = (0..organs).map(|o| opacity(o).to_bits()).collect();
    if cache.settings != settings || cache.opacities.len() != organs || cache.known.len() > NEAREST_KEPT {
        cache.masks.clear();
        cache.known.clear();
    } else if cache.opacities != opacities {
        let changed: Vec<usize> = (0..organs).filter(|&o| cache.opacities[o] != opacities[o]).collect();
        cache.forget(&changed, words);
    }
    (cache.settings, cache.opacities) = (settings, opacities);
    cache.frame += 1;
    let frame = cache.frame;
    let todo: Vec<&[u64]> = keys
        .iter()
        .copied()
        .filter(|&key| match cache.masks.get_mut(key) {
            Some((seen, _)) => {
                *seen = frame;
                false
            }
            None => true,
        })
        .collect();
    let kept = keys.len() - todo.len();
    // One generation for every other distinct configuration.
    let decoded: Vec<(Vec<usize>, Vec<usize>)> = todo
        .iter()
        .map(|key| {
            let present = (0..organs).filter(|&o| key[o / 64] >> (o % 64) & 1 == 1).collect();
            let nearest = key[words..].iter().take_while(|&&o| o != u64::MAX).map(|&o| o as usize).collect();
            (present, nearest)
        })
        .collect();
    let wanted: Vec<(&[usize], &[usize])> = decoded.iter().map(|(p, n)| (p.as_slice(), n.as_slice())).collect();
    let gen = configuration_masks(&wanted, opacity, &p, &bits, &mut cache.known);
    for (key, masks) in todo.into_iter().zip(gen) {
        cache.masks.insert(key.to_vec(), (frame, masks));
    }
    // Only this frame's configurations are kept for the next.
    cache.masks.retain(|_, (seen, _)| *seen == frame);
    let mut masks = Vec::with_capacity(keys.len().max(1) * organs);
    for key in &keys {
        let at = masks.len();
        masks.extend_from_slice(&defaults);
        for &(o, m) in cache.masks.get(*key).map(|(_, m)| m.as_slice()).unwrap_or_default() {
            masks[at + o] = m;
        }
    }
    config_of_region.resize((cols * rows) as usize, 0);
    if masks.is_empty() {
        masks.extend_from_slice(&defaults);
    }
    RegionMasks {
        region_px,
        cols,
        rows,
        subsamples: p.subsamples,
        organ_count: organs,
        config_of_region,
        configs: keys.len(),
        kept,
        covered,
        masks,
        ms: started.elapsed().as_secs_f64() * 1000.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Mesh;
    use crate::organ_set::Organ;

    fn square(x: f32, y: f32, half: f32) -> Mesh {
        // A square facing the camera of `Camera::view(.., Anterior)` (looking along +y).
        let mut m = Mesh {
            positions: vec![
                [x - half, 0.0, y - half],
                [x + half, 0.0, y - half],
                [x + half, 0.0, y + half],
                [x - half, 0.0, y + half],
            ],
            normals: vec![],
            indices: vec![0, 1, 2, 0, 2, 3],
        };
        m.compute_normals();
        m
    }

    #[test]
    fn configurations_follow_the_organs_present() {
        let mut set = OrganSet::default();
        set.organs.push(Organ::new("a".into(), "a".into(), [1.0; 3], square(-30.0, 0.0, 20.0)));
        set.organs.push(Organ::new("b".into(), "b".into(), [1.0; 3], square(30.0, 0.0, 20.0)));
        set.organs.push(Organ::new("c".into(), "c".into(), [1.0; 3], square(0.0, 0.0, 60.0)));
        let mut layout = Layout::new(&set);
        layout.organs[0].opacity = 0.5;
        layout.organs[1].opacity = 0.25;
        // c is opaque: it never gets a configuration of its own.
        let camera = Camera::view(&set.bounds(), crate::camera::View::Anterior);
        let p = RegionParams {
            width: 128,
            height: 128,
            region_px: 16,
            subsamples: 16,
            k: 6,
            method: MaskMethod::TabularNec,
        };
        let m = region_masks(&set, &layout, &camera, &p);
        // Regions with a, with b, and with neither.
        assert_eq!(m.configs, 3, "{:?}", m.config_of_region);
        assert_eq!(m.config_of_region.len(), 64);
        let centre_of = |o: usize| {
            let vp = camera.view_projection(1.0);
            let c = vp.project_point3(set.organs[o].mesh.bounds().center());
            (((c.x * 0.5 + 0.5) * 128.0) as u32, ((0.5 - c.y * 0.5) * 128.0) as u32)
        };
        let (ax, ay) = centre_of(0);
        let (bx, by) = centre_of(1);
        assert_eq!(m.mask_at(ax, ay, 0).count_ones(), 8, "a keeps half of 16 sub-samples");
        assert_eq!(m.mask_at(bx, by, 1).count_ones(), 4, "b keeps a quarter");
        assert_ne!(
            m.config_of_region[(ay / 16 * 8 + ax / 16) as usize],
            m.config_of_region[(by / 16 * 8 + bx / 16) as usize]
        );
    }

    #[test]
    fn masks_follow_no_more_nearest_organs_than_they_resolve() {
        let followed: Vec<usize> = [4, 8, 16, 32, 64].into_iter().map(|n| followed_nearest(8, n)).collect();
        assert_eq!(followed, [1, 2, 3, 4, 5]);
        assert_eq!(followed_nearest(2, 64), 2, "K itself is the most");
        assert_eq!(followed_nearest(0, 64), 1);
    }

    #[test]
    fn kept_masks_are_the_masks_generated_anew() {
        let mut set = OrganSet::default();
        for (i, x) in [-40.0f32, 0.0, 40.0].into_iter().enumerate() {
            set.organs.push(Organ::new(format!("o{i}"), "o".into(), [1.0; 3], square(x, 0.0, 30.0)));
        }
        let mut layout = Layout::new(&set);
        layout.organs.iter_mut().for_each(|o| o.opacity = 0.5);
        let p =
            RegionParams { width: 96, height: 96, region_px: 8, subsamples: 64, k: 2, method: MaskMethod::TabularNec };
        let mut cache = MaskCache::default();
        let bounds = set.bounds();
        for (k, az) in [0.0f32, 2.0, 4.0, 4.0].into_iter().enumerate() {
            let camera = Camera::orbit(&bounds, az, 0.0);
            let kept = region_masks_kept(&set, &layout, &camera, &p, &mut cache);
            let anew = region_masks(&set, &layout, &camera, &p);
            assert_eq!((&kept.config_of_region, &kept.masks), (&anew.config_of_region, &anew.masks));
            match k {
                0 => assert_eq!(kept.kept, 0),
                3 => assert_eq!(kept.kept, kept.configs, "the same view keeps every configuration"),
                _ => assert!(kept.kept > 0, "a small move keeps some"),
            }
        }
        // Another opacity for the middle square: only the configurations without it are kept.
        layout.organs[1].opacity = 0.3;
        let camera = Camera::orbit(&bounds, 4.0, 0.0);
        let kept = region_masks_kept(&set, &layout, &camera, &p, &mut cache);
        let anew = region_masks(&set, &layout, &camera, &p);
        assert_eq!((&kept.config_of_region, &kept.masks), (&anew.config_of_region, &anew.masks));
        assert!(kept.kept > 0 && kept.kept < kept.configs, "{} of {} kept", kept.kept, kept.configs);
        // Another sub-sample count: nothing is.
        let fewer = RegionParams { subsamples: 16, ..p };
        assert_eq!(region_masks_kept(&set, &layout, &camera, &fewer, &mut cache).kept, 0);
    }

    #[test]
    fn masks_kept_past_a_saturated_table_are_the_masks_generated_anew() {
        // Eight overlapping squares at staggered depths. At 16 sub-samples a table is saturated
        // after four masks of 50 %, so configurations share the masks made after it, and the
        // tables after their K nearest, with configurations of earlier frames.
        let mut set = OrganSet::default();
        for i in 0..8 {
            let mut mesh = square((i % 4) as f32 * 12.0 - 18.0, (i / 4) as f32 * 12.0 - 6.0, 20.0);
            mesh.positions.iter_mut().for_each(|v| v[1] = i as f32 * 3.0);
            set.organs.push(Organ::new(format!("o{i}"), "o".into(), [1.0; 3], mesh));
        }
        let mut layout = Layout::new(&set);
        layout.organs.iter_mut().for_each(|o| o.opacity = 0.5);
        let p = RegionParams {
            width: 128,
            height: 128,
            region_px: 8,
            subsamples: 16,
            k: 3,
            method: MaskMethod::TabularNec,
        };
        let mut cache = MaskCache::default();
        let bounds = set.bounds();
        for step in 0..12 {
            let az = step as f32 * 2.0;
            let camera = Camera::orbit(&bounds, az, 10.0 + az);
            let kept = region_masks_kept(&set, &layout, &camera, &p, &mut cache);
            let anew = region_masks(&set, &layout, &camera, &p);
            assert_eq!((&kept.config_of_region, &kept.masks), (&anew.config_of_region, &anew.masks), "at {az} degrees");
        }
        assert!(cache.known.values().any(|after| !after.saturated.is_empty()), "some tables were saturated");
        // A slider dragged: one organ's opacity changes a frame at a time, and the view moves.
        for (step, alpha) in [0.3f32, 0.35, 0.6].into_iter().enumerate() {
            layout.organs[3].opacity = alpha;
            let camera = Camera::orbit(&bounds, 20.0 + step as f32, 30.0);
            let kept = region_masks_kept(&set, &layout, &camera, &p, &mut cache);
            let anew = region_masks(&set, &layout, &camera, &p);
            assert_eq!((&kept.config_of_region, &kept.masks), (&anew.config_of_region, &anew.masks), "at {alpha}");
        }
    }

    #[test]
    fn masks_of_a_configuration_stack_right() {
        let bits = GpuBits::new(&layout::logical_to_bit(64));
        let p =
            RegionParams { width: 1, height: 1, region_px: 1, subsamples: 64, k: 6, method: MaskMethod::TabularNec };
        let alphas = [0.5f32, 0.5, 0.25, 0.75];
        let present = [0, 1, 2, 3];
        let nearest = [2, 0, 3, 1];
        let masks = config_masks(&present, &nearest, |o| alphas[o], &p, &bits);
        let of = |o: usize| masks.iter().find(|m| m.0 == o).map(|m| m.1).unwrap_or(0);
        // Layers in depth order keep 64 * a * prod(1 - a nearer): 16, 24, 12, 9 (12 * 0.75).
        let mut covered = 0u64;
        let mut through = 1.0f32;
        for &o in &nearest {
            let keep = (of(o) & !covered).count_ones() as f32;
            let exact = 64.0 * alphas[o] * through;
            assert!((keep - exact).abs() <= 1.0, "organ {o}: {keep} vs {exact}");
            covered |= of(o);
            through *= 1.0 - alphas[o];
        }
    }
}
