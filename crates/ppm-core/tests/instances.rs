//! Instances (one mesh placed many times by transforms, a two-level BVH) against the same
//! meshes flattened into world space: identity placements hit bit for bit like the flat
//! mesh, transformed ones like the flattened copies to float precision, mirrors keep a
//! closed mesh's outside outside, rays spawned from instance hits do not hit their own
//! surface again, memory stays close to one copy, and emissive placements become lights.

use glam::{DMat3, DMat4, DQuat, DVec3, Vec2, Vec3};
use ppm_core::bsdf::Bsdf;
use ppm_core::camera::Camera;
use ppm_core::geometry::{Geometry, Hit, MeshInstance, Ray, TriangleMesh};
use ppm_core::material::Material;
use ppm_core::sampling::{uniform_sphere, Rng};
use ppm_core::scene::SceneBuilder;

/// A bumpy closed sphere of 12 n^2 triangles around the origin, radius 1.
fn bumpy(n: u32) -> TriangleMesh {
    let mut m = TriangleMesh::displaced_sphere(Vec3::ZERO, 1.0, n, 0.1, 9.0, 0);
    // Vertex normals (the unit directions), so shading normals are transformed too.
    m.normals = m.positions.iter().map(|p| p.normalize()).collect();
    m
}

/// The mesh moved by `m` as a flattened copy is: points by M (f64), normals by M^-T, the
/// winding reversed for a mirroring M.
fn flatten(mesh: &TriangleMesh, m: DMat4) -> TriangleMesh {
    let mut out = mesh.clone();
    let linear = DMat3::from_mat4(m);
    for p in &mut out.positions {
        *p = m.transform_point3(p.as_dvec3()).as_vec3();
    }
    let n = linear.inverse().transpose();
    for v in &mut out.normals {
        *v = (n * v.as_dvec3()).normalize().as_vec3();
    }
    if linear.determinant() < 0.0 {
        for t in &mut out.indices {
            t.swap(1, 2);
        }
    }
    out
}

/// Rays from random points in a cube of half-size `extent` in random directions, every
/// second one aimed at a random point near the origin.
fn rays(seed: u64, count: usize, extent: f32) -> Vec<Ray> {
    let mut rng = Rng::new(seed, 0, 0);
    (0..count)
        .map(|i| {
            let o = (rng.uniform2().extend(rng.uniform()) * 2.0 - 1.0) * extent;
            let dir = if i % 2 == 0 {
                let target = (rng.uniform2().extend(rng.uniform()) * 2.0 - 1.0) * extent * 0.5;
                (target - o).normalize_or(Vec3::X)
            } else {
                uniform_sphere(rng.uniform2())
            };
            Ray::new(o, dir)
        })
        .collect()
}

fn bits(h: &Hit) -> [u32; 14] {
    [
        h.t.to_bits(),
        h.p.x.to_bits(),
        h.p.y.to_bits(),
        h.p.z.to_bits(),
        h.ng.x.to_bits(),
        h.ng.y.to_bits(),
        h.ng.z.to_bits(),
        h.ns.x.to_bits(),
        h.ns.y.to_bits(),
        h.ns.z.to_bits(),
        h.uv.x.to_bits(),
        h.uv.y.to_bits(),
        h.material,
        h.prim,
    ]
}

/// An identity placement is traced with the world ray itself: every hit (distance, point,
/// normals, barycentrics, material and id) and every shadow answer is the flat mesh's.
#[test]
fn identity_instances_hit_bit_for_bit_like_the_flat_mesh() {
    let quad = TriangleMesh::quad(Vec3::new(-2.0, -1.2, -2.0), Vec3::Z * 4.0, Vec3::X * 4.0, 1);
    let mesh = bumpy(24);
    // The quad first in both: the mesh's ids then follow the quad's in both scenes.
    let flat = Geometry::new(&[quad.clone(), mesh.clone()], &[]);
    let placed = MeshInstance {
        mesh: 0,
        to_world: DMat4::IDENTITY,
    };
    let instanced = Geometry::with_instances(&[quad], &[], &[mesh], &[placed]).unwrap();
    assert_eq!(instanced.instance_count(), 1);
    let mut hits = 0;
    for (i, mut ray) in rays(3, 20_000, 2.5).into_iter().enumerate() {
        if i % 3 == 0 {
            ray.t_max = 1.5;
        }
        let (a, b) = (flat.intersect(&ray), instanced.intersect(&ray));
        assert_eq!(a.as_ref().map(bits), b.as_ref().map(bits), "ray {i}");
        assert_eq!(flat.occluded(&ray), instanced.occluded(&ray), "ray {i}");
        hits += b.is_some_and(|h| h.material == 0) as usize;
    }
    assert!(hits > 3000, "too few hits on the instance: {hits}");
}

/// A rotation, a non-uniform scale, a mirror and a translation, composed.
fn transforms() -> Vec<DMat4> {
    vec![
        DMat4::from_translation(DVec3::new(2.5, 0.0, 0.0)),
        DMat4::from_scale_rotation_translation(
            DVec3::new(0.5, 1.5, 0.8),
            DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), 0.7),
            DVec3::new(-2.0, 1.0, 0.5),
        ),
        // A mirror in x.
        DMat4::from_translation(DVec3::new(0.0, -2.5, 0.0))
            * DMat4::from_scale(DVec3::new(-1.0, 1.0, 1.0)),
        DMat4::from_translation(DVec3::new(0.3, 2.0, -2.0))
            * DMat4::from_axis_angle(DVec3::Y, 2.0)
            * DMat4::from_scale(DVec3::new(0.7, 0.7, -1.2)),
    ]
}

/// Transformed placements answer like the flattened copies to float precision: the same
/// primitive, the distance and point within 1e-4, normals within 1e-4, the same sides.
#[test]
fn transformed_instances_hit_like_flattened_copies() {
    let mesh = bumpy(16);
    let ms = transforms();
    let copies: Vec<TriangleMesh> = ms.iter().map(|&m| flatten(&mesh, m)).collect();
    let flat = Geometry::new(&copies, &[]);
    let placements: Vec<MeshInstance> = (ms.iter())
        .map(|&to_world| MeshInstance { mesh: 0, to_world })
        .collect();
    let instanced = Geometry::with_instances(&[], &[], &[mesh], &placements).unwrap();
    assert_eq!(
        instanced.instanced_triangle_count(),
        flat.triangle_count() as u64
    );
    let (lo, hi) = flat.bounds();
    let (ilo, ihi) = instanced.bounds();
    // The placements' boxes (each a box around the moved box of the mesh) hold the copies.
    assert!(
        ilo.cmple(lo).all() && ihi.cmpge(hi).all(),
        "{ilo} {ihi} {lo} {hi}"
    );
    let (mut same, mut compared, mut disagree) = (0, 0, 0);
    for (i, ray) in rays(5, 20_000, 4.0).into_iter().enumerate() {
        let (a, b) = (flat.intersect(&ray), instanced.intersect(&ray));
        match (a, b) {
            (Some(a), Some(b)) if a.prim == b.prim => {
                compared += 1;
                assert!(
                    (a.t - b.t).abs() <= 1e-4 * a.t.max(1.0),
                    "ray {i}: {a:?} {b:?}"
                );
                assert!(a.p.abs_diff_eq(b.p, 1e-4), "ray {i}: {a:?} {b:?}");
                assert!(a.ng.abs_diff_eq(b.ng, 1e-4), "ray {i}: {a:?} {b:?}");
                assert!(a.ns.abs_diff_eq(b.ns, 1e-4), "ray {i}: {a:?} {b:?}");
                // A mirrored copy has its winding reversed: (b1, b2) swapped.
                let swapped = Vec2::new(b.uv.y, b.uv.x);
                same += (a.uv.abs_diff_eq(b.uv, 1e-4) || a.uv.abs_diff_eq(swapped, 1e-4)) as usize;
            }
            (None, None) => {}
            // Rays through a shared edge or grazing a silhouette may pick the neighbour.
            _ => disagree += 1,
        }
        assert_eq!(
            flat.occluded(&ray),
            instanced.occluded(&ray) || a.is_some() != b.is_some() && b.is_none(),
            "ray {i}"
        );
    }
    assert!(compared > 3000, "too few hits compared: {compared}");
    assert!(
        same > compared * 99 / 100,
        "barycentrics differ: {same} of {compared}"
    );
    assert!(disagree < 20, "{disagree} rays disagree on what they hit");
}

/// A mirrored closed mesh keeps its outside outside: a ray from outside aimed at its
/// centre meets a geometric normal facing it, whatever the sign of the determinant (the
/// emitting side and a glass's outside stay where they were).
#[test]
fn mirrors_keep_the_outside_outside() {
    let mesh = bumpy(12);
    for scale in [
        DVec3::new(-1.0, 1.0, 1.0),
        DVec3::new(1.0, -2.0, 0.5),
        DVec3::splat(-1.0),
    ] {
        let center = DVec3::new(0.5, -0.25, 2.0);
        let to_world = DMat4::from_translation(center) * DMat4::from_scale(scale);
        let g = Geometry::with_instances(
            &[],
            &[],
            std::slice::from_ref(&mesh),
            &[MeshInstance { mesh: 0, to_world }],
        )
        .unwrap();
        let mut rng = Rng::new(9, 0, 0);
        for _ in 0..2000 {
            let o = center.as_vec3() + uniform_sphere(rng.uniform2()) * 5.0;
            let ray = Ray::new(o, (center.as_vec3() - o).normalize());
            let h = g.intersect(&ray).expect("aimed at the centre");
            assert!(h.ng.dot(ray.dir) < 0.0, "{scale}: {h:?}");
            assert!(h.ns.dot(h.ng) > 0.0, "{scale}: {h:?}");
        }
    }
}

/// Rays spawned from hits on a convex instance far from the origin (rotated, scaled,
/// translated by about 1e3) never meet their own surface again: outward rays escape, inward
/// ones cross to another face, on the inner side of the tangent plane.
#[test]
fn spawned_rays_leave_instance_surfaces() {
    // A cube (one planar quad per face): convex.
    let mesh = TriangleMesh::displaced_sphere(Vec3::ZERO, 1.0, 1, 0.0, 1.0, 0);
    let center = DVec3::new(1000.0, -700.0, 300.0);
    let to_world = DMat4::from_scale_rotation_translation(
        DVec3::new(3.0, 0.5, 1.0),
        DQuat::from_axis_angle(DVec3::new(1.0, 1.0, 0.0).normalize(), 0.4),
        center,
    );
    let g =
        Geometry::with_instances(&[], &[], &[mesh], &[MeshInstance { mesh: 0, to_world }]).unwrap();
    let mut rng = Rng::new(21, 0, 0);
    let mut checked = 0;
    for _ in 0..4000 {
        let o = center.as_vec3() + uniform_sphere(rng.uniform2()) * 10.0;
        let target = center.as_vec3() + uniform_sphere(rng.uniform2()) * 0.3;
        let Some(h) = g.intersect(&Ray::new(o, (target - o).normalize())) else {
            continue;
        };
        let out = uniform_sphere(rng.uniform2());
        let out = if out.dot(h.ng) < 0.0 { -out } else { out };
        assert!(g.intersect(&Ray::spawn(h.p, h.ng, out)).is_none(), "{h:?}");
        let into = -out;
        let far = g
            .intersect(&Ray::spawn(h.p, h.ng, into))
            .expect("the far side");
        assert!(far.ng.dot(h.ng) < 1.0 - 1e-4, "{h:?} {far:?}");
        assert!((far.p - h.p).dot(h.ng) <= 1e-3, "{h:?} {far:?}");
        checked += 1;
    }
    assert!(checked > 3000, "{checked}");
}

/// 1,000 placements of a 10,092-triangle mesh hold less than 1.1 times one copy plus 512
/// bytes per placement (its record and its share of the top-level BVH), about 1/1000 of the
/// flattened scene's memory.
#[test]
fn a_thousand_instances_cost_about_one_copy() {
    let mesh = bumpy(29);
    let one = Geometry::new(std::slice::from_ref(&mesh), &[]).memory_bytes();
    let placements: Vec<MeshInstance> = (0..1000)
        .map(|i| MeshInstance {
            mesh: 0,
            to_world: DMat4::from_translation(DVec3::new(
                (i % 10) as f64 * 3.0,
                (i / 10 % 10) as f64 * 3.0,
                (i / 100) as f64 * 3.0,
            )),
        })
        .collect();
    let g = Geometry::with_instances(&[], &[], &[mesh], &placements).unwrap();
    assert_eq!(g.instanced_triangle_count(), 1000 * 10_092);
    let bytes = g.memory_bytes();
    let limit = one + one / 10 + 1000 * 512;
    assert!(
        bytes < limit,
        "{bytes} bytes for 1000 placements, one copy {one}"
    );
    assert!(bytes > one, "{bytes} {one}");
}

/// A singular transform or a mesh index out of range is an error naming the placement.
#[test]
fn bad_placements_are_errors() {
    let mesh = bumpy(2);
    let flat = DMat4::from_scale(DVec3::new(1.0, 0.0, 1.0));
    for (p, needle) in [
        (
            MeshInstance {
                mesh: 0,
                to_world: flat,
            },
            "singular",
        ),
        (
            MeshInstance {
                mesh: 3,
                to_world: DMat4::IDENTITY,
            },
            "shared meshes",
        ),
    ] {
        let placements = [
            MeshInstance {
                mesh: 0,
                to_world: DMat4::IDENTITY,
            },
            p,
        ];
        let e = Geometry::with_instances(&[], &[], std::slice::from_ref(&mesh), &placements)
            .err()
            .expect("an error");
        let text = e.to_string();
        assert!(
            text.contains("instance 1") && text.contains(needle),
            "{text}"
        );
    }
}

/// Emissive placements are copied into the flat level, each an area light of its own
/// area: the same lights and power as the scene with the copies placed by hand, mirror
/// included (the emitting side stays the transformed one).
#[test]
fn emissive_instances_are_lights_of_their_own_area() {
    let camera = || {
        Camera::new(
            Vec3::new(0.0, 0.0, 5.0),
            Vec3::ZERO,
            Vec3::Y,
            40.0,
            (16, 16),
        )
    };
    let lamp = TriangleMesh::quad(Vec3::new(-0.5, -0.5, 0.0), Vec3::X, Vec3::Y, 1);
    let placements = [
        DMat4::from_translation(DVec3::new(1.0, 0.0, 0.0)),
        DMat4::from_scale(DVec3::new(2.0, 1.0, -1.0)),
    ];
    let materials = |b: &mut SceneBuilder| {
        b.add_material(Material::new(Bsdf::diffuse(Vec3::splat(0.5)), Vec3::ZERO));
        b.add_material(Material::new(
            Bsdf::diffuse(Vec3::splat(0.5)),
            Vec3::new(1.0, 2.0, 3.0),
        ));
    };
    let mut by_hand = SceneBuilder::new(camera().unwrap());
    materials(&mut by_hand);
    for &m in &placements {
        by_hand.add_mesh(flatten(&lamp, m));
    }
    let mut instanced = SceneBuilder::new(camera().unwrap());
    materials(&mut instanced);
    let k = instanced.add_instanced_mesh(lamp);
    for &m in &placements {
        instanced.add_instance(k, m);
    }
    assert!(instanced.has_light());
    let (a, b) = (by_hand.build().unwrap(), instanced.build().unwrap());
    assert_eq!(a.lights.len(), 4);
    assert_eq!(b.lights.len(), a.lights.len());
    assert_eq!(b.total_power(), a.total_power());
    assert_eq!(b.geometry.instance_count(), 0);
    // Total area 1 + 2 times pi Le: the power of Lambertian emitters.
    let expected = Vec3::new(1.0, 2.0, 3.0) * 3.0 * std::f32::consts::PI;
    assert!(
        b.total_power().abs_diff_eq(expected, 1e-4),
        "{}",
        b.total_power()
    );
    for (x, y) in a.lights.iter().zip(&b.lights) {
        assert_eq!(format!("{x:?}"), format!("{y:?}"));
    }
}

/// 100 placements of a 10,092-triangle mesh on a 5 x 5 x 4 grid, each turned differently,
/// as instances and flattened into one BVH (1,009,200 triangles), and 2^16 rays into the grid.
pub fn grid_scenes() -> (Geometry, Geometry, Vec<Ray>) {
    let mesh = bumpy(29);
    let placements: Vec<MeshInstance> = (0..100)
        .map(|i| MeshInstance {
            mesh: 0,
            to_world: DMat4::from_translation(DVec3::new(
                (i % 5) as f64 * 2.5,
                (i / 5 % 5) as f64 * 2.5,
                (i / 25) as f64 * 2.5,
            )) * DMat4::from_axis_angle(
                DVec3::new(1.0, 1.0, 0.0).normalize(),
                i as f64 * 0.3,
            ),
        })
        .collect();
    let copies: Vec<TriangleMesh> = placements
        .iter()
        .map(|p| flatten(&mesh, p.to_world))
        .collect();
    let flat = Geometry::new(&copies, &[]);
    let instanced = Geometry::with_instances(&[], &[], &[mesh], &placements).unwrap();
    let mut rng = Rng::new(4, 0, 0);
    let center = Vec3::new(5.0, 5.0, 3.75);
    let rays = (0..1 << 16)
        .map(|_| {
            let o = center + uniform_sphere(rng.uniform2()) * 15.0;
            let target = center + (rng.uniform2().extend(rng.uniform()) * 2.0 - 1.0) * 5.0;
            Ray::new(o, (target - o).normalize())
        })
        .collect();
    (instanced, flat, rays)
}

/// Trace time of the instanced grid over the flattened one, runs alternated (A B A B ...):
/// `cargo test -p ppm-core --test instances -- --ignored --nocapture trace_time`.
/// Prints the ratio's min, median and max; a measurement, not a check (the machine may be
/// loaded), so it is ignored by default.
#[test]
#[ignore]
fn trace_time_instances_against_flattened() {
    let (instanced, flat, rays) = grid_scenes();
    println!(
        "triangles: {} placed, {} flattened; memory: {} bytes instanced, {} flattened",
        instanced.instanced_triangle_count(),
        flat.triangle_count(),
        instanced.memory_bytes(),
        flat.memory_bytes()
    );
    let time = |g: &Geometry| {
        let start = std::time::Instant::now();
        let mut hits = 0usize;
        for r in &rays {
            hits += g.intersect(r).is_some() as usize;
            hits += g.occluded(&Ray { t_max: 10.0, ..*r }) as usize;
        }
        std::hint::black_box(hits);
        start.elapsed().as_secs_f64()
    };
    let mut ratios: Vec<f64> = (0..7).map(|_| time(&instanced) / time(&flat)).collect();
    ratios.sort_by(f64::total_cmp);
    println!(
        "instanced / flattened trace time over 7 alternated runs: min {:.3} median {:.3} max {:.3}",
        ratios[0], ratios[3], ratios[6]
    );
}
