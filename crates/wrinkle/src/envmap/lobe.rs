//! Image-based lighting: the environment convolved with a lobe about each direction, worked out once per
//! environment and lobe (the slides' "irradiance for diffuse surfaces", and one prefiltered map per Phong
//! exponent for glossy ones).
//!
//! The convolution with the normalised Phong lobe of exponent s:
//!     C_s(d) = integral of L(w) (s + 1) / (2 pi) max(0, d.w)^s dw,
//! so that a constant environment of radiance L gives exactly L for every s. With s = 1 it is the
//! irradiance over pi, E(n) / pi: a white Lambertian surface in a constant environment L shades to L.
//! It is summed over a latitude-longitude grid of cells (the environment filtered to each cell's size),
//! each weighted by its solid angle, and divided by the lobe's own sum on that grid, which makes constants
//! exact; the result is a small latlong map, read bilinearly.

use super::chart::Layout;
use super::{Environment, EnvironmentOptions};
use crate::image::Image;
use crate::texture::reconstruct::Kernel;
use crate::texture::{Filter, FilterOptions};
use glam::Vec3;
use rayon::prelude::*;
use std::f32::consts::PI;

/// Rows of the result for a lobe whose half-maximum is `half` radians from its axis: two cells across
/// the half-maximum, from 32 (a clamped cosine's kink at the horizon blurs over a cell) to 64 rows (the
/// cost grows with the square of the rows, times the source's cells).
fn rows_for(half: f32) -> usize {
    ((2.0 * PI / half).ceil() as usize).clamp(32, 64)
}

/// `env` convolved with the Phong lobe of exponent `s` (>= 1), as a latlong environment in world
/// directions (the source's rotation and intensity applied).
pub fn convolve(env: &Environment, s: f32) -> Environment {
    let half = 0.5f32.powf(1.0 / s).acos();
    let rows = rows_for(half);
    let cols = 2 * rows;
    let cells = source_cells(env, (2 * rows).clamp(64, 96));
    // Directions beyond this angle from the axis add less than 1e-4 of the peak.
    let cut = 1e-4f32.powf(1.0 / s);
    let pixels: Vec<[f32; 4]> = (0..rows * cols)
        .into_par_iter()
        .map(|k| {
            let (i, j) = (k % cols, k / cols);
            let (s_, t) = ((i as f32 + 0.5) / cols as f32, 1.0 - (j as f32 + 0.5) / rows as f32);
            let d = Layout::LatLong.direction(0, s_, t).expect("every latlong point has a direction");
            let (mut sum, mut weight) = (Vec3::ZERO, 0.0);
            for &(w, radiance, solid_angle) in &cells {
                let c = d.dot(w);
                if c > cut {
                    let k = c.powf(s) * solid_angle;
                    sum += radiance * k;
                    weight += k;
                }
            }
            (sum / weight.max(f32::MIN_POSITIVE)).extend(1.0).to_array()
        })
        .collect();
    let image = Image { width: cols, height: rows, pixels };
    let options = EnvironmentOptions {
        filter: FilterOptions { filter: Filter::Reconstruct(Kernel::Bilinear), ..FilterOptions::default() },
        ..EnvironmentOptions::default()
    };
    Environment::new(Layout::LatLong, &[image], options).expect("a 2:1 latlong map")
}

/// The environment on a latlong grid of `rows` x 2 `rows` cells, finer than the result (so that a small bright
/// source keeps its place): each cell's direction, radiance (filtered over the cell) and solid angle.
fn source_cells(env: &Environment, rows: usize) -> Vec<(Vec3, Vec3, f32)> {
    let cols = 2 * rows;
    let (dtheta, dphi) = (PI / rows as f32, 2.0 * PI / cols as f32);
    (0..rows * cols)
        .into_par_iter()
        .map(|k| {
            let (i, j) = (k % cols, k / cols);
            let (s, t) = ((i as f32 + 0.5) / cols as f32, 1.0 - (j as f32 + 0.5) / rows as f32);
            let d = Layout::LatLong.direction(0, s, t).expect("every latlong point has a direction");
            let polar = (j as f32 + 0.5) * dtheta;
            let along_phi = Vec3::new(-d.z, 0.0, d.x).normalize_or_zero() * (dphi * polar.sin());
            let along_theta = d.cross(along_phi).normalize_or_zero() * dtheta;
            let solid_angle = dphi * ((j as f32 * dtheta).cos() - ((j + 1) as f32 * dtheta).cos());
            (d, env.radiance(d, along_phi, along_theta), solid_angle)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A constant environment stays itself under any lobe.
    #[test]
    fn constants_are_kept() {
        let env = Environment::constant(Vec3::new(0.25, 1.0, 4.0));
        for s in [1.0, 10.0, 300.0] {
            let c = convolve(&env, s);
            for d in [Vec3::Y, Vec3::new(0.3, -0.5, 0.8).normalize()] {
                assert!(c.radiance(d, Vec3::ZERO, Vec3::ZERO).distance(Vec3::new(0.25, 1.0, 4.0)) < 1e-4);
            }
        }
    }

    /// One bright cell (a "one-hot" direction): the diffuse convolution follows the clamped cosine about it.
    #[test]
    fn one_hot_direction_gives_the_cosine_lobe() {
        let (w, h) = (128, 64);
        let hot = (w / 2 + 3, h / 4);
        let image =
            Image::from_fn(
                w,
                h,
                |x, y| if (x, y) == hot { [1000.0, 1000.0, 1000.0, 1.0] } else { [0.0, 0.0, 0.0, 1.0] },
            );
        let env = Environment::new(Layout::LatLong, &[image], EnvironmentOptions::default()).unwrap();
        let light = Layout::LatLong
            .direction(0, (hot.0 as f32 + 0.5) / w as f32, 1.0 - (hot.1 as f32 + 0.5) / h as f32)
            .unwrap();
        let c = convolve(&env, 1.0);
        let peak = c.radiance(light, Vec3::ZERO, Vec3::ZERO).x;
        for k in 0..40 {
            let d = Vec3::new((k as f32 * 0.7).sin(), (k as f32 * 1.3).cos(), (k as f32 * 0.4).sin() - 0.3).normalize();
            let want = peak * d.dot(light).max(0.0);
            let got = c.radiance(d, Vec3::ZERO, Vec3::ZERO).x;
            assert!((got - want).abs() < 0.04 * peak, "{d}: {got} vs {want} (peak {peak})");
        }
    }
}
