//! sRGB <-> linear conversions (IEC 61966-2-1).

/// sRGB-encoded value in [0,1] to linear light.
#[inline]
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Linear light to sRGB-encoded value, clamped to [0,1].
#[inline]
pub fn linear_to_srgb(c: f32) -> f32 {
    let c = c.clamp(0.0, 1.0);
    if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// 8-bit RGBA texels in linear RGBA: colour decoded from sRGB with `srgb` (else value / 255), alpha
/// never decoded.
pub fn decode_rgba8(texels: &[[u8; 4]], srgb: bool) -> Vec<[f32; 4]> {
    let table = if srgb { srgb8_decode_table() } else { std::array::from_fn(|i| i as f32 / 255.0) };
    texels
        .iter()
        .map(|p| [table[p[0] as usize], table[p[1] as usize], table[p[2] as usize], p[3] as f32 / 255.0])
        .collect()
}

/// Decoding table for 8-bit sRGB texels: index by the byte, get linear light.
pub fn srgb8_decode_table() -> [f32; 256] {
    let mut t = [0.0; 256];
    for (i, v) in t.iter_mut().enumerate() {
        *v = srgb_to_linear(i as f32 / 255.0);
    }
    t
}

/// Fast linear -> 8-bit sRGB encoder: a 16384-entry table over [0,1] in linear light, fine enough at the dark
/// end (where sRGB is steepest) that every result is within one code of the exact one.
pub struct SrgbEncoder {
    table: Vec<u8>,
}

impl SrgbEncoder {
    const N: usize = 1 << 14;

    pub fn new() -> Self {
        let table = (0..Self::N)
            .map(|i| {
                let lin = (i as f32 + 0.5) / Self::N as f32;
                (linear_to_srgb(lin) * 255.0 + 0.5) as u8
            })
            .collect();
        SrgbEncoder { table }
    }

    #[inline]
    pub fn encode(&self, linear: f32) -> u8 {
        // NaN maps to 0 through the saturating cast.
        let i = (linear * Self::N as f32) as usize;
        self.table[i.min(Self::N - 1)]
    }
}

impl Default for SrgbEncoder {
    fn default() -> Self {
        Self::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_published_points() {
        // The sRGB mid-grey 0.5 is 0.21404 in linear light (IEC 61966-2-1).
        assert!((srgb_to_linear(0.5) - 0.214_041).abs() < 1e-5);
        for i in 0..=255 {
            let c = i as f32 / 255.0;
            assert!((linear_to_srgb(srgb_to_linear(c)) - c).abs() < 1e-5);
        }
    }

    #[test]
    fn table_encoder_within_one_code() {
        let enc = SrgbEncoder::new();
        for i in 0..=10000 {
            let lin = i as f32 / 10000.0;
            let exact = (linear_to_srgb(lin) * 255.0).round() as i32;
            assert!((enc.encode(lin) as i32 - exact).abs() <= 1, "at {lin}");
        }
        assert_eq!(enc.encode(f32::NAN), 0);
        assert_eq!(enc.encode(7.0), 255);
    }
}
