//! Tangent-space normal maps on a surface: the map's texel decoded to a unit vector (x, y, z) in the frame
//! of the tangent T (along +u), the bitangent B = w (N x T) (along +v) and the unit normal N, as glTF and
//! MikkTSpace define it: N' = normalize(s x T + s y B + z N), s the strength (glTF's normalTexture.scale).

use super::normal_map::Convention;
use crate::lanes::{F8, V3};
use crate::mapping::MappedTexture;
use crate::texture::LookupContext8;

pub struct TangentNormalMap {
    /// Linear RGB (a data map, never sRGB-decoded), each channel (c + 1) / 2 of a component c in [-1, 1].
    pub texture: MappedTexture,
    pub strength: f32,
    pub convention: Convention,
}

impl TangentNormalMap {
    /// The perturbed unit normals of eight samples whose unit normals are `n`, unit tangents `t`
    /// (perpendicular to `n`) and bitangent signs `w`.
    #[inline]
    pub fn normal8(&self, ctx: &LookupContext8<'_>, n: V3, t: V3, w: F8) -> V3 {
        let [r, g, b, _] = self.texture.eval8(ctx);
        let (two, one) = (F8::splat(2.0), F8::ONE);
        let s = F8::splat(self.strength);
        let y = match self.convention {
            Convention::OpenGl => g * two - one,
            Convention::DirectX => one - g * two,
        };
        let bitangent = n.cross(t) * w;
        (t * ((r * two - one) * s) + bitangent * (y * s) + n * (b * two - one)).normalize_or_zero()
    }
}
