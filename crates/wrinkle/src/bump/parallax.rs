//! Parallax occlusion mapping: the bump's height field carved into the surface (its highest point on the
//! surface itself, a height F lying |scale| - F below it), the view ray marched through it in tangent space
//! in equal depth steps, and the crossing found between the last step above the field and the first below
//! it. Every lookup of the material then reads the (u,v) where the ray meets the field (the course's
//! "Z texture": what the surface shows at a pixel moves with the view as a real relief would).
//!
//! Eight rays march together on the lanes. A step shorter than a pixel shows nothing new, so the march
//! takes at most one step per pixel the deepest ray crosses on screen (and at most `steps`): shallow
//! fields and views from above cost a step or two.

use super::function::BumpMap;
use crate::lanes::{CmpGe, CmpGt, F8, V3};
use crate::texture::{FilterOptions, LookupContext8};

/// How the height field is marched.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Parallax {
    /// The most equal steps from the surface down to the field's lowest point.
    pub steps: u32,
    /// The sample's depth becomes the crossing's, in the visibility pass too (the course's "dot product
    /// depth replace"): what pokes out of the carved field in front of the crossing shows.
    pub depth_replace: bool,
}

/// Where eight view rays meet the field: the (u,v) to read, and how much farther along each ray than the
/// surface (object units; 0 where a lane does not march).
pub struct Crossing8 {
    pub u: F8,
    pub v: F8,
    pub travel: F8,
}

impl Parallax {
    pub const MAX_STEPS: u32 = 256;

    /// Where each lane's view ray (`to_eye`: towards the eye, any length, object space) meets the height
    /// field of `bump` below the surface of `ctx`. Seen edge-on or from below, the lane's own (u,v).
    pub fn trace8(&self, bump: &BumpMap, ctx: &LookupContext8<'_>, to_eye: V3, filter: &FilterOptions) -> Crossing8 {
        let depth_of_field = bump.scale.abs();
        let s = ctx.surface;
        let n = s.n.normalize_or_zero();
        let v = to_eye.normalize_or_zero();
        let c = v.dot(n);
        // The view in the tangent frame: v = a Pu + b Pv + c N, (a, b) from the tangents' Gram matrix.
        let (pu, pv) = (s.dpdu, s.dpdv);
        let (guu, guv, gvv) = (pu.dot(pu), pu.dot(pv), pv.dot(pv));
        let det = guu * gvv - guv * guv;
        let (vu, vv) = (v.dot(pu), v.dot(pv));
        // Lanes seen from in front march; the others keep their (u,v) (a zero step).
        let marching = c.cmp_gt(F8::splat(1e-4)) & det.cmp_gt(F8::ZERO);
        if depth_of_field == 0.0 || marching.none() {
            return Crossing8 { u: ctx.u, v: ctx.v, travel: F8::ZERO };
        }
        // Each unit of depth along the ray moves (u,v) by -(a, b) / c.
        let k = marching.blend(-F8::ONE / (det * c), F8::ZERO);
        let (du, dv) = ((gvv * vu - guv * vv) * k, (guu * vv - guv * vu) * k);
        // Steps: one per pixel of the deepest travel, along the footprint's shorter axis.
        let fp = &ctx.footprint;
        let pixel = (fp.dudx * fp.dudx + fp.dvdx * fp.dvdx).min(fp.dudy * fp.dudy + fp.dvdy * fp.dvdy).sqrt();
        let travel = ((du * du + dv * dv).sqrt() * F8::splat(depth_of_field) / pixel)
            .as_array_ref()
            .iter()
            .fold(0.0f32, |m, &x| if x > m || x.is_nan() { x } else { m });
        let count = if travel.is_finite() { (travel.ceil() as u32 + 1).clamp(1, self.steps) } else { self.steps };
        // How far below the surface the field lies at (u,v): |scale| - F (a negative scale digs the other way).
        let sign = F8::splat(bump.scale.signum());
        let below = |depth: F8| {
            let at = LookupContext8 { u: ctx.u + du * depth, v: ctx.v + dv * depth, ..*ctx };
            F8::splat(depth_of_field) - bump.height8(&at, filter) * sign
        };
        let step = depth_of_field / count as f32;
        let (mut prev_depth, mut prev_gap) = (F8::ZERO, -below(F8::ZERO));
        // Where the field reaches the surface the ray meets it there.
        let at_top = prev_gap.cmp_ge(F8::ZERO);
        let mut hit = at_top.blend(F8::ZERO, F8::splat(depth_of_field));
        let mut open = marching & !at_top;
        for i in 1..=count {
            if open.none() {
                break;
            }
            let depth = F8::splat(step * i as f32);
            let gap = depth - below(depth);
            let crossed = open & gap.cmp_ge(F8::ZERO);
            // Where the gap, linear between the two steps, is 0.
            let rise = gap - prev_gap;
            let t = rise.cmp_gt(F8::ZERO).blend(-prev_gap / rise, F8::ONE);
            hit = crossed.blend(prev_depth + t * (depth - prev_depth), hit);
            open &= !crossed;
            (prev_depth, prev_gap) = (depth, gap);
        }
        let hit = marching.blend(hit, F8::ZERO);
        // A depth below the surface is hit / c along the ray (v is unit).
        let travel = marching.blend(hit / c, F8::ZERO);
        Crossing8 { u: ctx.u + du * hit, v: ctx.v + dv * hit, travel }
    }
}
