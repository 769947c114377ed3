//! Materials: a base colour, an optional colour texture, Blinn-Phong specular, an optional bump map or
//! tangent-space normal map.

use super::phong::Phong;
use crate::bump::{BumpMap, TangentNormalMap};
use crate::mapping::{MappedTexture, Mapping, Projection};
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

impl Material {
    /// The mappings of every texture the material reads (colour, specular, normal map, bump).
    pub fn mappings_mut(&mut self) -> impl Iterator<Item = &mut Mapping> {
        let textures =
            [self.texture.as_mut(), self.specular_map.as_mut(), self.normal_map.as_mut().map(|m| &mut m.texture)];
        textures.into_iter().flatten().map(|t| &mut t.mapping).chain(self.bump.as_mut().map(|b| &mut b.mapping))
    }

    fn projections(&self) -> impl Iterator<Item = &Projection> {
        let textures =
            [self.texture.as_ref(), self.specular_map.as_ref(), self.normal_map.as_ref().map(|m| &m.texture)];
        textures
            .into_iter()
            .flatten()
            .map(|t| &t.mapping.projection)
            .chain(self.bump.as_ref().map(|b| &b.mapping.projection))
    }

    /// Whether a mapping follows the normal, so the shader must work out its change across the pixel.
    pub fn reads_normal_change(&self) -> bool {
        self.projections().any(Projection::reads_normal)
    }

    /// Whether a mapping reads a mesh's second texture coordinate set.
    pub fn reads_second_uv(&self) -> bool {
        self.projections().any(|p| matches!(p, Projection::SecondUv))
    }
}
