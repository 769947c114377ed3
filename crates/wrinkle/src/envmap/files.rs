//! An environment's images from files: one picture (a latlong map, a sphere map, a dual paraboloid's two
//! halves side by side, or a cube as a cross or a strip), or one file per image (six cube faces in
//! OpenGL's order, or the paraboloid's +Z and -Z halves). 8-bit files are sRGB; HDR and EXR are linear.

use super::chart::Layout;
use super::cube::Arrangement;
use crate::image::{io, Image};
use crate::limits;
use crate::{Error, Result};
use std::path::PathBuf;

/// The layout of `paths` (given, or guessed: six files a cube, two a paraboloid; one picture by its shape,
/// 2:1 latlong, 1:1 sphere, 4:3, 3:4, 6:1 or 1:6 a cube) and its images, linear RGBA.
pub fn load(paths: &[PathBuf], layout: Option<Layout>) -> Result<(Layout, Vec<Image<[f32; 4]>>)> {
    if ![1, 2, 6].contains(&paths.len()) {
        return Err(Error::Invalid(format!(
            "an environment map is one picture, two paraboloid halves or six cube faces, got {} files",
            paths.len()
        )));
    }
    let pictures = paths.iter().map(|p| io::load_rgba_linear(p, true)).collect::<Result<Vec<_>>>()?;
    let first = &paths[0];
    let layout = match layout {
        Some(layout) => layout,
        None => guess(&pictures).ok_or_else(|| {
            let (w, h) = (pictures[0].width, pictures[0].height);
            Error::read(first, format!("cannot tell the layout of a {w}x{h} environment map: name it (latlong, cube, sphere or paraboloid)"))
        })?,
    };
    let images = match (layout, pictures.len()) {
        (Layout::Cube, 1) => {
            let p = &pictures[0];
            let arrangement = Arrangement::of_shape(p.width, p.height).ok_or_else(|| {
                Error::read(
                    first,
                    format!(
                        "a cube map in one picture is a cross (4:3), a vertical cross (3:4) or a strip (6:1 or 1:6), got {}x{}",
                        p.width, p.height
                    ),
                )
            })?;
            arrangement.split(p).map_err(|m| Error::read(first, m))?
        }
        (Layout::Paraboloid, 1) => {
            let p = &pictures[0];
            if p.width != 2 * p.height {
                return Err(Error::read(
                    first,
                    format!(
                        "a dual paraboloid in one picture is two squares side by side, got {}x{}",
                        p.width, p.height
                    ),
                ));
            }
            let n = p.height;
            (0..2).map(|k| Image::from_fn(n, n, |x, y| p.get(k * n + x, y))).collect()
        }
        _ => pictures,
    };
    // The float pyramids (4/3 of the texels, 16 bytes each), a cube's faces grown by a quarter per side.
    let texels: u64 = images.iter().map(|i| (i.width * i.height) as u64).sum();
    limits::reserve(texels * 16 * 4 / 3 * 25 / 16, || {
        format!("{}: an environment of {texels} texels", first.display())
    })?;
    Ok((layout, images))
}

fn guess(pictures: &[Image<[f32; 4]>]) -> Option<Layout> {
    match pictures.len() {
        6 => Some(Layout::Cube),
        2 => Some(Layout::Paraboloid),
        1 => {
            let (w, h) = (pictures[0].width, pictures[0].height);
            match () {
                _ if w == 2 * h => Some(Layout::LatLong),
                _ if w == h => Some(Layout::Sphere),
                _ => Arrangement::of_shape(w, h).map(|_| Layout::Cube),
            }
        }
        _ => None,
    }
}
