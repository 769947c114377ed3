//! The pixel's footprint in texture space: the screen derivatives of (u,v).

/// du/dx, dv/dx, du/dy, dv/dy: how far (u,v) moves across one pixel step in x and in y.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Footprint {
    pub dudx: f32,
    pub dvdx: f32,
    pub dudy: f32,
    pub dvdy: f32,
}

impl Footprint {
    /// The footprint of a texture replicated `ru` x `rv` times: u' = ru u, v' = rv v.
    pub fn replicated(&self, ru: f32, rv: f32) -> Footprint {
        Footprint { dudx: self.dudx * ru, dvdx: self.dvdx * rv, dudy: self.dudy * ru, dvdy: self.dvdy * rv }
    }

    /// The MIP level of a `width` x `height` table: log2 of the longer of the two pixel axes, in texels
    /// (Williams 1983); 0 when the pixel covers less than one texel.
    pub fn mip_level(&self, width: usize, height: usize) -> f32 {
        let (w, h) = (width as f32, height as f32);
        let lx = (self.dudx * w).hypot(self.dvdx * h);
        let ly = (self.dudy * w).hypot(self.dvdy * h);
        let len = lx.max(ly);
        if len > 1.0 {
            len.log2()
        } else {
            0.0
        }
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
        let r = fp.replicated(2.0, 1.0);
        assert!((r.mip_level(256, 256) - 3.0).abs() < 1e-6);
    }
}
