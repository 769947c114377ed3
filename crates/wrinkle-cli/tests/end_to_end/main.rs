//! The command's end-to-end tests, one module per area, in one test binary (each test binary links the
//! whole library with LTO: one of them instead of five saves minutes of every test run).

mod common;

mod cli;
mod emboss_cli;
mod normal_maps_cli;
mod paint_cli;
mod portable;
mod portable_build;
mod robustness_cli;
