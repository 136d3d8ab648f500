//! One 8-lane `f32` vector, [`F32x8`], and its comparison mask, [`Mask8`]: the type the
//! data-parallel kernels (the BVH node's slab test, the photon grid's distance scan and the
//! density estimate's block sum) are written over, once.
//!
//! Where the build has AVX (`target_feature = "avx"`, which the workspace's x86-64-v3 default
//! enables) a vector is one `__m256` and every operation one instruction. Elsewhere it is a
//! plain `[f32; 8]` and every operation a loop over the lanes. The two agree bit for bit,
//! because each portable operation is defined as the instruction's own semantics:
//!
//! - `+`, `-`, `*`, `/` are the IEEE-754 operations, rounded to nearest, never fused (a NaN
//!   result is NaN in both, its sign and payload unspecified, as in scalar Rust);
//! - [`F32x8::min`] is `a < b ? a : b` and [`F32x8::max`] is `a > b ? a : b`, as `minps` /
//!   `maxps` (so a NaN in either operand returns the second one, and `min(-0, +0)` is `+0`);
//! - the comparisons are ordered and quiet (false when either lane is NaN), like Rust's `<`.
//!
//! The tests check every operation of the build in use against that scalar definition, on
//! ordinary values, signed zeros, infinities and NaN. The vector is private to the crate: it
//! is the kernels' building block, not part of the renderer's interface.

use std::ops::{Add, BitAnd, Div, Mul, Sub};

/// Lanes in a vector.
pub(crate) const LANES: usize = 8;

#[cfg(all(target_arch = "x86_64", target_feature = "avx"))]
use std::arch::x86_64::*;

/// Eight `f32` lanes (an AVX register where the build has AVX).
#[derive(Clone, Copy, Debug)]
pub(crate) struct F32x8(
    #[cfg(all(target_arch = "x86_64", target_feature = "avx"))] __m256,
    #[cfg(not(all(target_arch = "x86_64", target_feature = "avx")))] [f32; LANES],
);

/// The lane-wise result of a comparison of two [`F32x8`]: each lane true or false.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Mask8(
    /// AVX: all bits set in a true lane, none in a false one (what `vcmpps` returns).
    #[cfg(all(target_arch = "x86_64", target_feature = "avx"))]
    __m256,
    #[cfg(not(all(target_arch = "x86_64", target_feature = "avx")))] [bool; LANES],
);

#[cfg(all(target_arch = "x86_64", target_feature = "avx"))]
impl F32x8 {
    /// All lanes `x`.
    #[inline(always)]
    pub(crate) fn splat(x: f32) -> Self {
        // SAFETY: AVX is enabled for the whole build (cfg on this impl); no memory access.
        F32x8(unsafe { _mm256_set1_ps(x) })
    }

    /// The lanes `a[0], ..., a[7]`.
    #[inline(always)]
    pub(crate) fn from_array(a: &[f32; LANES]) -> Self {
        // SAFETY: AVX is enabled (cfg on this impl); the unaligned load reads exactly the
        // 32 bytes of `a`, which the reference keeps valid.
        F32x8(unsafe { _mm256_loadu_ps(a.as_ptr()) })
    }

    /// The lanes as an array, lane 0 first.
    #[inline(always)]
    pub(crate) fn to_array(self) -> [f32; LANES] {
        let mut a = [0.0; LANES];
        // SAFETY: AVX is enabled (cfg on this impl); the unaligned store writes exactly the
        // 32 bytes of the local array `a`.
        unsafe { _mm256_storeu_ps(a.as_mut_ptr(), self.0) };
        a
    }

    /// Lane-wise `self < other ? self : other` (`vminps`).
    #[inline(always)]
    pub(crate) fn min(self, other: Self) -> Self {
        // SAFETY: AVX is enabled (cfg on this impl); no memory access.
        F32x8(unsafe { _mm256_min_ps(self.0, other.0) })
    }

    /// Lane-wise `self > other ? self : other` (`vmaxps`).
    #[inline(always)]
    pub(crate) fn max(self, other: Self) -> Self {
        // SAFETY: AVX is enabled (cfg on this impl); no memory access.
        F32x8(unsafe { _mm256_max_ps(self.0, other.0) })
    }

    /// Lane-wise `self < other` (ordered, quiet: false for NaN).
    #[inline(always)]
    pub(crate) fn lt(self, other: Self) -> Mask8 {
        // SAFETY: AVX is enabled (cfg on this impl); no memory access.
        Mask8(unsafe { _mm256_cmp_ps::<_CMP_LT_OQ>(self.0, other.0) })
    }

    /// Lane-wise `self <= other` (ordered, quiet: false for NaN).
    #[inline(always)]
    pub(crate) fn le(self, other: Self) -> Mask8 {
        // SAFETY: AVX is enabled (cfg on this impl); no memory access.
        Mask8(unsafe { _mm256_cmp_ps::<_CMP_LE_OQ>(self.0, other.0) })
    }

    /// Lane-wise `self > other` (ordered, quiet: false for NaN).
    #[inline(always)]
    pub(crate) fn gt(self, other: Self) -> Mask8 {
        // SAFETY: AVX is enabled (cfg on this impl); no memory access.
        Mask8(unsafe { _mm256_cmp_ps::<_CMP_GT_OQ>(self.0, other.0) })
    }
}

#[cfg(all(target_arch = "x86_64", target_feature = "avx"))]
impl Mask8 {
    /// Bit k set when lane k is true (`vmovmskps`).
    #[inline(always)]
    pub(crate) fn bits(self) -> u32 {
        // SAFETY: AVX is enabled (cfg on this impl); no memory access.
        unsafe { _mm256_movemask_ps(self.0) as u32 }
    }

    /// `v` in the true lanes and `+0.0` in the false ones (a bitwise and with the mask, so a
    /// NaN or infinity in a false lane is dropped, not multiplied by zero).
    #[inline(always)]
    pub(crate) fn select_or_zero(self, v: F32x8) -> F32x8 {
        // SAFETY: AVX is enabled (cfg on this impl); no memory access.
        F32x8(unsafe { _mm256_and_ps(self.0, v.0) })
    }
}

#[cfg(all(target_arch = "x86_64", target_feature = "avx"))]
impl BitAnd for Mask8 {
    type Output = Mask8;
    #[inline(always)]
    fn bitand(self, other: Mask8) -> Mask8 {
        // SAFETY: AVX is enabled (cfg on this impl); no memory access.
        Mask8(unsafe { _mm256_and_ps(self.0, other.0) })
    }
}

/// `impl $op for F32x8` with the AVX intrinsic or the scalar operator, lane by lane.
macro_rules! arithmetic {
    ($op:ident, $method:ident, $intrinsic:ident, $scalar:tt) => {
        impl $op for F32x8 {
            type Output = F32x8;
            #[inline(always)]
            fn $method(self, other: F32x8) -> F32x8 {
                #[cfg(all(target_arch = "x86_64", target_feature = "avx"))]
                {
                    // SAFETY: AVX is enabled for the whole build (cfg); no memory access.
                    F32x8(unsafe { $intrinsic(self.0, other.0) })
                }
                #[cfg(not(all(target_arch = "x86_64", target_feature = "avx")))]
                {
                    F32x8(std::array::from_fn(|k| self.0[k] $scalar other.0[k]))
                }
            }
        }
    };
}

arithmetic!(Add, add, _mm256_add_ps, +);
arithmetic!(Sub, sub, _mm256_sub_ps, -);
arithmetic!(Mul, mul, _mm256_mul_ps, *);
arithmetic!(Div, div, _mm256_div_ps, /);

#[cfg(not(all(target_arch = "x86_64", target_feature = "avx")))]
impl F32x8 {
    /// All lanes `x`.
    #[inline(always)]
    pub(crate) fn splat(x: f32) -> Self {
        F32x8([x; LANES])
    }

    /// The lanes `a[0], ..., a[7]`.
    #[inline(always)]
    pub(crate) fn from_array(a: &[f32; LANES]) -> Self {
        F32x8(*a)
    }

    /// The lanes as an array, lane 0 first.
    #[inline(always)]
    pub(crate) fn to_array(self) -> [f32; LANES] {
        self.0
    }

    /// Lane-wise `self < other ? self : other` (as `minps`).
    #[inline(always)]
    pub(crate) fn min(self, other: Self) -> Self {
        F32x8(std::array::from_fn(|k| {
            let (a, b) = (self.0[k], other.0[k]);
            if a < b {
                a
            } else {
                b
            }
        }))
    }

    /// Lane-wise `self > other ? self : other` (as `maxps`).
    #[inline(always)]
    pub(crate) fn max(self, other: Self) -> Self {
        F32x8(std::array::from_fn(|k| {
            let (a, b) = (self.0[k], other.0[k]);
            if a > b {
                a
            } else {
                b
            }
        }))
    }

    /// Lane-wise `self < other` (false for NaN).
    #[inline(always)]
    pub(crate) fn lt(self, other: Self) -> Mask8 {
        Mask8(std::array::from_fn(|k| self.0[k] < other.0[k]))
    }

    /// Lane-wise `self <= other` (false for NaN).
    #[inline(always)]
    pub(crate) fn le(self, other: Self) -> Mask8 {
        Mask8(std::array::from_fn(|k| self.0[k] <= other.0[k]))
    }

    /// Lane-wise `self > other` (false for NaN).
    #[inline(always)]
    pub(crate) fn gt(self, other: Self) -> Mask8 {
        Mask8(std::array::from_fn(|k| self.0[k] > other.0[k]))
    }
}

#[cfg(not(all(target_arch = "x86_64", target_feature = "avx")))]
impl Mask8 {
    /// Bit k set when lane k is true.
    #[inline(always)]
    pub(crate) fn bits(self) -> u32 {
        (0..LANES).fold(0, |bits, k| bits | (self.0[k] as u32) << k)
    }

    /// `v` in the true lanes and `+0.0` in the false ones (a NaN or infinity in a false lane
    /// is dropped, not multiplied by zero).
    #[inline(always)]
    pub(crate) fn select_or_zero(self, v: F32x8) -> F32x8 {
        F32x8(std::array::from_fn(
            |k| if self.0[k] { v.0[k] } else { 0.0 },
        ))
    }
}

#[cfg(not(all(target_arch = "x86_64", target_feature = "avx")))]
impl BitAnd for Mask8 {
    type Output = Mask8;
    #[inline(always)]
    fn bitand(self, other: Mask8) -> Mask8 {
        Mask8(std::array::from_fn(|k| self.0[k] & other.0[k]))
    }
}

impl F32x8 {
    /// `0.0` in every lane.
    #[inline(always)]
    pub(crate) fn zero() -> Self {
        F32x8::splat(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    /// Values that tell the semantics apart: signed zeros, infinities, NaN, subnormals,
    /// ties, and ordinary values of both signs.
    fn specials() -> Vec<f32> {
        vec![
            0.0,
            -0.0,
            1.0,
            -1.0,
            0.5,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            -f32::NAN,
            f32::MIN_POSITIVE / 4.0,
            f32::MAX,
            -f32::MAX,
            1e-30,
            3.0e7,
        ]
    }

    /// Lanes (a, b) covering every pair of specials, then random values at many scales.
    fn operand_blocks() -> Vec<([f32; LANES], [f32; LANES])> {
        let s = specials();
        let pairs: Vec<(f32, f32)> = s
            .iter()
            .flat_map(|&a| s.iter().map(move |&b| (a, b)))
            .collect();
        let mut blocks: Vec<_> = pairs
            .chunks(LANES)
            .map(|chunk| {
                let mut a = [1.0; LANES];
                let mut b = [2.0; LANES];
                for (k, &(x, y)) in chunk.iter().enumerate() {
                    (a[k], b[k]) = (x, y);
                }
                (a, b)
            })
            .collect();
        let mut rng = Rng::new(5, 0, 0);
        for trial in 0..2000 {
            let scale = [1e-20, 1e-3, 1.0, 1e4, 1e30][trial % 5];
            let mut value = || (rng.uniform() - 0.5) * scale;
            let a = std::array::from_fn(|_| value());
            let mut b: [f32; LANES] = std::array::from_fn(|_| value());
            b[trial % LANES] = a[trial % LANES]; // a tie
            blocks.push((a, b));
        }
        blocks
    }

    /// Every operation of the vector equals its scalar definition lane by lane, bit for bit:
    /// the contract that makes AVX and portable builds agree. A NaN result must be NaN in
    /// both, but its sign and payload are not compared: Rust leaves them unspecified (LLVM may
    /// swap the operands of a commutative `+` or `*`), and no result of the renderer depends
    /// on them.
    #[test]
    fn operations_match_their_scalar_definition_bit_for_bit() {
        let bits = |v: [f32; LANES]| {
            v.map(|x| {
                if x.is_nan() {
                    f32::NAN.to_bits()
                } else {
                    x.to_bits()
                }
            })
        };
        for (a, b) in operand_blocks() {
            let (va, vb) = (F32x8::from_array(&a), F32x8::from_array(&b));
            assert_eq!(bits(va.to_array()), bits(a));
            let scalar = |f: fn(f32, f32) -> f32| bits(std::array::from_fn(|k| f(a[k], b[k])));
            assert_eq!(
                bits((va + vb).to_array()),
                scalar(|x, y| x + y),
                "{a:?} {b:?}"
            );
            assert_eq!(
                bits((va - vb).to_array()),
                scalar(|x, y| x - y),
                "{a:?} {b:?}"
            );
            assert_eq!(
                bits((va * vb).to_array()),
                scalar(|x, y| x * y),
                "{a:?} {b:?}"
            );
            assert_eq!(
                bits((va / vb).to_array()),
                scalar(|x, y| x / y),
                "{a:?} {b:?}"
            );
            let min = |x: f32, y: f32| if x < y { x } else { y };
            let max = |x: f32, y: f32| if x > y { x } else { y };
            assert_eq!(bits(va.min(vb).to_array()), scalar(min), "{a:?} {b:?}");
            assert_eq!(bits(va.max(vb).to_array()), scalar(max), "{a:?} {b:?}");
            let mask = |f: fn(f32, f32) -> bool| {
                (0..LANES).fold(0u32, |m, k| m | (f(a[k], b[k]) as u32) << k)
            };
            assert_eq!(va.lt(vb).bits(), mask(|x, y| x < y), "{a:?} {b:?}");
            assert_eq!(va.le(vb).bits(), mask(|x, y| x <= y), "{a:?} {b:?}");
            assert_eq!(va.gt(vb).bits(), mask(|x, y| x > y), "{a:?} {b:?}");
            let both = va.le(vb) & va.gt(F32x8::zero());
            assert_eq!(both.bits(), mask(|x, y| x <= y && x > 0.0), "{a:?} {b:?}");
            let selected = va.lt(vb).select_or_zero(vb);
            let expected = std::array::from_fn(|k| if a[k] < b[k] { b[k] } else { 0.0 });
            assert_eq!(bits(selected.to_array()), bits(expected), "{a:?} {b:?}");
        }
        assert_eq!(bits(F32x8::splat(-0.0).to_array()), bits([-0.0; LANES]));
        assert_eq!(bits(F32x8::zero().to_array()), bits([0.0; LANES]));
    }
}
