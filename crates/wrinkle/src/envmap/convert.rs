//! Converting an environment to another layout: every texel of the new images is the environment filtered
//! over the directions the texel covers, in linear light.

use super::chart::Layout;
use super::cube::Arrangement;
use super::Environment;
use crate::image::Image;
use glam::Vec3;
use rayon::prelude::*;
use std::f32::consts::PI;

/// The images of layout `to` at `size` texels (a latlong map's height, a cube face's side, a sphere map's
/// or a paraboloid half's side). Texels outside a sphere map's or paraboloid's disc are transparent black.
pub fn convert(env: &Environment, to: Layout, size: usize) -> Vec<Image<[f32; 4]>> {
    let (w, h) = if to == Layout::LatLong { (2 * size, size) } else { (size, size) };
    (0..to.images())
        .map(|image| {
            let mut pixels = vec![[0.0f32; 4]; w * h];
            if w == 0 {
                return Image { width: w, height: h, pixels };
            }
            pixels.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
                let t = 1.0 - (y as f32 + 0.5) / h as f32;
                for (x, texel) in row.iter_mut().enumerate() {
                    let s = (x as f32 + 0.5) / w as f32;
                    let dir = |s: f32, t: f32| to.direction(image, s, t);
                    let Some(d) = dir(s, t) else { continue };
                    // The change to the next texel right and down (one-sided at a disc's rim).
                    let step = |a: Option<Vec3>, b: Option<Vec3>| match (a, b) {
                        (Some(a), Some(b)) => (a - b) * 0.5,
                        (Some(a), None) => a - d,
                        (None, Some(b)) => d - b,
                        (None, None) => Vec3::ZERO,
                    };
                    let (dx, dy) = (1.0 / w as f32, 1.0 / h as f32);
                    let ddx = step(dir(s + dx, t), dir(s - dx, t));
                    let ddy = step(dir(s, t - dy), dir(s, t + dy));
                    *texel = env.radiance(d, ddx, ddy).extend(1.0).to_array();
                }
            });
            Image { width: w, height: h, pixels }
        })
        .collect()
}

/// Texels per radian at the centre of a layout whose `size` is as `convert` counts it.
fn texels_per_radian(layout: Layout, size: usize) -> f32 {
    let n = size as f32;
    match layout {
        Layout::LatLong => n / PI,
        Layout::Cube => n / 2.0,
        // The ball's normal turns half as fast as the direction it reflects.
        Layout::Sphere | Layout::Paraboloid => n / 4.0,
    }
}

/// The size of layout `to` with the detail of `from` at `size`: the same texels per radian at the centre.
pub fn matching_size(from: Layout, size: usize, to: Layout) -> usize {
    let density = texels_per_radian(from, size);
    (density / texels_per_radian(to, 1)).round().max(1.0) as usize
}

/// The size of an environment's images as `convert` counts it.
pub fn size_of(layout: Layout, images: &[Image<[f32; 4]>]) -> usize {
    match layout {
        Layout::LatLong => images[0].height,
        _ => images[0].width,
    }
}

/// A layout's images as one picture: a cube as `arrangement`, a paraboloid's halves side by side.
pub fn picture(layout: Layout, images: &[Image<[f32; 4]>], arrangement: Arrangement) -> Image<[f32; 4]> {
    match layout {
        Layout::Cube => arrangement.join(images),
        Layout::Paraboloid => {
            let n = images[0].width;
            Image::from_fn(2 * n, n, |x, y| images[x / n].get(x % n, y))
        }
        Layout::LatLong | Layout::Sphere => images[0].clone(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::envmap::EnvironmentOptions;
    use crate::texture::{Filter, FilterOptions};

    /// A smooth latlong map (a few low spherical frequencies), through every other layout and back,
    /// stays within 1% RMSE of itself; through the sphere map, away from its rim (where all of -Z is
    /// squeezed into one circle).
    #[test]
    fn latlong_through_every_layout_and_back() {
        let sky = |d: Vec3| 1.0 + 0.5 * d.y + 0.3 * d.x * d.z + 0.2 * (2.0 * d.x).sin();
        let h = 64;
        let source = Image::from_fn(2 * h, h, |x, y| {
            let d = Layout::LatLong
                .direction(0, (x as f32 + 0.5) / (2 * h) as f32, 1.0 - (y as f32 + 0.5) / h as f32)
                .unwrap();
            let v = sky(d);
            [v, v * 0.5, 1.0, 1.0]
        });
        let options = EnvironmentOptions {
            filter: FilterOptions { filter: Filter::Ewa, ..FilterOptions::default() },
            ..EnvironmentOptions::default()
        };
        let env = Environment::new(Layout::LatLong, std::slice::from_ref(&source), options).unwrap();
        for to in [Layout::Cube, Layout::Sphere, Layout::Paraboloid] {
            let size = matching_size(Layout::LatLong, h, to);
            let there = Environment::new(to, &convert(&env, to, size), options).unwrap();
            let back = &convert(&there, Layout::LatLong, h)[0];
            let (mut err, mut norm) = (0.0f64, 0.0f64);
            for (k, (a, b)) in back.pixels.iter().zip(&source.pixels).enumerate() {
                let (x, y) = ((k % (2 * h)) as f32 + 0.5, (k / (2 * h)) as f32 + 0.5);
                let d = Layout::LatLong.direction(0, x / (2 * h) as f32, 1.0 - y / h as f32).unwrap();
                if to == Layout::Sphere && d.z < -0.5 {
                    continue;
                }
                err += f64::from(a[0] - b[0]).powi(2);
                norm += f64::from(b[0]).powi(2);
            }
            let rmse = (err / norm).sqrt();
            assert!(rmse < 0.01, "{}: relative RMSE {rmse}", to.name());
        }
    }

    #[test]
    fn sizes_keep_the_detail() {
        assert_eq!(matching_size(Layout::LatLong, 512, Layout::Cube), 326);
        assert_eq!(matching_size(Layout::Cube, 256, Layout::LatLong), 402);
        assert_eq!(matching_size(Layout::Sphere, 512, Layout::Paraboloid), 512);
    }
}
