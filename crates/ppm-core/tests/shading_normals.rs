//! Surfaces shaded with interpolated normals: every estimator reflects light with the shading
//! normal's cosine, as the path tracer does. Photon density estimates count photons per unit
//! of geometric area, so each photon is weighted by the ratio of the two cosines
//! (`GatherNormals`); without it a floor whose normals lean 40 degrees toward the lamp came
//! out 25% darker in ppm and sppm than in pt, and vcm's merging 4% darker.

use ppm_test_support::test_scenes;

use ppm_core::integrator::Radius;
use ppm_core::prelude::*;
use test_scenes::{assert_converges_to_pt, render_stats, sppm_stats};

/// A 2 x 2 floor at y = 0 (geometric normal +y) whose vertex normals all lean 40 degrees
/// toward +x, seen from above so that it fills the image; a lamp on the +x side facing the
/// floor, and a diffuse wall on the -x side for indirect light. Open to the sky.
fn tilted_floor(resolution: u32) -> Scene {
    let camera = Camera::new(
        Vec3::new(0.0, 3.5, 0.01),
        Vec3::ZERO,
        Vec3::NEG_Z,
        28.0,
        (resolution, resolution),
    )
    .unwrap();
    let mut b = SceneBuilder::new(camera);
    let white = b.add_material(Material::new(Bsdf::diffuse(Vec3::splat(0.8)), Vec3::ZERO));
    let lamp = b.add_material(Material::new(Bsdf::diffuse(Vec3::ZERO), Vec3::splat(10.0)));
    let tilt = 40f32.to_radians();
    let mut floor = TriangleMesh::new(
        vec![
            Vec3::new(-1.0, 0.0, -1.0),
            Vec3::new(-1.0, 0.0, 1.0),
            Vec3::new(1.0, 0.0, 1.0),
            Vec3::new(1.0, 0.0, -1.0),
        ],
        vec![[0, 1, 2], [0, 2, 3]],
        white,
    );
    floor.normals = vec![Vec3::new(tilt.sin(), tilt.cos(), 0.0); 4];
    b.add_mesh(floor);
    // The lamp faces -x (cross(edge_u, edge_v)), the wall +x.
    b.add_mesh(TriangleMesh::quad(
        Vec3::new(1.2, 1.0, -1.0),
        Vec3::new(0.0, 0.0, 2.0),
        Vec3::new(0.0, 0.6, 0.0),
        lamp,
    ));
    b.add_mesh(TriangleMesh::quad(
        Vec3::new(-1.2, 0.0, -1.0),
        Vec3::new(0.0, 2.0, 0.0),
        Vec3::new(0.0, 0.0, 2.0),
        white,
    ));
    b.build().unwrap()
}

#[test]
fn photon_estimates_reflect_with_the_shading_normal_as_path_tracing_does() {
    let scene = tilted_floor(24);
    let pt = render_stats(
        &scene,
        &RenderSettings {
            seed: 1,
            ..RenderSettings::for_algorithm(&scene, Algorithm::Path)
        },
        600,
    );
    // Direct light from photons, so that the whole floor is a density estimate.
    let ppm = RenderSettings {
        photons: 20_000,
        radius: Radius::World(0.04),
        direct: DirectMode::Photons,
        seed: 2,
        ..RenderSettings::for_algorithm(&scene, Algorithm::Ppm)
    };
    let ppm = render_stats(&scene, &ppm, 64);
    assert_converges_to_pt("tilted floor", "ppm", &pt, &ppm, 2.0);
    let sppm = RenderSettings {
        photons: 5_000,
        radius: Radius::World(0.04),
        direct: DirectMode::Photons,
        seed: 3,
        ..RenderSettings::for_algorithm(&scene, Algorithm::Sppm)
    };
    let sppm = sppm_stats(&scene, &sppm, 16, 16);
    assert_converges_to_pt("tilted floor", "sppm", &pt, &sppm, 2.0);
    // A merge radius and light paths (one per pixel) enough for merging to carry a good part
    // of the floor's light: without the ratio vcm is 1.9% dark here (9 standard errors).
    let vcm = RenderSettings {
        radius: Radius::World(0.1),
        seed: 4,
        ..RenderSettings::for_algorithm(&scene, Algorithm::Vcm)
    };
    let vcm = render_stats(&scene, &vcm, 200);
    assert_converges_to_pt("tilted floor", "vcm", &pt, &vcm, 2.0);
}
