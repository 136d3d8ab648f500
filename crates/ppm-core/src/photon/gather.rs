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
//! summed per lane and added up across the lanes at the end, over the photons of at most
//! `max_bounce` bounces ([`super::Photon::bounce`]); at a point shaded with an
//! interpolated normal ns, the flux is also weighted by (wi_p . ns) / (wi_p . n) and counts
//! only where wi_p . ns > 0 as well ([`super::GatherNormals`]). Candidates outside the sphere
//! or from the other side are masked to zero (not multiplied by a zero weight, so a huge flux
//! next door cannot turn into NaN). Written once over [`F32x8`], whose AVX and portable forms
//! agree bit for bit, and tested lane by lane against the scalar formula.

use crate::simd::{F32x8, LANES};
use glam::Vec3;

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
    /// The bounce of the photon's key ([`super::Photon::bounce`]), exact in f32; padding 0.
    pub(super) bounce: Vec<f32>,
}

impl Columns {
    /// All columns, for block reads.
    #[inline(always)]
    pub(super) fn view(&self) -> ColumnsView<'_> {
        // Spelled out rather than through array `map`, which LLVM does not always inline
        // (a call per density estimate).
        let [x, y, z] = &self.position;
        let [r, g, b] = &self.flux;
        let [u, v, w] = &self.wi;
        let bounce = &self.bounce;
        let all = [
            x.as_slice(),
            y.as_slice(),
            z.as_slice(),
            r.as_slice(),
            g.as_slice(),
            b.as_slice(),
            u.as_slice(),
            v.as_slice(),
            w.as_slice(),
            bounce.as_slice(),
        ];
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
            .chain([&self.bounce])
            .map(|c| c.capacity() * std::mem::size_of::<f32>())
            .sum()
    }
}

/// The columns of a [`Columns`], all equally long.
pub(super) struct ColumnsView<'a> {
    /// Position x, y, z, flux r, g, b, direction x, y, z, bounce.
    all: [&'a [f32]; 10],
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
            bounce: lanes(9),
        }
    }
}

/// [`LANES`] consecutive candidates, column by column.
#[derive(Clone, Copy)]
pub(super) struct Block<'a> {
    pub(super) position: [&'a [f32; LANES]; 3],
    pub(super) flux: [&'a [f32; LANES]; 3],
    pub(super) wi: [&'a [f32; LANES]; 3],
    pub(super) bounce: &'a [f32; LANES],
}

/// One density estimate's constants.
#[derive(Clone, Copy, Debug)]
pub(super) struct FluxQuery {
    pub(super) p: Vec3,
    /// The geometric normal on the viewer's side: photons count when wi . n > 0.
    pub(super) n: Vec3,
    /// The shading normal on the viewer's side, read by [`FluxSum::add`] when `SHADED`.
    pub(super) ns: Vec3,
    pub(super) r2: f32,
    pub(super) norm: f32,
    pub(super) slope: f32,
    /// Photons of more bounces than this do not count (an integer, exact in f32).
    pub(super) max_bounce: f32,
}

/// Per-lane running sums of the weighted flux, one per channel.
pub(super) struct FluxSum {
    lanes: [F32x8; 3],
}

impl FluxSum {
    pub(super) fn new() -> Self {
        FluxSum {
            lanes: [F32x8::zero(); 3],
        }
    }

    /// Adds the first `valid` candidates of `block` (the others are masked off): per lane k,
    /// `Phi_k max(norm - slope d_k², 0)` where `k < valid`, `d_k² <= r²`, `wi_k . n > 0` and
    /// `bounce_k <= max_bounce`;
    /// when `SHADED`, times `(wi_k . ns) / (wi_k . n)` and only where `wi_k . ns > 0` and that
    /// ratio is finite ([`super::GatherNormals::weight`], lane by lane).
    #[inline(always)]
    pub(super) fn add<const SHADED: bool>(
        &mut self,
        block: Block<'_>,
        valid: usize,
        q: &FluxQuery,
    ) {
        let load = F32x8::from_array;
        let splat = F32x8::splat;
        let [xs, ys, zs] = block.position;
        let [wx, wy, wz] = block.wi;
        let (dx, dy, dz) = (
            load(xs) - splat(q.p.x),
            load(ys) - splat(q.p.y),
            load(zs) - splat(q.p.z),
        );
        let d2 = (dx * dx + dy * dy) + dz * dz;
        let side = (load(wx) * splat(q.n.x) + load(wy) * splat(q.n.y)) + load(wz) * splat(q.n.z);
        // max(x, 0) returns 0 for NaN (the second operand), like f32::max.
        let weight = (splat(q.norm) - splat(q.slope) * d2).max(F32x8::zero());
        let lane = load(&[0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0]);
        // Ordered comparisons: false for NaN.
        let mut counts = lane.lt(splat(valid.min(LANES) as f32))
            & d2.le(splat(q.r2))
            & side.gt(F32x8::zero())
            & load(block.bounce).le(splat(q.max_bounce));
        let mut weight = weight;
        if SHADED {
            let shading =
                (load(wx) * splat(q.ns.x) + load(wy) * splat(q.ns.y)) + load(wz) * splat(q.ns.z);
            let ratio = shading / side;
            counts = counts & shading.gt(F32x8::zero()) & ratio.lt(splat(f32::INFINITY));
            weight = weight * ratio;
        }
        for (sum, flux) in self.lanes.iter_mut().zip(block.flux) {
            *sum = *sum + counts.select_or_zero(weight * load(flux));
        }
    }

    /// The sum over all lanes, lane 0 first.
    #[inline]
    pub(super) fn total(&self) -> Vec3 {
        let sum = |lanes: F32x8| lanes.to_array().iter().fold(0.0, |s, &x| s + x);
        Vec3::new(sum(self.lanes[0]), sum(self.lanes[1]), sum(self.lanes[2]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    /// Every lane of the block sum equals the per-photon formula evaluated in scalar code, bit
    /// for bit, on blocks with candidates inside, outside, on the sphere, from behind, huge fluxes
    /// outside, padding, and of too many bounces (from 0 to 7, some rounds counting all, some
    /// none, some up to 3); flat, and shaded with the weight of `GatherNormals`.
    #[test]
    #[allow(clippy::needless_range_loop)] // lanes index several arrays at once
    fn block_sums_match_the_per_photon_formula() {
        let mut rng = Rng::new(11, 0, 0);
        let mut q = FluxQuery {
            p: Vec3::new(0.3, -1.2, 2.0),
            n: Vec3::new(0.0, 0.6, 0.8),
            ns: Vec3::new(0.48, 0.6, 0.64),
            r2: 0.04,
            norm: 2.0 / (std::f32::consts::PI * 0.04),
            slope: 2.0 / (std::f32::consts::PI * 0.04) / 0.04,
            max_bounce: 0.0,
        };
        let (mut counted, mut too_deep) = (0, 0);
        let bounces = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0];
        for round in 0..2000 {
            q.max_bounce = [63.0, 3.0, 0.0, 7.0, 3.0][round % 5];
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
                bounce: &bounces,
            };
            let valid = if round % 3 == 0 {
                1 + round % LANES
            } else {
                LANES
            };
            let shaded = round % 2 == 1;
            let mut sum = FluxSum::new();
            if shaded {
                sum.add::<true>(block, valid, &q);
            } else {
                sum.add::<false>(block, valid, &q);
            }
            let normals = crate::photon::GatherNormals {
                geometric: q.n,
                shading: if shaded { q.ns } else { q.n },
            };
            let lanes = sum.lanes.map(F32x8::to_array);
            for k in 0..LANES {
                let x = Vec3::new(c[0][0][k], c[0][1][k], c[0][2][k]);
                let flux = Vec3::new(c[1][0][k], c[1][1][k], c[1][2][k]);
                let wi = Vec3::new(c[2][0][k], c[2][1][k], c[2][2][k]);
                let d2 = x.distance_squared(q.p);
                let w = normals.weight(wi);
                let counts = k < valid && d2 <= q.r2 && w > 0.0;
                too_deep += (counts && bounces[k] > q.max_bounce) as usize;
                let counts = counts && bounces[k] <= q.max_bounce;
                let expected = if counts {
                    counted += 1;
                    let kernel = (q.norm - q.slope * d2).max(0.0);
                    flux * if shaded { kernel * w } else { kernel }
                } else {
                    Vec3::ZERO
                };
                let got = Vec3::new(lanes[0][k], lanes[1][k], lanes[2][k]);
                let bits = |v: Vec3| v.to_array().map(f32::to_bits);
                assert_eq!(bits(got), bits(expected), "round {round} lane {k}");
            }
        }
        assert!(counted > 1000 && too_deep > 300, "{counted} {too_deep}");
    }
}
