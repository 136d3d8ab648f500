//! Accumulation of per-iteration estimates into an image (no file formats here).

use crate::StateError;
use glam::Vec3;
use rayon::prelude::*;

mod splat;
pub use splat::SplatBuffer;

/// A linear RGB image, row-major from the top-left pixel.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<Vec3>,
}

impl Image {
    /// A black image.
    pub fn new(width: u32, height: u32) -> Self {
        Image {
            width,
            height,
            pixels: vec![Vec3::ZERO; (width * height) as usize],
        }
    }

    /// The pixel at column x, row y.
    pub fn get(&self, x: u32, y: u32) -> Vec3 {
        self.pixels[(y * self.width + x) as usize]
    }

    /// Mean over all pixels, per channel (summed in f64).
    pub fn mean(&self) -> Vec3 {
        let mut s = [0.0f64; 3];
        for p in &self.pixels {
            s[0] += p.x as f64;
            s[1] += p.y as f64;
            s[2] += p.z as f64;
        }
        let n = self.pixels.len().max(1) as f64;
        Vec3::new((s[0] / n) as f32, (s[1] / n) as f32, (s[2] / n) as f32)
    }
}

/// Fractional bits of the film's fixed-point sums: one unit is 2^-48 (3.6e-15).
///
/// Every f32 estimate of at least 2^-25 (3e-8) is a whole number of units, so it is added
/// exactly; smaller ones are rounded to the nearest unit (an absolute error below 1.8e-15).
pub const FIXED_POINT_BITS: u32 = 48;
/// 2^FIXED_POINT_BITS.
const FIXED_POINT_SCALE: f64 = (1u64 << FIXED_POINT_BITS) as f64;
/// The largest estimate the film adds: 2^56 (7.2e16, far beyond the radiance of any
/// physical scene); larger ones are rejected like NaN (dropped and counted, never silently
/// clamped). 2^24 iterations of estimates this large still fit in a u128 sum
/// (2^(56 + 48 + 24) = 2^128); beyond that the sum saturates at u128::MAX.
pub const MAX_ESTIMATE: f64 = (1u64 << 56) as f64;

/// True if the film adds `e`: every channel finite, non-negative and at most
/// [`MAX_ESTIMATE`]. Any other estimate is rejected (dropped and counted).
#[inline]
fn addable(e: Vec3) -> bool {
    e.is_finite() && e.min_element() >= 0.0 && e.max_element() as f64 <= MAX_ESTIMATE
}

/// An estimate as a whole number of 2^-48 units (`e` finite and >= 0), clamped at
/// [`MAX_ESTIMATE`]: e * 2^48 is exact in f64 (24 significant bits shifted), so only the
/// rounding of values below 2^-25 loses anything.
/// Values below 2^63 units (estimates below 2^15) take the one-instruction f64-to-i64
/// conversion; only larger ones the longer conversions to u64 or u128 (the same value
/// whichever converts it).
#[inline]
fn to_fixed(e: f32) -> u128 {
    const I64_RANGE: f64 = 9_223_372_036_854_775_808.0; // 2^63
    const U64_RANGE: f64 = 18_446_744_073_709_551_616.0; // 2^64
    let units = ((e as f64).min(MAX_ESTIMATE) * FIXED_POINT_SCALE).round();
    if units < I64_RANGE {
        units as i64 as u64 as u128
    } else if units < U64_RANGE {
        units as u64 as u128
    } else {
        units as u128
    }
}

/// Estimates below 2^15 are below 2^63 units: [`to_fixed_small`] converts them.
const SMALL_ESTIMATE: f32 = 32768.0;
/// The bits of [`SMALL_ESTIMATE`]: an f32 whose bits, read as an unsigned integer, are below
/// these is in [+0, 2^15) (negative values, -0, infinities and NaN all have larger patterns).
const SMALL_ESTIMATE_BITS: u32 = SMALL_ESTIMATE.to_bits();

/// [`to_fixed`] of an estimate in [-0, [`SMALL_ESTIMATE`]), the same value in fewer
/// instructions: no clamp, and rounding half away from zero as truncation after adding 1/2.
///
/// x = e 2^48 is exact, and the truncation of the computed x + 0.5 is round(x) for every f32 e
/// in range: x has at most 24 significant bits, so x + 0.5 is exact unless x < 2^-6 (its
/// lowest bit below 2^-29; then x + 0.5 rounds into [0.5, 0.52], truncated to 0 = round(x))
/// or x >= 2^52 (a whole number whose lowest bit is at least 2^29; 0.5 is then at most half
/// an ulp and rounds back to x, ties to even x). At most x + 0.5 = 2^63 - 2^39.
///
/// # Safety
/// `e` must be in [-0, [`SMALL_ESTIMATE`]): the truncation is unchecked (no saturation, no
/// NaN test), which needs a finite value in (-1, 2^63).
#[inline]
unsafe fn to_fixed_small(e: f32) -> u128 {
    let units = (e as f64) * FIXED_POINT_SCALE + 0.5;
    // SAFETY: by the caller's contract units is finite and in [0.5, 2^63 - 2^39] (above).
    unsafe { units.to_int_unchecked::<i64>() as u64 as u128 }
}

/// `sum + units`, saturating at u128::MAX (the same as `u128::saturating_add`, written as a
/// mask so that it compiles to add, add-with-carry and two ORs, without a branch).
#[inline]
fn saturating_add_fixed(sum: u128, units: u128) -> u128 {
    let (total, overflow) = sum.overflowing_add(units);
    total | 0u128.wrapping_sub(overflow as u128)
}

/// A fixed-point sum as a value: the sum correctly rounded to f64 (the value of `sum as
/// f64`), then scaled by a power of two (exact), without the software u128 conversion.
/// Sums below 2^64 convert as u64. A larger one keeps its top 64 bits, the lowest of them
/// ORed with every bit shifted out (a sticky bit: f64 keeps 53 of the 64, so it decides
/// only whether the part rounded off is above, at or below half), converts those and scales
/// by 2^shift.
#[inline]
fn from_fixed(sum: u128) -> f64 {
    let value = match u64::try_from(sum) {
        Ok(small) => small as f64,
        Err(_) => {
            let shift = 64 - sum.leading_zeros();
            let dropped = sum & ((1u128 << shift) - 1);
            let top = (sum >> shift) as u64 | (dropped != 0) as u64;
            top as f64 * f64::from_bits(((1023 + shift) as u64) << 52)
        }
    };
    value / FIXED_POINT_SCALE
}

/// The running average of one estimate per pixel per iteration, over a contiguous slice of
/// iterations `first_iteration..first_iteration + iterations`.
///
/// Sums are exact fixed-point integers (u128, [`FIXED_POINT_BITS`] fractional bits), not
/// floating point: integer addition is associative, so the sum over iterations 0..N is the
/// same bit for bit whether it was accumulated in one run, resumed from a saved film, or
/// joined from slices rendered on different machines ([`Film::append`]). An f64 sum would
/// depend on the order of the additions. Saturating addition of non-negative values is
/// min(exact sum, u128::MAX) in any order, so even the saturated case stays associative.
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    pub width: u32,
    pub height: u32,
    sum: Vec<[u128; 3]>,
    /// The index of the first iteration accumulated (random streams are keyed by it).
    first_iteration: u64,
    iterations: u64,
    /// Samples dropped because they were NaN, infinite, negative or above [`MAX_ESTIMATE`].
    rejected: u64,
    /// (iteration, pixel) of the first dropped sample: random streams are keyed by them, so
    /// the offending path can be traced again in isolation.
    first_rejected: Option<(u64, u32)>,
}

/// The parts of a [`Film`], for saving it and reading it back ([`Film::from_parts`]).
#[derive(Clone, Debug, PartialEq)]
pub struct FilmParts {
    pub width: u32,
    pub height: u32,
    /// Fixed-point sums ([`FIXED_POINT_BITS`] fractional bits), row-major, R, G, B.
    pub sum: Vec<[u128; 3]>,
    pub first_iteration: u64,
    pub iterations: u64,
    pub rejected: u64,
    pub first_rejected: Option<(u64, u32)>,
}

impl Film {
    /// An empty film.
    pub fn new(width: u32, height: u32) -> Self {
        Film::starting_at(width, height, 0)
    }

    /// An empty film whose first iteration will be `first_iteration` (a shard of a render).
    pub fn starting_at(width: u32, height: u32, first_iteration: u64) -> Self {
        Film {
            width,
            height,
            sum: vec![[0; 3]; (width * height) as usize],
            first_iteration,
            iterations: 0,
            rejected: 0,
            first_rejected: None,
        }
    }

    /// A film from saved parts; the sums must hold one entry per pixel.
    pub fn from_parts(parts: FilmParts) -> Result<Self, StateError> {
        let expected = parts.width as usize * parts.height as usize;
        if parts.sum.len() != expected {
            return Err(StateError::Length {
                what: "film".into(),
                got: parts.sum.len(),
                expected,
            });
        }
        Ok(Film {
            width: parts.width,
            height: parts.height,
            sum: parts.sum,
            first_iteration: parts.first_iteration,
            iterations: parts.iterations,
            rejected: parts.rejected,
            first_rejected: parts.first_rejected,
        })
    }

    /// The film's parts, for saving.
    pub fn to_parts(&self) -> FilmParts {
        FilmParts {
            width: self.width,
            height: self.height,
            sum: self.sum.clone(),
            first_iteration: self.first_iteration,
            iterations: self.iterations,
            rejected: self.rejected,
            first_rejected: self.first_rejected,
        }
    }

    /// The fixed-point sums ([`FIXED_POINT_BITS`] fractional bits), row-major, R, G, B: what
    /// [`Film::to_parts`] copies, borrowed (for writing them out).
    pub fn sums(&self) -> &[[u128; 3]] {
        &self.sum
    }

    /// Adds one iteration: one estimate per pixel, row-major. Non-finite or negative estimates,
    /// and those above [`MAX_ESTIMATE`], are dropped (counted in [`Film::rejected`]) and count
    /// as zero.
    pub fn add_iteration(&mut self, estimates: &[Vec3]) {
        /// Pixels per parallel work item.
        const CHUNK: usize = 4096;
        assert_eq!(estimates.len(), self.sum.len());
        let iteration = self.next_iteration();
        // Each chunk counts its rejected estimates and its first one; chunks are reduced in
        // pixel order, so the first rejected pixel is the same at any thread count.
        let (rejected, first) = self
            .sum
            .par_chunks_mut(CHUNK)
            .zip(estimates.par_chunks(CHUNK))
            .enumerate()
            .map(|(chunk, (sums, estimates))| {
                let mut rejected = 0u64;
                let mut first = None;
                for (i, (s, e)) in sums.iter_mut().zip(estimates).enumerate() {
                    // Most estimates are in [+0, 2^15) in every channel: one integer test of
                    // the largest bit pattern for the pixel, then no branch per channel.
                    let bits = e.to_array().map(f32::to_bits);
                    if bits[0].max(bits[1]).max(bits[2]) < SMALL_ESTIMATE_BITS {
                        for (c, b) in s.iter_mut().zip(bits) {
                            // SAFETY: every channel is in [+0, 2^15) (the test above).
                            let units = unsafe { to_fixed_small(f32::from_bits(b)) };
                            *c = saturating_add_fixed(*c, units);
                        }
                    } else if addable(*e) {
                        for (c, v) in s.iter_mut().zip(e.to_array()) {
                            *c = saturating_add_fixed(*c, to_fixed(v));
                        }
                    } else {
                        rejected += 1;
                        first.get_or_insert((chunk * CHUNK + i) as u32);
                    }
                }
                (rejected, first)
            })
            .reduce(|| (0, None), |(ra, fa), (rb, fb)| (ra + rb, fa.or(fb)));
        self.rejected += rejected;
        if let Some(pixel) = first {
            self.first_rejected.get_or_insert((iteration, pixel));
        }
        self.iterations += 1;
    }

    /// Joins the slice of iterations that follows this one: afterwards the film holds both,
    /// bit for bit what one film accumulating all of them would hold.
    pub fn append(&mut self, later: &Film) -> Result<(), StateError> {
        if (later.width, later.height) != (self.width, self.height) {
            return Err(StateError::Size {
                saved_width: later.width,
                saved_height: later.height,
                width: self.width,
                height: self.height,
            });
        }
        if later.first_iteration != self.next_iteration() {
            return Err(StateError::NotContiguous {
                first: self.first_iteration,
                end: self.next_iteration(),
                next_first: later.first_iteration,
                next_end: later.next_iteration(),
            });
        }
        for (s, t) in self.sum.iter_mut().zip(&later.sum) {
            for (a, b) in s.iter_mut().zip(t) {
                *a = a.saturating_add(*b);
            }
        }
        self.iterations += later.iterations;
        self.rejected += later.rejected;
        // This slice's iterations come first: its first rejected sample, if any, is earlier.
        self.first_rejected = self.first_rejected.or(later.first_rejected);
        Ok(())
    }

    /// Adds to the rejected-sample count (for samples dropped before they reached the film).
    pub fn count_rejected(&mut self, n: u64) {
        self.rejected += n;
    }

    /// Iterations accumulated.
    pub fn iterations(&self) -> u64 {
        self.iterations
    }

    /// The index of the first iteration accumulated (0 unless this is a shard or a resumed
    /// slice).
    pub fn first_iteration(&self) -> u64 {
        self.first_iteration
    }

    /// The index of the next iteration to render: random streams and the photon-mapping
    /// radius are functions of it.
    pub fn next_iteration(&self) -> u64 {
        self.first_iteration + self.iterations
    }

    /// Non-finite samples dropped so far.
    pub fn rejected(&self) -> u64 {
        self.rejected
    }

    /// (iteration, pixel) of the first sample dropped as NaN, infinite or negative.
    pub fn first_rejected(&self) -> Option<(u64, u32)> {
        self.first_rejected
    }

    /// The average of all iterations (black before the first).
    pub fn image(&self) -> Image {
        let inv = 1.0 / self.iterations.max(1) as f64;
        Image {
            width: self.width,
            height: self.height,
            pixels: self
                .sum
                .iter()
                .map(|s| {
                    Vec3::new(
                        (from_fixed(s[0]) * inv) as f32,
                        (from_fixed(s[1]) * inv) as f32,
                        (from_fixed(s[2]) * inv) as f32,
                    )
                })
                .collect(),
        }
    }

    /// Bytes held by the sums.
    pub fn memory_bytes(&self) -> usize {
        self.sum.len() * std::mem::size_of::<[u128; 3]>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn average_and_rejection() {
        let mut film = Film::new(2, 1);
        film.add_iteration(&[Vec3::ONE, Vec3::splat(3.0)]);
        film.add_iteration(&[Vec3::splat(f32::NAN), Vec3::splat(1.0)]);
        let img = film.image();
        assert_eq!(img.pixels[0], Vec3::splat(0.5));
        assert_eq!(img.pixels[1], Vec3::splat(2.0));
        assert_eq!(film.rejected(), 1);
        assert_eq!(film.first_rejected(), Some((1, 0)));
    }

    /// Estimates beyond the film's range are rejected and counted, not clamped into the
    /// image; the largest one is still added exactly.
    #[test]
    fn estimates_beyond_the_range_are_rejected_not_clamped() {
        let max = MAX_ESTIMATE as f32;
        let mut film = Film::new(3, 1);
        let beyond = Vec3::new(1.0, max * 2.0, 1.0);
        film.add_iteration(&[Vec3::splat(max), beyond, Vec3::splat(f32::INFINITY)]);
        assert_eq!(film.rejected(), 2);
        assert_eq!(film.first_rejected(), Some((0, 1)));
        let img = film.image();
        assert_eq!(img.pixels[0], Vec3::splat(max));
        assert_eq!(img.pixels[1], Vec3::ZERO);
    }

    #[test]
    fn long_accumulation_keeps_precision() {
        // 10^5 iterations of a value that f32 cannot represent exactly: the mean must stay
        // within 1e-6 relative of the exact value.
        let mut film = Film::new(1, 1);
        let v = Vec3::splat(0.1);
        for _ in 0..100_000 {
            film.add_iteration(&[v]);
        }
        let m = film.image().pixels[0].x as f64;
        assert!((m - 0.1f32 as f64).abs() / 0.1 < 1e-6, "{m}");
    }

    /// A small deterministic generator of positive f32 values spanning many magnitudes.
    pub(super) fn values(seed: u64, n: usize) -> Vec<Vec3> {
        let mut state = seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            // Mantissa and an exponent in 2^-30 .. 2^20.
            let m = (state >> 40) as f32 / (1u64 << 24) as f32 + 0.5;
            m * 2f32.powi((state % 51) as i32 - 30)
        };
        (0..n).map(|_| Vec3::new(next(), next(), next())).collect()
    }

    #[test]
    fn estimates_of_at_least_2_pow_minus_25_are_stored_exactly() {
        for v in values(3, 2000).iter().flat_map(|v| v.to_array()) {
            let back = from_fixed(to_fixed(v));
            if v >= 2f32.powi(-25) {
                assert_eq!(back, v as f64, "{v:e}");
            } else {
                assert!((back - v as f64).abs() <= 0.5 / FIXED_POINT_SCALE, "{v:e}");
            }
        }
        assert_eq!(to_fixed(f32::MAX), to_fixed(MAX_ESTIMATE as f32));
    }

    /// The conversions' short cuts (i64 and u64 below 2^63 and 2^64 units, u64 below 2^64
    /// for sums) give the value of the plain u128 conversion, on both sides of each boundary.
    #[test]
    fn fast_conversions_equal_the_u128_conversion() {
        let reference_to =
            |e: f32| ((e as f64).min(MAX_ESTIMATE) * FIXED_POINT_SCALE).round() as u128;
        let mut estimates: Vec<f32> = values(7, 3000).iter().flat_map(|v| v.to_array()).collect();
        for boundary in [2f32.powi(15), 2f32.powi(16), MAX_ESTIMATE as f32] {
            let mut below = boundary;
            let mut above = boundary;
            for _ in 0..4 {
                estimates.extend([below, above, below * 0.75, above * 1.5]);
                below = f32::from_bits(below.to_bits() - 1);
                above = f32::from_bits(above.to_bits() + 1);
            }
        }
        estimates.extend([0.0, -0.0, f32::MIN_POSITIVE, 1e-45, f32::MAX]);
        // Where rounding decides: ties x = k + 1/2 units (round away from zero), the values
        // next to 1/2 unit, and around 2^-25 (2^23 units, above which every x is whole) and
        // 2^4 .. 2^5 (2^52 .. 2^53 units, where adding 1/2 is itself a tie in f64).
        let unit = 2f32.powi(-(FIXED_POINT_BITS as i32));
        for k in [0.5f32, 1.5, 2.5, 3.5, 1023.5, 8_388_607.5] {
            let tie = k * unit;
            for e in [
                tie,
                f32::from_bits(tie.to_bits() - 1),
                f32::from_bits(tie.to_bits() + 1),
            ] {
                estimates.push(e);
            }
        }
        for boundary in [2f32.powi(-25), 16.0, 17.0, 31.0] {
            for d in 0..4 {
                estimates.extend([
                    f32::from_bits(boundary.to_bits() - d),
                    f32::from_bits(boundary.to_bits() + d),
                ]);
            }
        }
        for &e in &estimates {
            assert_eq!(to_fixed(e), reference_to(e), "{e:e}");
            if e < SMALL_ESTIMATE {
                // SAFETY: e is in [-0, 2^15) (every value here is non-negative or -0).
                assert_eq!(unsafe { to_fixed_small(e) }, reference_to(e), "{e:e}");
            }
        }
        for sum in [0u128, 1, u128::MAX - 5, u128::MAX] {
            for units in [0u128, 1, 5, 6, 1 << 62] {
                assert_eq!(saturating_add_fixed(sum, units), sum.saturating_add(units));
            }
        }
        // The film's two paths (every channel small, or not) add what the reference converts;
        // a pixel with a channel beyond MAX_ESTIMATE is rejected whole.
        let pixels: Vec<Vec3> = estimates
            .chunks_exact(3)
            .map(|c| Vec3::new(c[0], c[1], c[2]))
            .collect();
        let mut film = Film::new(pixels.len() as u32, 1);
        film.add_iteration(&pixels);
        film.add_iteration(&pixels);
        let beyond = |e: &Vec3| e.max_element() as f64 > MAX_ESTIMATE;
        let rejected = pixels.iter().filter(|e| beyond(e)).count() as u64;
        assert!(rejected > 0, "no pixel beyond the range to test");
        assert_eq!(film.rejected(), 2 * rejected);
        for (sum, e) in film.sums().iter().zip(&pixels) {
            let expected = match beyond(e) {
                true => [0; 3],
                false => e.to_array().map(|v| reference_to(v) * 2),
            };
            assert_eq!(*sum, expected, "{e}");
        }
        let reference_from = |sum: u128| sum as f64 / FIXED_POINT_SCALE;
        for base in [1u128 << 53, 1u128 << 63, 1u128 << 64, 1u128 << 100] {
            for delta in [0u128, 1, 2, 3, 1023, 1024, 1025, 2047, 2048, 2049] {
                for sum in [base + delta, base - delta.min(base), base * 3 + delta] {
                    assert_eq!(
                        from_fixed(sum).to_bits(),
                        reference_from(sum).to_bits(),
                        "{sum}"
                    );
                }
            }
        }
        assert_eq!(
            from_fixed(u64::MAX as u128),
            reference_from(u64::MAX as u128)
        );
    }

    /// The point of fixed-point sums: slices of iterations accumulated separately and joined
    /// give the film of one accumulation, bit for bit, however the slices are grouped.
    #[test]
    fn joined_slices_equal_one_accumulation() {
        let (w, h) = (7, 5);
        let n = (w * h) as usize;
        let iterations: Vec<Vec<Vec3>> = (0..9).map(|i| values(i, n)).collect();
        let mut whole = Film::new(w, h);
        for e in &iterations {
            whole.add_iteration(e);
        }
        let slice = |first: usize, end: usize| {
            let mut f = Film::starting_at(w, h, first as u64);
            for e in &iterations[first..end] {
                f.add_iteration(e);
            }
            f
        };
        // (a + b) + c
        let mut left = slice(0, 2);
        left.append(&slice(2, 6)).unwrap();
        left.append(&slice(6, 9)).unwrap();
        // a + (b + c)
        let mut bc = slice(2, 6);
        bc.append(&slice(6, 9)).unwrap();
        let mut right = slice(0, 2);
        right.append(&bc).unwrap();
        assert_eq!(left, whole);
        assert_eq!(right, whole);
        assert_eq!(whole.image(), left.image());
        assert_eq!((whole.first_iteration(), whole.next_iteration()), (0, 9));
    }

    #[test]
    fn only_following_slices_join() {
        let mut a = Film::starting_at(2, 2, 0);
        a.add_iteration(&[Vec3::ONE; 4]);
        let gap = Film::starting_at(2, 2, 2);
        assert!(matches!(
            a.append(&gap),
            Err(StateError::NotContiguous {
                end: 1,
                next_first: 2,
                ..
            })
        ));
        assert!(matches!(
            a.append(&Film::starting_at(3, 2, 1)),
            Err(StateError::Size { .. })
        ));
        a.append(&Film::starting_at(2, 2, 1)).unwrap();
        // Overlap: a now ends at 1 (the empty slice added nothing), a second slice from 0 overlaps.
        assert!(a.append(&Film::new(2, 2)).is_err());
    }

    #[test]
    fn the_first_rejected_sample_is_the_earliest_after_a_join() {
        let nan = Vec3::splat(f32::NAN);
        let mut a = Film::new(1, 1);
        a.add_iteration(&[Vec3::ONE]);
        let mut b = Film::starting_at(1, 1, 1);
        b.add_iteration(&[nan]);
        b.add_iteration(&[nan]);
        a.append(&b).unwrap();
        assert_eq!((a.rejected(), a.first_rejected()), (2, Some((1, 0))));
    }

    #[test]
    fn sums_saturate_instead_of_wrapping() {
        let mut film = Film::new(1, 1);
        let huge = Vec3::splat(MAX_ESTIMATE as f32);
        // The largest estimate, 2^56, is 2^104 units: 2^24 of them fill the u128.
        film.sum[0] = [u128::MAX - 5; 3];
        film.add_iteration(&[huge]);
        assert_eq!(film.sum[0], [u128::MAX; 3]);
    }
}
