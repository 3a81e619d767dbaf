//! The lab: the experiments and benchmarks of the thesis's chapter 5 and of the issues since, apart
//! from what the viewer uses. Each measures the core's real code paths and returns plain records;
//! the command line (`ui/src/lab`) reports them as CSV, plots and JSON.
//!
//! - [`mod@bench`]: the culling benchmark (orbit or city routes), thesis §5 and Figure 22.
//! - [`city`]: the synthetic city of the occluder experiments, thesis §5.1.1.
//! - [`occluder_selection`]: culled share against occluder count per selection, thesis Figure 14.
//! - [`masks`]: faulty pixels of stacked masks per method, thesis Figures 19 and 20.

pub mod bench;
pub mod city;
pub mod masks;
pub mod occluder_selection;

/// A CSV field (RFC 4180): quoted where it holds a comma, quote or line break. Every CSV vbrain
/// writes (the experiments', the quiz results) goes through it.
pub fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}
