//! Shading of eight samples: the lookup context of the exact surface frame at each sample's (u,v), the
//! bump map's perturbation, the colour and specular textures through their mappings, and Blinn-Phong
//! lighting from several lights.

pub mod layer;
pub mod material;
pub mod phong;

pub use layer::{Layer, Mode, Target};
pub use material::{AlphaMode, Chrome, Material};
pub use phong::{Lobe8, Phong};

use crate::bump::blinn::{perturbed_normal8, perturbed_normal_sided8};
use crate::bump::lean::WorldSpread8;
use crate::bump::{BumpFilter, BumpFormula, BumpMap, DisplacementMode, SlopeFilter};
use crate::envmap::Environment;
use crate::geometry::frame_lanes::Frame8;
use crate::geometry::mesh_lanes::MeshFrame8;
use crate::geometry::{Instance, Primitive};
use crate::lanes::{CmpGt, CmpLt, F8, LANES, V3};
use crate::light::{Light, ShadowMap, Shadows, Spot};
use crate::texture::{FilterOptions, FilteredTexture, Footprint, Footprint8, LookupContext8, SurfaceLanes, UvSet8};
use glam::Vec3;
use std::sync::Arc;

/// What the shader needs besides the surface: the eye, the lights, the materials and switches.
pub struct ShadeContext<'a> {
    pub eye: Vec3,
    /// For orthographic views, the direction towards the eye (the same for every pixel).
    pub ortho_to_eye: Option<Vec3>,
    pub lights: &'a [Light],
    pub materials: &'a [Material],
    /// What each material's mappings read beyond the first set's (u,v), found once per frame.
    pub needs: Vec<MappingNeeds>,
    pub bump_enabled: bool,
    /// Replaces every bump's own filter when set (`--bump-filter`).
    pub bump_filter: Option<BumpFilter>,
    /// What reflecting materials mirror.
    pub environment: Option<&'a Environment>,
    /// Per object, the six views rendered from its centroid that it mirrors instead (`reflect_views`).
    pub object_views: &'a [Option<Environment>],
    /// The environment as a light, where the scene has one.
    pub ibl: Option<Ibl>,
    /// The pictures spot lights project.
    pub slides: &'a [FilteredTexture],
    /// The lights' shadow maps, where any light casts shadows.
    pub shadows: Option<&'a Shadows>,
}

/// Image-based lighting: the scene's environment lights diffuse surfaces through its cosine-convolved map
/// and glossy ones through its map convolved with their Phong lobe.
pub struct Ibl {
    /// The environment lights' colour times intensity, summed.
    pub radiance: Vec3,
    /// Irradiance over pi (the lobe of exponent 1).
    pub diffuse: Arc<Environment>,
    /// Per material, its specular lobe's convolution where it has a highlight.
    pub glossy: Vec<Option<Arc<Environment>>>,
}

impl Ibl {
    /// The Phong exponent of a Blinn-Phong shininess: the lobe about R that (N.H)^n makes about H, about a
    /// quarter as wide in angle squared (the usual rule, exact near the mirror direction at normal view).
    pub fn phong_exponent(shininess: f32) -> f32 {
        (shininess / 4.0).max(1.0)
    }

    /// Diffuse albedo x C_1(N) + ks x C_s(R), times the lights' radiance.
    #[inline(never)]
    fn shade8(&self, material: usize, n: V3, v: V3, albedo: V3, ks: F8) -> V3 {
        let still = V3::ZERO;
        let mut c = albedo * self.diffuse.radiance8(&n, &still, &still);
        if let Some(glossy) = &self.glossy[material] {
            c = c + glossy.radiance8(&reflected(n, v), &still, &still) * ks;
        }
        c * V3::splat(self.radiance)
    }
}

/// What a material's mappings need of a sample beyond its position, frame and (u,v).
#[derive(Clone, Copy, Debug, Default)]
pub struct MappingNeeds {
    /// The unit normal's change across the pixel (projections that follow the normal).
    pub normal_change: bool,
    /// A mesh's texture coordinate set 1.
    pub second_uv: bool,
}

impl MappingNeeds {
    /// What `material` needs; `mirrors`: whether there is an environment to reflect (whose footprint is
    /// the reflected ray's, which turns with the normal).
    pub fn of(material: &Material, mirrors: bool) -> MappingNeeds {
        MappingNeeds {
            normal_change: material.reads_normal_change() || (mirrors && material.reflects()),
            second_uv: material.reads_second_uv(),
        }
    }
}

/// The result of shading one sample, with the data of the AOVs.
#[derive(Clone, Copy, Debug, Default)]
pub struct ShadedSample {
    /// Linear RGB.
    pub color: Vec3,
    /// The unit shading normal N' in world space, facing the eye for two-sided surfaces.
    pub normal: Vec3,
    /// Distance from the eye (along the view axis for orthographic views: from the camera plane).
    pub depth: f32,
}

/// Eight shaded samples (structure of arrays).
pub struct ShadedPacket {
    pub color: V3,
    pub normal: V3,
    pub depth: F8,
    /// The coordinates the colour texture was looked up with, after its mapping and before its uv
    /// transform (the surface's (u,v) without a texture): what the uv AOV shows.
    pub uv: (F8, F8),
}

impl ShadedPacket {
    pub fn lane(&self, i: usize) -> ShadedSample {
        ShadedSample { color: self.color.lane(i), normal: self.normal.lane(i), depth: self.depth.as_array_ref()[i] }
    }
}

/// The lookup context of eight samples at their own (u,v).
#[inline(always)]
fn context_of<'s>(surface: &'s SurfaceLanes<'s>, at: &SurfaceSamples8<'_>) -> LookupContext8<'s> {
    LookupContext8 { surface, u: at.uv.0, v: at.uv.1, footprint: at.footprint }
}

/// Eight samples of one primitive as the shader receives them.
pub struct SurfaceSamples8<'a> {
    /// P, Pu, Pv (and the second derivatives of parametric surfaces) in object space.
    pub frame: &'a Frame8,
    pub uv: (F8, F8),
    pub footprint: Footprint8,
    /// A mesh's texture coordinate set 1, where the material reads it.
    pub uv1: Option<&'a UvSet8>,
    /// Each sample's triangle, numbered within its object.
    pub triangles: [u32; LANES],
    /// What a mesh adds: which way Pu x Pv points and its own tangent frame. `None` on parametric
    /// surfaces, whose Pu x Pv is the outward normal and whose tangent runs along Pu.
    pub mesh: Option<&'a MeshFrame8>,
}

impl ShadeContext<'_> {
    /// The surface as the lookup contexts of `material` see it: the frame's lanes, with a mesh's side,
    /// its ray differentials and, where the mappings read it, the normal's change across the pixel.
    #[inline(always)]
    fn surface<'s>(&self, inst: &Instance, at: &'s SurfaceSamples8<'s>) -> SurfaceLanes<'s> {
        let frame = at.frame;
        let mut surface = SurfaceLanes::new(frame.p, frame.pu, frame.pv, &at.footprint, inst.object, at.triangles);
        surface.object_to_eye = inst.object_to_camera;
        surface.uv1 = at.uv1;
        let normal_change = self.needs[inst.material].normal_change;
        match &at.mesh {
            Some(m) => {
                surface.n = surface.n * m.side;
                (surface.dpdx, surface.dpdy) = (m.dpdx, m.dpdy);
                if normal_change {
                    [surface.dndx, surface.dndy] = m.normal_change;
                }
            }
            None if normal_change => [surface.dndx, surface.dndy] = frame.unit_normal_change(&at.footprint),
            None => {}
        }
        surface
    }

    /// Moves the lookup context of eight samples to where their view rays meet a parallax-mapped bump's
    /// height field, and says how much farther along the rays that is (`None` without parallax). The
    /// context is changed in place: moved out whole, its reference (alone in a 32-byte slot) was read
    /// back in one wide load after a narrow store, which stalled the store forwarding.
    #[inline(always)]
    fn parallax_of(&self, inst: &Instance, material: &Material, ctx: &mut LookupContext8<'_>) -> Option<F8> {
        match material.bump.as_ref().filter(|_| self.bump_enabled) {
            Some(bump) if bump.parallax.is_some() => self.parallax(inst, bump, ctx),
            _ => None,
        }
    }

    /// Moves `ctx` to where each view ray meets the bump's height field; the travel there (world units).
    #[inline(never)]
    fn parallax(&self, inst: &Instance, bump: &BumpMap, ctx: &mut LookupContext8<'_>) -> Option<F8> {
        let parallax = bump.parallax?;
        let to_eye = match self.ortho_to_eye {
            Some(_) => V3::splat(inst.camera_to_object.transform_vector3(Vec3::Z)),
            None => V3::splat(inst.camera_to_object.transform_point3(Vec3::ZERO)) - ctx.surface.p,
        };
        let crossing = parallax.trace8(bump, ctx, to_eye, &self.bump_filter_of(bump));
        (ctx.u, ctx.v) = (crossing.u, crossing.v);
        // The travel in world units: the object's transform may scale.
        let stretch = V3::transform_vector(&inst.object_to_world, to_eye.normalize_or_zero()).length();
        Some(crossing.travel * stretch)
    }

    /// Where a parallax-mapped surface with depth replacement is seen at eight samples: how much farther
    /// along each ray than the surface (world units), else `None`.
    pub fn replaced_depth8(&self, inst: &Instance, at: &SurfaceSamples8<'_>) -> Option<F8> {
        let material = &self.materials[inst.material];
        if !material.replaces_depth() {
            return None;
        }
        let surface = self.surface(inst, at);
        self.parallax_of(inst, material, &mut context_of(&surface, at))
    }

    /// The filter of a bump: its own, or `--bump-filter`'s.
    fn bump_filter_of(&self, bump: &BumpMap) -> FilterOptions {
        match self.bump_filter {
            Some(chosen) => FilterOptions { filter: chosen.texture, ..bump.filter },
            None => bump.filter,
        }
    }

    /// What a bump's filter does about the spread of the normals: its own choice, or `--bump-filter`'s.
    fn slopes_of(&self, bump: &BumpMap) -> SlopeFilter {
        self.bump_filter.map_or(bump.slopes, |chosen| chosen.slopes)
    }

    /// The alpha of eight samples of one primitive: the material's opacity through the layers that write
    /// alpha (what the alpha test compares with the cutoff).
    pub fn alpha8(&self, inst: &Instance, at: &SurfaceSamples8<'_>) -> F8 {
        let material = &self.materials[inst.material];
        let surface = self.surface(inst, at);
        let mut ctx = context_of(&surface, at);
        self.parallax_of(inst, material, &mut ctx);
        let mut alpha = F8::splat(material.opacity);
        for layer in material.layers.iter().filter(|l| l.writes_alpha()) {
            let texel = layer.source.eval8(&ctx);
            alpha = match layer.target {
                Target::Kd => layer.mode.alpha8(alpha, texel[3], layer.rgba),
                _ => layer.mode.scalar8(alpha, layer.scalar_texel(texel)),
            };
        }
        alpha
    }

    /// What a spot light lets through to eight points: its cone's falloff, times the slide it projects
    /// there (filtered over where the pixel's footprint falls on the slide; black outside it).
    #[inline(never)]
    fn spot_tint8(&self, spot: &Spot, inst: &Instance, position: V3, surface: &SurfaceLanes) -> V3 {
        let cone = spot.cone8(position);
        let Some(slide) = spot.slide.map(|k| &self.slides[k]) else { return V3 { x: cone, y: cone, z: cone } };
        let (s, t, z) = spot.slide8(position);
        let at = |d: V3| spot.slide8(position + V3::transform_vector(&inst.object_to_world, d));
        let ((sx, tx, _), (sy, ty, _)) = (at(surface.dpdx), at(surface.dpdy));
        let (s, t, z, cone) = (s.to_array(), t.to_array(), z.to_array(), cone.to_array());
        let (ds, dt) = (
            [sx - F8::new(s), sy - F8::new(s)].map(|d| d.to_array()),
            [tx - F8::new(t), ty - F8::new(t)].map(|d| d.to_array()),
        );
        let mut out = V3::ZERO;
        for i in 0..LANES {
            if z[i] <= 0.0 || cone[i] == 0.0 {
                continue;
            }
            let footprint = Footprint { dudx: ds[0][i], dvdx: dt[0][i], dudy: ds[1][i], dvdy: dt[1][i] };
            out.set_lane(i, slide.lookup(s[i], t[i], &footprint).truncate() * cone[i]);
        }
        out
    }

    /// How much of a light reaches eight points by its shadow map (1 where `lit` is black in every lane:
    /// nothing to darken).
    #[inline(never)]
    fn shadow8(&self, map: &ShadowMap, inst: &Instance, position: V3, surface: &SurfaceLanes, lit: V3) -> V3 {
        let dark = |c: F8| c.cmp_gt(F8::ZERO).none();
        if dark(lit.x) && dark(lit.y) && dark(lit.z) {
            return V3 { x: F8::ONE, y: F8::ONE, z: F8::ONE };
        }
        let shadows = self.shadows.expect("a map comes with its shadows");
        let own = shadows.self_shadowless[inst.object as usize].then_some(inst.object);
        let world = |d: V3| V3::transform_vector(&inst.object_to_world, d);
        let n = V3::mul_mat3(&inst.normal_matrix, surface.n).normalize_or_zero();
        let k = map.visibility8(position, n, world(surface.dpdx), world(surface.dpdy), own);
        V3 { x: k, y: k, z: k }
    }

    /// Shades eight samples of one primitive. Lookups go through their lane forms; everything else runs
    /// on all lanes at once.
    #[inline]
    pub fn shade8(&self, inst: &Instance, at: &SurfaceSamples8<'_>) -> ShadedPacket {
        let material = &self.materials[inst.material];
        let frame = at.frame;
        let surface = self.surface(inst, at);
        let n_geo = surface.n;
        let mut ctx = context_of(&surface, at);
        let travel = self.parallax_of(inst, material, &mut ctx);
        // A displacement's F shades too (the displaced surface's own normal), with a bump's F added.
        // A LEAN or Toksvig filter also gives the covariance of the slopes under the pixel.
        let mut spread = None;
        let bump = material.bump.as_ref().filter(|_| self.bump_enabled).map(|b| {
            let filter = self.bump_filter_of(b);
            let g = match self.slopes_of(b) {
                SlopeFilter::Plain => b.eval8(&ctx, &filter),
                slopes => {
                    let (g, c) = b.eval_spread8(&ctx, &filter);
                    spread = Some((slopes, Spread::Bump(b.formula, c)));
                    g
                }
            };
            (g, b.formula)
        });
        let displaced = material.displacement.as_ref().map(|d| d.map.eval8(&ctx, &d.map.filter));
        let gradient = match (displaced, bump) {
            (Some(d), Some((b, _))) => Some((std::array::from_fn(|k| d[k] + b[k]), BumpFormula::Full)),
            (Some(d), None) => Some((d, BumpFormula::Full)),
            (None, bump) => bump,
        };
        let n_obj = match (gradient, &material.normal_map, self.bump_enabled) {
            (Some((g, formula)), _, _) => match &at.mesh {
                None => perturbed_normal8(frame, g, formula),
                Some(m) => perturbed_normal_sided8(frame.pu, frame.pv, g, formula, m.side),
            },
            (None, Some(map), true) => {
                let n = n_geo.normalize_or_zero();
                let (t, w) = match &at.mesh {
                    None => (frame.pu.normalize_or_zero(), F8::ONE),
                    Some(m) => (m.tangent, m.tangent_sign),
                };
                if map.slopes != SlopeFilter::Plain {
                    if let Some(c) = map.spread8(&ctx) {
                        spread = Some((map.slopes, Spread::NormalMap { t, bitangent: map.bitangent(n, t, w), n, c }));
                    }
                }
                map.normal8(&ctx, n, t, w)
            }
            _ => n_geo,
        };
        let mut position = V3::transform_point(&inst.object_to_world, frame.p);
        if let (Some(d), Some(g), None) = (&material.displacement, displaced, &at.mesh) {
            // The sample lies on the displaced surface, F (times its weight) along the unit normal (a
            // mesh's sample is already on its displaced triangle).
            let n_unit = n_geo.normalize_or_zero();
            let weight = match d.mode {
                DisplacementMode::Full => F8::ONE,
                DisplacementMode::Silhouette { .. } => {
                    let to_eye = match self.ortho_to_eye {
                        Some(e) => V3::splat(e),
                        None => (V3::splat(self.eye) - position).normalize_or_zero(),
                    };
                    let facing = V3::mul_mat3(&inst.normal_matrix, n_unit).normalize_or_zero().dot(to_eye).abs();
                    let constant = match &inst.primitive {
                        Primitive::Parametric(s) => s.constant_curvature(),
                        Primitive::Mesh(_) => None,
                    };
                    let threshold = match d.constant_threshold(constant) {
                        Some(t) => F8::splat(t),
                        None => d.threshold8(frame.max_curvature8()),
                    };
                    d.weight8(facing, threshold)
                }
            };
            position = V3::transform_point(&inst.object_to_world, frame.p + n_unit * (g[0] * weight));
        }
        let (to_eye, depth) = match self.ortho_to_eye {
            Some(d) => (V3::splat(d), (V3::splat(self.eye) - position).dot(V3::splat(d))),
            None => {
                let to_eye = V3::splat(self.eye) - position;
                (to_eye, to_eye.length())
            }
        };
        // Depth replacement: the sample lies where its ray meets the parallax field.
        let depth = match travel {
            Some(travel) if material.replaces_depth() => depth + travel,
            _ => depth,
        };
        let v = to_eye.normalize_or_zero();
        let mut n = V3::mul_mat3(&inst.normal_matrix, n_obj).normalize_or_zero();
        let mut back = None;
        if inst.two_sided {
            let turned = V3::mul_mat3(&inst.normal_matrix, n_geo).dot(v).cmp_lt(F8::ZERO);
            n = V3::select(turned, -n, n);
            back = Some(turned);
        }
        let mut kd = (V3::splat(material.color), F8::splat(material.opacity));
        let mut uv = None;
        let (mut ks, mut shininess, mut emission) = (F8::splat(material.phong.specular), None, None);
        // Alpha matters only to the alpha test, which has already kept these samples.
        for layer in material.layers.iter().filter(|l| l.target != Target::Opacity) {
            let texel = match (layer.target, uv) {
                (Target::Kd, None) => {
                    let (texel, coords) = layer.source.eval8_with_coords(&ctx);
                    uv = Some(coords);
                    texel
                }
                _ => layer.source.eval8(&ctx),
            };
            let [r, g, b, a] = texel;
            match layer.target {
                Target::Kd => kd = layer.mode.colour8(kd, (V3 { x: r, y: g, z: b }, a), layer.rgba),
                Target::Emission => {
                    let (ef, ct) = (emission.unwrap_or(V3::splat(material.emission)), V3 { x: r, y: g, z: b });
                    // Emitted light is not a reflectance: add is not clamped to 1.
                    emission = Some(match layer.mode {
                        Mode::Add => ef + ct,
                        mode => mode.colour8((ef, F8::ONE), (ct, a), layer.rgba).0,
                    });
                }
                Target::Ks => ks = layer.mode.scalar8(ks, layer.scalar_texel(texel)),
                Target::Shininess => {
                    shininess = Some(layer.mode.scalar8(shininess.unwrap_or(F8::ONE), layer.scalar_texel(texel)))
                }
                Target::Opacity => {}
            }
        }
        let albedo = kd.0;
        // The exponent of a shininess layer is a fraction of the material's, at least 1.
        let mut exponent = shininess.map(|s| (F8::splat(material.phong.shininess) * s).max(F8::ONE));
        // The spread of the normals widens the highlight: LEAN's lobe, or Toksvig's lower exponent
        // s' = s / (1 + s sigma^2) with his factor (1 + s') / (1 + s) on ks.
        let mut lobe = None;
        let spreads = spread.is_some();
        if let Some((slopes, of)) = spread {
            let world = match of {
                Spread::Bump(formula, c) => WorldSpread8::of(frame.pu, frame.pv, formula, &inst.normal_matrix, n, c),
                Spread::NormalMap { t, bitangent, n: n_obj, c } => {
                    WorldSpread8::of_tangent_frame(t, bitangent, n_obj, &inst.normal_matrix, n, c)
                }
            };
            let s = exponent.unwrap_or(F8::splat(material.phong.shininess));
            match slopes {
                SlopeFilter::Toksvig => {
                    let lowered = s / (F8::ONE + s * world.isotropic());
                    ks = ks * (F8::ONE + lowered) / (F8::ONE + s);
                    exponent = Some(lowered);
                }
                _ => lobe = Some(Lobe8::widened(world, s)),
            }
        }
        let phong = match material.highlight_cutoff_holds() && !spreads {
            true => material.phong,
            false => Phong { cutoff: 0.0, ..material.phong },
        };
        let mut color = V3::ZERO;
        for (k, light) in self.lights.iter().enumerate() {
            let mut lit = phong.shade8(light, position, n, v, albedo, ks, exponent, lobe.as_ref());
            if let Light::Spot(spot) = light {
                lit = lit * self.spot_tint8(spot, inst, position, &surface);
            }
            if let Some(map) = self.shadows.and_then(|s| s.maps[k].as_ref()) {
                lit = lit * self.shadow8(map, inst, position, &surface, lit);
            }
            color = color + lit;
        }
        if let Some(ibl) = &self.ibl {
            color = color + ibl.shade8(inst.material, n, v, albedo, ks);
        }
        if material.emits() {
            color = color + emission.unwrap_or(V3::splat(material.emission));
        }
        if let Some(chrome) = &material.chrome {
            let still = V3::ZERO;
            color = color + chrome.map.radiance8(&reflected(n, v), &still, &still) * V3::splat(chrome.strength);
        }
        let mirrored = self.object_views.get(inst.object as usize).and_then(Option::as_ref).or(self.environment);
        if let (Some(env), true) = (mirrored, material.reflects()) {
            let mirror = Mirror { n, v, back, distance: self.ortho_to_eye.is_none().then_some(depth) };
            color = color + mirror.reflection(inst, material, env, &surface);
        }
        let uv = uv.unwrap_or(at.uv);
        ShadedPacket { color, normal: n, depth, uv }
    }
}

/// The covariance of the slopes under eight samples' pixels and what it is taken along: a bump's (Fu, Fv)
/// on its surface, or a normal map's tangent-space slopes in its frame (object space). A temporary of one
/// packet's shading, never stored, so its variants' sizes do not matter.
#[allow(clippy::large_enum_variant)]
enum Spread {
    Bump(BumpFormula, [F8; 3]),
    NormalMap { t: V3, bitangent: V3, n: V3, c: [F8; 3] },
}

/// The view vector `v` (towards the eye) mirrored about the unit normal `n`: R = 2 (N.V) N - V.
#[inline]
fn reflected(n: V3, v: V3) -> V3 {
    let nv = n.dot(v);
    n * (nv + nv) - v
}

/// What the reflection of eight samples needs: the world shading normal and the unit vector to the eye,
/// which lanes show their back (normal turned over), and how far the eye is (perspective views).
struct Mirror {
    n: V3,
    v: V3,
    back: Option<F8>,
    distance: Option<F8>,
}

impl Mirror {
    /// The environment seen along the view ray reflected about the shading normal (bumps included), times
    /// the material's reflectance (Schlick's Fresnel where asked), filtered over the reflected rays'
    /// change across the pixel: R = 2 (N.V) N - V and its differential from the eye's and the normal's
    /// (Igehy's ray differentials; the normal's change is the surface's, not the bump's).
    #[inline(never)]
    fn reflection(&self, inst: &Instance, material: &Material, env: &Environment, surface: &SurfaceLanes) -> V3 {
        let (n, v) = (self.n, self.v);
        let nv = n.dot(v);
        let r = reflected(n, v);
        let world = |d: V3| V3::transform_vector(&inst.object_to_world, d);
        let turned = |d: V3| {
            // The normal's change, as the world normal sees it (and turned over where the normal is).
            let d = V3::mul_mat3(&inst.normal_matrix, d);
            let d = d - n * n.dot(d);
            match self.back {
                Some(back) => V3::select(back, -d, d),
                None => d,
            }
        };
        let differential = |dp: V3, dn: V3| {
            // V = (E - P) / |E - P| turns as P moves across the pixel (not at all for parallel rays).
            let dv = match self.distance {
                Some(distance) => {
                    let dp = world(dp);
                    (dp - v * v.dot(dp)) * (-F8::ONE / distance.max(F8::splat(1e-20)))
                }
                None => V3::ZERO,
            };
            let dn = turned(dn);
            (n * (dn.dot(v) + n.dot(dv)) + dn * nv) * F8::splat(2.0) - dv
        };
        let (drdx, drdy) = (differential(surface.dpdx, surface.dndx), differential(surface.dpdy, surface.dndy));
        let seen = env.radiance8(&r, &drdx, &drdy);
        let k = V3::splat(material.reflect);
        let k = match material.fresnel {
            true => {
                let c = (F8::ONE - nv.max(F8::ZERO)).min(F8::ONE);
                let c5 = (c * c) * (c * c) * c;
                k + (V3::splat(Vec3::ONE) - k) * c5
            }
            false => k,
        };
        seen * k
    }
}
