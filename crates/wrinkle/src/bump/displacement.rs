//! Displacement mapping (Lingard): the surface itself moved along its normal by a bump function's F, so
//! silhouettes and occlusion show the bumps; and Lingard's cheaper proposal, displacing only near the
//! silhouette and bump-mapping the rest. The dicing is geometry/dice.rs; the frame's driver runs it.

use super::BumpMap;
use crate::lanes::F8;

/// The fraction of silhouette mode's threshold below which F moves the surface fully.
const FULL: f32 = 0.75;

/// Where the surface is moved.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DisplacementMode {
    /// Everywhere.
    Full,
    /// Only where the surface is seen at a grazing angle, |N.V| below a threshold: fully below three
    /// quarters of it, blended smoothly to nothing at it. Elsewhere the same F bump-maps the flat surface. Without a
    /// threshold, each point of a parametric surface takes its own from F's largest value and the surface's
    /// curvature there (`Displacement::threshold_at`); a mesh's is `THRESHOLD`.
    Silhouette { threshold: Option<f32> },
}

/// A displacement map: F (a bump map's source, scale, mapping and filter), where it applies, and how
/// finely the surface is diced.
pub struct Displacement {
    pub map: BumpMap,
    pub mode: DisplacementMode,
    /// The longest a diced edge may be on screen, in pixels.
    pub edge_px: f32,
}

impl Displacement {
    /// The default `threshold` of silhouette mode.
    pub const THRESHOLD: f32 = 0.3;
    /// The finest and coarsest dicing a scene may ask for, pixels per edge.
    pub const EDGE_PX: (f32, f32) = (0.25, 64.0);

    /// Silhouette mode's threshold where the surface's largest curvature is `curvature` (object units; none
    /// known: infinite). A point at angle a from the outline moves (1 - cos a) / curvature away from the
    /// outline's plane, so F's largest value h can carry it out past the outline only where
    /// cos a >= 1 - h curvature, |N.V| = sin a below sqrt(x (2 - x)) with x = h curvature; the threshold is
    /// 4/3 of that, so the whole stretch is fully displaced.
    pub fn threshold_at(&self, curvature: f32) -> f32 {
        match self.mode {
            DisplacementMode::Full => 1.0,
            DisplacementMode::Silhouette { threshold: Some(t) } => t,
            DisplacementMode::Silhouette { threshold: None } if curvature.is_finite() => {
                let x = (self.map.largest_height() * curvature).min(1.0);
                ((x * (2.0 - x)).sqrt() / FULL).clamp(1e-6, 1.0)
            }
            DisplacementMode::Silhouette { threshold: None } => Self::THRESHOLD,
        }
    }

    /// The threshold where it is the same all over a surface whose largest curvature is `constant` (known
    /// only where it is the same everywhere): given, or of full displacement, or from that curvature;
    /// `None` where it must be worked out point by point (`threshold_at`).
    pub fn constant_threshold(&self, constant: Option<f32>) -> Option<f32> {
        match (self.mode, constant) {
            (DisplacementMode::Silhouette { threshold: None }, None) => None,
            (_, curvature) => Some(self.threshold_at(curvature.unwrap_or(f32::INFINITY))),
        }
    }

    /// `threshold_at` on eight lanes.
    #[inline]
    pub fn threshold8(&self, curvature: F8) -> F8 {
        F8::new(curvature.to_array().map(|k| self.threshold_at(k)))
    }

    /// How much of F moves a point whose unit normal and direction to the eye have |N.V| = `facing`, with
    /// silhouette mode's `threshold` there.
    #[inline]
    pub fn weight(&self, facing: f32, threshold: f32) -> f32 {
        match self.mode {
            DisplacementMode::Full => 1.0,
            DisplacementMode::Silhouette { .. } => {
                let x = ((threshold - facing) / ((1.0 - FULL) * threshold)).clamp(0.0, 1.0);
                x * x * (3.0 - 2.0 * x)
            }
        }
    }

    /// `weight` on eight lanes.
    #[inline]
    pub fn weight8(&self, facing: F8, threshold: F8) -> F8 {
        match self.mode {
            DisplacementMode::Full => F8::ONE,
            DisplacementMode::Silhouette { .. } => {
                let x = ((threshold - facing) * (F8::splat(1.0 / (1.0 - FULL)) / threshold)).max(F8::ZERO).min(F8::ONE);
                x * x * (F8::splat(3.0) - F8::splat(2.0) * x)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bump::{BumpFormula, BumpSource, BumpTable};
    use std::sync::Arc;

    fn silhouette(threshold: Option<f32>) -> Displacement {
        let table = BumpTable::new(&crate::image::GreyImage::new(2, 2, 0.0));
        let map =
            BumpMap { formula: BumpFormula::Full, ..BumpMap::new(BumpSource::Table(Arc::new(table)), 1.0).unwrap() };
        Displacement { map, mode: DisplacementMode::Silhouette { threshold }, edge_px: 1.0 }
    }

    #[test]
    fn silhouette_weight_blends_from_full_to_none() {
        let d = silhouette(Some(0.4));
        let t = d.threshold_at(f32::INFINITY);
        assert_eq!(t, 0.4);
        for (facing, want) in [(0.0, 1.0), (0.3, 1.0), (0.35, 0.5), (0.4, 0.0), (0.9, 0.0)] {
            assert!((d.weight(facing, t) - want).abs() < 1e-6, "{facing}: {}", d.weight(facing, t));
        }
        let facings = [0.0, 0.1, 0.2, 0.25, 0.3, 0.35, 0.4, 1.0];
        let lanes = d.weight8(F8::new(facings), F8::splat(t));
        for (&w, &facing) in lanes.as_array_ref().iter().zip(&facings) {
            assert!((w - d.weight(facing, t)).abs() < 1e-6);
        }
        // Monotone between: no ring where the surface moves back out.
        let mut last = 1.0;
        for k in 0..=100 {
            let w = d.weight(k as f32 / 100.0, t);
            assert!(w <= last + 1e-7);
            last = w;
        }
    }

    /// The automatic threshold covers exactly the points F's largest value can carry past the outline: on a
    /// sphere of radius r with F at most h, those within angle acos(r / (r + h)) of it.
    #[test]
    fn automatic_threshold_reaches_as_far_as_the_height_can() {
        let mut d = silhouette(None);
        let table = BumpTable::new(&crate::image::GreyImage::new(2, 2, 1.0));
        d.map.source = BumpSource::Table(Arc::new(table));
        let (r, h) = (2.0f32, 0.05f32);
        d.map.scale = h;
        let t = d.threshold_at(1.0 / r);
        // The weight is 1 up to three quarters of the threshold.
        let reach = (r / (r + h)).acos().sin();
        assert!((FULL * t - reach).abs() < 0.02 * reach, "{t} {reach}");
    }
}
