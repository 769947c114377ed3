//! The pixel's footprint in texture space: the screen derivatives of (u,v).

use crate::lanes::{F8, LANES};

/// du/dx, dv/dx, du/dy, dv/dy: how far (u,v) moves across one pixel step in x and in y.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Footprint {
    pub dudx: f32,
    pub dvdx: f32,
    pub dudy: f32,
    pub dvdy: f32,
}

impl Footprint {
    /// The MIP level of a `width` x `height` table: log2 of the longer of the two pixel axes, in texels
    /// (Williams 1983); 0 when the pixel covers less than one texel.
    pub fn mip_level(&self, width: usize, height: usize) -> f32 {
        mip_level_of(self.longer_axis_squared(width, height))
    }

    /// The square of the longer pixel axis in texels of a `width` x `height` table.
    #[inline]
    pub fn longer_axis_squared(&self, width: usize, height: usize) -> f32 {
        // Through u32 (sizes are far below 2^32): one conversion instruction; from usize it takes a branch.
        let (w, h) = (width as u32 as f32, height as u32 as f32);
        let (ux, vx, uy, vy) = (self.dudx * w, self.dvdx * h, self.dudy * w, self.dvdy * h);
        (ux * ux + vx * vx).max(uy * uy + vy * vy)
    }

    /// The MIP level from the pixel's area instead (the slides' alternative): log2 of the square root of
    /// the area of the parallelogram the pixel covers, in texels; 0 below one texel.
    pub fn mip_level_area(&self, width: usize, height: usize) -> f32 {
        let area = ((self.dudx * self.dvdy - self.dudy * self.dvdx) * (width * height) as f32).abs();
        if area > 1.0 {
            0.5 * area.log2()
        } else {
            0.0
        }
    }

    /// The footprint with both axes `k` times as long.
    #[inline]
    pub fn scaled(&self, k: f32) -> Footprint {
        Footprint { dudx: self.dudx * k, dvdx: self.dvdx * k, dudy: self.dudy * k, dvdy: self.dvdy * k }
    }

    /// The footprint measured in texels of a `width` x `height` level: (du/dx, dv/dx, du/dy, dv/dy) * size.
    #[inline]
    pub fn in_texels(&self, width: usize, height: usize) -> [f32; 4] {
        let (w, h) = (width as f32, height as f32);
        [self.dudx * w, self.dvdx * h, self.dudy * w, self.dvdy * h]
    }
}

/// `Footprint::mip_level` from the square of the longer axis in texels: log2 of the axis, from its square
/// (no square root, no hypot call); 0 below one texel.
#[inline]
pub fn mip_level_of(len2: f32) -> f32 {
    if len2 > 1.0 {
        0.5 * len2.log2()
    } else {
        0.0
    }
}

/// floor(log2(x)) for x above 1, read from the exponent's bits (a normal number or infinity: 0 to 128), where
/// the MIP levels' log2 need not be waited for; 0 at or below 1 and for NaN.
#[inline]
pub fn floor_log2_above_one(x: f32) -> u32 {
    if x > 1.0 {
        (x.to_bits() >> 23) - 127
    } else {
        0
    }
}

/// Eight footprints as lanes (structure of arrays): what the rasterizer interpolates and the lane filters read.
#[derive(Clone, Copy, Debug)]
pub struct Footprint8 {
    pub dudx: F8,
    pub dvdx: F8,
    pub dudy: F8,
    pub dvdy: F8,
}

impl Footprint8 {
    pub fn from_lanes(f: &[Footprint; LANES]) -> Footprint8 {
        let lane = |get: fn(&Footprint) -> f32| F8::new(f.map(|p| get(&p)));
        Footprint8 { dudx: lane(|p| p.dudx), dvdx: lane(|p| p.dvdx), dudy: lane(|p| p.dudy), dvdy: lane(|p| p.dvdy) }
    }

    /// The footprints with both axes `k` times as long.
    #[inline]
    pub fn scaled(&self, k: f32) -> Footprint8 {
        let k = F8::splat(k);
        Footprint8 { dudx: self.dudx * k, dvdx: self.dvdx * k, dudy: self.dudy * k, dvdy: self.dvdy * k }
    }

    /// The footprint of lane `i`.
    #[inline]
    pub fn lane(&self, i: usize) -> Footprint {
        let at = |x: F8| x.as_array_ref()[i];
        Footprint { dudx: at(self.dudx), dvdx: at(self.dvdx), dudy: at(self.dudy), dvdy: at(self.dvdy) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mip_level_is_log2_of_longest_axis_in_texels() {
        let fp = Footprint { dudx: 4.0 / 256.0, dvdx: 0.0, dudy: 0.0, dvdy: 1.0 / 256.0 };
        assert!((fp.mip_level(256, 256) - 2.0).abs() < 1e-6);
        assert_eq!(fp.mip_level(16, 16), 0.0);
        let twice = Footprint { dudx: 2.0 * fp.dudx, ..fp };
        assert!((twice.mip_level(256, 256) - 3.0).abs() < 1e-6);
        // The area rule: 4 x 1 texels is an area of 4, a level of log2(sqrt(4)) = 1.
        assert!((fp.mip_level_area(256, 256) - 1.0).abs() < 1e-6);
        assert_eq!(fp.mip_level_area(16, 16), 0.0);
    }
}
