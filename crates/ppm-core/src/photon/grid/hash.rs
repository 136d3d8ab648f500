//! Where a photon goes in the grid: the cell containing a point, and the bucket of a cell.

use glam::{IVec3, Vec3};

/// The cell-to-bucket map, copied out of the grid so that parallel closures can borrow it.
#[derive(Clone, Copy, Debug)]
pub(super) struct CellHash {
    pub(super) inv_cell: f32,
    pub(super) buckets: u32,
}

impl CellHash {
    /// Integer coordinates of the cell containing `p`: floor, so that -0.5 is in cell -1.
    /// Coordinates beyond the `i32` range saturate, which keeps the map monotonic.
    #[inline]
    pub(super) fn cell(&self, p: Vec3) -> IVec3 {
        let q = p * self.inv_cell;
        IVec3::new(floor_i32(q.x), floor_i32(q.y), floor_i32(q.z))
    }

    /// The bucket of cell `c`: the row of cells along x through `c` starts at a hashed
    /// bucket, and the row's cells take the buckets after it (modulo the table size), so
    /// neighbours along x are neighbours in memory and a query reads a 2 x 2 x 2 block of
    /// cells as 4 runs instead of 8 scattered buckets (`HashGrid::bucket_runs`).
    ///
    /// The row's bucket: a linear combination of (y, z) with large odd 64-bit constants
    /// (injective on any realistic block of cells), the SplitMix64 finaliser (full
    /// avalanche), then the top 32 bits mapped onto `0..buckets` by a multiply-shift.
    /// The classic `x p1 ^ y p2 ^ z p3` (Teschner et al. 2003) is avoided: with sign-extended
    /// negative coordinates the xor collides often (a 16³ block around the origin has only
    /// 2518 distinct values out of 4096).
    #[inline]
    pub(super) fn bucket(&self, c: IVec3) -> usize {
        let mut h = (c.y as u64)
            .wrapping_mul(0xc2b2_ae3d_27d4_eb4f)
            .wrapping_add((c.z as u64).wrapping_mul(0x1656_67b1_9e37_79f9));
        h = (h ^ (h >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        h = (h ^ (h >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        h ^= h >> 31;
        let row = ((h >> 32) * self.buckets as u64) >> 32;
        // `buckets` is a power of two: the mask is the modulo, also for negative x.
        (row as u32).wrapping_add(c.x as u32) as usize & (self.buckets as usize - 1)
    }
}

/// `floor(x)` as an `i32`, saturating (NaN gives 0), monotonic in `x`.
///
/// `f32::floor` is a libm call on x86-64 without SSE4.1, inside the build's hottest loop;
/// truncate instead and step down when truncation rounded a negative value up. For
/// |x| >= 2^24 every float is an integer, so the comparison is exact wherever it matters.
#[inline]
fn floor_i32(x: f32) -> i32 {
    let t = x as i32;
    t.saturating_sub((t as f32 > x) as i32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cells_use_floor_for_negative_coordinates() {
        let hash = CellHash {
            inv_cell: 2.0,
            buckets: 8,
        };
        // Truncation toward zero would merge cells -1 and 0 into one twice as wide.
        assert_eq!(
            hash.cell(Vec3::new(-0.25, -0.5, 0.25)),
            IVec3::new(-1, -1, 0)
        );
        assert_eq!(hash.cell(Vec3::new(-0.0, 0.5, -0.51)), IVec3::new(0, 1, -2));
        assert_eq!(hash.cell(Vec3::splat(-1e-30)), IVec3::splat(-1));
    }

    #[test]
    fn floor_i32_matches_floor() {
        // Magnitudes from 1e-3 to 3e9 (past the i32 range), both signs, with fractions.
        let mut m = 1e-3f32;
        while m < 3e9 {
            let (above, below) = (
                f32::from_bits(m.to_bits() + 1),
                -f32::from_bits(m.to_bits() + 1),
            );
            for v in [m, -m, m + 0.5, -m - 0.5, above, below] {
                let expected = v.floor().clamp(i32::MIN as f32, i32::MAX as f32) as i32;
                assert_eq!(floor_i32(v), expected, "{v}");
            }
            m *= 1.01;
        }
        for v in [
            0.0,
            -0.0,
            -1.0,
            1.0,
            -0.5,
            0.5,
            -1e-30,
            16777217.0,
            -16777216.0,
        ] {
            assert_eq!(floor_i32(v), v.floor() as i32, "{v}");
        }
        assert_eq!(floor_i32(f32::NAN), 0);
        assert_eq!(floor_i32(f32::NEG_INFINITY), i32::MIN);
        assert_eq!(floor_i32(f32::INFINITY), i32::MAX);
    }

    #[test]
    fn buckets_are_in_range_and_well_spread() {
        for buckets in [1u32, 2, 64, 4096] {
            let hash = CellHash {
                inv_cell: 1.0,
                buckets,
            };
            let mut used = vec![false; buckets as usize];
            // A 16^3 block of cells around the origin, as many cells as the largest table.
            for z in -8..8 {
                for y in -8..8 {
                    for x in -8..8 {
                        used[hash.bucket(IVec3::new(x, y, z))] = true;
                    }
                }
            }
            // A random map of 4096 cells into n buckets fills n (1 - e^(-4096/n)) of them
            // on average: 63% for n = 4096 and ~100% for the smaller tables.
            let filled = used.iter().filter(|&&u| u).count() as f32 / buckets as f32;
            let expected = 1.0 - (-4096.0 / buckets as f32).exp();
            assert!(
                filled > 0.95 * expected,
                "{buckets} buckets: {filled} filled"
            );
        }
    }

    #[test]
    fn cells_along_x_take_consecutive_buckets() {
        for buckets in [1u32, 16, 1 << 18] {
            let hash = CellHash {
                inv_cell: 1.0,
                buckets,
            };
            for (y, z) in [(0, 0), (-3, 7), (i32::MAX, i32::MIN), (12345, -54321)] {
                for x in [-2, -1, 0, 1, 1000, i32::MAX - 1] {
                    let b = hash.bucket(IVec3::new(x, y, z));
                    let next = hash.bucket(IVec3::new(x + 1, y, z));
                    assert_eq!(next, (b + 1) % buckets as usize, "{x} {y} {z}");
                }
            }
        }
    }
}
