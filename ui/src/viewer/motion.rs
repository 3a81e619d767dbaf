//! How many screen-door sub-samples a frame gets while the camera or an organ moves: the setting at
//! most, halved while moving frames take longer than [`BUDGET`] and doubled back while they take
//! under a third of it, so that a drag stays responsive on a heavy scene or a slow machine. Times
//! are the wall clock between two moving frames of the viewer.

use std::time::Duration;
use vbrain::transparency::clamp_subsamples;

/// What a moving frame may take: ten frames a second.
pub const BUDGET: Duration = Duration::from_millis(100);

#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MotionQuality {
    /// Sub-samples for moving frames, where they had to come down from the setting.
    count: Option<usize>,
}

impl MotionQuality {
    /// Sub-samples for the next moving frame, with `setting` the most.
    pub fn subsamples(&self, setting: usize) -> usize {
        clamp_subsamples(self.count.unwrap_or(setting).min(setting))
    }

    /// After a moving frame drawn with `used` sub-samples came `took` after the one before.
    pub fn observe(&mut self, setting: usize, used: usize, took: Duration) {
        let next = match took {
            t if t > BUDGET => used / 2,
            t if t < BUDGET / 3 => used * 2,
            _ => used,
        };
        let next = clamp_subsamples(next.min(setting));
        self.count = (next < clamp_subsamples(setting)).then_some(next);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slow_moving_frames_take_fewer_sub_samples_and_quick_ones_more() {
        let mut q = MotionQuality::default();
        assert_eq!(q.subsamples(16), 16);
        q.observe(16, 16, Duration::from_millis(300));
        assert_eq!(q.subsamples(16), 8);
        q.observe(16, 8, Duration::from_millis(200));
        assert_eq!(q.subsamples(16), 4);
        q.observe(16, 4, Duration::from_millis(500));
        assert_eq!(q.subsamples(16), 4, "never under one pass");
        q.observe(16, 4, Duration::from_millis(60));
        assert_eq!(q.subsamples(16), 4, "within the budget: kept");
        q.observe(16, 4, Duration::from_millis(20));
        assert_eq!(q.subsamples(16), 8);
        q.observe(16, 8, Duration::from_millis(10));
        assert_eq!(q, MotionQuality::default(), "back at the setting");
        q.observe(16, 16, Duration::from_millis(10));
        assert_eq!(q.subsamples(16), 16, "never over the setting");
        assert_eq!(q.subsamples(4), 4);
    }
}
