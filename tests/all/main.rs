//! The core's integration tests, one binary (linked once): the architecture, loading (and fuzzed
//! input), the default set and its cortex's shape, culling, occluders, rendering, shaders and
//! transparency. GPU tests run on any adapter (lavapipe in CI); with none they fail and say what
//! to install.

#![allow(clippy::unwrap_used, clippy::expect_used)] // test helpers may panic

mod architecture;
mod brain_shape;
mod common;
mod culling;
mod default_set;
mod input_fuzz;
mod loading;
mod lod;
mod mri;
mod occluders;
mod quiz;
mod render;
mod sections;
mod shaders;
mod territories;
mod tracts;
mod transparency;
