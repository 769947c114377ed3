//! The painted channels of the texture atlas. Each texel is held as the code its saved file stores (8-bit
//! sRGB colour, 16-bit height, 8-bit specular and opacity), so the textures rendered while painting are the
//! ones `wrinkle render` reads back from the saved files, and undo restores texels exactly.

use glam::Vec3;
use std::path::Path;
use std::sync::Arc;
use wrinkle::image::color::{linear_to_srgb, srgb8_decode_table};
use wrinkle::image::{io, Image};
use wrinkle::texture::EditableTexture;
use wrinkle::{BumpTable, FilteredTexture, Result, TextureOptions};

/// What a channel of the atlas paints.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Channel {
    /// The diffuse colour (a `replace` layer on kd).
    Color,
    /// Blinn's bump function F (0.5 is the surface itself).
    Height,
    /// The specular coefficient (a `replace` layer on ks).
    Specular,
    /// The coverage under the alpha test (a `replace` layer on opacity).
    Opacity,
}

impl Channel {
    pub const ALL: [Channel; 4] = [Channel::Color, Channel::Height, Channel::Specular, Channel::Opacity];

    pub fn name(self) -> &'static str {
        match self {
            Channel::Color => "color",
            Channel::Height => "height",
            Channel::Specular => "specular",
            Channel::Opacity => "opacity",
        }
    }

    pub fn parse(name: &str) -> Option<Channel> {
        Channel::ALL.into_iter().find(|c| c.name() == name)
    }

    /// The file the channel is saved to.
    pub fn file_name(self) -> String {
        format!("{}.png", self.name())
    }

    /// Whether a texel is a colour (else one value).
    pub fn is_colour(self) -> bool {
        self == Channel::Color
    }

    fn index(self) -> usize {
        self as usize
    }

    /// The texel a code stands for: linear RGB, or the value in every component.
    pub fn decode(self, code: u32) -> Vec3 {
        match self {
            Channel::Color => {
                let table = decode_table();
                let [r, g, b, _] = code.to_le_bytes();
                Vec3::new(table[r as usize], table[g as usize], table[b as usize])
            }
            Channel::Height => Vec3::splat(code as f32 / 65535.0),
            Channel::Specular | Channel::Opacity => Vec3::splat(code as f32 / 255.0),
        }
    }

    /// The code of a texel (linear RGB, or the value in x), clamped to what the channel holds.
    pub fn encode(self, value: Vec3) -> u32 {
        let quantise = |v: f32, top: f32| (v.clamp(0.0, 1.0) * top).round() as u32;
        match self {
            Channel::Color => {
                let byte = |v: f32| quantise(linear_to_srgb(v.clamp(0.0, 1.0)), 255.0) as u8;
                u32::from_le_bytes([byte(value.x), byte(value.y), byte(value.z), 255])
            }
            Channel::Height => quantise(value.x, 65535.0),
            Channel::Specular | Channel::Opacity => quantise(value.x, 255.0),
        }
    }
}

fn decode_table() -> &'static [f32; 256] {
    static TABLE: std::sync::OnceLock<[f32; 256]> = std::sync::OnceLock::new();
    TABLE.get_or_init(srgb8_decode_table)
}

/// The four channels of a square atlas, row 0 at the top (v = 1), and what each held when it was loaded
/// (the eraser's target); the image channels' textures, brought up to date where texels changed.
pub struct Atlas {
    pub size: usize,
    codes: [Vec<u32>; 4],
    loaded: [Vec<u32>; 4],
    /// Per channel: the textures of colour, specular and opacity (built on first use).
    textures: [Option<EditableTexture>; 4],
    /// The height channel as Blinn's bump table (built on first use).
    bump: Option<Arc<BumpTable>>,
    /// Per channel: the columns and rows (x0, y0, x1, y1) changed since its texture was last brought up to date.
    changed: [Option<(usize, usize, usize, usize)>; 4],
}

impl Atlas {
    /// An atlas whose channels hold `start` everywhere, but where `given` brings a channel's texels.
    pub fn new(size: usize, start: impl Fn(Channel) -> Vec3, given: Vec<(Channel, Vec<u32>)>) -> Atlas {
        let mut codes: [Vec<u32>; 4] = Channel::ALL.map(|c| vec![c.encode(start(c)); size * size]);
        for (channel, texels) in given {
            assert_eq!(texels.len(), size * size, "a channel's texels fill the atlas");
            codes[channel.index()] = texels;
        }
        Atlas { size, loaded: codes.clone(), codes, textures: Default::default(), bump: None, changed: [None; 4] }
    }

    pub fn codes(&self, channel: Channel) -> &[u32] {
        &self.codes[channel.index()]
    }

    /// Writes texel `texel`'s code.
    pub fn set(&mut self, channel: Channel, texel: u32, code: u32) {
        let c = channel.index();
        self.codes[c][texel as usize] = code;
        let (x, y) = (texel as usize % self.size, texel as usize / self.size);
        self.changed[c] = Some(match self.changed[c] {
            None => (x, y, x + 1, y + 1),
            Some((x0, y0, x1, y1)) => (x0.min(x), y0.min(y), x1.max(x + 1), y1.max(y + 1)),
        });
    }

    /// What the texel held when the atlas was loaded.
    pub fn loaded(&self, channel: Channel, texel: u32) -> u32 {
        self.loaded[channel.index()][texel as usize]
    }

    /// The colour channel as the renderer's 8-bit sRGB texture, the specular or opacity channel as a linear
    /// grey one: what a scene layer reading the saved file holds. Built once, then brought up to date only where texels changed (`EditableTexture`): a dab costs what it
    /// covers, not the atlas's size.
    pub fn texture(&mut self, channel: Channel) -> Arc<FilteredTexture> {
        let c = channel.index();
        let bytes = |code: u32| match channel {
            Channel::Color => code.to_le_bytes(),
            _ => [code as u8, code as u8, code as u8, 255],
        };
        let (size, codes) = (self.size, &self.codes[c]);
        let texel = |i: usize, row: usize| bytes(codes[row * size + i]);
        match (&mut self.textures[c], self.changed[c].take()) {
            (Some(texture), Some(region)) => texture.update(region, texel),
            (Some(_), None) => {}
            (none, _) => {
                let pixels: Vec<[u8; 4]> = codes.iter().map(|&code| bytes(code)).collect();
                let image = Image { width: size, height: size, pixels };
                let built = EditableTexture::new(&image, channel.is_colour(), TextureOptions::default());
                *none = Some(built.expect("the atlas's channels are opaque"));
            }
        }
        Arc::new(self.textures[c].as_ref().expect("built above").texture())
    }

    /// The height channel as Blinn's bump table (value / 65535, as a 16-bit height file reads).
    /// Built once, then brought up to date where heights changed (in place while no material holds it).
    pub fn bump_table(&mut self) -> Arc<BumpTable> {
        let c = Channel::Height.index();
        let (size, codes) = (self.size, &self.codes[c]);
        let height = |code: u32| code as f32 / 65535.0;
        let whole = || {
            let pixels = codes.iter().map(|&code| height(code)).collect();
            Arc::new(BumpTable::new(&Image { width: size, height: size, pixels }))
        };
        match (&mut self.bump, self.changed[c].take()) {
            (Some(table), Some(region)) => match Arc::get_mut(table) {
                Some(t) => t.update(region, |i, row| height(codes[row * size + i])),
                None => *table = whole(),
            },
            (Some(_), None) => {}
            (none, _) => *none = Some(whole()),
        }
        self.bump.clone().expect("built above")
    }

    /// The channel's file as PNG bytes: colour 8-bit sRGB RGB, height 16-bit grey, specular and opacity 8-bit
    /// grey.
    pub fn png(&self, channel: Channel) -> Result<Vec<u8>> {
        let (size, codes) = (self.size, self.codes(channel));
        let name = Path::new(channel.name());
        let mut out = Vec::new();
        match channel {
            Channel::Color => {
                let rgb: Vec<u8> = codes.iter().flat_map(|c| c.to_le_bytes().into_iter().take(3)).collect();
                io::encode_png8(&mut out, name, (size, size), 3, &rgb)?;
            }
            Channel::Height => {
                let samples: Vec<u16> = codes.iter().map(|&c| c as u16).collect();
                io::encode_png16(&mut out, name, (size, size), 1, &samples)?;
            }
            _ => {
                let grey: Vec<u8> = codes.iter().map(|&c| c as u8).collect();
                io::encode_png8(&mut out, name, (size, size), 1, &grey)?;
            }
        }
        Ok(out)
    }
}

/// A saved channel's file read back as codes at `size` x `size` (nearest texel where its size differs).
pub fn read_channel(channel: Channel, path: &Path, size: usize) -> Result<Vec<u32>> {
    let (width, height, codes): (usize, usize, Vec<u32>) = match channel {
        Channel::Color => {
            let image = io::load_rgba8(path)?;
            let codes = image.pixels.iter().map(|&[r, g, b, _]| u32::from_le_bytes([r, g, b, 255])).collect();
            (image.width, image.height, codes)
        }
        _ => {
            let top = if channel == Channel::Height { 65535.0 } else { 255.0 };
            let image = io::load_grey(path)?;
            let codes = image.pixels.iter().map(|&v| (v.clamp(0.0, 1.0) * top).round() as u32).collect();
            (image.width, image.height, codes)
        }
    };
    if (width, height) == (size, size) {
        return Ok(codes);
    }
    Ok((0..size * size)
        .map(|k| {
            let (col, row) = (k % size, k / size);
            codes[(row * height / size) * width + col * width / size]
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_round_trip() {
        for channel in Channel::ALL {
            for code in [0u32, 1, 77, 128, 254, 255] {
                let code = if channel.is_colour() { u32::from_le_bytes([code as u8, 3, 250, 255]) } else { code };
                assert_eq!(channel.encode(channel.decode(code)), code, "{channel:?} {code}");
            }
        }
        assert_eq!(Channel::Height.encode(Vec3::splat(0.5)), 32768);
        assert_eq!(Channel::parse("opacity"), Some(Channel::Opacity));
        assert_eq!(Channel::parse("alpha"), None);
    }
}
