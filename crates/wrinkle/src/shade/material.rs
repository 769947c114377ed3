//! Materials: a base colour, an optional colour texture, Blinn-Phong specular, an optional bump map.

use super::phong::Phong;
use crate::bump::BumpMap;
use crate::mapping::MappedTexture;
use glam::Vec3;

pub struct Material {
    /// Multiplies the texture (or stands alone), linear RGB.
    pub color: Vec3,
    pub texture: Option<MappedTexture>,
    pub phong: Phong,
    pub bump: Option<BumpMap>,
    /// Multiplies `phong.specular` by the map's mean of R, G, B (clamped to [0, 1]): a Ks map.
    pub specular_map: Option<MappedTexture>,
}
