//! The inner loop of the density estimate: the kernel-weighted flux of [`LANES`] candidate
//! photons at once, without a branch per photon.
//!
//! For a gather point p with side normal n, radius r and the Epanechnikov kernel
//! k(d²) = norm - slope d² (norm = 2 / (pi r²), slope = norm / r², see [`super::Kernel`]),
//! every candidate contributes
//!
//! ```text
//! Phi_p max(norm - slope d_p², 0)   if d_p² <= r² and wi_p . n > 0,   else 0,
//! ```
//!
//! summed per lane and added up across the lanes at the end. Candidates outside the sphere
//! or from the other side are masked to zero (not multiplied by a zero weight, so a huge flux
//! next door cannot turn into NaN). The AVX version and the portable one perform the same
//! operations in the same order, so they agree bit for bit (tested).

use glam::Vec3;

/// Candidates tested at once.
pub(super) const LANES: usize = 8;

/// The stored photons as columns (structure of arrays), in the grid's order, each with
/// [`LANES`] entries of padding so that a block read never runs out of bounds.
#[derive(Clone, Debug, Default)]
pub(super) struct Columns {
    /// Position by coordinate; padding infinity (never within any radius).
    pub(super) position: [Vec<f32>; 3],
    /// Flux by channel; padding 0.
    pub(super) flux: [Vec<f32>; 3],
    /// The incoming direction as the side test decodes it ([`super::Photon::wi_unfolded`]);
    /// padding 0.
    pub(super) wi: [Vec<f32>; 3],
}

impl Columns {
    /// All columns, for block reads.
    #[inline(always)]
    pub(super) fn view(&self) -> ColumnsView<'_> {
        let columns = [&self.position, &self.flux, &self.wi].map(|c| c.each_ref());
        let [[x, y, z], [r, g, b], [u, v, w]] = columns;
        let all = [x, y, z, r, g, b, u, v, w].map(Vec::as_slice);
        // Equal lengths let the compiler check a block read against one of them only.
        let len = all[0].len();
        assert!(all.iter().all(|c| c.len() == len));
        ColumnsView { all }
    }

    /// Bytes allocated.
    pub(super) fn memory_bytes(&self) -> usize {
        [&self.position, &self.flux, &self.wi]
            .iter()
            .flat_map(|c| c.iter())
            .map(|c| c.capacity() * std::mem::size_of::<f32>())
            .sum()
    }
}

/// The columns of a [`Columns`], all equally long.
pub(super) struct ColumnsView<'a> {
    /// Position x, y, z, flux r, g, b, direction x, y, z.
    all: [&'a [f32]; 9],
}

impl<'a> ColumnsView<'a> {
    /// The candidates `i..i + LANES` (they may run into the next bucket or the padding:
    /// [`FluxSum::add`] masks them off).
    #[inline(always)]
    pub(super) fn block(&self, i: usize) -> Block<'a> {
        let lanes =
            |k: usize| -> &'a [f32; LANES] { self.all[k][i..i + LANES].try_into().unwrap() };
        Block {
            position: [lanes(0), lanes(1), lanes(2)],
            flux: [lanes(3), lanes(4), lanes(5)],
            wi: [lanes(6), lanes(7), lanes(8)],
        }
    }
}

/// [`LANES`] consecutive candidates, column by column.
#[derive(Clone, Copy)]
pub(super) struct Block<'a> {
    pub(super) position: [&'a [f32; LANES]; 3],
    pub(super) flux: [&'a [f32; LANES]; 3],
    pub(super) wi: [&'a [f32; LANES]; 3],
}

/// One density estimate's constants.
#[derive(Clone, Copy, Debug)]
pub(super) struct FluxQuery {
    pub(super) p: Vec3,
    /// Photons count when wi . n > 0.
    pub(super) n: Vec3,
    pub(super) r2: f32,
    pub(super) norm: f32,
    pub(super) slope: f32,
}

/// Per-lane running sums of the weighted flux, one per channel.
pub(super) struct FluxSum {
    lanes: [[f32; LANES]; 3],
}

impl FluxSum {
    pub(super) fn new() -> Self {
        FluxSum {
            lanes: [[0.0; LANES]; 3],
        }
    }

    /// Adds the first `valid` candidates of `block` (the others are masked off).
    #[inline(always)]
    pub(super) fn add(&mut self, block: Block<'_>, valid: usize, q: &FluxQuery) {
        #[cfg(all(target_arch = "x86_64", target_feature = "avx"))]
        {
            self.add_avx(block, valid, q)
        }
        #[cfg(not(all(target_arch = "x86_64", target_feature = "avx")))]
        {
            self.add_portable(block, valid, q)
        }
    }

    /// The sum over all lanes, lane 0 first.
    #[inline]
    pub(super) fn total(&self) -> Vec3 {
        let sum = |lanes: &[f32; LANES]| lanes.iter().fold(0.0, |s, &x| s + x);
        Vec3::new(
            sum(&self.lanes[0]),
            sum(&self.lanes[1]),
            sum(&self.lanes[2]),
        )
    }

    /// [`FluxSum::add`] in plain Rust.
    #[cfg_attr(
        all(target_arch = "x86_64", target_feature = "avx"),
        allow(dead_code) // only the tests call it there
    )]
    #[inline(always)]
    fn add_portable(&mut self, block: Block<'_>, valid: usize, q: &FluxQuery) {
        let [xs, ys, zs] = block.position;
        let [wx, wy, wz] = block.wi;
        for k in 0..LANES {
            let (dx, dy, dz) = (xs[k] - q.p.x, ys[k] - q.p.y, zs[k] - q.p.z);
            let d2 = dx * dx + dy * dy + dz * dz;
            let side = wx[k] * q.n.x + wy[k] * q.n.y + wz[k] * q.n.z;
            let weight = (q.norm - q.slope * d2).max(0.0);
            let counts = k < valid && d2 <= q.r2 && side > 0.0;
            for (sum, flux) in self.lanes.iter_mut().zip(block.flux) {
                sum[k] += if counts { weight * flux[k] } else { 0.0 };
            }
        }
    }

    /// [`FluxSum::add`] with 8-wide AVX.
    #[cfg(all(target_arch = "x86_64", target_feature = "avx"))]
    #[inline(always)]
    fn add_avx(&mut self, block: Block<'_>, valid: usize, q: &FluxQuery) {
        use std::arch::x86_64::*;
        const _: () = assert!(LANES == 8, "one __m256 holds the block");
        // SAFETY: AVX is enabled for this whole build (cfg above), and every load and store
        // reads or writes exactly one `[f32; 8]` through a valid reference (unaligned access).
        unsafe {
            let load = |a: &[f32; LANES]| _mm256_loadu_ps(a.as_ptr());
            let dx = _mm256_sub_ps(load(block.position[0]), _mm256_set1_ps(q.p.x));
            let dy = _mm256_sub_ps(load(block.position[1]), _mm256_set1_ps(q.p.y));
            let dz = _mm256_sub_ps(load(block.position[2]), _mm256_set1_ps(q.p.z));
            let d2 = _mm256_add_ps(
                _mm256_add_ps(_mm256_mul_ps(dx, dx), _mm256_mul_ps(dy, dy)),
                _mm256_mul_ps(dz, dz),
            );
            let side = _mm256_add_ps(
                _mm256_add_ps(
                    _mm256_mul_ps(load(block.wi[0]), _mm256_set1_ps(q.n.x)),
                    _mm256_mul_ps(load(block.wi[1]), _mm256_set1_ps(q.n.y)),
                ),
                _mm256_mul_ps(load(block.wi[2]), _mm256_set1_ps(q.n.z)),
            );
            // max(x, 0) returns 0 for NaN, like f32::max.
            let weight = _mm256_max_ps(
                _mm256_sub_ps(
                    _mm256_set1_ps(q.norm),
                    _mm256_mul_ps(_mm256_set1_ps(q.slope), d2),
                ),
                _mm256_setzero_ps(),
            );
            let lane = _mm256_setr_ps(0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0);
            // Ordered, non-signalling comparisons: false for NaN, like the scalar ones.
            let counts = _mm256_and_ps(
                _mm256_and_ps(
                    _mm256_cmp_ps::<_CMP_LT_OQ>(
                        lane,
                        _mm256_set1_ps(valid.min(LANES) as i32 as f32),
                    ),
                    _mm256_cmp_ps::<_CMP_LE_OQ>(d2, _mm256_set1_ps(q.r2)),
                ),
                _mm256_cmp_ps::<_CMP_GT_OQ>(side, _mm256_setzero_ps()),
            );
            for (sum, flux) in self.lanes.iter_mut().zip(block.flux) {
                let term = _mm256_and_ps(counts, _mm256_mul_ps(weight, load(flux)));
                let s = _mm256_add_ps(_mm256_loadu_ps(sum.as_ptr()), term);
                _mm256_storeu_ps(sum.as_mut_ptr(), s);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    /// The AVX and portable blocks agree bit for bit, and both equal the per-photon formula,
    /// on blocks with candidates inside, outside, on the sphere, from behind, huge fluxes
    /// outside and padding.
    #[test]
    #[allow(clippy::needless_range_loop)] // lanes index several arrays at once
    fn block_sums_match_the_per_photon_formula() {
        let mut rng = Rng::new(11, 0, 0);
        let q = FluxQuery {
            p: Vec3::new(0.3, -1.2, 2.0),
            n: Vec3::new(0.0, 0.6, 0.8),
            r2: 0.04,
            norm: 2.0 / (std::f32::consts::PI * 0.04),
            slope: 2.0 / (std::f32::consts::PI * 0.04) / 0.04,
        };
        let mut counted = 0;
        for round in 0..2000 {
            let mut c = [[[0.0f32; LANES]; 3]; 3];
            for k in 0..LANES {
                let offset = (rng.uniform2().extend(rng.uniform()) * 2.0 - 1.0) * 0.3;
                let mut x = q.p + offset;
                if k == 3 {
                    // Exactly on the sphere along x.
                    x = q.p + Vec3::new(0.2, 0.0, 0.0);
                }
                let wi = (rng.uniform2().extend(rng.uniform()) * 2.0 - 1.0).normalize();
                let flux = if k == 5 && round % 2 == 0 {
                    Vec3::splat(f32::INFINITY) // must stay out when it does not count
                } else {
                    rng.uniform2().extend(rng.uniform()) * 10.0
                };
                for a in 0..3 {
                    c[0][a][k] = x[a];
                    c[1][a][k] = flux[a];
                    c[2][a][k] = wi[a];
                }
            }
            let block = Block {
                position: c[0].each_ref(),
                flux: c[1].each_ref(),
                wi: c[2].each_ref(),
            };
            let valid = if round % 3 == 0 {
                1 + round % LANES
            } else {
                LANES
            };
            let mut portable = FluxSum::new();
            portable.add_portable(block, valid, &q);
            #[cfg(all(target_arch = "x86_64", target_feature = "avx"))]
            {
                let mut avx = FluxSum::new();
                avx.add_avx(block, valid, &q);
                let bits = |s: &FluxSum| s.lanes.map(|l| l.map(f32::to_bits));
                assert_eq!(bits(&avx), bits(&portable), "round {round}");
            }
            for k in 0..LANES {
                let x = Vec3::new(c[0][0][k], c[0][1][k], c[0][2][k]);
                let flux = Vec3::new(c[1][0][k], c[1][1][k], c[1][2][k]);
                let wi = Vec3::new(c[2][0][k], c[2][1][k], c[2][2][k]);
                let d2 = x.distance_squared(q.p);
                let counts = k < valid && d2 <= q.r2 && wi.dot(q.n) > 0.0;
                let expected = if counts {
                    counted += 1;
                    flux * (q.norm - q.slope * d2).max(0.0)
                } else {
                    Vec3::ZERO
                };
                let got = Vec3::new(
                    portable.lanes[0][k],
                    portable.lanes[1][k],
                    portable.lanes[2][k],
                );
                assert_eq!(got, expected, "round {round} lane {k}");
            }
        }
        assert!(counted > 1000, "{counted}");
    }
}
