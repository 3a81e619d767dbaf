//! The experiments behind the headless commands: each runs its measurement, prints a summary
//! (or with `--json` one object), and writes a CSV and a PNG plot ([`plot`]). They take plain
//! options, never clap types: `cli` parses the arguments, and the checks that need more than one
//! argument stay here.

pub mod bench;
pub mod masks;
pub mod occluders;
pub mod plot;
pub mod transparency_bench;
