//! Displacement mapping (Lingard): the surface itself moved along its normal by a bump function's F, so
//! silhouettes and occlusion show the bumps; and Lingard's cheaper proposal, displacing only near the
//! silhouette and bump-mapping the rest. The dicing is geometry/dice.rs; the frame's driver runs it.

use super::BumpMap;
use crate::lanes::F8;

/// Where the surface is moved.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DisplacementMode {
    /// Everywhere.
    Full,
    /// Only where the surface is seen at a grazing angle, |N.V| below `threshold`: fully below half of it,
    /// blended smoothly to nothing at it. Elsewhere the same F bump-maps the flat surface.
    Silhouette { threshold: f32 },
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

    /// How much of F moves a point whose unit normal and direction to the eye have |N.V| = `facing`.
    #[inline]
    pub fn weight(&self, facing: f32) -> f32 {
        match self.mode {
            DisplacementMode::Full => 1.0,
            DisplacementMode::Silhouette { threshold } => {
                let x = ((threshold - facing) / (0.5 * threshold)).clamp(0.0, 1.0);
                x * x * (3.0 - 2.0 * x)
            }
        }
    }

    /// `weight` on eight lanes.
    #[inline]
    pub fn weight8(&self, facing: F8) -> F8 {
        match self.mode {
            DisplacementMode::Full => F8::ONE,
            DisplacementMode::Silhouette { threshold } => {
                let x = ((F8::splat(threshold) - facing) * F8::splat(2.0 / threshold)).max(F8::ZERO).min(F8::ONE);
                x * x * (F8::splat(3.0) - F8::splat(2.0) * x)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bump::{BumpFormula, BumpSource, BumpTable};
    use crate::mapping::Mapping;
    use crate::texture::FilterOptions;
    use std::sync::Arc;

    fn silhouette(threshold: f32) -> Displacement {
        let table = BumpTable::new(&crate::image::GreyImage::new(2, 2, 0.0));
        let map = BumpMap {
            source: BumpSource::Table(Arc::new(table)),
            scale: 1.0,
            mapping: Mapping::default(),
            formula: BumpFormula::Full,
            filter: FilterOptions::default(),
            parallax: None,
        };
        Displacement { map, mode: DisplacementMode::Silhouette { threshold }, edge_px: 1.0 }
    }

    #[test]
    fn silhouette_weight_blends_from_full_to_none() {
        let d = silhouette(0.4);
        for (facing, want) in [(0.0, 1.0), (0.2, 1.0), (0.3, 0.5), (0.4, 0.0), (0.9, 0.0)] {
            assert!((d.weight(facing) - want).abs() < 1e-6, "{facing}: {}", d.weight(facing));
        }
        let lanes = d.weight8(F8::new([0.0, 0.1, 0.2, 0.25, 0.3, 0.35, 0.4, 1.0]));
        for (i, &w) in lanes.as_array_ref().iter().enumerate() {
            let facing = [0.0, 0.1, 0.2, 0.25, 0.3, 0.35, 0.4, 1.0][i];
            assert!((w - d.weight(facing)).abs() < 1e-6);
        }
        // Monotone between: no ring where the surface moves back out.
        let mut last = 1.0;
        for k in 0..=100 {
            let w = d.weight(k as f32 / 100.0);
            assert!(w <= last + 1e-7);
            last = w;
        }
    }
}
