//! What a frame draws faded organs with while the camera or an organ moves: screen-door with the
//! setting's sub-samples at most, halved while moving frames take longer than [`BUDGET`] and
//! doubled back while they take under a third of it; below one pass (4 sub-samples), weighted
//! blended transparency, one pass over the faded organs whatever their number (on the benchmark's
//! whole brain at 50 %, as close to exact as one screen-door pass and barely dearer than the
//! opaque frame), so that a drag stays responsive on a heavy scene or a slow machine. When the
//! motion stops, the still image converges to the full sub-samples. Times are the wall clock
//! between two moving frames of the viewer.
//! - Level of detail (Callahan 2005, ch. 5): moving frames step down the ladder [`DETAIL`] while
//!   they take longer than [`SCALE_BUDGET`] and up while they take under a third of it: first
//!   smaller images, their sides one of [`SCALES`] of the view's, scaled up (the least error for
//!   the time saved), then the organs' coarser levels of detail (where they have fewer triangles
//!   than culling keeps). Still frames are drawn at full detail and size.

use std::time::Duration;
use vbrain::transparency::{clamp_subsamples, TransparencyMode, TransparencySettings};

/// What a moving frame may take: ten frames a second.
pub const BUDGET: Duration = Duration::from_millis(100);

/// What a moving frame may take before it is drawn smaller: twenty frames a second.
pub const SCALE_BUDGET: Duration = Duration::from_millis(50);

/// The render scales moving frames step through: each about halves the pixels of the one before.
pub const SCALES: [f32; 4] = [1.0, 0.71, 0.5, 0.35];

/// The steps moving frames take to hold their rate, cheapest in error first: the render scale,
/// then the organs' level of detail ([`vbrain::lod`]).
pub const DETAIL: [(u8, f32); 6] = [(0, 1.0), (0, 0.71), (0, 0.5), (0, 0.35), (1, 0.35), (2, 0.35)];

/// How a moving frame draws faded organs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Moving {
    /// Screen-door with this many sub-samples.
    Subsamples(usize),
    /// Weighted blended transparency.
    Blended,
}

#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MotionQuality {
    /// Where moving frames had to come down from the setting.
    down: Option<Moving>,
    /// The detail of moving frames: an index into [`DETAIL`].
    detail: usize,
}

impl MotionQuality {
    /// How the next moving frame draws, with `setting` sub-samples the most.
    pub fn moving(&self, setting: usize) -> Moving {
        let setting = clamp_subsamples(setting);
        match self.down {
            Some(Moving::Subsamples(n)) => Moving::Subsamples(clamp_subsamples(n.min(setting))),
            Some(Moving::Blended) => Moving::Blended,
            None => Moving::Subsamples(setting),
        }
    }

    /// The transparency settings of a frame: `settings` as they are while still, or with a
    /// screen-door mode, as the next moving frame draws.
    pub fn frame(&self, settings: TransparencySettings, moving: bool) -> TransparencySettings {
        let mut t = settings;
        if settings.mode.mask_method().is_none() {
            return t;
        }
        match (moving, self.moving(settings.interactive_subsamples)) {
            (true, Moving::Blended) => t.mode = TransparencyMode::WeightedBlended,
            // Still, the first frame draws the moving count; more follow, one pass a frame.
            (_, Moving::Subsamples(n)) => t.interactive_subsamples = n,
            (false, Moving::Blended) => t.interactive_subsamples = clamp_subsamples(1),
        }
        t
    }

    /// The side of the next moving frame's image, as a share of the view's.
    pub fn scale(&self) -> f32 {
        DETAIL[self.detail.min(DETAIL.len() - 1)].1
    }

    /// The level of detail the next moving frame draws organs at (0: their full meshes).
    pub fn level(&self) -> u8 {
        DETAIL[self.detail.min(DETAIL.len() - 1)].0
    }

    /// After a moving frame (of any kind) came `took` after the one before: less detail next
    /// while frames are slow, more while they are quick.
    pub fn observe_detail(&mut self, took: Duration) {
        if took > SCALE_BUDGET {
            self.detail = (self.detail + 1).min(DETAIL.len() - 1);
        } else if took < SCALE_BUDGET / 3 {
            self.detail = self.detail.saturating_sub(1);
        }
    }

    /// After a moving frame drawn as `used` came `took` after the one before.
    pub fn observe(&mut self, setting: usize, used: Moving, took: Duration) {
        let setting = clamp_subsamples(setting);
        let one_pass = clamp_subsamples(1);
        let next = match (used, took) {
            (Moving::Subsamples(n), t) if t > BUDGET && n <= one_pass => Moving::Blended,
            (Moving::Subsamples(n), t) if t > BUDGET => Moving::Subsamples(clamp_subsamples(n / 2)),
            (Moving::Subsamples(n), t) if t < BUDGET / 3 => Moving::Subsamples(clamp_subsamples(2 * n)),
            (Moving::Blended, t) if t < BUDGET / 3 => Moving::Subsamples(one_pass),
            (used, _) => used,
        };
        self.down = match next {
            Moving::Subsamples(n) if n >= setting => None,
            next => Some(next),
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slow_moving_frames_are_drawn_smaller_then_coarser_and_quick_ones_finer() {
        let mut q = MotionQuality::default();
        assert_eq!((q.level(), q.scale()), (0, 1.0), "full detail at first");
        for expected in [(0, 0.71), (0, 0.5), (0, 0.35), (1, 0.35), (2, 0.35), (2, 0.35)] {
            q.observe_detail(Duration::from_millis(80));
            assert_eq!((q.level(), q.scale()), expected);
        }
        q.observe_detail(Duration::from_millis(30));
        assert_eq!(q.level(), 2, "within the budget: kept");
        q.observe_detail(Duration::from_millis(10));
        assert_eq!((q.level(), q.scale()), (1, 0.35), "well within it: finer");
        for _ in 0..4 {
            q.observe_detail(Duration::from_millis(10));
        }
        assert_eq!((q.level(), q.scale()), (0, 1.0), "back at full detail");
    }

    #[test]
    fn slow_moving_frames_take_fewer_sub_samples_then_blend_and_quick_ones_come_back() {
        let mut q = MotionQuality::default();
        let slow = Duration::from_millis(300);
        assert_eq!(q.moving(16), Moving::Subsamples(16));
        q.observe(16, Moving::Subsamples(16), slow);
        assert_eq!(q.moving(16), Moving::Subsamples(8));
        q.observe(16, Moving::Subsamples(8), Duration::from_millis(200));
        assert_eq!(q.moving(16), Moving::Subsamples(4));
        q.observe(16, Moving::Subsamples(4), Duration::from_millis(60));
        assert_eq!(q.moving(16), Moving::Subsamples(4), "within the budget: kept");
        q.observe(16, Moving::Subsamples(4), Duration::from_millis(500));
        assert_eq!(q.moving(16), Moving::Blended, "under one pass: blended");
        q.observe(16, Moving::Blended, slow);
        assert_eq!(q.moving(16), Moving::Blended, "nothing cheaper");
        q.observe(16, Moving::Blended, Duration::from_millis(20));
        assert_eq!(q.moving(16), Moving::Subsamples(4));
        q.observe(16, Moving::Subsamples(4), Duration::from_millis(20));
        assert_eq!(q.moving(16), Moving::Subsamples(8));
        q.observe(16, Moving::Subsamples(8), Duration::from_millis(10));
        assert_eq!(q, MotionQuality::default(), "back at the setting");
        q.observe(16, Moving::Subsamples(16), Duration::from_millis(10));
        assert_eq!(q.moving(16), Moving::Subsamples(16), "never over the setting");
        assert_eq!(q.moving(4), Moving::Subsamples(4));
    }

    #[test]
    fn only_moving_screen_door_frames_blend() {
        let q = MotionQuality { down: Some(Moving::Blended), ..Default::default() };
        let sd = TransparencySettings::default();
        assert!(sd.mode.mask_method().is_some());
        assert_eq!(q.frame(sd, true).mode, TransparencyMode::WeightedBlended);
        let still = q.frame(sd, false);
        assert_eq!((still.mode, still.interactive_subsamples), (sd.mode, 4), "still: screen-door from one pass");
        let peel = TransparencySettings { mode: TransparencyMode::Peel, ..sd };
        assert_eq!(q.frame(peel, true), peel, "other modes as set");
        let q = MotionQuality { down: Some(Moving::Subsamples(8)), ..Default::default() };
        assert_eq!(q.frame(sd, true).interactive_subsamples, 8);
    }
}
