//! A bump map: the bump function F on a surface (a table or a procedural pattern, its amplitude, its
//! mapping and its filter, from the colour textures' vocabulary) and its evaluation at a sample: F, Fu, Fv
//! along the surface parameters, for Blinn's perturbation (blinn.rs).
//!
//! The table is read at the mapped coordinates (s,t); the chain rule through the mapping gives the
//! derivatives along the surface: Fu = Fs ds/du + Ft dt/du, Fv alike.

use super::lean::{SlopeFilter, SlopeMoments, Spread};
use super::table::BumpTable;
use super::{BumpFormula, Gradient};
use crate::error::{Error, Result};
use crate::lanes::F8;
use crate::mapping::Mapping;
use crate::procedural::solid::{Procedural, Space};
use crate::texture::reconstruct::Kernel;
use crate::texture::{Filter, FilterOptions, FilteredTexture, Footprint, LookupContext, LookupContext8};
use glam::{Vec2, Vec3, Vec4};
use std::sync::{Arc, OnceLock};

/// Where F comes from.
pub enum BumpSource {
    /// A table T: F = scale * T(s,t) at the mapped coordinates.
    Table(Arc<BumpTable>),
    /// A procedural pattern t: F = scale * t, with Fu and Fv from its analytic gradient.
    Procedural(Arc<Procedural>),
    /// An offset vector map (the slides' "offset vector" map, in tangent space): Bs and Bt, F's slopes along
    /// the texture's s and t per period, stored in R and G as (b + 1) / 2 (green up the picture) and filtered
    /// like a colour texture: Fs = scale * Bs, Ft = scale * Bt. F itself is not stored (it reads 0).
    Offsets(Arc<OffsetMap>),
}

/// An offset vector map and, built on first use by LEAN or Toksvig filtering, its slopes' moments.
pub struct OffsetMap {
    pub texture: FilteredTexture,
    moments: OnceLock<SlopeMoments>,
}

impl OffsetMap {
    pub fn new(texture: FilteredTexture) -> OffsetMap {
        OffsetMap { texture, moments: OnceLock::new() }
    }

    /// The slopes (Bs, Bt) of one texel.
    fn slopes(c: Vec4) -> Vec2 {
        Vec2::new(2.0 * c.x - 1.0, 2.0 * c.y - 1.0)
    }

    fn moments(&self) -> &SlopeMoments {
        self.moments.get_or_init(|| SlopeMoments::of_texture(&self.texture, OffsetMap::slopes))
    }
}

/// A bump function on a surface: F = scale * (the source at the mapped coordinates, or at the point).
pub struct BumpMap {
    pub source: BumpSource,
    pub scale: f32,
    pub mapping: Mapping,
    pub formula: BumpFormula,
    /// How a table is filtered against aliasing (Blinn section 5): any texture filter; `nearest` and
    /// `bilinear` are Blinn's two FVALs on the full-resolution table.
    pub filter: FilterOptions,
    /// What the filter does about the spread of the normals under a pixel (LEAN, Toksvig).
    pub slopes: SlopeFilter,
    /// Parallax occlusion mapping: every lookup of the material reads where the view ray meets the height
    /// field carved into the surface.
    pub parallax: Option<super::Parallax>,
}

impl BumpMap {
    /// F = `scale` * the source on the surface's own (u,v), Blinn's formula, a table read bilinearly at full
    /// resolution (his FVAL), no parallax: a scene's defaults; set the public fields to change them.
    pub fn new(source: BumpSource, scale: f32) -> Result<BumpMap> {
        if !scale.is_finite() {
            return Err(Error::parameter("scale", format!("must be finite, got {scale}")));
        }
        Ok(BumpMap {
            source,
            scale,
            mapping: Mapping::default(),
            formula: BumpFormula::Blinn,
            filter: FilterOptions { filter: Filter::Reconstruct(Kernel::Bilinear), ..FilterOptions::default() },
            slopes: SlopeFilter::Plain,
            parallax: None,
        })
    }

    /// scale times the mapping's Jacobian columns `jacobian`: F's derivatives along u and v are
    /// Fs k_u.x + Ft k_u.y and Fs k_v.x + Ft k_v.y. The scale is folded in first, so a plain repeat r gives
    /// (scale r) Fs exactly.
    #[inline]
    fn chain(&self, jacobian: [Vec2; 2]) -> [Vec2; 2] {
        jacobian.map(|c| c * self.scale)
    }

    /// F, Fu, Fv at one sample, the table filtered by `filter` (the bump's own, or an override).
    #[inline]
    pub fn eval(&self, ctx: &LookupContext, filter: &FilterOptions) -> Gradient {
        let table = match &self.source {
            BumpSource::Table(t) => t,
            BumpSource::Procedural(p) => return self.procedural(p, ctx),
            BumpSource::Offsets(map) => return self.offsets(map, ctx, filter),
        };
        let (mapped, jacobian) = self.mapping.apply_with_jacobian(ctx);
        let g = table.lookup(mapped.uv.x, mapped.uv.y, &mapped.footprint, filter);
        self.chained(g, Spread::default(), jacobian).0
    }

    /// F, Fu, Fv on eight lanes: a table through the surface's (u,v) on the lanes, anything else lane by
    /// lane.
    #[inline(always)]
    pub fn eval8(&self, ctx: &LookupContext8<'_>, filter: &FilterOptions) -> [F8; 3] {
        let (BumpSource::Table(table), Some(jacobian)) = (&self.source, self.mapping.constant_jacobian()) else {
            let g: [Gradient; 8] = std::array::from_fn(|i| self.eval(&ctx.lane(i), filter));
            return [F8::new(g.map(|g| g.f)), F8::new(g.map(|g| g.fu)), F8::new(g.map(|g| g.fv))];
        };
        let (mapped, _) = self.mapping.apply8(ctx);
        let [f, fs, ft] = table.lookup8(mapped.u, mapped.v, &mapped.footprint, filter);
        let [ku, kv] = self.chain(jacobian);
        let k = F8::splat;
        [k(self.scale) * f, fs * k(ku.x) + ft * k(ku.y), fs * k(kv.x) + ft * k(kv.y)]
    }

    /// The mean F, Fu, Fv at one sample under `filter` and the covariance of (Fu, Fv) there (LEAN's): the
    /// moments of a table's or an offset map's slopes, filtered, carried to u and v through the chain rule;
    /// a procedural bump's from the unfiltered gradient at four points of the pixel.
    #[inline]
    pub fn eval_spread(&self, ctx: &LookupContext, filter: &FilterOptions) -> (Gradient, Spread) {
        let (mapped, jacobian) = self.mapping.apply_with_jacobian(ctx);
        let (s, t, fp) = (mapped.uv.x, mapped.uv.y, &mapped.footprint);
        let (g, spread) = match &self.source {
            BumpSource::Table(table) => table.lookup_spread(s, t, fp, filter),
            BumpSource::Offsets(map) => {
                let (_, spread) = map.moments().lookup(s, t, fp, filter);
                (self.offsets_raw(map, &mapped, filter), spread)
            }
            BumpSource::Procedural(p) => {
                let mean = self.procedural(p, ctx);
                return (mean, self.procedural_spread(p, ctx, mean));
            }
        };
        self.chained(g, spread, jacobian)
    }

    /// Table-space (F, Fs, Ft) and their covariance carried to the surface: F scaled, the slopes and their
    /// covariance through the chain rule's rows.
    #[inline]
    fn chained(&self, g: Gradient, spread: Spread, jacobian: [Vec2; 2]) -> (Gradient, Spread) {
        let [ku, kv] = self.chain(jacobian);
        let rows = [Vec2::new(ku.x, ku.y), Vec2::new(kv.x, kv.y)];
        let gradient = Gradient { f: self.scale * g.f, fu: g.fu * ku.x + g.fv * ku.y, fv: g.fu * kv.x + g.fv * kv.y };
        (gradient, spread.through(rows))
    }

    /// The covariance of a procedural bump's (Fu, Fv) over the pixel: E[g g^T] from the gradient at the
    /// centres of the pixel's four quarters (each band-limited to an eighth of the pixel, so the octaves the
    /// pixel's own band limiting drops are there), less the filtered mean's square.
    fn procedural_spread(&self, p: &Procedural, ctx: &LookupContext, mean: Gradient) -> Spread {
        let mut second = [0.0f32; 3];
        let fp = &ctx.footprint;
        let eighth =
            Footprint { dudx: 0.125 * fp.dudx, dvdx: 0.125 * fp.dvdx, dudy: 0.125 * fp.dudy, dvdy: 0.125 * fp.dvdy };
        for (a, b) in [(-0.25, -0.25), (0.25, -0.25), (-0.25, 0.25), (0.25, 0.25)] {
            let at = LookupContext {
                p: ctx.p + a * ctx.dpdx + b * ctx.dpdy,
                uv: ctx.uv + Vec2::new(a * fp.dudx + b * fp.dudy, a * fp.dvdx + b * fp.dvdy),
                dpdx: 0.125 * ctx.dpdx,
                dpdy: 0.125 * ctx.dpdy,
                footprint: eighth,
                ..*ctx
            };
            let g = self.procedural(p, &at);
            second = [second[0] + g.fu * g.fu, second[1] + g.fv * g.fv, second[2] + g.fu * g.fv];
        }
        let [xx, yy, xy] = second.map(|m| 0.25 * m);
        Spread {
            xx: (xx - mean.fu * mean.fu).max(0.0),
            yy: (yy - mean.fv * mean.fv).max(0.0),
            xy: xy - mean.fu * mean.fv,
        }
    }

    /// `eval_spread` on eight lanes: (F, Fu, Fv) and (var Fu, var Fv, cov); a table's mapping on the lanes
    /// and its lookups lane by lane.
    #[inline]
    pub fn eval_spread8(&self, ctx: &LookupContext8<'_>, filter: &FilterOptions) -> ([F8; 3], [F8; 3]) {
        let lanes: [(Gradient, Spread); 8] = match (&self.source, self.mapping.constant_jacobian()) {
            (BumpSource::Table(table), Some(jacobian)) => {
                let (mapped, _) = self.mapping.apply8(ctx);
                let (s, t) = (mapped.u.as_array_ref(), mapped.v.as_array_ref());
                std::array::from_fn(|i| {
                    let (g, spread) = table.lookup_spread(s[i], t[i], &mapped.footprint.lane(i), filter);
                    self.chained(g, spread, jacobian)
                })
            }
            _ => std::array::from_fn(|i| self.eval_spread(&ctx.lane(i), filter)),
        };
        let g = |k: fn(&Gradient) -> f32| F8::new(lanes.map(|(g, _)| k(&g)));
        let c = |k: fn(&Spread) -> f32| F8::new(lanes.map(|(_, c)| k(&c)));
        ([g(|g| g.f), g(|g| g.fu), g(|g| g.fv)], [c(|c| c.xx), c(|c| c.yy), c(|c| c.xy)])
    }

    /// F alone at one sample (a displacement's): `eval`'s F, a table's without its derivatives.
    #[inline]
    pub fn height(&self, ctx: &LookupContext, filter: &FilterOptions) -> f32 {
        match &self.source {
            BumpSource::Table(table) => {
                let mapped = self.mapping.apply(ctx);
                self.scale * table.height_at(mapped.uv.x, mapped.uv.y, &mapped.footprint, filter)
            }
            _ => self.eval(ctx, filter).f,
        }
    }

    /// F alone on eight lanes (a parallax march's reads): a table through the surface's (u,v) on the lanes
    /// without its derivatives, anything else as `eval8`.
    #[inline(always)]
    pub fn height8(&self, ctx: &LookupContext8<'_>, filter: &FilterOptions) -> F8 {
        let (BumpSource::Table(table), Some(_)) = (&self.source, self.mapping.constant_jacobian()) else {
            return self.eval8(ctx, filter)[0];
        };
        let (mapped, _) = self.mapping.apply8(ctx);
        F8::splat(self.scale) * table.height8(mapped.u, mapped.v, &mapped.footprint, filter)
    }

    /// The largest |F| the bump reaches: a table's largest entry times the scale; a procedural pattern's
    /// values lie within [-1, 1]; an offset map stores no F.
    pub fn largest_height(&self) -> f32 {
        self.scale.abs()
            * match &self.source {
                BumpSource::Table(t) => t.largest(),
                BumpSource::Procedural(_) => 1.0,
                BumpSource::Offsets(_) => 0.0,
            }
    }

    /// An offset vector map's slopes along s and t, carried to u and v through the mapping's Jacobian.
    fn offsets(&self, map: &OffsetMap, ctx: &LookupContext, filter: &FilterOptions) -> Gradient {
        let (mapped, jacobian) = self.mapping.apply_with_jacobian(ctx);
        self.chained(self.offsets_raw(map, &mapped, filter), Spread::default(), jacobian).0
    }

    /// An offset vector map's slopes along s and t at the mapped context.
    fn offsets_raw(&self, map: &OffsetMap, mapped: &LookupContext, filter: &FilterOptions) -> Gradient {
        let (s, t, fp) = (mapped.uv.x, mapped.uv.y, &mapped.footprint);
        let texture = &map.texture;
        let c = match texture.options().filter == *filter {
            true => texture.lookup(s, t, fp),
            false => texture.with_options(*filter).lookup(s, t, fp),
        };
        let b = OffsetMap::slopes(c);
        Gradient { f: 0.0, fu: b.x, fv: b.y }
    }

    /// A procedural bump: in object space by the chain rule through the surface, Fu = grad t . Pu; in uv
    /// space through the mapping like a table.
    fn procedural(&self, p: &Procedural, ctx: &LookupContext) -> Gradient {
        match p.space {
            Space::Object => {
                let t = p.eval_d(ctx);
                let g = Vec3::from_array(t.grad);
                Gradient { f: self.scale * t.value, fu: self.scale * g.dot(ctx.dpdu), fv: self.scale * g.dot(ctx.dpdv) }
            }
            Space::Uv => {
                let (mapped, jacobian) = self.mapping.apply_with_jacobian(ctx);
                let t = p.eval_d(&mapped);
                let [ku, kv] = self.chain(jacobian);
                let g = t.grad;
                Gradient { f: self.scale * t.value, fu: g[0] * ku.x + g[1] * ku.y, fv: g[0] * kv.x + g[1] * kv.y }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Surface;
    use crate::procedural::effects::{Kind, Params, Pattern};

    fn at(surface: &Surface, u: f32, v: f32) -> LookupContext {
        let f = surface.frame(u, v);
        LookupContext::on_surface(f.p, f.pu, f.pv, Vec2::new(u, v), Footprint::default())
    }

    /// Fu, Fv from a solid pattern's analytic gradient against differences of F along the surface's parameters.
    #[test]
    fn procedural_derivatives_follow_the_surface() {
        let pattern = Pattern::new(Params::new(Kind::Fbm), 3, false).unwrap();
        let bump = BumpMap {
            source: BumpSource::Procedural(Arc::new(Procedural { pattern, space: Space::Object })),
            scale: 0.1,
            mapping: Mapping::default(),
            formula: BumpFormula::Blinn,
            filter: FilterOptions::default(),
            slopes: SlopeFilter::Plain,
            parallax: None,
        };
        let torus = Surface::Torus { major_radius: 1.0, minor_radius: 0.3 };
        let opts = FilterOptions::default();
        for i in 0..50 {
            let (u, v) = (0.013 + 0.019 * i as f32, 0.7 - 0.011 * i as f32);
            let g = bump.eval(&at(&torus, u, v), &opts);
            let f = |u: f32, v: f32| bump.eval(&at(&torus, u, v), &opts).f as f64;
            // A step of 0.02 cells of the finest octave (1e-4 was 0.1 cells, whose truncation error reached
            // the tolerance), divided by the step the f32 parameters really took.
            let h = 2e-5f32;
            let fu = (f(u + h, v) - f(u - h, v)) / ((u + h) - (u - h)) as f64;
            let fv = (f(u, v + h) - f(u, v - h)) / ((v + h) - (v - h)) as f64;
            assert!((g.fu as f64 - fu).abs() < 2e-2 * (1.0 + fu.abs()), "Fu {} vs {fu}", g.fu);
            assert!((g.fv as f64 - fv).abs() < 2e-2 * (1.0 + fv.abs()), "Fv {} vs {fv}", g.fv);
        }
    }
}
