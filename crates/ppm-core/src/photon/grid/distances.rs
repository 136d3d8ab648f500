//! The squared distances of 8 candidate photons from a query point, and which are inside.

use crate::simd::{F32x8, LANES};
use glam::Vec3;

/// The coordinates of [`LANES`] consecutive candidates, one array per axis.
pub(super) type Positions<'a> = [&'a [f32; LANES]; 3];

/// The squared distances from `p` of the [`LANES`] candidates `(xs[k], ys[k], zs[k])`, and the
/// mask of those with `d² <= r2` (bit k for candidate k).
///
/// `d² = (dx² + dy²) + dz²` in this order and without fused multiply-adds, as
/// `Vec3::distance_squared` computes it, so each lane equals that scalar expression bit for
/// bit (tested) and results do not depend on how the crate was compiled.
#[inline(always)]
pub(super) fn block_distances(position: Positions<'_>, p: Vec3, r2: f32) -> (u32, [f32; LANES]) {
    let [xs, ys, zs] = position;
    let dx = F32x8::from_array(xs) - F32x8::splat(p.x);
    let dy = F32x8::from_array(ys) - F32x8::splat(p.y);
    let dz = F32x8::from_array(zs) - F32x8::splat(p.z);
    let d2 = (dx * dx + dy * dy) + dz * dz;
    // Ordered <=: false for NaN, like the scalar comparison.
    (d2.le(F32x8::splat(r2)).bits(), d2.to_array())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn block_distances_match_scalar_distance_squared_bit_for_bit() {
        let mut rng = crate::sampling::Rng::new(7, 0, 0);
        let mut coordinate = |scale: f32| (rng.uniform() - 0.5) * scale;
        for trial in 0..20_000 {
            let scale = [1e-3, 1.0, 3.0, 1e5][trial % 4];
            let p = Vec3::new(coordinate(scale), coordinate(scale), coordinate(scale));
            let mut xyz = [[0.0f32; LANES]; 3];
            for k in 0..LANES {
                for axis in xyz.iter_mut() {
                    axis[k] = coordinate(scale);
                }
            }
            // Padding lanes, a candidate at p (d² = 0) and one exactly on the radius.
            xyz[0][7] = f32::INFINITY;
            xyz[1][6] = f32::NAN;
            (xyz[0][5], xyz[1][5], xyz[2][5]) = (p.x, p.y, p.z);
            let q = Vec3::new(xyz[0][4], xyz[1][4], xyz[2][4]);
            let r2 = if trial % 2 == 0 {
                q.distance_squared(p)
            } else {
                0.1 * scale * scale
            };
            let position = xyz.each_ref();
            let (mask, d2) = block_distances(position, p, r2);
            for k in 0..LANES {
                let expected = Vec3::new(xyz[0][k], xyz[1][k], xyz[2][k]).distance_squared(p);
                assert_eq!(
                    d2[k].to_bits(),
                    expected.to_bits(),
                    "trial {trial}, lane {k}"
                );
                assert_eq!(
                    mask >> k & 1 == 1,
                    expected <= r2,
                    "trial {trial}, lane {k}"
                );
            }
            // The candidate at p is in, padding and NaN are out, the one on the radius is in.
            assert_eq!(mask & 0b1110_0000, 0b0010_0000, "trial {trial}");
            assert!(trial % 2 == 1 || mask & 0b1_0000 != 0, "trial {trial}");
        }
    }
}
