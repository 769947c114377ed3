//! Perlin's density modulation functions (the slides, after Perlin and Hoffert 1989).
//!
//! bias(b, t) = t^(ln b / ln 0.5) bends [0, 1] up or down with bias(b, 0) = 0, bias(b, 1/2) = b,
//! bias(b, 1) = 1. gain(g, t) is a spline of two bias curves that sets how fast the middle of a soft
//! region rises: gain(g, 1/4) = (1 - g)/2, gain(g, 1/2) = 1/2, gain(g, 3/4) = (1 + g)/2.
//! The slides print the first branch of gain without its "/ 2"; with it the identities above hold, as in
//! Perlin's own definition. Both are evaluated in f64 and rounded once, so the identities hold exactly in f32.

/// bias(b, t) = t^(ln b / ln 0.5), for b in (0, 1) and t in [0, 1] (t is clamped).
#[inline]
pub fn bias(b: f32, t: f32) -> f32 {
    bias64(b as f64, t as f64) as f32
}

/// gain(g, t): bias(1 - g, 2t) / 2 below t = 1/2, 1 - bias(1 - g, 2 - 2t) / 2 above.
#[inline]
pub fn gain(g: f32, t: f32) -> f32 {
    let (g, t) = (g as f64, (t as f64).clamp(0.0, 1.0));
    let b = 1.0 - g;
    (if t < 0.5 { bias64(b, 2.0 * t) / 2.0 } else { 1.0 - bias64(b, 2.0 - 2.0 * t) / 2.0 }) as f32
}

fn bias64(b: f64, t: f64) -> f64 {
    // ln b / ln 0.5 = -log2 b.
    t.clamp(0.0, 1.0).powf(-b.log2())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn values() -> impl Iterator<Item = f32> {
        (1..200).map(|i| i as f32 / 200.0)
    }

    #[test]
    fn bias_identities_hold_exactly() {
        for b in values() {
            assert_eq!(bias(b, 0.0), 0.0);
            assert_eq!(bias(b, 0.5), b, "b = {b}");
            assert_eq!(bias(b, 1.0), 1.0);
        }
        // The published curves: b = 0.25 bends down, b = 0.75 bends up.
        assert!(bias(0.25, 0.3) < 0.3 && bias(0.75, 0.3) > 0.3);
        assert_eq!(bias(0.5, 0.37), 0.37);
    }

    #[test]
    fn gain_identities_hold_exactly() {
        for g in values() {
            assert_eq!(gain(g, 0.0), 0.0);
            assert_eq!(gain(g, 0.25), ((1.0 - g as f64) / 2.0) as f32, "g = {g}");
            assert_eq!(gain(g, 0.5), 0.5);
            assert_eq!(gain(g, 0.75), ((1.0 + g as f64) / 2.0) as f32, "g = {g}");
            assert_eq!(gain(g, 1.0), 1.0);
        }
        // A higher gain rises faster through the middle.
        let slope = |g: f32| (gain(g, 0.51) - gain(g, 0.49)) / 0.02;
        assert!(slope(0.75) > 1.0 && slope(0.25) < 1.0);
    }
}
