//! The core crate's integration tests, one module per area, in one test binary: each binary links the whole
//! library with LTO, so twenty of them cost minutes of every test run (the fuzz harness, with its own
//! allocator, stays apart in tests/fuzz_corpus.rs).

mod common;

mod aliasing;
mod animation;
mod billboards;
mod bump_reference;
mod displacement;
mod emboss_reference;
mod environment;
mod examples;
mod filtering;
mod height_maps;
mod layers;
mod lean;
mod mappings;
mod meshes;
mod normal_map_reference;
mod procedural_aliasing;
mod public_api;
mod raster_reference;
mod sampling;
mod scene_robustness;
mod shading_rate;
mod shadows;
mod spot_lights;
mod texel_location;
mod texture_files;
mod transparency;
mod transparent_background;
mod unwrap;
