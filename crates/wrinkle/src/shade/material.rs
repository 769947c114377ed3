//! Materials: a base colour, an optional colour texture, Blinn-Phong specular, an optional bump map or
//! tangent-space normal map.

use super::phong::Phong;
use crate::bump::{BumpMap, TangentNormalMap};
use crate::mapping::MappedTexture;
use glam::Vec3;

pub struct Material {
    /// Multiplies the texture (or stands alone), linear RGB.
    pub color: Vec3,
    pub texture: Option<MappedTexture>,
    pub phong: Phong,
    pub bump: Option<BumpMap>,
    /// A tangent-space normal map (instead of a bump map).
    pub normal_map: Option<TangentNormalMap>,
    /// Multiplies `phong.specular` by the map's mean of R, G, B (clamped to [0, 1]): a Ks map.
    pub specular_map: Option<MappedTexture>,
}
