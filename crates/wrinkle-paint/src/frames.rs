//! The view's frames as the page receives them: JPEG while the picture moves (small and quick to encode),
//! PNG when it rests (exactly what was rendered).

use image::codecs::jpeg::JpegEncoder;
use std::path::Path;
use wrinkle::image::io;
use wrinkle::{Error, Frame, Result};

/// JPEG quality while dragging.
const JPEG_QUALITY: u8 = 85;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrameFormat {
    Png,
    Jpeg,
}

impl FrameFormat {
    pub fn mime(self) -> &'static str {
        match self {
            FrameFormat::Png => "image/png",
            FrameFormat::Jpeg => "image/jpeg",
        }
    }
}

/// The frame's colour as 8-bit sRGB in `format`.
pub fn encode_frame(frame: &Frame, format: FrameFormat) -> Result<Vec<u8>> {
    let rgb = frame.srgb8();
    let mut out = Vec::new();
    match format {
        FrameFormat::Png => io::encode_png8(&mut out, Path::new("frame.png"), (frame.width, frame.height), 3, &rgb)?,
        FrameFormat::Jpeg => JpegEncoder::new_with_quality(&mut out, JPEG_QUALITY)
            .encode(&rgb, frame.width as u32, frame.height as u32, image::ExtendedColorType::Rgb8)
            .map_err(|e| Error::Invalid(format!("encoding a JPEG frame: {e}")))?,
    }
    Ok(out)
}
