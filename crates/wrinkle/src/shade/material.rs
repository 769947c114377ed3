//! Materials: a base colour, an optional colour texture, Blinn-Phong specular, an optional bump function.

use super::light::Phong;
use crate::bump::{BumpFormula, BumpTable, Interp};
use crate::procedural::solid::Procedural;
use crate::texture::{Filter, Texture};
use glam::{Vec2, Vec3};
use std::sync::Arc;

pub struct Material {
    /// Multiplies the texture (or stands alone), linear RGB.
    pub color: Vec3,
    pub texture: Option<Arc<dyn Texture>>,
    pub phong: Phong,
    pub bump: Option<Bump>,
    /// Multiplies `phong.specular` by the map's mean of R, G, B (clamped to [0, 1]): a Ks map.
    pub specular_map: Option<Arc<dyn Texture>>,
}

/// How the bump function is filtered against aliasing (Blinn section 5).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BumpFilter {
    /// Full-resolution table everywhere; supersample (`--spp`) to remove aliasing.
    None,
    /// The table's MIP level chosen from the pixel's (u,v) footprint.
    Mip,
    /// Any texture filter (trilinear, ripmap, sat, aniso, ewa, ...) applied to the table and its
    /// derivatives alike.
    Filtered(Filter),
}

impl BumpFilter {
    /// Every choice by name: `none`, `mip`, then every texture filter.
    pub fn choices() -> Vec<(&'static str, BumpFilter)> {
        let texture = Filter::ALL.iter().map(|&(n, f)| (n, BumpFilter::Filtered(f)));
        [("none", BumpFilter::None), ("mip", BumpFilter::Mip)].into_iter().chain(texture).collect()
    }

    pub fn parse(name: &str) -> Option<BumpFilter> {
        BumpFilter::choices().into_iter().find(|(n, _)| *n == name).map(|(_, f)| f)
    }
}

/// Where F comes from.
pub enum BumpSource {
    /// A table T: F(u,v) = scale * T(repeat_u u, repeat_v v).
    Table(Arc<BumpTable>),
    /// A procedural pattern t: F = scale * t, with Fu and Fv from its analytic gradient.
    Procedural(Arc<Procedural>),
}

/// A bump function: F = scale * (the source at (u,v), or at the object-space point).
pub struct Bump {
    pub source: BumpSource,
    pub scale: f32,
    pub repeat: Vec2,
    pub interp: Interp,
    pub formula: BumpFormula,
    pub filter: BumpFilter,
}
