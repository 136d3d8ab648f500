//! The large-mesh workload: a displaced sphere of 12 n^2 triangles (995,328 at n = 288) inside
//! the Cornell box, and three seeded ray sets over it (camera rays, incoherent cosine rays from
//! the camera rays' hits, shadow rays from those hits to the light), the same rays for every
//! build. `examples/large_mesh.rs` writes them to a file so another ray tracer can trace the
//! very same rays, and `benches/large_mesh.rs` measures them under criterion.

use ppm_core::geometry::{Ray, TriangleMesh};
use ppm_core::prelude::*;
use ppm_core::sampling::{cosine_hemisphere, Frame, Rng};
use std::io::Write;
use std::path::Path;

/// Subdivisions per cube face of the benchmark's sphere: 12 * 288^2 = 995,328 triangles.
pub const LARGE_N: u32 = 288;

/// The Cornell box (`scenes/cornell_box.yml`) with a bumpy sphere of `12 n^2` triangles in its
/// middle, seen by the scene's camera at `width` x `height`.
pub fn large_scene(n: u32, width: u32, height: u32) -> Scene {
    let mut builder = ppm_tests::load_small("cornell_box.yml", width, height);
    let white = builder.meshes[0].materials[0];
    builder.add_mesh(TriangleMesh::displaced_sphere(
        Vec3::new(0.0, 1.0, -0.1),
        0.55,
        n,
        0.08,
        24.0,
        white,
    ));
    builder.build().expect("the large-mesh scene builds")
}

/// The three ray sets of the benchmark.
pub struct RaySets {
    /// One jittered camera ray per pixel, in pixel order (coherent).
    pub camera: Vec<Ray>,
    /// One cosine-distributed ray from each camera ray's hit (incoherent).
    pub incoherent: Vec<Ray>,
    /// One shadow ray from each camera ray's hit to a point sampled on the lights.
    pub shadow: Vec<Ray>,
}

/// The ray sets of `scene` (seeded: the same rays on every run and for every BVH).
pub fn ray_sets(scene: &Scene) -> RaySets {
    let (w, h) = (scene.camera.width as usize, scene.camera.height as usize);
    let camera: Vec<Ray> = (0..w * h)
        .map(|pixel| {
            let mut rng = Rng::new(1, 0, pixel as u64);
            let film = Vec2::new((pixel % w) as f32, (pixel / w) as f32) + rng.uniform2();
            scene.camera.generate_ray(film)
        })
        .collect();
    let mut incoherent = Vec::new();
    let mut shadow = Vec::new();
    for (i, ray) in camera.iter().enumerate() {
        let Some(hit) = scene.intersect(ray) else {
            continue;
        };
        let mut rng = Rng::new(2, 0, i as u64);
        // The hemisphere on the side the camera ray came from.
        let n = if hit.ng.dot(ray.dir) < 0.0 {
            hit.ng
        } else {
            -hit.ng
        };
        let wi = Frame::new(n).to_world(cosine_hemisphere(rng.uniform2()));
        incoherent.push(Ray::spawn(hit.p, hit.ng, wi));
        if let Some((light, _)) = scene.choose_light(rng.uniform()) {
            if let Some(s) = light.sample_direct(hit.p, rng.uniform2()) {
                shadow.push(Ray::spawn_to(hit.p, hit.ng, s.p, s.n));
            }
        }
    }
    RaySets {
        camera,
        incoherent,
        shadow,
    }
}

/// Writes the scene's triangles and the ray sets in a flat little-endian format another ray
/// tracer can read without a parser: `u32` triangle count, then per triangle its nine vertex
/// coordinates (`f32`); then for each set (camera, incoherent, shadow) a `u32` ray count and
/// per ray `origin.xyz, dir.xyz, t_max` (`f32`, t_max possibly infinite).
pub fn write_ray_file(path: &Path, scene: &Scene, sets: &RaySets) -> std::io::Result<()> {
    let mut out = std::io::BufWriter::new(std::fs::File::create(path)?);
    let geometry = &scene.geometry;
    let count = geometry.triangle_count() as u32;
    out.write_all(&count.to_le_bytes())?;
    for prim in 0..count {
        for v in geometry.triangle(prim).0.v {
            for c in v.to_array() {
                out.write_all(&c.to_le_bytes())?;
            }
        }
    }
    for rays in [&sets.camera, &sets.incoherent, &sets.shadow] {
        out.write_all(&(rays.len() as u32).to_le_bytes())?;
        for r in rays {
            for c in [r.origin.to_array(), r.dir.to_array()].concat() {
                out.write_all(&c.to_le_bytes())?;
            }
            out.write_all(&r.t_max.to_le_bytes())?;
        }
    }
    out.flush()
}
