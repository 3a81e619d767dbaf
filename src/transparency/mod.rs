//! Order-independent transparency by sub-pixel screen-door masks (thesis chapter 4).
//!
//! A *mask* is a set of a pixel's sub-samples ("pixels" in the thesis, which works on one mask as a
//! little image). A transparent organ keeps only the sub-samples in its mask; the depth test
//! resolves the rest, and the average over a pixel's sub-samples is its colour. That is right only
//! if stacked masks are right: with opacities a0 (nearest), a1, ... the i-th layer must keep
//! n * a_i * prod_{j<i}(1 - a_j) of the n sub-samples.
//!
//! - [`mask`]: the bit set of sub-samples (logical indices `0..n`, n up to 1024).
//! - [`table`]: the tabular pixel mask (§4.3) with neighbourhood error compensation (§4.3.3);
//!   Mulder's pixel-tree masks are the same splitting in a random order.
//! - [`white_noise`]: random masks, the usual reference.
//! - [`layout`]: which MSAA sample of which pass each logical sub-sample is.
//! - [`regions`]: masks regenerated per screen region from the organs present there (§4.3.4).

pub mod layout;
pub mod mask;
mod region_keys;
pub mod regions;
pub mod table;
pub mod white_noise;

pub use mask::Mask;
pub use table::{MaskTable, SplitOrder};

/// How masks are made. Serialised in settings by these names.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MaskMethod {
    /// Random sub-samples, the right count for each mask but no care for stacking.
    WhiteNoise,
    /// Mulder's pixel tree: binary splitting with the error carried in a random order.
    PixelTree,
    /// The tabular pixel mask, rows split in table order.
    Tabular,
    /// The tabular pixel mask with neighbourhood error compensation (the K nearest objects).
    TabularNec,
}

impl MaskMethod {
    pub const ALL: [MaskMethod; 4] =
        [MaskMethod::WhiteNoise, MaskMethod::PixelTree, MaskMethod::Tabular, MaskMethod::TabularNec];

    pub fn name(self) -> &'static str {
        match self {
            MaskMethod::WhiteNoise => "white_noise",
            MaskMethod::PixelTree => "pixel_tree",
            MaskMethod::Tabular => "tabular",
            MaskMethod::TabularNec => "tabular_nec",
        }
    }
}

/// The earlier objects (indices below j) that neighbourhood error compensation weighs when object j's
/// mask is made out of depth order: see [`SplitOrder::Neighbours`].
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Neighbourhood {
    /// Every earlier object nearer than j.
    pub nearer: Vec<usize>,
    /// The earlier objects just farther than j, nearest first.
    pub farther: Vec<usize>,
}

/// Masks for objects generated in the given order: `alphas[j]` is object j's opacity and
/// `neighbours(j)` the earlier objects that neighbourhood error compensation weighs (used by
/// [`MaskMethod::TabularNec`] only). `seed` drives the random
/// methods. Returns the masks and the row entries the table held (0 for white noise).
pub fn generate(
    method: MaskMethod,
    n: usize,
    alphas: &[f32],
    neighbours: impl Fn(usize) -> Neighbourhood,
    seed: u64,
) -> (Vec<Mask>, usize) {
    let mut rng = crate::rng::XorShift::seeded(seed);
    if method == MaskMethod::WhiteNoise {
        return (alphas.iter().map(|&a| white_noise::mask(n, a, &mut rng)).collect(), 0);
    }
    let mut table = MaskTable::new(n);
    for (j, &a) in alphas.iter().enumerate() {
        match method {
            MaskMethod::PixelTree => {
                let mut order: Vec<usize> = (0..table.rows().len()).collect();
                rng.shuffle(&mut order);
                table.add(a, SplitOrder::Given(&order));
            }
            MaskMethod::Tabular => {
                table.add(a, SplitOrder::Table);
            }
            _ => {
                let Neighbourhood { nearer, farther } = neighbours(j);
                table.add(a, SplitOrder::Neighbours { nearer: &nearer, farther: &farther });
            }
        }
    }
    let entries = table.row_entries();
    (table.into_masks(), entries)
}

/// How transparent (faded) organs are drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum TransparencyMode {
    /// Screen-door with tabular masks and neighbourhood error compensation, regenerated per region.
    Screendoor,
    /// Screen-door with white-noise masks.
    ScreendoorWhitenoise,
    /// Screen-door with Mulder's pixel-tree masks.
    ScreendoorPixeltree,
    /// Alpha blending in draw order, depth written (what plain blending without sorting gives).
    AlphaUnsorted,
    /// Alpha blending, organs sorted back to front by centre, back faces culled.
    AlphaSorted,
    /// Weighted blended order-independent transparency (McGuire and Bavoil 2013).
    WeightedBlended,
    /// Depth peeling (Everitt 2001): one layer a pass, front to back.
    Peel,
    /// Dual depth peeling (Bavoil and Myers 2008): the nearest and farthest layer each pass.
    DualPeel,
    /// The k-buffer (Callahan 2005): triangles sorted roughly on the CPU, the k nearest fragments
    /// of each pixel sorted exactly on the GPU.
    #[serde(rename = "kbuffer")]
    KBuffer,
    /// The reference: each organ's nearest surface per sample, composited in depth order (slow).
    Exact,
}

impl TransparencyMode {
    pub const ALL: [TransparencyMode; 10] = [
        TransparencyMode::Screendoor,
        TransparencyMode::ScreendoorWhitenoise,
        TransparencyMode::ScreendoorPixeltree,
        TransparencyMode::AlphaUnsorted,
        TransparencyMode::AlphaSorted,
        TransparencyMode::WeightedBlended,
        TransparencyMode::Peel,
        TransparencyMode::DualPeel,
        TransparencyMode::KBuffer,
        TransparencyMode::Exact,
    ];

    pub fn name(self) -> &'static str {
        match self {
            TransparencyMode::Screendoor => "screendoor",
            TransparencyMode::ScreendoorWhitenoise => "screendoor-whitenoise",
            TransparencyMode::ScreendoorPixeltree => "screendoor-pixeltree",
            TransparencyMode::AlphaUnsorted => "alpha-unsorted",
            TransparencyMode::AlphaSorted => "alpha-sorted",
            TransparencyMode::WeightedBlended => "weighted-blended",
            TransparencyMode::Peel => "peel",
            TransparencyMode::DualPeel => "dual-peel",
            TransparencyMode::KBuffer => "kbuffer",
            TransparencyMode::Exact => "exact",
        }
    }

    pub fn parse(s: &str) -> Option<TransparencyMode> {
        TransparencyMode::ALL.into_iter().find(|m| m.name() == s)
    }

    /// The mask method of a screen-door mode.
    pub fn mask_method(self) -> Option<MaskMethod> {
        match self {
            TransparencyMode::Screendoor => Some(MaskMethod::TabularNec),
            TransparencyMode::ScreendoorWhitenoise => Some(MaskMethod::WhiteNoise),
            TransparencyMode::ScreendoorPixeltree => Some(MaskMethod::PixelTree),
            _ => None,
        }
    }
}

/// Screen-door parameters, persisted by the viewer.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct TransparencySettings {
    pub mode: TransparencyMode,
    /// Sub-samples per mask for stills and exports: 4 per pass, up to 64 (the thesis's 8x8).
    pub subsamples: usize,
    /// Sub-samples while the camera or an organ moves (fewer passes, faster).
    pub interactive_subsamples: usize,
    /// Side of a mask region in pixels.
    pub region_px: u32,
    /// Most nearest organs that neighbourhood error compensation favours (at most log2 of the
    /// sub-samples less one are followed).
    pub k: usize,
    /// Most layers the depth-peeling modes peel (they stop earlier once nothing is left).
    pub peel_layers: usize,
    /// The k-buffer's slots per pixel, in [`KBUFFER_K`].
    pub kbuffer: usize,
}

impl Default for TransparencySettings {
    fn default() -> Self {
        TransparencySettings {
            mode: TransparencyMode::Screendoor,
            subsamples: 64,
            interactive_subsamples: 16,
            region_px: 32,
            k: DEFAULT_K,
            peel_layers: 8,
            kbuffer: *KBUFFER_K.end(),
        }
    }
}

/// Neighbourhood error compensation's K by default: the most nearest organs of a region whose
/// depth order its masks follow (fewer where the masks have few sub-samples:
/// [`regions::followed_nearest`]), and in the mask experiment the farther neighbours a new mask
/// weighs.
/// 8 keeps the experiment's worst stacking level within 2 sub-samples at 32x32 (6 gave 4).
pub const DEFAULT_K: usize = 8;

/// The most layers the depth-peeling modes may be asked to peel.
pub const MAX_PEEL_LAYERS: usize = 64;

/// The k-buffer's slots per pixel that every command, the viewer and scene files accept (Callahan
/// found 2 to 6 enough for nearly sorted streams; 8 slots cost 64 bytes a pixel).
pub const KBUFFER_K: std::ops::RangeInclusive<usize> = 2..=8;

/// Mask region sides in pixels that every command, the viewer and scene files accept.
pub const REGION_PX: std::ops::RangeInclusive<u32> = 4..=256;

/// Nearest organs that error compensation may favour (K) in every command, the viewer and scene
/// files.
pub const K_RANGE: std::ops::RangeInclusive<usize> = 1..=64;

impl TransparencySettings {
    /// The settings with every value inside what the renderer and the menus accept (settings and
    /// scene files are input): sub-samples among [`SUBSAMPLE_CHOICES`], regions in [`REGION_PX`],
    /// K in [`K_RANGE`], peel layers 1..=[`MAX_PEEL_LAYERS`], k-buffer slots in [`KBUFFER_K`].
    pub fn clamped(mut self) -> TransparencySettings {
        self.subsamples = clamp_subsamples(self.subsamples);
        self.interactive_subsamples = clamp_subsamples(self.interactive_subsamples);
        self.region_px = self.region_px.clamp(*REGION_PX.start(), *REGION_PX.end());
        self.k = self.k.clamp(*K_RANGE.start(), *K_RANGE.end());
        self.peel_layers = self.peel_layers.clamp(1, MAX_PEEL_LAYERS);
        self.kbuffer = self.kbuffer.clamp(*KBUFFER_K.start(), *KBUFFER_K.end());
        self
    }
}

/// Sub-sample counts the renderer supports (4 per pass).
pub const SUBSAMPLE_CHOICES: [usize; 5] = [4, 8, 16, 32, 64];

/// The nearest supported sub-sample count at or below `n` (at least 4).
pub fn clamp_subsamples(n: usize) -> usize {
    SUBSAMPLE_CHOICES.into_iter().rev().find(|&c| c <= n).unwrap_or(4)
}
