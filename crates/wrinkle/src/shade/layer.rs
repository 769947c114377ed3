//! Texture layers: a source through its mapping, the material property it writes (`Target`) and how it
//! combines with what is there (`Mode`, OpenGL 1.x's texture environment).
//!
//! The equations are those of the OpenGL 1.x specification (glTexEnv, the RGB and RGBA base formats), with
//! (Cf, Af) the fragment's colour and alpha so far and (Ct, At) the texel's:
//!
//! | mode     | RGB texture           | RGBA texture                          |
//! | -------- | --------------------- | ------------------------------------- |
//! | replace  | Ct, Af                | Ct, At                                |
//! | modulate | Cf Ct, Af             | Cf Ct, Af At                          |
//! | decal    | Ct, Af                | Cf (1 - At) + Ct At, Af               |
//! | blend    | Cf (1 - Ct) + Cc Ct, Af | Cf (1 - Ct) + Cc Ct, Af At          |
//! | add      | Cf + Ct (clamped), Af | Cf + Ct (clamped), Af At              |
//!
//! Scalar targets (ks, shininess, opacity) read a texel as one value, a luminance texture in OpenGL's
//! terms: the mean of R, G and B, or for `opacity` the alpha of an RGBA texture. They take the luminance
//! rows (replace Lt, modulate Lf Lt, blend Lf (1 - Lt) + Lc Lt, add Lf + Lt); decal has no luminance form.

use crate::lanes::{F8, V3};
use crate::mapping::MappedTexture;
use glam::Vec3;

/// The material property a layer writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Target {
    /// The diffuse colour and the fragment's alpha (an RGBA texture's alpha goes to the alpha).
    Kd,
    /// The specular coefficient.
    Ks,
    /// The Blinn-Phong exponent, as a fraction of the material's `shininess` (a texel of 1 keeps it).
    Shininess,
    /// The fragment's alpha (coverage under `alpha_mode = "mask"`).
    Opacity,
    /// Emitted radiance, added to the lit colour.
    Emission,
}

impl Target {
    pub const NAMES: [(&'static str, Target); 5] = [
        ("kd", Target::Kd),
        ("ks", Target::Ks),
        ("shininess", Target::Shininess),
        ("opacity", Target::Opacity),
        ("emission", Target::Emission),
    ];

    /// Whether the target is a colour (else one value per sample).
    pub fn is_colour(self) -> bool {
        matches!(self, Target::Kd | Target::Emission)
    }
}

/// How a layer's texel combines with the fragment (glTexEnv's `GL_TEXTURE_ENV_MODE`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Mode {
    Replace,
    Modulate,
    Decal,
    /// Blend towards the constant colour Cc (`GL_TEXTURE_ENV_COLOR`) by the texel.
    Blend(Vec3),
    Add,
}

impl Mode {
    pub const NAMES: [&'static str; 5] = ["replace", "modulate", "decal", "blend", "add"];

    /// The colour and alpha after the layer: `(cf, af)` the fragment's, `(ct, at)` the texel's; `rgba`
    /// whether the texture has an alpha channel (OpenGL's RGBA base format).
    #[inline]
    pub fn colour8(self, (cf, af): (V3, F8), (ct, at): (V3, F8), rgba: bool) -> (V3, F8) {
        let product = if rgba { af * at } else { af };
        match self {
            Mode::Replace => (ct, if rgba { at } else { af }),
            Mode::Modulate => (cf * ct, product),
            Mode::Decal if rgba => (cf * (F8::ONE - at) + ct * at, af),
            Mode::Decal => (ct, af),
            Mode::Blend(cc) => (cf * (V3::splat(Vec3::ONE) - ct) + V3::splat(cc) * ct, product),
            Mode::Add => {
                let sum = cf + ct;
                (V3 { x: clamp01(sum.x), y: clamp01(sum.y), z: clamp01(sum.z) }, product)
            }
        }
    }

    /// The alpha alone after the layer (what the alpha test needs of a colour layer).
    #[inline]
    pub fn alpha8(self, af: F8, at: F8, rgba: bool) -> F8 {
        match self {
            Mode::Replace if rgba => at,
            Mode::Modulate | Mode::Blend(_) | Mode::Add if rgba => af * at,
            _ => af,
        }
    }

    /// A scalar target after the layer: `lf` the fragment's value, `lt` the texel's (luminance rows).
    #[inline]
    pub fn scalar8(self, lf: F8, lt: F8) -> F8 {
        match self {
            Mode::Replace | Mode::Decal => lt,
            Mode::Modulate => lf * lt,
            Mode::Blend(cc) => lf * (F8::ONE - lt) + F8::splat((cc.x + cc.y + cc.z) / 3.0) * lt,
            Mode::Add => clamp01(lf + lt),
        }
    }
}

#[inline]
fn clamp01(x: F8) -> F8 {
    x.max(F8::ZERO).min(F8::ONE)
}

/// One texture layer of a material.
#[derive(Clone)]
pub struct Layer {
    pub source: MappedTexture,
    pub target: Target,
    pub mode: Mode,
    /// The texture has an alpha channel (OpenGL's RGBA base format rather than RGB).
    pub rgba: bool,
}

impl Layer {
    /// A texture modulating `target`: today's one-texture forms (`texture` on kd, `specular_map` on ks) and
    /// the maps of model files.
    pub fn modulate(source: MappedTexture, target: Target, rgba: bool) -> Layer {
        Layer { source, target, mode: Mode::Modulate, rgba }
    }

    /// A scalar target's texel: the mean of R, G, B, or an RGBA texture's alpha on `opacity`; clamped to
    /// [0, 1] for the reflectance and the coverage.
    #[inline]
    pub fn scalar_texel(&self, [r, g, b, a]: [F8; 4]) -> F8 {
        match self.target {
            Target::Opacity if self.rgba => clamp01(a),
            Target::Ks | Target::Opacity => clamp01((r + g + b) * F8::splat(1.0 / 3.0)),
            _ => (r + g + b) * F8::splat(1.0 / 3.0),
        }
    }

    /// Whether the layer can change the fragment's alpha (the alpha test evaluates only those).
    pub fn writes_alpha(&self) -> bool {
        match self.target {
            Target::Opacity => true,
            Target::Kd => self.rgba && self.mode != Mode::Decal,
            _ => false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn colour(mode: Mode, cf: [f32; 4], ct: [f32; 4], rgba: bool) -> [f32; 4] {
        let v = |c: [f32; 4]| (V3::splat(Vec3::new(c[0], c[1], c[2])), F8::splat(c[3]));
        let (c, a) = mode.colour8(v(cf), v(ct), rgba);
        let rgb = c.lane(3);
        [rgb.x, rgb.y, rgb.z, a.as_array_ref()[3]]
    }

    /// Each mode against the OpenGL 1.x table, written out per channel.
    #[test]
    fn modes_follow_the_opengl_equations() {
        let (cf, ct) = ([0.8, 0.4, 0.2, 0.9], [0.5, 0.25, 1.0, 0.6]);
        let cc = Vec3::new(0.1, 0.9, 0.3);
        let close = |a: [f32; 4], b: [f32; 4]| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-6);
        let per = |f: &dyn Fn(usize) -> f32, a: f32| [f(0), f(1), f(2), a];
        let cases: [(Mode, bool, [f32; 4]); 10] = [
            (Mode::Replace, false, per(&|i| ct[i], cf[3])),
            (Mode::Replace, true, per(&|i| ct[i], ct[3])),
            (Mode::Modulate, false, per(&|i| cf[i] * ct[i], cf[3])),
            (Mode::Modulate, true, per(&|i| cf[i] * ct[i], cf[3] * ct[3])),
            (Mode::Decal, false, per(&|i| ct[i], cf[3])),
            (Mode::Decal, true, per(&|i| cf[i] * (1.0 - ct[3]) + ct[i] * ct[3], cf[3])),
            (Mode::Blend(cc), false, per(&|i| cf[i] * (1.0 - ct[i]) + cc[i] * ct[i], cf[3])),
            (Mode::Blend(cc), true, per(&|i| cf[i] * (1.0 - ct[i]) + cc[i] * ct[i], cf[3] * ct[3])),
            (Mode::Add, false, per(&|i| (cf[i] + ct[i]).min(1.0), cf[3])),
            (Mode::Add, true, per(&|i| (cf[i] + ct[i]).min(1.0), cf[3] * ct[3])),
        ];
        for (mode, rgba, want) in cases {
            let got = colour(mode, cf, ct, rgba);
            assert!(close(got, want), "{mode:?} rgba={rgba}: {got:?} != {want:?}");
            assert_eq!(mode.alpha8(F8::splat(cf[3]), F8::splat(ct[3]), rgba).as_array_ref()[0], want[3]);
        }
        let s = |m: Mode| m.scalar8(F8::splat(0.7), F8::splat(0.4)).as_array_ref()[5];
        assert_eq!(s(Mode::Replace), 0.4);
        assert!((s(Mode::Modulate) - 0.28).abs() < 1e-7);
        assert!((s(Mode::Blend(Vec3::splat(0.5))) - (0.7 * 0.6 + 0.5 * 0.4)).abs() < 1e-7);
        assert_eq!(s(Mode::Add), 1.0);
    }
}
