//! Blinn's bump mapping (1978): the perturbed normal N' = N + D, bump functions as tables,
//! and the generators of the paper's figures.

pub mod blinn;
pub mod generators;
pub mod integrate;
pub mod normal_map;
pub mod schlag;
pub mod table;

pub use blinn::{BumpFormula, Perturbation};
pub use table::{BumpSample, BumpTable, Interp};
