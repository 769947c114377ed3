//! Materials: a diffuse colour, opacity and emission, Blinn-Phong specular, texture layers over them, an
//! optional bump map or tangent-space normal map, an optional displacement, and how alpha is used.

use super::layer::{Layer, Mode, Target};
use super::phong::Phong;
use crate::bump::{BumpMap, Displacement, TangentNormalMap};
use crate::envmap::Environment;
use crate::mapping::{MappedTexture, Mapping, Projection};
use glam::Vec3;
use std::sync::Arc;

/// How a material's alpha is used (glTF's `alphaMode`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AlphaMode {
    /// Alpha is ignored: the surface covers what it covers.
    Opaque,
    /// The alpha test: samples whose alpha is below the cutoff are not part of the surface.
    Mask { cutoff: f32 },
    /// Sorted transparency; refused when a scene is loaded, until the transparent pass exists.
    Blend,
}

pub struct Material {
    /// The diffuse colour Kd before the layers, linear RGB.
    pub color: Vec3,
    /// The fragment's alpha before the layers.
    pub opacity: f32,
    /// Emitted radiance before the layers, linear RGB.
    pub emission: Vec3,
    pub phong: Phong,
    /// Texture layers, applied in order.
    pub layers: Vec<Layer>,
    pub alpha_mode: AlphaMode,
    pub bump: Option<BumpMap>,
    /// A tangent-space normal map (instead of a bump map).
    pub normal_map: Option<TangentNormalMap>,
    /// Moves the surface itself; its F also shades (with a bump's added).
    pub displacement: Option<Displacement>,
    /// How much of the environment the surface mirrors (linear RGB): the reflected view ray's lookup times
    /// this, added to the lit colour.
    pub reflect: Vec3,
    /// `reflect` is the reflectance at normal incidence, rising towards 1 at grazing angles (Schlick).
    pub fresnel: bool,
    /// Mirror the scene itself, rendered each frame as six views of this many pixels square from the
    /// object's centroid (0: mirror the scene's environment).
    pub reflect_views: usize,
    /// A chrome map of its own (the slides' chrome mapping), with or without a scene environment.
    pub chrome: Option<Chrome>,
}

/// Chrome mapping: a view-independent, heavily blurred picture of surroundings looked up by the reflected
/// view ray, added times `strength`; what is seen in it matters less than that it moves with the view.
#[derive(Clone)]
pub struct Chrome {
    /// Already blurred (an environment convolved with a broad Phong lobe).
    pub map: Arc<Environment>,
    pub strength: Vec3,
}

impl Default for Material {
    /// Grey and matte.
    fn default() -> Material {
        Material {
            color: Vec3::splat(0.8),
            opacity: 1.0,
            emission: Vec3::ZERO,
            phong: Phong::new(0.0, 20.0),
            layers: Vec::new(),
            alpha_mode: AlphaMode::Opaque,
            bump: None,
            normal_map: None,
            displacement: None,
            reflect: Vec3::ZERO,
            fresnel: false,
            reflect_views: 0,
            chrome: None,
        }
    }
}

impl Material {
    /// The first layer on the diffuse colour: the object's colour texture (the uv AOV shows its
    /// coordinates).
    pub fn colour_texture(&self) -> Option<&MappedTexture> {
        self.layers.iter().find(|l| l.target == Target::Kd).map(|l| &l.source)
    }

    /// Makes `texture` the one colour texture, modulating the diffuse colour (today's `texture` field):
    /// it replaces every layer on Kd.
    pub fn set_colour_texture(&mut self, texture: MappedTexture, rgba: bool) {
        self.layers.retain(|l| l.target != Target::Kd);
        self.layers.insert(0, Layer::modulate(texture, Target::Kd, rgba));
    }

    /// Whether the highlight's cutoff, worked out for the material's own specular and exponent, holds for
    /// every sample: layers on ks that only modulate lower the specular, any other layer on ks or on the
    /// exponent can raise what a sample's highlight adds.
    pub fn highlight_cutoff_holds(&self) -> bool {
        self.layers.iter().all(|l| match l.target {
            Target::Ks => l.mode == Mode::Modulate,
            Target::Shininess => false,
            _ => true,
        })
    }

    /// Whether the material emits (a colour or a layer on emission).
    pub fn emits(&self) -> bool {
        self.emission != Vec3::ZERO || self.layers.iter().any(|l| l.target == Target::Emission)
    }

    /// Whether the surface mirrors the environment.
    pub fn reflects(&self) -> bool {
        self.reflect != Vec3::ZERO
    }

    /// Whether the bump is parallax-mapped with depth replacement: the sample lies at the crossing.
    pub fn replaces_depth(&self) -> bool {
        self.bump.as_ref().and_then(|b| b.parallax).is_some_and(|p| p.depth_replace)
    }

    /// Whether alpha removes samples in the visibility pass, and below which value.
    pub fn alpha_cutoff(&self) -> Option<f32> {
        match self.alpha_mode {
            AlphaMode::Mask { cutoff } => Some(cutoff),
            _ => None,
        }
    }

    /// The mappings of every texture the material reads (layers, normal map, bump, displacement).
    pub fn mappings_mut(&mut self) -> impl Iterator<Item = &mut Mapping> {
        let layers = self.layers.iter_mut().map(|l| &mut l.source.mapping);
        let normal_map = self.normal_map.as_mut().map(|m| &mut m.texture.mapping);
        let displacement = self.displacement.as_mut().map(|d| &mut d.map.mapping);
        layers.chain(normal_map).chain(self.bump.as_mut().map(|b| &mut b.mapping)).chain(displacement)
    }

    fn projections(&self) -> impl Iterator<Item = &Projection> {
        let layers = self.layers.iter().map(|l| &l.source.mapping.projection);
        let normal_map = self.normal_map.as_ref().map(|m| &m.texture.mapping.projection);
        let displacement = self.displacement.as_ref().map(|d| &d.map.mapping.projection);
        layers.chain(normal_map).chain(self.bump.as_ref().map(|b| &b.mapping.projection)).chain(displacement)
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
