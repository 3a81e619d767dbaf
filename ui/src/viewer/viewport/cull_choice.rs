//! Whether occlusion culling pays on this machine, for this layout: the viewer measures a frame
//! with it and a frame with frustum culling only, every [`PROBE_EVERY`] and whenever the layout
//! changes, and draws with the cheaper until the next measurement.
//!
//! - A frame's cost is its culling time plus its drawing time: the GPU's time where the adapter
//!   has timestamp queries, else the wall time until the GPU has finished. Milliseconds.
//! - Until both are measured, occlusion culling is used (it pays on software GPUs, by 3-5x).
//! - Only the setting "occlusion" is chosen for; "none" and "frustum" are drawn as set.

use std::time::{Duration, Instant};
use vbrain::cull::CullMode;

/// How often the two ways are measured again while the layout stays.
pub const PROBE_EVERY: Duration = Duration::from_secs(5);

#[derive(Clone, Debug, Default)]
pub struct CullChoice {
    /// The last measured cost of a frame with occlusion culling, and with frustum culling.
    occlusion: Option<f64>,
    frustum: Option<f64>,
    /// When the pair was last measured, and the layout it was measured for.
    measured: Option<(Instant, u64)>,
    /// The mode the frame being drawn measures, if it is a probe.
    probing: Option<CullMode>,
}

impl CullChoice {
    /// The mode of the next frame, and whether it is a probe (to be measured with the GPU's time);
    /// `layout` is a key of what is drawn, whose change calls for a new measurement.
    pub fn next(&mut self, now: Instant, layout: u64) -> (CullMode, bool) {
        let stale = match self.measured {
            Some((at, key)) => key != layout || now.duration_since(at) >= PROBE_EVERY,
            None => true,
        };
        if stale && self.probing.is_none() {
            // A new pair: occlusion first, then frustum.
            (self.occlusion, self.frustum) = (None, None);
            self.measured = Some((now, layout));
        }
        let probe = match (self.occlusion, self.frustum) {
            (None, _) => Some(CullMode::Occlusion),
            (Some(_), None) => Some(CullMode::Frustum),
            _ => None,
        };
        self.probing = probe;
        (probe.unwrap_or_else(|| self.chosen()), probe.is_some())
    }

    /// A probe frame drawn with `mode` cost `ms` (culling and drawing).
    pub fn observe(&mut self, mode: CullMode, ms: f64) {
        if self.probing != Some(mode) {
            return;
        }
        match mode {
            CullMode::Occlusion => self.occlusion = Some(ms),
            _ => self.frustum = Some(ms),
        }
        self.probing = None;
    }

    /// The cheaper mode as last measured; occlusion until both are.
    pub fn chosen(&self) -> CullMode {
        match (self.occlusion, self.frustum) {
            (Some(o), Some(f)) if f < o => CullMode::Frustum,
            _ => CullMode::Occlusion,
        }
    }

    /// Why the viewer culls as it does, for the statistics overlay.
    pub fn reason(&self) -> String {
        match (self.occlusion, self.frustum) {
            (Some(o), Some(f)) if f < o => {
                format!(
                    "frustum only: occlusion culling would cost {:.1} ms more a frame ({o:.1} against {f:.1})",
                    o - f
                )
            }
            (Some(o), Some(f)) => format!("occlusion: it saves {:.1} ms a frame ({o:.1} against {f:.1})", f - o),
            _ => "occlusion: measuring whether it pays".into(),
        }
    }
}

/// A key of what the layout draws: which organs are opaque and where each is, as the occluder
/// database fingerprints it; a change calls for measuring culling again.
pub fn layout_key(layout: &vbrain::layout::Layout) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    vbrain::cull::database::layout_fingerprint(layout).hash(&mut h);
    h.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Runs a measurement whose frames cost `cull + triangles * draw_ns`: occlusion culling spends
    /// 6 ms to draw 50,000 triangles, frustum culling 0.7 ms to draw 250,000.
    fn choose(choice: &mut CullChoice, now: Instant, draw_ns: f64) -> CullMode {
        for _ in 0..2 {
            let (mode, probe) = choice.next(now, 1);
            assert!(probe);
            let (cull, triangles) = if mode == CullMode::Occlusion { (6.0, 50_000.0) } else { (0.7, 250_000.0) };
            choice.observe(mode, cull + triangles * draw_ns * 1e-6);
        }
        choice.next(now, 1).0
    }

    #[test]
    fn a_fast_gpu_culls_by_the_frustum_and_a_slow_one_by_occlusion() {
        let start = Instant::now();
        let mut choice = CullChoice::default();
        assert_eq!(choice.next(start, 1), (CullMode::Occlusion, true), "measured first");
        let mut choice = CullChoice::default();
        // A real GPU: 1 ns a triangle. Culling 200,000 fewer saves 0.2 ms for 5.3 ms of culling.
        assert_eq!(choose(&mut choice, start, 1.0), CullMode::Frustum);
        assert!(choice.reason().starts_with("frustum only"), "{}", choice.reason());
        // A software GPU: 480 ns a triangle.
        let later = start + PROBE_EVERY;
        assert_eq!(choose(&mut choice, later, 480.0), CullMode::Occlusion);
        assert!(choice.reason().starts_with("occlusion: it saves"), "{}", choice.reason());
        // Kept without probes until the layout changes or the time is up.
        assert_eq!(choice.next(later + Duration::from_secs(1), 1), (CullMode::Occlusion, false));
        assert_eq!(choice.next(later + Duration::from_secs(1), 2), (CullMode::Occlusion, true), "a new layout");
    }
}
