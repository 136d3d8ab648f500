//! Workloads of the scene benchmarks, built from real renders of the shipped scenes.

use ppm_core::geometry::{Hit, Ray};
use ppm_core::integrator::{stores_photons, trace_light_path, RenderSettings};
use ppm_core::photon::{Photon, PhotonBuffer};
use ppm_core::prelude::*;
use ppm_core::sampling::Rng;

/// Jittered camera rays over the whole image, in pixel order (coherent, like the eye pass).
pub fn camera_rays(scene: &Scene, count: usize) -> Vec<Ray> {
    let (w, h) = (scene.camera.width as usize, scene.camera.height as usize);
    (0..count)
        .map(|i| {
            let pixel = i % (w * h);
            let mut rng = Rng::new(1, 0, i as u64);
            let film = Vec2::new((pixel % w) as f32, (pixel / w) as f32) + rng.uniform2();
            scene.camera.generate_ray(film)
        })
        .collect()
}

/// The photons one iteration of the photon pass stores, in path order.
pub fn photons(scene: &Scene, settings: &RenderSettings, paths: u32) -> Vec<Photon> {
    let mut buffer = PhotonBuffer::with_capacity(paths as usize * 8);
    {
        let mut writer = buffer.writer();
        let mut counters = Default::default();
        for path in 0..paths {
            trace_light_path(scene, settings, 0, path, &mut writer, &mut counters);
        }
    }
    buffer.as_slice().to_vec()
}

/// Gather points as the eye pass finds them: first hits of camera rays on surfaces that store
/// photons, with the direction toward the camera.
pub fn gather_points(scene: &Scene, count: usize) -> Vec<(Hit, Vec3)> {
    camera_rays(scene, count * 2)
        .iter()
        .filter_map(|ray| {
            let hit = scene.intersect(ray)?;
            stores_photons(&scene.material(&hit).bsdf).then_some((hit, -ray.dir))
        })
        .take(count)
        .collect()
}

/// Shadow rays from gather points to points sampled on the lights.
pub fn shadow_rays(scene: &Scene, count: usize) -> Vec<Ray> {
    let mut rng = Rng::new(2, 0, 0);
    gather_points(scene, count)
        .iter()
        .filter_map(|(hit, _)| {
            let (light, _) = scene.choose_light(rng.uniform())?;
            let s = light.sample_direct(hit.p, rng.uniform2())?;
            Some(Ray::spawn_to(hit.p, hit.ng, s.p, s.n))
        })
        .collect()
}
pub mod large_mesh;
