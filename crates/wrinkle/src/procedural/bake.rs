//! Baking a pattern into an image: pixel (i, j) samples the pattern at its centre (u, v) =
//! ((i + 0.5) / W, 1 - (j + 0.5) / H) (row 0 at the top, v up), with the pixel's size as the footprint.
//! A tileable pattern repeats over [0, 1) in u and v, so the image's opposite edges join.

use super::effects::Pattern;
use crate::image::Image;
use rayon::prelude::*;

/// The pattern's t in [0, 1] at every pixel of a `width` x `height` image.
pub fn bake(pattern: &Pattern, width: usize, height: usize) -> Image<f32> {
    let mut pixels = vec![0.0f32; width * height];
    bake_rows(pattern, width, height, 0, &mut pixels);
    Image { width, height, pixels }
}

/// The rows from `first` down of a `width` x `height` bake, as many as `out` holds (whole rows), in
/// parallel: a band of the image, so that a large one can be written without being held whole.
pub fn bake_rows(pattern: &Pattern, width: usize, height: usize, first: usize, out: &mut [f32]) {
    if width == 0 {
        return;
    }
    let (du, dv) = (1.0 / width as f32, 1.0 / height as f32);
    let footprint = du.max(dv);
    out.par_chunks_mut(width).enumerate().for_each(|(k, row)| {
        let v = 1.0 - ((first + k) as f32 + 0.5) * dv;
        pattern.row(0.0, du, v, footprint, row);
    });
}

#[cfg(test)]
mod tests {
    use super::super::effects::{Kind, Params};
    use super::*;

    /// Differences across the wrap seam (last column to first, last row to first) and between interior
    /// neighbours, as (largest, mean) of each.
    fn seam_and_interior(img: &Image<f32>) -> ((f32, f32), (f32, f32)) {
        let (w, h) = (img.width, img.height);
        let stats = |d: Vec<f32>| (d.iter().cloned().fold(0.0, f32::max), d.iter().sum::<f32>() / d.len() as f32);
        let mut interior = Vec::new();
        for y in 0..h {
            for x in 0..w {
                if x + 1 < w {
                    interior.push((img.get(x + 1, y) - img.get(x, y)).abs());
                }
                if y + 1 < h {
                    interior.push((img.get(x, y + 1) - img.get(x, y)).abs());
                }
            }
        }
        let mut seam: Vec<f32> = (0..h).map(|y| (img.get(0, y) - img.get(w - 1, y)).abs()).collect();
        seam.extend((0..w).map(|x| (img.get(x, 0) - img.get(x, h - 1)).abs()));
        (stats(seam), stats(interior))
    }

    #[test]
    fn tileable_images_join_without_a_seam() {
        for kind in Kind::ALL.into_iter().filter(|k| k.tiles()) {
            let mut params = Params::new(kind);
            params.scale = 5.0;
            params.seed = 3;
            let tiled = bake(&Pattern::new(params.clone(), 2, true).unwrap(), 128, 96);
            // (The mean across the seam is no test: the checker's and grid's cell edges lie on the tile's.)
            let ((seam_max, _), (inner_max, _)) = seam_and_interior(&tiled);
            assert!(seam_max <= inner_max, "{kind:?}: seam step {seam_max} > interior {inner_max}");
            if matches!(kind, Kind::Fbm | Kind::Noise | Kind::Turbulence | Kind::Clouds) {
                // The same noise without the period does show a seam.
                params.scale = 5.3;
                let free = bake(&Pattern::new(params, 2, false).unwrap(), 128, 96);
                let ((_, seam_mean), (_, inner_mean)) = seam_and_interior(&free);
                assert!(seam_mean > 3.0 * inner_mean, "{kind:?}: the untiled image should not join");
            }
        }
    }

    #[test]
    fn baked_pixels_are_the_pattern_at_their_centres() {
        let p = Pattern::new(Params::new(Kind::Marble), 2, false).unwrap();
        let img = bake(&p, 16, 8);
        let t = p.eval([(3.0 + 0.5) / 16.0, 1.0 - (5.0 + 0.5) / 8.0, 0.0], 1.0 / 8.0);
        assert!((img.get(3, 5) - t).abs() < 1e-6);
    }
}
