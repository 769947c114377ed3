//! Wrap modes: what a texel index outside the texture reads, per axis.

/// How coordinates outside [0, 1] read the texture along one axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Wrap {
    /// Periodic: the texture tiles the plane.
    #[default]
    Repeat,
    /// The edge texel extends outwards.
    Clamp,
    /// Every other period is flipped, so the edges meet themselves.
    Mirror,
    /// Outside the texture is the border colour.
    Border,
}

impl Wrap {
    pub const NAMES: [(&'static str, Wrap); 4] =
        [("repeat", Wrap::Repeat), ("clamp", Wrap::Clamp), ("mirror", Wrap::Mirror), ("border", Wrap::Border)];

    pub fn parse(name: &str) -> Option<Wrap> {
        Wrap::NAMES.iter().find(|(n, _)| *n == name).map(|&(_, w)| w)
    }

    /// The texel that index `i` of an `n`-texel axis reads, or `None` for the border colour.
    /// Indices are rarely more than a few texels outside (coordinates are reduced to one period before);
    /// the common cases cost a compare, not a division.
    #[inline]
    pub fn resolve(self, i: isize, n: usize) -> Option<usize> {
        let n = n as isize;
        if (0..n).contains(&i) {
            return Some(i as usize);
        }
        Some(match self {
            Wrap::Repeat => {
                if i < 0 && i >= -n {
                    i + n
                } else if i >= n && i < 2 * n {
                    i - n
                } else {
                    i.rem_euclid(n)
                }
            }
            Wrap::Clamp => i.clamp(0, n - 1),
            Wrap::Mirror => {
                let k = i.rem_euclid(2 * n);
                if k < n {
                    k
                } else {
                    2 * n - 1 - k
                }
            }
            Wrap::Border => return None,
        } as usize)
    }

    /// A coordinate reduced to one period for `Repeat` (keeps indices small and f32 precise far from the
    /// origin); other modes keep the coordinate, their indices are resolved texel by texel.
    #[inline]
    pub fn reduce(self, s: f32) -> f32 {
        match self {
            Wrap::Repeat => s - s.floor(),
            _ => s,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_mode_against_its_definition() {
        let n = 4;
        let cases: [(isize, [Option<usize>; 4]); 6] = [
            (-9, [Some(3), Some(0), Some(0), None]),
            (-1, [Some(3), Some(0), Some(0), None]),
            (2, [Some(2), Some(2), Some(2), Some(2)]),
            (4, [Some(0), Some(3), Some(3), None]),
            (6, [Some(2), Some(3), Some(1), None]),
            (13, [Some(1), Some(3), Some(2), None]),
        ];
        for (i, want) in cases {
            for (mode, w) in [Wrap::Repeat, Wrap::Clamp, Wrap::Mirror, Wrap::Border].into_iter().zip(want) {
                assert_eq!(mode.resolve(i, n), w, "{mode:?} at {i}");
            }
        }
        // A one-texel axis far outside.
        assert_eq!(Wrap::Repeat.resolve(-3, 1), Some(0));
        assert_eq!(Wrap::Mirror.resolve(-3, 1), Some(0));
    }
}
