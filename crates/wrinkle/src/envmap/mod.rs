//! Environment maps: the radiance arriving from every direction, stored in one of the slides' layouts
//! and looked up by a direction with its change across the pixel, through the texture filters.

pub mod chart;
pub mod convert;
pub mod cube;
pub mod files;
pub(crate) mod lobe;

pub use chart::{ChartPoint, Face, Layout};
pub use cube::Arrangement;

use crate::image::Image;
use crate::lanes::{F8, LANES, V3};
use crate::texture::{FilterOptions, FilteredTexture, Footprint, MipFilter, TextureOptions, Wrap};
use glam::{Mat3, Vec3, Vec4};
use std::sync::{Arc, Mutex};

/// How an environment is looked up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnvironmentOptions {
    /// What every lookup is multiplied by.
    pub intensity: f32,
    /// Degrees the map is turned about the world's +Y (counter-clockwise seen from above).
    pub rotate: f32,
    pub filter: FilterOptions,
}

impl Default for EnvironmentOptions {
    fn default() -> Self {
        EnvironmentOptions { intensity: 1.0, rotate: 0.0, filter: FilterOptions::default() }
    }
}

/// An environment map ready for filtered lookups.
pub struct Environment {
    layout: Layout,
    /// One texture per image of the layout; a cube's faces padded (`cube::padded`).
    textures: Vec<FilteredTexture>,
    /// Where a face's [0, 1] lies in its padded texture: s' = inset + s * scale (0 and 1 unpadded).
    inset: f32,
    scale: f32,
    intensity: f32,
    /// World directions into the map's frame.
    to_map: Mat3,
    /// The convolutions with Phong lobes made so far (`lobe`), by exponent.
    lobes: Mutex<Vec<(f32, Arc<Environment>)>>,
}

impl Environment {
    /// An environment from the images of `layout` (linear RGBA, row 0 at the top): one latlong image twice
    /// as wide as high, six square cube faces in OpenGL's order, one square sphere map, or the two square
    /// halves of a dual paraboloid (+Z, then -Z).
    pub fn new(layout: Layout, images: &[Image<[f32; 4]>], options: EnvironmentOptions) -> Result<Self, String> {
        check_images(layout, images)?;
        let wrap = match layout {
            Layout::LatLong => [Wrap::Repeat, Wrap::Clamp],
            _ => [Wrap::Clamp; 2],
        };
        let texture_options = TextureOptions {
            wrap,
            border: Vec4::ZERO,
            mip_filter: MipFilter::Box,
            filter: options.filter,
            lod_bias: 0.0,
        };
        let (stored, inset, scale) = match layout {
            Layout::Cube => {
                let (n, p) = (images[0].width as f32, cube::padding(images[0].width) as f32);
                (cube::padded(images), p / (n + 2.0 * p), n / (n + 2.0 * p))
            }
            Layout::Sphere | Layout::Paraboloid => (images.iter().map(rim_extended).collect(), 0.0, 1.0),
            Layout::LatLong => (images.to_vec(), 0.0, 1.0),
        };
        let textures = stored.iter().map(|image| FilteredTexture::new(image, texture_options)).collect();
        let to_map = Mat3::from_rotation_y(-options.rotate.to_radians());
        Ok(Environment {
            layout,
            textures,
            inset,
            scale,
            intensity: options.intensity,
            to_map,
            lobes: Mutex::default(),
        })
    }

    /// The same radiance from every direction.
    pub fn constant(radiance: Vec3) -> Environment {
        let image = Image::new(2, 1, radiance.extend(1.0).to_array());
        Environment::new(Layout::LatLong, &[image], EnvironmentOptions::default()).expect("a 2:1 latlong map")
    }

    pub fn layout(&self) -> Layout {
        self.layout
    }

    /// The environment convolved with the normalised Phong lobe of exponent `s` (`lobe::convolve`): 1 for
    /// diffuse surfaces (irradiance over pi), a material's for glossy ones. Made once per exponent, then
    /// kept with the environment.
    pub fn lobe(&self, s: f32) -> Arc<Environment> {
        let mut lobes = self.lobes.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        // By bits, so that a NaN exponent finds its own lobe too (NaN equals nothing) instead of adding one
        // each call.
        if let Some((_, made)) = lobes.iter().find(|(e, _)| e.to_bits() == s.to_bits()) {
            return Arc::clone(made);
        }
        let made = Arc::new(lobe::convolve(self, s));
        lobes.push((s, Arc::clone(&made)));
        made
    }

    /// The radiance arriving from unit world direction `d`, filtered over the directions `d + ddx` and
    /// `d + ddy` reach (its change across the pixel): `radiance8` on one lane.
    pub fn radiance(&self, d: Vec3, ddx: Vec3, ddy: Vec3) -> Vec3 {
        self.radiance8(&V3::splat(d), &V3::splat(ddx), &V3::splat(ddy)).lane(0)
    }

    /// The radiance arriving from eight unit world directions, each filtered over its change across the
    /// pixel. The chart and the footprints run on all lanes; the texture lookups one lane at a time.
    #[inline]
    pub fn radiance8(&self, d: &V3, ddx: &V3, ddy: &V3) -> V3 {
        let d = V3::mul_mat3(&self.to_map, *d);
        let (ddx, ddy) = (V3::mul_mat3(&self.to_map, *ddx), V3::mul_mat3(&self.to_map, *ddy));
        // Only the change along the sphere moves the point.
        let (ddx, ddy) = (ddx - d * d.dot(ddx), ddy - d * d.dot(ddy));
        let (at, [ds, dt]) = self.layout.locate8(&d);
        let k = F8::splat(self.scale);
        let footprint = [ds.dot(ddx) * k, dt.dot(ddx) * k, ds.dot(ddy) * k, dt.dot(ddy) * k].map(|f| f.to_array());
        let inset = F8::splat(self.inset);
        let (s, t) = ((inset + at.s * k).to_array(), (inset + at.t * k).to_array());
        let mut out = V3::ZERO;
        for i in 0..LANES {
            let fp = Footprint {
                dudx: footprint[0][i],
                dvdx: footprint[1][i],
                dudy: footprint[2][i],
                dvdy: footprint[3][i],
            };
            let texel = self.textures[at.image[i] as usize].lookup(s[i], t[i], &fp);
            out.set_lane(i, texel.truncate() * self.intensity);
        }
        out
    }
}

/// A disc image (sphere map, paraboloid half) whose texels outside the disc repeat the rim's, radially:
/// filters near the rim then read the rim, not the black corners.
fn rim_extended(image: &Image<[f32; 4]>) -> Image<[f32; 4]> {
    let n = image.width as f32;
    Image::from_fn(image.width, image.height, |x, y| {
        let (px, py) = (2.0 * (x as f32 + 0.5) / n - 1.0, 2.0 * (y as f32 + 0.5) / n - 1.0);
        let r = (px * px + py * py).sqrt();
        let inside = 1.0 - 1.0 / n;
        if r <= inside {
            return image.get(x, y);
        }
        let (qx, qy) = (px * inside / r, py * inside / r);
        let at = |q: f32| (((q + 1.0) * 0.5 * n) as usize).min(image.width - 1);
        image.get(at(qx), at(qy))
    })
}

/// The images a layout needs: their count, shapes and equal sizes.
fn check_images(layout: Layout, images: &[Image<[f32; 4]>]) -> Result<(), String> {
    let want = layout.images();
    if images.len() != want {
        return Err(format!("a {} map has {want} image(s), got {}", layout.name(), images.len()));
    }
    let (w, h) = (images[0].width, images[0].height);
    if w == 0 || h == 0 {
        return Err(format!("a {} map's images are empty ({w}x{h})", layout.name()));
    }
    let shape_ok = match layout {
        Layout::LatLong => w == 2 * h,
        _ => w == h,
    };
    if !shape_ok {
        let shape = if layout == Layout::LatLong { "twice as wide as high" } else { "square" };
        return Err(format!("a {} map's images are {shape}, got {w}x{h}", layout.name()));
    }
    if let Some(other) = images.iter().find(|i| (i.width, i.height) != (w, h)) {
        return Err(format!(
            "the images of a {} map must be one size: {w}x{h} and {}x{}",
            layout.name(),
            other.width,
            other.height
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A constant environment gives its radiance in every direction, whatever the footprint.
    #[test]
    fn constant_environment_is_constant() {
        let env = Environment::constant(Vec3::new(0.2, 0.5, 3.0));
        for d in [Vec3::X, -Vec3::Y, Vec3::new(0.3, 0.4, -0.5).normalize()] {
            for size in [0.0, 0.01, 1.0] {
                let got = env.radiance(d, Vec3::Y.cross(d) * size + Vec3::X * size, Vec3::Z * size);
                assert!(got.distance(Vec3::new(0.2, 0.5, 3.0)) < 1e-5, "{d} {size}: {got}");
            }
        }
    }

    /// Rotation turns the map about +Y: a map bright only at its centre column (-Z) is seen towards -X
    /// when turned by 90 degrees.
    #[test]
    fn rotation_turns_about_up() {
        let image = Image::from_fn(64, 32, |x, _| if x == 32 || x == 31 { [1.0; 4] } else { [0.0, 0.0, 0.0, 1.0] });
        let options = EnvironmentOptions { rotate: 90.0, ..EnvironmentOptions::default() };
        let env = Environment::new(Layout::LatLong, &[image], options).unwrap();
        let look = |d: Vec3| env.radiance(d, Vec3::ZERO, Vec3::ZERO).x;
        assert!(look(-Vec3::X) > 0.4 && look(-Vec3::Z) == 0.0, "{} {}", look(-Vec3::X), look(-Vec3::Z));
    }

    #[test]
    fn wrong_images_are_named() {
        let square = Image::new(4, 4, [0.0; 4]);
        let err = |layout, images: &[Image<[f32; 4]>]| match Environment::new(
            layout,
            images,
            EnvironmentOptions::default(),
        ) {
            Err(e) => e,
            Ok(_) => panic!("accepted"),
        };
        assert_eq!(
            err(Layout::LatLong, std::slice::from_ref(&square)),
            "a latlong map's images are twice as wide as high, got 4x4"
        );
        assert_eq!(err(Layout::Cube, std::slice::from_ref(&square)), "a cube map has 6 image(s), got 1");
        let mut faces = vec![square; 6];
        faces[3] = Image::new(8, 8, [0.0; 4]);
        assert_eq!(err(Layout::Cube, &faces), "the images of a cube map must be one size: 4x4 and 8x8");
    }
}
