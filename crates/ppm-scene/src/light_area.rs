//! Emissive triangles that single precision leaves without area.
//!
//! The scene is built in f32 coordinates relative to the camera. A lamp much smaller than the
//! spacing of f32 values at its distance (a 1e-6 quad 400 units away, where that spacing is
//! 3e-5) loses its area there: its triangles cannot be hit or sampled and emit nothing, which
//! the renderer can only notice as a dark or black image. The loader names such lamps.

use ppm_core::light::Light;
use ppm_core::scene::{Scene, SceneBuilder};

/// Emissive triangles of the scene as described, per material index: what
/// [`lights_without_area`] compares the built scene's lights against. (The loader has
/// already refused quads without area and dropped OBJ faces without area, with a warning, so
/// every triangle here had area in the description's f64 numbers; the builder holds them in
/// f32 relative to the camera, where a tiny one may already have none.)
pub fn emissive_triangles(builder: &SceneBuilder) -> Vec<usize> {
    let emits: Vec<bool> = builder
        .materials
        .iter()
        .map(|mat| mat.emission.max_element() > 0.0)
        .collect();
    let mut count = vec![0usize; emits.len()];
    for &m in builder.meshes.iter().flat_map(|mesh| &mesh.materials) {
        if emits.get(m as usize) == Some(&true) {
            count[m as usize] += 1;
        }
    }
    count
}

/// The light materials with triangles in the description (`described`, from
/// [`emissive_triangles`]) none of which became a light in the built `scene`: (material, its
/// described triangles), by material index. (A lamp that lost only some triangles is not
/// named: exact duplicates are dropped too, and are reported on their own.)
pub fn lights_without_area(scene: &Scene, described: &[usize]) -> Vec<(u32, usize)> {
    let mut lit = vec![0usize; described.len()];
    for light in &scene.lights {
        if let Light::Triangle(t) = light {
            if let Some(n) = lit.get_mut(scene.geometry.triangle(t.prim).1 as usize) {
                *n += 1;
            }
        }
    }
    (0..described.len())
        .filter(|&m| described[m] > 0 && lit[m] == 0)
        .map(|m| (m as u32, described[m]))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use ppm_core::prelude::*;

    /// A lamp quad of side `side`, seen from 500 units away, beside a normal one: what
    /// [`lights_without_area`] says of it.
    fn check(side: f32) -> Vec<(u32, usize)> {
        let camera = Camera::new(
            Vec3::new(0.0, 100.0, 400.0),
            Vec3::ZERO,
            Vec3::Y,
            40.0,
            (8, 8),
        )
        .unwrap();
        let mut b = SceneBuilder::new(camera);
        let tiny = b.add_material(Material::new(Bsdf::diffuse(Vec3::ZERO), Vec3::splat(1e9)));
        let big = b.add_material(Material::new(Bsdf::diffuse(Vec3::ZERO), Vec3::splat(1.0)));
        b.add_mesh(TriangleMesh::quad(
            Vec3::new(0.0, 250.0, 0.0),
            Vec3::new(side, 0.0, 0.0),
            Vec3::new(0.0, 0.0, side),
            tiny,
        ));
        b.add_mesh(TriangleMesh::quad(
            Vec3::new(5.0, 250.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
            big,
        ));
        let described = emissive_triangles(&b);
        lights_without_area(&b.build().unwrap(), &described)
    }

    #[test]
    fn a_lamp_below_single_precision_is_named_and_a_small_one_is_not() {
        assert_eq!(check(1e-6), [(0, 2)]);
        assert_eq!(check(1e-3), []);
    }
}
