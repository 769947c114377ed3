//! Materials: a base colour, an optional colour texture, Blinn-Phong specular, an optional bump function.

use super::light::Phong;
use crate::bump::{BumpFormula, BumpTable, Interp};
use crate::procedural::solid::Procedural;
use crate::texture::Texture;
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
