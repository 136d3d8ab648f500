//! Four triangles against one ray at once: the watertight test of [`super::triangle`] on
//! four lanes (glam's `Vec4`: SSE on x86-64, plain arrays elsewhere).
//!
//! Every lane performs the very operations of the scalar [`ShearedRay::intersect`], in the
//! same order (products and sums are rounded one at a time, nothing is fused), so a lane's
//! verdict, t and barycentrics are bit for bit the scalar ones. The two rare branches of the
//! scalar test are not vectorised: a lane with an edge function of exactly zero (the ray
//! through an edge or vertex, decided in double precision) or with t within its error bound
//! of zero (a ray leaving this triangle) is handed to the scalar test itself.

use super::triangle::{gamma, t_error_bound, ShearedRay};
use glam::{Vec3, Vec4};

/// Up to four triangles in structure-of-arrays form.
#[derive(Clone, Copy, Debug)]
pub(crate) struct TrianglePacket {
    /// `v[vertex][axis]`: coordinate `axis` of vertex `vertex` of each lane's triangle.
    v: [[Vec4; 3]; 3],
    /// Global primitive id of each lane (0 in unused lanes).
    pub(crate) id: [u32; 4],
    /// Bitmask of the lanes in use.
    lanes: u32,
}

/// Per-ray constants of the packet test: the permuted origin and the shear, on all lanes.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PacketRay {
    origin: [Vec4; 3],
    shear: [Vec4; 3],
    axes: [usize; 3],
}

impl PacketRay {
    #[inline(always)]
    pub(crate) fn new(ray: &ShearedRay) -> Self {
        let axes = [ray.kx, ray.ky, ray.kz];
        let o = ray.origin.to_array();
        PacketRay {
            origin: axes.map(|k| Vec4::splat(o[k])),
            shear: [ray.sx, ray.sy, ray.sz].map(Vec4::splat),
            axes,
        }
    }
}

impl TrianglePacket {
    /// Packs up to four triangles `(v0, v1, v2, id)`.
    pub(crate) fn new(triangles: &[([Vec3; 3], u32)]) -> Self {
        assert!(triangles.len() <= 4, "a packet holds at most 4 triangles");
        let mut v = [[[0.0f32; 4]; 3]; 3];
        let mut id = [0; 4];
        for (lane, (tri, prim)) in triangles.iter().enumerate() {
            for (vertex, p) in tri.iter().enumerate() {
                for (axis, c) in p.to_array().into_iter().enumerate() {
                    v[vertex][axis][lane] = c;
                }
            }
            id[lane] = *prim;
        }
        TrianglePacket {
            v: v.map(|vertex| vertex.map(Vec4::from_array)),
            id,
            lanes: (1 << triangles.len()) - 1,
        }
    }

    /// Vertex `vertex` of lane `lane`.
    #[inline]
    fn vertex(&self, vertex: usize, lane: usize) -> Vec3 {
        let [x, y, z] = self.v[vertex];
        Vec3::new(x[lane], y[lane], z[lane])
    }

    /// Number of lanes in use (they are the first ones).
    pub(crate) fn count(&self) -> usize {
        self.lanes.count_ones() as usize
    }

    /// The three vertices of lane `lane`'s triangle, exactly as packed.
    #[inline(always)]
    pub(crate) fn vertices(&self, lane: usize) -> [Vec3; 3] {
        [0, 1, 2].map(|vertex| self.vertex(vertex, lane))
    }

    /// Calls `hit(lane, t, b1, b2)` for every lane whose triangle the ray meets at t in
    /// (0, t_max], exactly as [`ShearedRay::intersect`] would answer lane by lane.
    #[inline(always)]
    pub(crate) fn intersect(
        &self,
        ray: &ShearedRay,
        packet_ray: &PacketRay,
        t_max: f32,
        mut hit: impl FnMut(usize, f32, f32, f32),
    ) {
        let [kx, ky, kz] = packet_ray.axes;
        let [ox, oy, oz] = packet_ray.origin;
        let [sx, sy, sz] = packet_ray.shear;
        // A vertex relative to the origin, permuted and sheared in x and y.
        let transform = |v: &[Vec4; 3]| {
            let (px, py, pz) = (v[kx] - ox, v[ky] - oy, v[kz] - oz);
            (px - sx * pz, py - sy * pz, pz)
        };
        let (x0, y0, z0) = transform(&self.v[0]);
        let (x1, y1, z1) = transform(&self.v[1]);
        let (x2, y2, z2) = transform(&self.v[2]);

        let e0 = x1 * y2 - y1 * x2;
        let e1 = x2 * y0 - y2 * x0;
        let e2 = x0 * y1 - y0 * x1;
        let zero = Vec4::ZERO;
        // Lanes the scalar test decides in double precision: its answer, not ours.
        let mut scalar = (e0.cmpeq(zero) | e1.cmpeq(zero) | e2.cmpeq(zero)).bitmask() & self.lanes;
        let negative = e0.cmplt(zero) | e1.cmplt(zero) | e2.cmplt(zero);
        let positive = e0.cmpgt(zero) | e1.cmpgt(zero) | e2.cmpgt(zero);
        let det = e0 + e1 + e2;
        let (z0, z1, z2) = (sz * z0, sz * z1, sz * z2);
        let t_scaled = e0 * z0 + e1 * z1 + e2 * z2;
        let t_max_det = Vec4::splat(t_max) * det;
        let beyond = (det.cmplt(zero) & t_scaled.cmplt(t_max_det))
            | (det.cmpgt(zero) & t_scaled.cmpgt(t_max_det));
        let rejected = (negative & positive) | det.cmpeq(zero) | beyond;
        let candidates = !rejected.bitmask() & self.lanes & !scalar;
        if candidates != 0 {
            let inv_det = det.recip();
            let t = t_scaled * inv_det;
            let max_z = z0.abs().max(z1.abs()).max(z2.abs());
            let max_x = x0.abs().max(x1.abs()).max(x2.abs());
            let max_y = y0.abs().max(y1.abs()).max(y2.abs());
            let max_e = e0.abs().max(e1.abs()).max(e2.abs());
            let delta_t = t_error_bound(max_x, max_y, max_z, max_e, inv_det.abs(), |n| {
                Vec4::splat(gamma(n))
            });
            let far = t.cmpgt(delta_t).bitmask() & candidates;
            // Within the error bound of zero: the scalar test recomputes t in double precision.
            scalar |= t.cmpge(-delta_t).bitmask() & candidates & !far;
            let (b1, b2) = (e1 * inv_det, e2 * inv_det);
            let mut lanes = far;
            while lanes != 0 {
                let lane = lanes.trailing_zeros() as usize;
                lanes &= lanes - 1;
                hit(lane, t[lane], b1[lane], b2[lane]);
            }
        }
        while scalar != 0 {
            let lane = scalar.trailing_zeros() as usize;
            scalar &= scalar - 1;
            let (v0, v1, v2) = (
                self.vertex(0, lane),
                self.vertex(1, lane),
                self.vertex(2, lane),
            );
            if let Some((t, b1, b2)) = ray.intersect(v0, v1, v2, t_max) {
                hit(lane, t, b1, b2);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::{uniform_sphere, Rng};

    /// Every lane answers like the scalar test, bit for bit, on random rays and on rays
    /// through shared vertices and edges and rays leaving the triangles (the scalar branches).
    #[test]
    fn lanes_match_the_scalar_test_bit_for_bit() {
        let mut rng = Rng::new(7, 0, 0);
        let point = |rng: &mut Rng| (rng.uniform2().extend(rng.uniform()) * 2.0 - 1.0) * 3.0;
        let (mut hits, mut on_edges, mut leaving) = (0, 0, 0);
        for round in 0..4000 {
            // A fan around a shared vertex (edges shared between lanes) and one random triangle.
            let centre = point(&mut rng);
            let spokes: Vec<Vec3> = (0..4).map(|_| point(&mut rng)).collect();
            let mut tris: Vec<([Vec3; 3], u32)> = (0..3)
                .map(|i| ([centre, spokes[i], spokes[i + 1]], 10 + i as u32))
                .collect();
            tris.push(([point(&mut rng), point(&mut rng), point(&mut rng)], 20));
            tris.truncate(1 + round % 4);
            let packet = TrianglePacket::new(&tris);
            let (origin, dir) = match round % 3 {
                0 => (point(&mut rng), uniform_sphere(rng.uniform2())),
                // Through the shared vertex or the middle of a shared edge.
                1 => {
                    let o = point(&mut rng);
                    let target = if rng.uniform() < 0.5 {
                        centre
                    } else {
                        (centre + spokes[1]) * 0.5
                    };
                    (o, (target - o).normalize())
                }
                // From a point on the first triangle (a spawned ray, before any offset).
                _ => {
                    let [a, b, c] = tris[0].0;
                    let (u, v) = (rng.uniform(), rng.uniform());
                    let (u, v) = if u + v > 1.0 {
                        (1.0 - u, 1.0 - v)
                    } else {
                        (u, v)
                    };
                    (
                        a + (b - a) * u + (c - a) * v,
                        uniform_sphere(rng.uniform2()),
                    )
                }
            };
            let ray = ShearedRay::new(origin, dir);
            let t_max = if round % 5 == 0 { 2.0 } else { f32::INFINITY };
            let mut got = [None; 4];
            packet.intersect(&ray, &PacketRay::new(&ray), t_max, |lane, t, b1, b2| {
                assert!(got[lane].is_none(), "lane {lane} reported twice");
                got[lane] = Some((t.to_bits(), b1.to_bits(), b2.to_bits()));
            });
            for (lane, (tri, _)) in tris.iter().enumerate() {
                let expected = ray
                    .intersect(tri[0], tri[1], tri[2], t_max)
                    .map(|(t, b1, b2)| (t.to_bits(), b1.to_bits(), b2.to_bits()));
                assert_eq!(got[lane], expected, "round {round} lane {lane}");
                hits += expected.is_some() as u32;
                on_edges += (round % 3 == 1 && expected.is_some()) as u32;
                leaving += (round % 3 == 2 && lane == 0) as u32;
            }
            for (lane, padding) in got.iter().enumerate().skip(tris.len()) {
                assert_eq!(*padding, None, "padding lane {lane} reported a hit");
            }
        }
        assert!(
            hits > 1000 && on_edges > 300 && leaving > 1000,
            "{hits} {on_edges} {leaving}"
        );
    }
}
