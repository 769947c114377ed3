//! Blinn's bump mapping (1978): the perturbed normal N' = N + D, bump functions as tables or procedures
//! and their evaluation at a sample (function.rs), and the generators of the paper's figures.

pub mod blinn;
pub mod bytes;
pub mod displacement;
pub mod function;
pub mod generators;
pub mod integrate;
pub mod lean;
pub mod normal_map;
pub mod parallax;
pub mod range;
pub mod schlag;
pub mod table;
pub mod tangent_space;

pub use blinn::BumpFormula;
pub use displacement::{Displacement, DisplacementMode};
pub use function::{BumpMap, BumpSource, OffsetMap};
pub use lean::{BumpFilter, SlopeFilter};
pub use parallax::{Crossing8, Parallax};
pub use table::{BumpTable, Interp};
pub use tangent_space::TangentNormalMap;

/// A bump function's value F and its derivatives along the two coordinates it was evaluated over: the
/// table's (s,t) for a table lookup, the surface's (u,v) once a bump map has applied its chain rule.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Gradient {
    pub f: f32,
    pub fu: f32,
    pub fv: f32,
}
