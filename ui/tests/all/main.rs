//! The ui crate's integration tests, in one binary so that it links once: the `vbrain` command
//! line run as a user would ([`cli`], the experiments and benchmarks in [`benches`]) and with what
//! breaks things ([`hardening`]), the glTF export checked by the Khronos validator ([`export`]),
//! Anki decks imported by Anki's own library ([`study`]), the viewer under egui_kittest
//! ([`viewer`], [`quiz`]), and README.md's controls table against the viewer's shortcut table
//! ([`shortcuts`]).

#![allow(clippy::unwrap_used, clippy::expect_used)] // tests and their helpers may panic

mod benches;
mod cli;
mod dropped;
mod export;
mod first_hour;
mod hardening;
mod install;
mod lecture;
mod quiz;
mod shortcuts;
mod slice;
mod study;
mod territories;
mod viewer;
mod writers;
