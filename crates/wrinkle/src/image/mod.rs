//! Image buffers and colour spaces. Pixels are stored row by row, row 0 at the top of the picture.

pub mod color;
pub mod indexed;
pub mod io;
pub mod output;
pub mod resample;
#[cfg(test)]
mod scratch;
pub mod stream;
pub mod strips;

/// A rectangular buffer of pixels of type `T`, row 0 at the top.
#[derive(Clone, Debug, PartialEq)]
pub struct Image<T> {
    pub width: usize,
    pub height: usize,
    pub pixels: Vec<T>,
}

impl<T: Copy> Image<T> {
    /// An image of `width` x `height` pixels, every one `fill`.
    pub fn new(width: usize, height: usize, fill: T) -> Self {
        Image { width, height, pixels: vec![fill; width * height] }
    }

    /// An image whose pixel (x, y) is `f(x, y)`.
    pub fn from_fn(width: usize, height: usize, mut f: impl FnMut(usize, usize) -> T) -> Self {
        let mut pixels = Vec::with_capacity(width * height);
        for y in 0..height {
            for x in 0..width {
                pixels.push(f(x, y));
            }
        }
        Image { width, height, pixels }
    }

    #[inline]
    pub fn get(&self, x: usize, y: usize) -> T {
        self.pixels[y * self.width + x]
    }

    #[inline]
    pub fn set(&mut self, x: usize, y: usize, value: T) {
        self.pixels[y * self.width + x] = value;
    }

    /// One row of pixels.
    pub fn row(&self, y: usize) -> &[T] {
        &self.pixels[y * self.width..(y + 1) * self.width]
    }
}

/// A grey height or data image, values nominally in [0, 1] (black 0, white 1).
pub type GreyImage = Image<f32>;
/// A linear-light RGB image.
pub type RgbImage = Image<[f32; 3]>;
