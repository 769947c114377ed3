//! Image buffers and colour spaces. Pixels are stored row by row, row 0 at the top of the picture.

pub mod color;
pub mod indexed;
pub mod io;
pub mod levels;
pub mod output;
mod png_rows;
pub mod resample;
#[cfg(test)]
mod scratch;
pub mod stream;
pub mod strips;

use crate::error::{Error, Result};

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

impl<T> Image<T> {
    /// The image as a borrowed view.
    pub fn view(&self) -> ImageRef<'_, T> {
        ImageRef { width: self.width, height: self.height, pixels: &self.pixels }
    }
}

/// A rectangular image over a caller's buffer, row 0 at the top: what the readers of images take, so that
/// pixels held elsewhere (a NumPy array, a memory-mapped file, a frame of another library) are read in
/// place, without a copy into an [`Image`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImageRef<'a, T> {
    width: usize,
    height: usize,
    pixels: &'a [T],
}

impl<'a, T> ImageRef<'a, T> {
    /// A view of `width` x `height` pixels stored row after row in `pixels`, which must hold exactly that
    /// many; neither side may be 0.
    pub fn new(width: usize, height: usize, pixels: &'a [T]) -> Result<Self> {
        if width == 0 || height == 0 {
            return Err(Error::parameter("image", format!("must not be empty, got {width}x{height}")));
        }
        if width.checked_mul(height) != Some(pixels.len()) {
            return Err(Error::parameter(
                "image",
                format!("must hold {width}x{height} pixels, got a buffer of {}", pixels.len()),
            ));
        }
        Ok(ImageRef { width, height, pixels })
    }

    pub fn width(&self) -> usize {
        self.width
    }

    pub fn height(&self) -> usize {
        self.height
    }

    /// Every pixel, row after row from the top.
    pub fn pixels(&self) -> &'a [T] {
        self.pixels
    }

    /// One row of pixels.
    pub fn row(&self, y: usize) -> &'a [T] {
        &self.pixels[y * self.width..(y + 1) * self.width]
    }
}

impl<T: Clone> ImageRef<'_, T> {
    /// A copy that owns its pixels.
    pub fn to_image(&self) -> Image<T> {
        Image { width: self.width, height: self.height, pixels: self.pixels.to_vec() }
    }
}

impl<'a, T> From<&'a Image<T>> for ImageRef<'a, T> {
    fn from(image: &'a Image<T>) -> Self {
        image.view()
    }
}

/// A grey height or data image, values nominally in [0, 1] (black 0, white 1).
pub type GreyImage = Image<f32>;
/// A linear-light RGB image.
pub type RgbImage = Image<[f32; 3]>;
