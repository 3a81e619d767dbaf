//! The experiments behind the headless commands.

pub mod bench;
pub mod masks;
pub mod occluders;
pub mod plot;
pub mod transparency_bench;
