//! Tangent-space normal maps on a surface: the map's texel decoded to a unit vector (x, y, z) in the frame
//! of the tangent T (along +u), the bitangent B = w (N x T) (along +v) and the unit normal N, as glTF and
//! MikkTSpace define it: N' = normalize(s x T + s y B + z N), s the strength (glTF's normalTexture.scale).

use super::lean::{SlopeFilter, SlopeMoments};
use super::normal_map::{decode_normal, Convention};
use crate::lanes::{F8, LANES, V3};
use crate::mapping::MappedTexture;
use crate::texture::LookupContext8;
use glam::Vec2;
use std::sync::OnceLock;

pub struct TangentNormalMap {
    /// Linear RGB (a data map, never sRGB-decoded), each channel (c + 1) / 2 of a component c in [-1, 1].
    pub texture: MappedTexture,
    pub strength: f32,
    pub convention: Convention,
    /// What the texture's filter does about the spread of the normals under a pixel (LEAN, Toksvig).
    pub slopes: SlopeFilter,
    /// The moments of the map's slopes (x/z, y/z), built on first use by LEAN or Toksvig filtering.
    moments: OnceLock<SlopeMoments>,
}

impl TangentNormalMap {
    pub fn new(texture: MappedTexture, strength: f32, convention: Convention) -> TangentNormalMap {
        TangentNormalMap { texture, strength, convention, slopes: SlopeFilter::Plain, moments: OnceLock::new() }
    }

    /// The covariance of the slopes (s x/z, s y/z) of eight samples' normals under their pixels, along the
    /// tangent and the bitangent; `None` for a procedural map (no image to take moments of).
    pub fn spread8(&self, ctx: &LookupContext8<'_>) -> Option<[F8; 3]> {
        let image = self.texture.texture.image()?;
        let moments = self.moments.get_or_init(|| {
            SlopeMoments::of_texture(image, |c| {
                let [x, y, z] = decode_normal([c.x, c.y, c.z], self.convention);
                // A texel below the surface (z <= 0) is read as the steepest slope the map can mean.
                Vec2::new(x, y) / z.max(0.05)
            })
        });
        let (mapped, _) = self.texture.mapping.apply8(ctx);
        let (s, t) = (mapped.u.as_array_ref(), mapped.v.as_array_ref());
        let filter = &image.options().filter;
        let lanes: [[f32; 3]; LANES] = std::array::from_fn(|i| {
            let (_, c) = moments.lookup(s[i], t[i], &mapped.footprint.lane(i), filter);
            [c.xx, c.yy, c.xy]
        });
        let k = F8::splat(self.strength * self.strength);
        Some(std::array::from_fn(|m| F8::new(lanes.map(|c| c[m])) * k))
    }

    /// The bitangents B = w (N x T) of unit normals `n`, tangents `t` and signs `w`.
    #[inline]
    pub fn bitangent(&self, n: V3, t: V3, w: F8) -> V3 {
        n.cross(t) * w
    }

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
        (t * ((r * two - one) * s) + self.bitangent(n, t, w) * (y * s) + n * (b * two - one)).normalize_or_zero()
    }
}
