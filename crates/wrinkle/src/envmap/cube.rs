//! Cube maps in files: the six faces as one picture (a horizontal or vertical cross, or a strip), and
//! faces padded with their neighbours' texels so that filters reach across the seams.

use super::chart::{Face, Layout};
use crate::image::Image;

/// How six faces are arranged in one picture.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Arrangement {
    /// 4 x 3 faces: +Y above +Z; -X, +Z, +X, -Z in the middle row; -Y below +Z.
    Cross,
    /// 3 x 4 faces: +Y; -X, +Z, +X; -Y; then -Z upside down below -Y.
    VerticalCross,
    /// 6 x 1 faces in OpenGL's order: +X, -X, +Y, -Y, +Z, -Z.
    Strip,
    /// 1 x 6 faces in the same order, top to bottom.
    VerticalStrip,
}

impl Arrangement {
    pub const ALL: [(&'static str, Arrangement); 4] = [
        ("cross", Arrangement::Cross),
        ("vertical-cross", Arrangement::VerticalCross),
        ("strip", Arrangement::Strip),
        ("vertical-strip", Arrangement::VerticalStrip),
    ];

    pub fn parse(name: &str) -> Option<Arrangement> {
        Arrangement::ALL.iter().find(|(n, _)| *n == name).map(|&(_, a)| a)
    }

    /// The picture's size in faces (columns, rows).
    pub fn grid(self) -> (usize, usize) {
        match self {
            Arrangement::Cross => (4, 3),
            Arrangement::VerticalCross => (3, 4),
            Arrangement::Strip => (6, 1),
            Arrangement::VerticalStrip => (1, 6),
        }
    }

    /// Where a face sits (column, row), and whether it is stored upside down.
    fn cell(self, face: Face) -> (usize, usize, bool) {
        let k = face as usize;
        match (self, face) {
            (Arrangement::Strip, _) => (k, 0, false),
            (Arrangement::VerticalStrip, _) => (0, k, false),
            (_, Face::PosY) => (1, 0, false),
            (_, Face::NegX) => (0, 1, false),
            (_, Face::PosZ) => (1, 1, false),
            (_, Face::PosX) => (2, 1, false),
            (_, Face::NegY) => (1, 2, false),
            (Arrangement::Cross, Face::NegZ) => (3, 1, false),
            (_, Face::NegZ) => (1, 3, true),
        }
    }

    /// The arrangement a picture of this shape has, if any.
    pub fn of_shape(width: usize, height: usize) -> Option<Arrangement> {
        Arrangement::ALL.iter().map(|&(_, a)| a).find(|a| {
            let (c, r) = a.grid();
            width * r == height * c
        })
    }

    /// The six faces of a picture, in OpenGL's order.
    pub fn split(self, picture: &Image<[f32; 4]>) -> Result<Vec<Image<[f32; 4]>>, String> {
        let (c, r) = self.grid();
        let n = picture.width / c;
        if n == 0 || picture.width != n * c || picture.height != n * r {
            return Err(format!(
                "a cube map as a {} is {c} x {r} square faces, got {}x{} pixels",
                self.name(),
                picture.width,
                picture.height
            ));
        }
        Ok(Face::ALL
            .iter()
            .map(|&face| {
                let (col, row, turned) = self.cell(face);
                Image::from_fn(n, n, |x, y| {
                    let (x, y) = if turned { (n - 1 - x, n - 1 - y) } else { (x, y) };
                    picture.get(col * n + x, row * n + y)
                })
            })
            .collect())
    }

    /// One picture of six square faces (OpenGL's order); cells without a face are black and transparent.
    pub fn join(self, faces: &[Image<[f32; 4]>]) -> Image<[f32; 4]> {
        let (c, r) = self.grid();
        let n = faces[0].width;
        let mut picture = Image::new(n * c, n * r, [0.0; 4]);
        for (&face, image) in Face::ALL.iter().zip(faces) {
            let (col, row, turned) = self.cell(face);
            for y in 0..n {
                for x in 0..n {
                    let (sx, sy) = if turned { (n - 1 - x, n - 1 - y) } else { (x, y) };
                    picture.set(col * n + x, row * n + y, image.get(sx, sy));
                }
            }
        }
        picture
    }

    fn name(self) -> &'static str {
        Arrangement::ALL.iter().find(|(_, a)| *a == self).map(|(n, _)| *n).expect("every arrangement is named")
    }
}

/// The padding of a face of `n` texels on each side: an eighth of it (at least one texel), so that a
/// filter whose footprint is up to an eighth of a face reads the neighbouring faces' texels across a seam
/// at every MIP level.
pub fn padding(n: usize) -> usize {
    n.div_ceil(8).max(1)
}

/// Each face grown by `padding(n)` texels on every side, the new texels looked up (bilinearly) in the faces
/// their directions point at: the cube's surface continued past the face's edges.
pub fn padded(faces: &[Image<[f32; 4]>]) -> Vec<Image<[f32; 4]>> {
    let n = faces[0].width;
    let p = padding(n);
    let size = n + 2 * p;
    Face::ALL
        .iter()
        .map(|&face| {
            Image::from_fn(size, size, |x, y| {
                let (x, y) = (x as isize - p as isize, y as isize - p as isize);
                if (0..n as isize).contains(&x) && (0..n as isize).contains(&y) {
                    return faces[face as usize].get(x as usize, y as usize);
                }
                let (s, t) = ((x as f32 + 0.5) / n as f32, 1.0 - (y as f32 + 0.5) / n as f32);
                let d = Layout::Cube.direction(face as usize, s, t).expect("every cube point has a direction");
                let (at, _) = Layout::Cube.locate(d);
                bilinear(&faces[at.image], at.s, at.t)
            })
        })
        .collect()
}

/// The bilinear texel of a face at (s, t) (t up), clamped at its edges.
fn bilinear(face: &Image<[f32; 4]>, s: f32, t: f32) -> [f32; 4] {
    let n = face.width as f32;
    let (x, y) = (s * n - 0.5, (1.0 - t) * n - 0.5);
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let at = |i: f32, j: f32| face.get(i.clamp(0.0, n - 1.0) as usize, j.clamp(0.0, n - 1.0) as usize);
    let (a, b, c, d) = (at(x0, y0), at(x0 + 1.0, y0), at(x0, y0 + 1.0), at(x0 + 1.0, y0 + 1.0));
    std::array::from_fn(|k| {
        let top = a[k] + (b[k] - a[k]) * fx;
        let bottom = c[k] + (d[k] - c[k]) * fx;
        top + (bottom - top) * fy
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn numbered_faces(n: usize) -> Vec<Image<[f32; 4]>> {
        (0..6).map(|k| Image::from_fn(n, n, |x, y| [k as f32, x as f32, y as f32, 1.0])).collect()
    }

    /// Every arrangement splits what it joins, and is recognised by its shape.
    #[test]
    fn arrangements_round_trip() {
        let faces = numbered_faces(4);
        for (_, a) in Arrangement::ALL {
            let picture = a.join(&faces);
            assert_eq!(Arrangement::of_shape(picture.width, picture.height), Some(a));
            assert_eq!(a.split(&picture).unwrap(), faces);
        }
        let err = Arrangement::Cross.split(&Image::new(10, 7, [0.0; 4])).unwrap_err();
        assert_eq!(err, "a cube map as a cross is 4 x 3 square faces, got 10x7 pixels");
    }

    /// The cross is continuous: +Z's right column meets +X's left column, +Y's bottom row +Z's top row.
    #[test]
    fn cross_neighbours_share_edges() {
        let n = 8;
        let d = |face: usize, x: usize, y: usize| {
            Layout::Cube.direction(face, (x as f32 + 0.5) / n as f32, 1.0 - (y as f32 + 0.5) / n as f32).unwrap()
        };
        for y in 0..n {
            // Across the seam the directions differ by about one texel's angle (2 / n at the edge).
            assert!(d(4, n - 1, y).distance(d(0, 0, y)) < 2.5 / n as f32);
            assert!(d(2, y, n - 1).distance(d(4, y, 0)) < 2.5 / n as f32);
        }
    }

    /// Padding continues each face with its neighbours' texels: just past +Z's right edge lies +X's left
    /// column.
    #[test]
    fn padding_reads_the_neighbouring_face() {
        let n = 16;
        let faces = numbered_faces(n);
        let padded = padded(&faces);
        let p = padding(n);
        assert_eq!(padded[4].width, n + 2 * p);
        for y in 2..n - 2 {
            let texel = padded[4].get(p + n, p + y);
            assert_eq!(texel[0], 0.0, "+X lies right of +Z");
            assert!(texel[1] < 1.0, "its first column: {texel:?}");
            assert!((texel[2] - y as f32).abs() < 0.6, "row {y}: {texel:?}");
        }
    }
}
