//! The reference every filter is measured against: the integral of the bilinearly reconstructed texture
//! over the pixel's preimage, by many stratified samples. Here the preimage is the footprint's
//! parallelogram (the pixel mapped through the derivatives); callers that know the exact mapping (a ray
//! intersection per sample) integrate with [`integrate`] and exact coordinates instead.

use super::reconstruct::{bilinear, Addressing};
use super::texel::TexelSource;
use super::Footprint;

/// The mean of `sample` at the centres of an `n` x `n` grid of strata over the unit pixel, offsets in
/// [-0.5, 0.5]^2 from its centre.
#[inline]
pub fn integrate<T: super::texel::Texel>(n: usize, mut sample: impl FnMut(f32, f32) -> T) -> T {
    let step = 1.0 / n as f32;
    let mut sum = T::default();
    for b in 0..n {
        let oy = (b as f32 + 0.5) * step - 0.5;
        let mut row = T::default();
        for a in 0..n {
            row = row + sample((a as f32 + 0.5) * step - 0.5, oy);
        }
        sum = sum + row;
    }
    sum * (step * step)
}

/// The bilinear texture integrated over the footprint's parallelogram centred at (s, t), `n` x `n` samples.
pub fn sample<S: TexelSource>(
    level0: &S,
    addr: &Addressing<S::Texel>,
    s: f32,
    t: f32,
    fp: &Footprint,
    n: usize,
) -> S::Texel {
    integrate(n, |ox, oy| bilinear(level0, addr, s + fp.dudx * ox + fp.dudy * oy, t + fp.dvdx * ox + fp.dvdy * oy))
}
