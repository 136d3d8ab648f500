//! Lamps lying in another surface's plane, or facing one close by.
//!
//! A light quad placed exactly on a ceiling (or any emissive face coinciding with another
//! face) is ambiguous: camera and shadow rays find the lamp or the surface by rounding, so the
//! lamp looks speckled, while photons leave it regardless; the integrators then disagree
//! (7-8% on a Cornell box with its lamp moved into the ceiling's plane). Found by probing:
//! short rays along each emissive triangle's normal through a few of its interior points, from
//! either side of its plane; one that meets a primitive of another material at that plane
//! names the lamp. (The lamp's own other triangles do not count: a tiny lamp far from the
//! camera has vertices a few ulps apart, and a probe then meets its neighbouring triangle.)

use ppm_core::geometry::Ray;
use ppm_core::light::Light;
use ppm_core::scene::Scene;

/// Emissive triangles probed at most (spread evenly over the lights): the check stays a
/// fraction of the load time for a fully emissive million-triangle mesh.
const MAX_PROBED: usize = 4096;

/// Barycentric coordinates (b1, b2) of the probed points, inside the triangle.
const POINTS: [(f32, f32); 5] = [
    (1.0 / 3.0, 1.0 / 3.0),
    (0.6, 0.2),
    (0.2, 0.6),
    (0.2, 0.2),
    (0.45, 0.45),
];

/// The material indices of the emissive triangles that a primitive of another material
/// touches across their plane, within 1e-5 of their size (each index once, in order).
pub fn lights_in_other_surfaces(scene: &Scene) -> Vec<u32> {
    let triangles: Vec<_> = scene
        .lights
        .iter()
        .filter_map(|l| match l {
            Light::Triangle(t) => Some(t),
            _ => None,
        })
        .collect();
    let step = triangles.len().div_ceil(MAX_PROBED).max(1);
    let mut found = Vec::new();
    for light in triangles.iter().step_by(step) {
        let material = scene.geometry.triangle(light.prim).1;
        let size = light.area.sqrt();
        let [v0, v1, v2] = light.tri.v;
        let n = light.normal;
        let touched = POINTS.iter().enumerate().any(|(k, &(b1, b2))| {
            let p = v0 * (1.0 - b1 - b2) + v1 * b1 + v2 * b2;
            // Start a little off the plane (a few sizes of rounding at p) on either side and
            // look across it; two distances, as a tie at the plane goes either way.
            let scale = p.abs().max_element().max(size);
            let delta = scale * if k % 2 == 0 { 1e-5 } else { 3e-5 };
            [n, -n].iter().any(|&side| {
                let ray = Ray {
                    t_max: 2.0 * delta,
                    ..Ray::new(p + side * delta, -side)
                };
                scene.intersect(&ray).is_some_and(|hit| {
                    hit.material != material && (hit.t - delta).abs() < 0.5 * delta
                })
            })
        });
        if touched && !found.contains(&material) {
            found.push(material);
        }
    }
    found
}

/// A lamp faces a surface when the surface is nearer than this fraction of the lamp
/// triangle's size (the square root of its area) along its emitting normal.
const FACING_GAP: f32 = 0.1;

/// The emissive materials most of whose (probed) triangles emit into an opaque surface
/// closer than [`FACING_GAP`] of their size, each with the largest such gap met: a lamp
/// turned over under a ceiling (its winding reversed) lights the slit between them, and only
/// what leaks out of the slit reaches the room (about half of the light of a 0.5 wide lamp
/// 1 cm under the ceiling of the Cornell box). Surfaces that transmit (a glass cover) do not
/// count, nor do the lamp's own triangles.
pub fn lights_facing_near_surfaces(scene: &Scene) -> Vec<(u32, f32)> {
    use ppm_core::bsdf::BsdfFlags;
    let triangles: Vec<_> = scene
        .lights
        .iter()
        .filter_map(|l| match l {
            Light::Triangle(t) => Some(t),
            _ => None,
        })
        .collect();
    let step = triangles.len().div_ceil(MAX_PROBED).max(1);
    // Per material: probed triangles, the ones facing a surface, the largest gap.
    let mut counts: Vec<(u32, usize, usize, f32)> = Vec::new();
    for light in triangles.iter().step_by(step) {
        let material = scene.geometry.triangle(light.prim).1;
        let size = light.area.sqrt();
        let [v0, v1, v2] = light.tri.v;
        let n = light.normal;
        let mut gap = 0.0f32;
        let faces = POINTS.iter().all(|&(b1, b2)| {
            let p = v0 * (1.0 - b1 - b2) + v1 * b1 + v2 * b2;
            // Off the lamp's own plane by a few sizes of rounding, then along the normal.
            let offset = p.abs().max_element().max(size) * 1e-4;
            let ray = Ray {
                t_max: FACING_GAP * size,
                ..Ray::new(p + n * offset, n)
            };
            scene.intersect(&ray).is_some_and(|hit| {
                let bsdf = &scene.materials[hit.material as usize].bsdf;
                let opaque = !bsdf.flags().intersects(BsdfFlags::TRANSMISSION);
                gap = gap.max(hit.t + offset);
                hit.material != material && opaque
            })
        });
        let entry = match counts.iter_mut().find(|c| c.0 == material) {
            Some(entry) => entry,
            None => {
                counts.push((material, 0, 0, 0.0));
                counts.last_mut().expect("just pushed")
            }
        };
        entry.1 += 1;
        if faces {
            entry.2 += 1;
            entry.3 = entry.3.max(gap);
        }
    }
    counts
        .into_iter()
        .filter(|&(_, probed, facing, _)| 2 * facing > probed)
        .map(|(material, _, _, gap)| (material, gap))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use ppm_core::prelude::*;

    /// A floor, a ceiling at y = 2 and a lamp quad facing down at `lamp_y`.
    fn room(lamp_y: f32) -> Scene {
        room_with_lamp(lamp_y, false)
    }

    /// [`room`], with the lamp turned over (facing up) if `reversed`.
    fn room_with_lamp(lamp_y: f32, reversed: bool) -> Scene {
        let camera = Camera::new(
            Vec3::new(0.0, 1.0, 3.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::Y,
            50.0,
            (8, 8),
        )
        .unwrap();
        let mut b = SceneBuilder::new(camera);
        let white = b.add_material(Material::new(Bsdf::diffuse(Vec3::splat(0.7)), Vec3::ZERO));
        let lamp = b.add_material(Material::new(Bsdf::diffuse(Vec3::ZERO), Vec3::splat(10.0)));
        let quad = |c: [f32; 3], u: [f32; 3], v: [f32; 3], m| {
            TriangleMesh::quad(Vec3::from(c), Vec3::from(u), Vec3::from(v), m)
        };
        b.add_mesh(quad(
            [-1.0, 0.0, -1.0],
            [0.0, 0.0, 2.0],
            [2.0, 0.0, 0.0],
            white,
        ));
        b.add_mesh(quad(
            [-1.0, 2.0, -1.0],
            [2.0, 0.0, 0.0],
            [0.0, 0.0, 2.0],
            white,
        ));
        let (u, v) = ([0.5, 0.0, 0.0], [0.0, 0.0, 0.5]);
        let (u, v) = if reversed { (v, u) } else { (u, v) };
        b.add_mesh(quad([-0.25, lamp_y, -0.25], u, v, lamp));
        b.build().unwrap()
    }

    #[test]
    fn a_lamp_in_the_ceilings_plane_is_found_and_one_below_it_is_not() {
        assert_eq!(lights_in_other_surfaces(&room(2.0)), [1]);
        for y in [1.98, 1.999, 1.0] {
            assert_eq!(
                lights_in_other_surfaces(&room(y)),
                [] as [u32; 0],
                "lamp at {y}"
            );
        }
    }

    /// A lamp turned over 1 cm under the ceiling emits into it; facing down, or turned over
    /// far from it, it does not.
    #[test]
    fn a_lamp_facing_the_ceiling_close_by_is_found() {
        let found = lights_facing_near_surfaces(&room_with_lamp(1.99, true));
        assert_eq!(found.len(), 1, "{found:?}");
        assert_eq!(found[0].0, 1);
        assert!((found[0].1 - 0.01).abs() < 1e-3, "{found:?}");
        assert!(lights_facing_near_surfaces(&room_with_lamp(1.99, false)).is_empty());
        assert!(lights_facing_near_surfaces(&room_with_lamp(1.0, true)).is_empty());
    }

    /// A lamp 1e-4 wide, 500 units from the camera (its vertices a few ulps apart in the
    /// scene's camera-relative coordinates), alone: its probes meet its own other triangle,
    /// which is not another surface.
    #[test]
    fn a_tiny_distant_lamp_alone_is_in_no_other_surface() {
        let camera = Camera::new(
            Vec3::new(0.0, 100.0, 400.0),
            Vec3::ZERO,
            Vec3::Y,
            40.0,
            (8, 8),
        )
        .unwrap();
        let mut b = SceneBuilder::new(camera);
        let lamp = b.add_material(Material::new(Bsdf::diffuse(Vec3::ZERO), Vec3::splat(1e9)));
        b.add_mesh(TriangleMesh::quad(
            Vec3::new(0.0, 250.0, 0.0),
            Vec3::new(1e-4, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 1e-4),
            lamp,
        ));
        assert_eq!(
            lights_in_other_surfaces(&b.build().unwrap()),
            [] as [u32; 0]
        );
    }
}
