//! Sums of contributions splatted into arbitrary pixels during a pass (light-tracing
//! connections to the camera), in the film's exact fixed-point units.

use super::{addable, from_fixed, saturating_add_fixed, to_fixed};
use glam::Vec3;

/// Per-pixel sums of contributions that land in arbitrary pixels during a pass (light paths
/// connected to the camera), in the film's exact fixed-point units: integer sums do not depend
/// on the order of the additions, so the buffer's value is the same whichever thread splatted
/// what, and buffers filled separately join by addition ([`SplatBuffer::join`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SplatBuffer {
    sum: Vec<[u128; 3]>,
    /// Contributions dropped as NaN, infinite or negative.
    rejected: u64,
}

impl SplatBuffer {
    /// `pixels` empty sums.
    pub fn new(pixels: usize) -> Self {
        SplatBuffer {
            sum: vec![[0; 3]; pixels],
            rejected: 0,
        }
    }

    /// Empties every sum (the allocation is kept).
    pub fn clear(&mut self) {
        self.sum.fill([0; 3]);
        self.rejected = 0;
    }

    /// Adds `value` to pixel `pixel`; a NaN, infinite or negative value, or one above
    /// [`MAX_ESTIMATE`](super::MAX_ESTIMATE), is dropped and counted.
    #[inline]
    pub fn add(&mut self, pixel: usize, value: Vec3) {
        if addable(value) {
            for (c, v) in self.sum[pixel].iter_mut().zip(value.to_array()) {
                *c = saturating_add_fixed(*c, to_fixed(v));
            }
        } else {
            self.rejected += 1;
        }
    }

    /// Adds every sum of `other` (of the same size) to this one's.
    pub fn join(&mut self, other: &SplatBuffer) {
        for (s, t) in self.sum.iter_mut().zip(&other.sum) {
            for (a, b) in s.iter_mut().zip(t) {
                *a = saturating_add_fixed(*a, *b);
            }
        }
        self.rejected += other.rejected;
    }

    /// The sum at `pixel`, rounded to f32.
    #[inline]
    pub fn value(&self, pixel: usize) -> Vec3 {
        let s = &self.sum[pixel];
        Vec3::new(
            from_fixed(s[0]) as f32,
            from_fixed(s[1]) as f32,
            from_fixed(s[2]) as f32,
        )
    }

    /// Contributions dropped so far.
    pub fn rejected(&self) -> u64 {
        self.rejected
    }

    /// Bytes held by the sums.
    pub fn memory_bytes(&self) -> usize {
        self.sum.len() * std::mem::size_of::<[u128; 3]>()
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::values;
    use super::*;

    /// Splats summed in any order and in any grouping give the same buffer, bit for bit.
    #[test]
    fn splats_do_not_depend_on_their_order() {
        let v = values(11, 300);
        let mut forward = SplatBuffer::new(4);
        for (i, e) in v.iter().enumerate() {
            forward.add(i % 4, *e);
        }
        let (mut a, mut b) = (SplatBuffer::new(4), SplatBuffer::new(4));
        for (i, e) in v.iter().enumerate().rev() {
            if i % 3 == 0 {
                a.add(i % 4, *e)
            } else {
                b.add(i % 4, *e)
            }
        }
        b.add(0, Vec3::splat(f32::NAN));
        a.join(&b);
        assert_eq!(a.sum, forward.sum);
        assert_eq!(a.rejected(), 1);
        assert!(a.value(1).max_element() > 0.0);
    }
}
